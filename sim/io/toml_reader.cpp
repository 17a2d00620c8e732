// TOML input tables with file/line-aware errors (toml_reader.hpp).
#include "sim/io/toml_reader.hpp"

#include <cmath>
#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "sim/model/model.hpp"

namespace lg {
namespace {
int lineOfNode(const toml::node& n) { return static_cast<int>(n.source().begin.line); }
}  // namespace

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

bool isName(const std::string& s) {
  if (s.empty() || s.size() > 64) return false;
  if (!(std::isalnum(static_cast<unsigned char>(s[0])) || s[0] == '_')) return false;
  for (unsigned char c : s)
    if (!(std::isalnum(c) || c == '_' || c == '-' || c == '.')) return false;
  return true;
}
std::string nameRule() {
  return "must be 1 to 64 letters, digits, '_', '-' or '.', starting with a letter, a digit or '_' (names become "
         "file names and CSV columns)";
}

// ---- TomlReader ------------------------------------------------------------------------------------
int TomlReader::line() const { return lineOfNode(t_); }
int TomlReader::lineOf(const std::string& key) const {
  const toml::node* n = t_.get(key);
  return n ? lineOfNode(*n) : line();
}
void TomlReader::fail(const std::string& key, const std::string& rule) const {
  throw InputError(file_, lineOf(key), full(key), rule);
}

void TomlReader::allowOnly(std::initializer_list<const char*> keys) const {
  std::set<std::string> ok(keys.begin(), keys.end());
  for (const auto& [k, v] : t_) {
    const std::string key(k.str());
    if (!ok.count(key)) {
      std::string list;
      for (const auto& a : ok) list += (list.empty() ? "" : ", ") + a;
      throw InputError(file_, lineOfNode(v), full(key), "unknown key (allowed here: " + list + ")");
    }
  }
}

double TomlReader::number(const std::string& key) const {
  const toml::node* n = t_.get(key);
  if (!n) fail(key, "missing required number");
  return toNumber(*n, key);
}
double TomlReader::number(const std::string& key, double def) const {
  const toml::node* n = t_.get(key);
  return n ? toNumber(*n, key) : def;
}
double TomlReader::positive(const std::string& key) const { return checkPositive(key, number(key)); }
double TomlReader::positive(const std::string& key, double def) const {
  return has(key) ? checkPositive(key, number(key)) : def;
}
double TomlReader::nonNegative(const std::string& key, double def) const {
  const double v = number(key, def);
  if (!(v >= 0)) fail(key, "value " + fmt(v) + " must be >= 0");
  return v;
}
double TomlReader::duration(const std::string& key, double def) const {
  const double v = positive(key, def);
  if (has(key) && !(v <= kMaxDuration))
    fail(key, "value " + fmt(v) + " s must be <= " + fmt(kMaxDuration) + " s (a drop test lasts seconds)");
  return v;
}
long long TomlReader::integer(const std::string& key, long long def) const {
  const toml::node* n = t_.get(key);
  if (!n) return def;
  if (!n->is_integer()) fail(key, "must be an integer");
  return *n->value<int64_t>();
}
long long TomlReader::count(const std::string& key, long long def, long long lo, long long hi) const {
  const toml::node* n = t_.get(key);
  if (!n) return def;
  if (n->is_integer()) {  // compared as the integer it is, never through a rounded double
    const long long v = *n->value<int64_t>();
    if (v < lo || v > hi) fail(key, "value " + std::to_string(v) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
    return v;
  }
  if (!n->is_floating_point()) fail(key, "must be a number");
  const double v = *n->value<double>();
  if (!std::isfinite(v)) fail(key, "value must be finite");
  if (v != std::floor(v)) fail(key, "value " + fmt(v) + " must be a whole number");
  if (!(v >= static_cast<double>(lo) && v <= static_cast<double>(hi)))
    fail(key, "value " + fmt(v) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]");
  return static_cast<long long>(v);
}
std::string TomlReader::name(const std::string& key) const {
  const std::string v = string(key);
  if (!isName(v)) fail(key, "name '" + v + "' " + nameRule());
  return v;
}
std::string TomlReader::name(const std::string& key, const std::string& def) const { return has(key) ? name(key) : def; }
std::string TomlReader::string(const std::string& key) const {
  const toml::node* n = t_.get(key);
  if (!n) fail(key, "missing required string");
  if (!n->is_string()) fail(key, "must be a string");
  return std::string(*n->value<std::string>());
}
std::string TomlReader::string(const std::string& key, const std::string& def) const {
  return has(key) ? string(key) : def;
}
bool TomlReader::boolean(const std::string& key, bool def) const {
  const toml::node* n = t_.get(key);
  if (!n) return def;
  if (!n->is_boolean()) fail(key, "must be true or false");
  return *n->value<bool>();
}
Vec3<double> TomlReader::vec3(const std::string& key) const {
  const toml::node* n = t_.get(key);
  if (!n) fail(key, "missing required vector [x, y, z]");
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) fail(key, "must be a vector of 3 numbers [x, y, z]");
  Vec3<double> v;
  for (int i = 0; i < 3; ++i) v[i] = toNumber(*a->get(i), key);
  return v;
}
Vec3<double> TomlReader::vec3(const std::string& key, const Vec3<double>& def) const {
  return has(key) ? vec3(key) : def;
}
Vec3<double> TomlReader::unitVec3(const std::string& key) const { return normalize(key, vec3(key)); }
Vec3<double> TomlReader::unitVec3(const std::string& key, const Vec3<double>& def) const {
  return has(key) ? unitVec3(key) : def;
}
Vec3<double> TomlReader::normalize(const std::string& key, const Vec3<double>& v) const {
  if (!(v.norm() > 1e-12)) fail(key, "direction must be a non-zero vector");
  return v.normalized();
}
double TomlReader::toNumber(const toml::node& n, const std::string& key) const {
  double v = 0;
  if (n.is_floating_point()) v = *n.value<double>();
  else if (n.is_integer()) v = static_cast<double>(*n.value<int64_t>());
  else fail(key, "must be a number");
  if (!std::isfinite(v)) fail(key, "value must be finite");
  if (std::abs(v) > kMaxMagnitude)
    fail(key, "value " + fmt(v) + " is beyond " + fmt(kMaxMagnitude) + " in magnitude: no quantity of a gear is that large in SI units");
  return v;
}
double TomlReader::checkPositive(const std::string& key, double v) const {
  if (!(v > 0)) fail(key, "value " + fmt(v) + " must be > 0");
  return v;
}

// ---- whole tables and files ------------------------------------------------------------------------
std::vector<const toml::table*> tablesOf(const toml::table& doc, const std::string& key, const std::string& file) {
  std::vector<const toml::table*> out;
  const toml::node* n = doc.get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) throw InputError(file, lineOfNode(*n), key, "must be an array of tables [[" + key + "]]");
  for (const auto& e : *a) {
    const toml::table* t = e.as_table();
    if (!t) throw InputError(file, lineOfNode(e), key, "each entry must be a table [[" + key + "]]");
    out.push_back(t);
  }
  return out;
}

