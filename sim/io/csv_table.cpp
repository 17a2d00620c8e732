// Numeric CSV files (csv_table.hpp).
#include "sim/io/csv_table.hpp"

#include <charconv>
#include <cmath>
#include <set>

#include "sim/io/scene.hpp"        // InputError
#include "sim/io/toml_reader.hpp"  // readText

namespace lg {
namespace {

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const auto b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> f;
  std::size_t at = 0;
  for (;;) {
    const auto comma = line.find(',', at);
    f.push_back(trim(line.substr(at, comma == std::string::npos ? std::string::npos : comma - at)));
    if (comma == std::string::npos) return f;
    at = comma + 1;
  }
}

// A header name without its surrounding double quotes.
std::string unquote(const std::string& s) {
  return s.size() >= 2 && s.front() == '"' && s.back() == '"' ? s.substr(1, s.size() - 2) : s;
}

// "stroke [m]" -> "stroke": a name without its bracketed unit.
std::string bare(const std::string& h) {
  if (h.empty() || h.back() != ']') return h;
  const auto open = h.rfind('[');
  return open == std::string::npos || open == 0 ? h : trim(h.substr(0, open));
}

// The whole field as a number ("+1.5e3" too); false if it is not one.
bool parseNumber(const std::string& s, double& v) {
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

std::string shown(const std::string& s) { return s.size() > 60 ? s.substr(0, 57) + "..." : s; }

}  // namespace

CsvTable::CsvTable(const std::string& path, const std::string& what, const std::string& example,
                   const std::string& context)
    : path_(path), what_(what), example_(example), context_(context) {
  const std::string text = readText(path, what);
  std::size_t at = 0;
  int line = 0;
  while (at < text.size()) {
    const auto nl = text.find('\n', at);
    const std::size_t len = (nl == std::string::npos ? text.size() : nl) - at;
    ++line;
    if (len > kMaxLine)
      throw InputError(path, line, "", "the line has " + std::to_string(len) + " characters, more than " +
                                           std::to_string(kMaxLine) + ": not a row of a table" + context_);
    const std::string l = trim(text.substr(at, len));
    at = nl == std::string::npos ? text.size() : nl + 1;
    if (l.empty() || l[0] == '#') continue;
    std::vector<std::string> f = split(l);
    if (header_.empty()) {
      if (l.find(';') != std::string::npos || l.find('\t') != std::string::npos)
        throw InputError(path, line, "header",
                         "'" + shown(l) + "' is separated by " + (l.find(';') != std::string::npos ? "';'" : "tabs") +
                             ": columns are separated by commas, e.g. " + example_ + context_);
      double probe = 0;
      if (parseNumber(f[0], probe))
        throw InputError(path, line, "header",
                         "the first line (after # comments) must name the columns, e.g. " + example_ + "; it holds '" +
                             shown(l) + "'" + context_);
      std::set<std::string> seen;
      for (std::size_t k = 0; k < f.size(); ++k) {
        f[k] = unquote(f[k]);
        if (f[k].empty())
          throw InputError(path, line, "header", "column " + std::to_string(k + 1) + " has no name (e.g. " + example_ + ")" + context_);
        if (!seen.insert(bare(f[k])).second) throw InputError(path, line, shown(f[k]), "the header names this column twice" + context_);
      }
      header_ = std::move(f);
      headerLine_ = line;
      continue;
    }
    if (f.size() < header_.size())
      throw InputError(path, line, header_[f.size()],
                       "the row has " + std::to_string(f.size()) + " fields, the header (line " + std::to_string(headerLine_) +
                           ") " + std::to_string(header_.size()) + ": this column is missing" + context_);
    if (f.size() > header_.size())
      throw InputError(path, line, "column " + std::to_string(header_.size() + 1),
                       "the row has " + std::to_string(f.size()) + " fields, the header (line " + std::to_string(headerLine_) +
                           ": " + shown(headerList()) + ") " + std::to_string(header_.size()) + context_);
    rows_.emplace_back(line, std::move(f));
  }
  if (header_.empty())
    throw InputError(path, 0, "header", "no header line: the " + what_ + " must begin (after # comments) with the names of "
                                        "its columns, e.g. " + example_ + context_);
}

int CsvTable::column(const std::string& name) const {
  for (std::size_t k = 0; k < header_.size(); ++k)
    if (header_[k] == name || bare(header_[k]) == name) return static_cast<int>(k);
  return -1;
}

std::string CsvTable::headerList() const {
  std::string s;
  for (const auto& h : header_) s += (s.empty() ? "" : ", ") + h;
  return s;
}

std::vector<double> CsvTable::numbers(int k) const {
  std::vector<double> v;
  v.reserve(rows_.size());
  for (const auto& [line, fields] : rows_) {
    double x = 0;
    const std::string& f = fields[static_cast<std::size_t>(k)];
    if (!parseNumber(f, x)) throw InputError(path_, line, header_[k], "value '" + shown(f) + "' is not a number" + context_);
    if (!std::isfinite(x)) throw InputError(path_, line, header_[k], "value '" + shown(f) + "' must be a finite number" + context_);
    v.push_back(x);
  }
  return v;
}

std::vector<double> CsvTable::numbers(const std::string& name) const {
  const int k = column(name);
  if (k < 0)
    throw InputError(path_, headerLine_, name, "the header has no column '" + name + "' (it names: " + shown(headerList()) +
                                                   "); expected e.g. " + example_ + context_);
  return numbers(k);
}

void CsvTable::fail(long i, const std::string& name, const std::string& rule) const {
  throw InputError(path_, i < 0 ? headerLine_ : rowLine(static_cast<std::size_t>(i)), name, rule + context_);
}

}  // namespace lg
