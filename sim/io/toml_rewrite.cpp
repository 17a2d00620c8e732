// A TOML document written as an edit of its source text (toml_rewrite.hpp).
#include "sim/io/toml_rewrite.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <sstream>
#include <vector>

namespace lg {

std::string tomlFloat(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  std::string s(buf, r.ptr);
  if (s.find_first_of(".eE") == std::string::npos) s += ".0";  // a float, not an integer
  return s;
}

bool sameToml(const toml::node& a, const toml::node& b) {
  if (a.type() != b.type()) return false;
  if (const auto* ta = a.as_table()) {
    const auto* tb = b.as_table();
    if (ta->size() != tb->size()) return false;
    for (const auto& [k, v] : *ta) {
      const toml::node* w = tb->get(k.str());
      if (!w || !sameToml(v, *w)) return false;
    }
    return true;
  }
  if (const auto* xa = a.as_array()) {
    const auto* xb = b.as_array();
    if (xa->size() != xb->size()) return false;
    for (std::size_t i = 0; i < xa->size(); ++i)
      if (!sameToml(*xa->get(i), *xb->get(i))) return false;
    return true;
  }
  if (const auto* fa = a.as_floating_point()) {
    const double x = fa->get(), y = b.as_floating_point()->get();
    if (std::isnan(x) || std::isnan(y)) return std::isnan(x) && std::isnan(y);
    return std::memcmp(&x, &y, sizeof x) == 0;
  }
  if (const auto* ia = a.as_integer()) return ia->get() == b.as_integer()->get();
  if (const auto* sa = a.as_string()) return sa->get() == b.as_string()->get();
  if (const auto* ba = a.as_boolean()) return ba->get() == b.as_boolean()->get();
  if (const auto* da = a.as_date()) return da->get() == b.as_date()->get();
  if (const auto* ma = a.as_time()) return ma->get() == b.as_time()->get();
  if (const auto* ea = a.as_date_time()) return ea->get() == b.as_date_time()->get();
  return false;
}

namespace {

bool isBareKey(std::string_view k) {
  if (k.empty()) return false;
  for (const char c : k)
    if (!((c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_' || c == '-')) return false;
  return true;
}

std::string tomlString(std::string_view s) {
  std::string out = "\"";
  for (const char ch : s) {
    const auto c = static_cast<unsigned char>(ch);
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\b': out += "\\b"; break;
      case '\t': out += "\\t"; break;
      case '\n': out += "\\n"; break;
      case '\f': out += "\\f"; break;
      case '\r': out += "\\r"; break;
      default:
        if (c < 0x20 || c == 0x7f) {
          char u[8];
          std::snprintf(u, sizeof u, "\\u%04X", c);
          out += u;
        } else {
          out += ch;
        }
    }
  }
  return out + "\"";
}

std::string tomlKey(std::string_view k) { return isBareKey(k) ? std::string(k) : tomlString(k); }

std::string joinPath(const std::vector<std::string>& path) {
  std::string s;
  for (const auto& k : path) s += (s.empty() ? "" : ".") + tomlKey(k);
  return s;
}

// A value written on one line: numbers, strings, booleans, dates, arrays and inline tables. False for
// what cannot be (nothing today; kept for types a later TOML may add).
bool inlineValue(const toml::node& n, std::string& out) {
  if (const auto* t = n.as_table()) {
    if (t->empty()) {
      out += "{}";
      return true;
    }
    out += "{ ";
    bool first = true;
    for (const auto& [k, v] : *t) {
      out += (first ? "" : ", ") + tomlKey(k.str()) + " = ";
      first = false;
      if (!inlineValue(v, out)) return false;
    }
    out += " }";
    return true;
  }
  if (const auto* a = n.as_array()) {
    out += "[";
    for (std::size_t i = 0; i < a->size(); ++i) {
      if (i) out += ", ";
      if (!inlineValue(*a->get(i), out)) return false;
    }
    out += "]";
    return true;
  }
  if (const auto* f = n.as_floating_point()) return out += tomlFloat(f->get()), true;
  if (const auto* i = n.as_integer()) return out += std::to_string(i->get()), true;
  if (const auto* s = n.as_string()) return out += tomlString(s->get()), true;
  if (const auto* b = n.as_boolean()) return out += b->get() ? "true" : "false", true;
  std::ostringstream o;
  if (const auto* d = n.as_date()) o << *d;
  else if (const auto* t = n.as_time()) o << *t;
  else if (const auto* dt = n.as_date_time()) o << *dt;
  else return false;
  out += o.str();
  return true;
}

// A value that sits on a key's line: anything but a table of its own section or an array of them.
bool isLineValue(const toml::node& n) {
  if (const auto* t = n.as_table()) return t->is_inline();
  if (const auto* a = n.as_array()) return !(a->is_array_of_tables() && !a->empty() && !a->get(0)->as_table()->is_inline());
  return true;
}

class Editor {
 public:
  Editor(std::string_view source) : src_(source) {
    if (src_.empty() || src_.back() != '\n') src_ += '\n';
    lineStart_.push_back(0);
    for (std::size_t i = 0; i < src_.size(); ++i)
      if (src_[i] == '\n') lineStart_.push_back(i + 1);
  }

  const std::string& reason() const { return reason_; }
  bool fail(const std::string& why) {
    if (reason_.empty()) reason_ = why;
    return false;
  }

  // The updated table 'upd' over the source's table 'orig' (at 'path').
  bool table(const toml::table& orig, const toml::table& upd, const std::vector<std::string>& path) {
    for (const auto& [k, ov] : orig)
      if (!upd.contains(k.str()) && !remove(ov, path, k.str())) return false;
    for (const auto& [k, uv] : upd) {
      auto p = path;
      p.push_back(std::string(k.str()));
      const toml::node* ov = orig.get(k.str());
      if (!(ov ? node(*ov, uv, p) : add(orig, uv, p))) return false;
    }
    return true;
  }

  // The edited text: the source with every edit applied, the appended sections after it.
  std::string result() const {
    auto edits = edits_;
    std::stable_sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin < b.begin; });
    std::string out;
    std::size_t pos = 0;
    for (const auto& e : edits) {
      out.append(src_, pos, e.begin - pos);
      out += e.text;
      pos = e.end;
    }
    out.append(src_, pos, std::string::npos);
    return out + tail_;
  }

  // Whether the edits overlap (they never should; checked before the text is used).
  bool overlapping() const {
    auto edits = edits_;
    std::stable_sort(edits.begin(), edits.end(), [](const Edit& a, const Edit& b) { return a.begin < b.begin; });
    for (std::size_t i = 1; i < edits.size(); ++i)
      if (edits[i].begin < edits[i - 1].end) return true;
    return false;
  }

 private:
  struct Edit {
    std::size_t begin, end;
    std::string text;
  };
  std::string src_;
  std::vector<std::size_t> lineStart_;  // byte offset of each line's start (line 1 at [0])
  std::vector<Edit> edits_;
  std::string tail_;
  std::string reason_;

  // The byte offset of a source position (line and column from 1, columns in code points).
  std::size_t offset(const toml::source_position& p) const {
    if (p.line < 1 || p.line > lineStart_.size() - 1) return std::string::npos;
    std::size_t at = lineStart_[p.line - 1];
    for (toml::source_index c = 1; c < p.column; ++c) {
      if (at >= src_.size() || src_[at] == '\n') return std::string::npos;
      ++at;
      while (at < src_.size() && (static_cast<unsigned char>(src_[at]) & 0xC0) == 0x80) ++at;
    }
    return at;
  }
  std::size_t nextLine(const toml::source_position& p) const {
    return p.line < lineStart_.size() ? lineStart_[p.line] : src_.size();
  }
  // A value replaced; a comment after it on its line keeps its column where the spaces before it allow
  // (one space at least).
  void replace(const toml::node& n, std::string text) {
    const std::size_t begin = offset(n.source().begin);
    std::size_t end = offset(n.source().end);
    std::size_t spaces = 0;
    while (end + spaces < src_.size() && src_[end + spaces] == ' ') ++spaces;
    if (n.source().begin.line == n.source().end.line && end + spaces < src_.size() && src_[end + spaces] == '#' &&
        spaces > 0) {
      const std::size_t was = end - begin;
      if (text.size() > was) end += std::min(text.size() - was, spaces - 1);
      else text.append(was - text.size(), ' ');
    }
    edits_.push_back({begin, end, std::move(text)});
  }
  bool located(const toml::node& n, const std::vector<std::string>& path) {
    if (offset(n.source().begin) == std::string::npos || offset(n.source().end) == std::string::npos ||
        offset(n.source().end) < offset(n.source().begin))
      return fail("the source position of '" + joinPath(path) + "' is not known");
    return true;
  }

  // Whether table 't' at 'path' has a header of its own ("[a.b]", or "[[a.b]]" as an array's element).
  bool headed(const toml::table& t, const std::vector<std::string>& path, bool element) const {
    const std::size_t at = offset(t.source().begin);
    if (at == std::string::npos) return false;
    const std::string open = element ? "[[" : "[", close = element ? "]]" : "]";
    if (src_.compare(at, open.size(), open) != 0 || (!element && src_.compare(at, 2, "[[") == 0)) return false;
    const std::size_t end = src_.find(close, at + open.size());
    if (end == std::string::npos) return false;
    std::string name;
    for (std::size_t i = at + open.size(); i < end; ++i)
      if (src_[i] != ' ' && src_[i] != '\t') name += src_[i];
    std::string want;
    for (const auto& k : path) want += (want.empty() ? "" : ".") + tomlKey(k);
    return name == want;
  }

  bool node(const toml::node& ov, const toml::node& uv, const std::vector<std::string>& path) {
    if (sameToml(ov, uv)) return true;
    if (const auto* ot = ov.as_table(); ot && uv.is_table() && !ot->is_inline())
      return table(*ot, *uv.as_table(), path);
    if (const auto* oa = ov.as_array(); oa && uv.is_array()) {
      if (!isLineValue(ov)) return tables(*oa, *uv.as_array(), path);
      const auto* ua = uv.as_array();
      bool scalars = oa->size() == ua->size();
      for (std::size_t i = 0; scalars && i < oa->size(); ++i)
        scalars = !oa->get(i)->is_table() && !oa->get(i)->is_array() && !ua->get(i)->is_table() && !ua->get(i)->is_array();
      if (scalars) {  // element by element: a multi-line array keeps its layout
        for (std::size_t i = 0; i < oa->size(); ++i) {
          auto p = path;
          p.back() += "[" + std::to_string(i) + "]";
          if (!node(*oa->get(i), *ua->get(i), p)) return false;
        }
        return true;
      }
    }
    if (!isLineValue(ov)) return fail("'" + joinPath(path) + "' changes from a table to a value");
    if (!located(ov, path)) return false;
    std::string text;
    if (!inlineValue(uv, text)) return fail("'" + joinPath(path) + "' cannot be written on its line");
    replace(ov, std::move(text));
    return true;
  }

  // An array of tables written as [[path]] sections: each common element edited, new ones appended.
  bool tables(const toml::array& oa, const toml::array& ua, const std::vector<std::string>& path) {
    if (ua.size() < oa.size()) return fail("'" + joinPath(path) + "' loses elements");
    for (std::size_t i = 0; i < ua.size(); ++i) {
      const auto* ut = ua.get(i)->as_table();
      if (!ut) return fail("'" + joinPath(path) + "' mixes tables and values");
      if (i < oa.size()) {
        if (!headed(*oa.get(i)->as_table(), path, true)) return fail("'" + joinPath(path) + "' has an element without its [[header]]");
        if (!table(*oa.get(i)->as_table(), *ut, path)) return false;
      } else if (!section(*ut, path, true)) {
        return false;
      }
    }
    return true;
  }

  // A key of 'upd' that the source's table 'orig' lacks.
  bool add(const toml::table& orig, const toml::node& uv, const std::vector<std::string>& path) {
    if (!isLineValue(uv)) {
      if (const auto* t = uv.as_table()) return section(*t, path, false);
      for (const auto& e : *uv.as_array())
        if (!section(*e.as_table(), path, true)) return false;
      return true;
    }
    std::string line = tomlKey(path.back()) + " = ";
    if (!inlineValue(uv, line)) return fail("'" + joinPath(path) + "' cannot be written on its line");
    line += "\n";
    const std::vector<std::string> parent(path.begin(), path.end() - 1);
    std::size_t at = std::string::npos;  // after the table's last value on its own lines, else after its header
    for (const auto& [k, v] : orig)
      if (isLineValue(v)) {
        const std::size_t end = offset(v.source().end);
        if (end == std::string::npos) return fail("the source position of '" + joinPath(parent) + "' is not known");
        const std::size_t next = nextLine(v.source().end);
        at = at == std::string::npos ? next : std::max(at, next);
      }
    if (at == std::string::npos) {
      if (parent.empty()) {  // the root: before its first section
        at = src_.size();
        for (const auto& [k, v] : orig)
          if (!isLineValue(v)) {
            const std::size_t b = offset(v.source().begin);
            if (b != std::string::npos) at = std::min(at, lineStart_[v.source().begin.line - 1]);
          }
      } else if (headed(orig, parent, false) || headed(orig, parent, true)) {
        at = nextLine(orig.source().begin);
      } else {
        return fail("'" + joinPath(parent) + "' has no [header] of its own to add '" + path.back() + "' under");
      }
    }
    edits_.push_back({at, at, std::move(line)});
    return true;
  }

  // A new table appended at the end as its own section (its sub-tables after it).
  bool section(const toml::table& t, const std::vector<std::string>& path, bool element) {
    tail_ += "\n" + std::string(element ? "[[" : "[") + joinPath(path) + (element ? "]]" : "]") + "\n";
    for (const auto& [k, v] : t)
      if (isLineValue(v)) {
        tail_ += tomlKey(k.str()) + " = ";
        if (!inlineValue(v, tail_)) return fail("'" + joinPath(path) + "." + std::string(k.str()) + "' cannot be written");
        tail_ += "\n";
      }
    for (const auto& [k, v] : t)
      if (!isLineValue(v)) {
        auto p = path;
        p.push_back(std::string(k.str()));
        if (const auto* sub = v.as_table()) {
          if (!section(*sub, p, false)) return false;
        } else {
          for (const auto& e : *v.as_array())
            if (!section(*e.as_table(), p, true)) return false;
        }
      }
    return true;
  }

  // A key of the source that 'upd' no longer has: its line(s) deleted.
  bool remove(const toml::node& ov, const std::vector<std::string>& path, std::string_view key) {
    auto p = path;
    p.push_back(std::string(key));
    if (!isLineValue(ov)) return fail("the table '" + joinPath(p) + "' would be removed");
    if (!located(ov, p)) return false;
    const std::size_t from = lineStart_[ov.source().begin.line - 1];
    const std::size_t keyAt = src_.find_first_not_of(" \t", from);
    if (keyAt == std::string::npos || src_.compare(keyAt, tomlKey(key).size(), tomlKey(key)) != 0)
      return fail("'" + joinPath(p) + "' does not start its line");
    edits_.push_back({from, nextLine(ov.source().end), ""});
    return true;
  }
};

}  // namespace

TomlRewrite rewriteToml(std::string_view source, const std::string& file, const toml::table& updated) {
  TomlRewrite r;
  if (source.empty()) {
    r.reason = "no source text";
    return r;
  }
  std::optional<toml::table> orig;  // (moved, not copied: a copy would lose the source positions)
  try {
    orig.emplace(toml::parse(source, std::string_view(file)));
  } catch (const toml::parse_error& e) {
    r.reason = std::string("the source does not parse: ") + std::string(e.description());
    return r;
  }
  Editor ed(source);
  if (!ed.table(*orig, updated, {})) {
    r.reason = ed.reason();
    return r;
  }
  if (ed.overlapping()) {
    r.reason = "two edits overlap";
    return r;
  }
  std::string text = ed.result();
  try {
    const toml::table back = toml::parse(std::string_view(text), std::string_view(file));
    if (!sameToml(back, updated)) {
      r.reason = "the edited text does not read back as the document";
      return r;
    }
  } catch (const toml::parse_error& e) {
    r.reason = std::string("the edited text does not parse: ") + std::string(e.description());
    return r;
  }
  r.text = std::move(text);
  return r;
}

}  // namespace lg