const toml::table* tableOf(const toml::table& doc, const std::string& key, const std::string& file) {
  const toml::node* n = doc.get(key);
  if (!n) return nullptr;
  const toml::table* t = n->as_table();
  if (!t) {
    int line = lineOfNode(*n);  // an array of tables has no line of its own: its first table's
    if (const toml::array* a = n->as_array(); line == 0 && a && !a->empty()) line = lineOfNode(*a->get(0));
    throw InputError(file, line, key,
                     std::string("must be a table [") + key + "]" + (n->is_array_of_tables() ? ", not an array of tables [[" + key + "]]" : ""));
  }
  return t;
}

namespace {
// The key of the statement a TOML syntax error at 'line' (1-based) belongs to: the left-hand side of
// the nearest assignment at or above it (a multi-line array continues its first line's statement), or
// the header on the error line itself; "" if none. toml++ reports where it noticed the error only.
std::string syntaxErrorKey(const std::string& text, int line) {
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  auto content = [&](int i) {  // line i without its comment, trimmed
    std::string l = lines[i].substr(0, lines[i].find('#'));
    const auto a = l.find_first_not_of(" \t\r"), b = l.find_last_not_of(" \t\r");
    return a == std::string::npos ? std::string() : l.substr(a, b - a + 1);
  };
  auto openBracket = [](const std::string& l) { return std::count(l.begin(), l.end(), '[') > std::count(l.begin(), l.end(), ']'); };
  for (int i = std::min(line, static_cast<int>(lines.size())) - 1; i >= 0; --i) {
    const std::string l = content(i);
    if (l.empty()) continue;
    if (l[0] == '[') {
      if (i != line - 1) return "";
      int j = i - 1;
      while (j >= 0 && content(j).empty()) --j;
      if (j >= 0 && openBracket(content(j))) continue;  // a value above is still open
      return l;
    }
    const auto eq = l.find('=');
    if (eq == std::string::npos && i == line - 1 && (std::isalpha(static_cast<unsigned char>(l[0])) || l[0] == '_'))
      return l.substr(0, l.find_first_of(" \t"));  // "mass 20.0": a key without its '='
    if (eq != std::string::npos) {
      std::string k = l.substr(0, eq);
      k.erase(k.find_last_not_of(" \t") + 1);
      return k;
    }
  }
  return "";
}
}  // namespace

toml::table parseToml(const std::string& text, const std::string& file) {
  try {
    return toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    int line = static_cast<int>(e.source().begin.line);
    const std::string what(e.description());
    // An unterminated multi-line string is noticed at the end of the file: name the line it opens on.
    if (what.find("end-of-file") != std::string::npos)
      for (const char* q : {"\"\"\"", "\'\'\'"}) {
        size_t count = 0, last = std::string::npos;
        for (size_t pos = text.find(q); pos != std::string::npos; pos = text.find(q, pos + 3)) {
          ++count;
          last = pos;
        }
        if (count % 2 == 1) {
          line = 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(last), '\n'));
          throw InputError(file, line, syntaxErrorKey(text, line),
                           std::string("TOML syntax: a multi-line string opened here (") + q + ") is never closed");
        }
      }
    throw InputError(file, line, syntaxErrorKey(text, line), "TOML syntax: " + what);
  }
}

std::string fileProblem(const std::string& path) {
  std::error_code ec;
  const auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st)) return "no such file";
  if (std::filesystem::is_directory(st)) return "a directory, not a file";
  if (!std::filesystem::is_regular_file(st)) return "not a regular file (a pipe, a socket or a device)";
  return "";
}

std::string readText(const std::string& path, const std::string& what) {
  if (const std::string why = fileProblem(path); !why.empty())
    throw InputError(path, 0, "", "cannot read the " + what + ": " + why);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the " + what);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

void TomlReader::masses(const std::string& key, const Model<double>& m, std::map<std::string, double>& masses) const {
  const toml::node* n = get(key);
  if (!n) return;
  const toml::table* t = n->as_table();
  if (!t) fail(key, "must be a table of body = mass [kg]");
  TomlReader r(*t, file_, full(key));
  for (const auto& [k, v] : *t) {
    const std::string body(k.str());
    if (m.bodyIndex(body) < 0) r.fail(body, "'" + body + "' is not a body of the scene");
    masses[body] = r.positive(body);
  }
}

}  // namespace lg
