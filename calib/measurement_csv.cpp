// Measurement CSV files (measurement_csv.hpp).
#include "calib/measurement_csv.hpp"

#include <charconv>
#include <cmath>
#include <set>

#include "sim/io/scene.hpp"  // InputError
#include "sim/io/toml_reader.hpp"  // readText

namespace lg::calib {
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

// The whole field as a number ("+1.5e3" too); false if it is not one.
bool parseNumber(const std::string& s, double& v) {
  const char* b = s.data();
  const char* e = s.data() + s.size();
  if (b != e && *b == '+') ++b;
  if (b == e) return false;
  const auto r = std::from_chars(b, e, v);
  return r.ec == std::errc() && r.ptr == e;
}

}  // namespace

MeasurementCsv::MeasurementCsv(const std::string& path) : path_(path) {
  const std::string text = readText(path, "measurement file");
  std::size_t at = 0;
  int line = 0;
  while (at < text.size()) {
    const auto nl = text.find('\n', at);
    const std::string raw = text.substr(at, nl == std::string::npos ? std::string::npos : nl - at);
    at = nl == std::string::npos ? text.size() : nl + 1;
    ++line;
    const std::string l = trim(raw);
    if (l.empty() || l[0] == '#') continue;
    std::vector<std::string> f = split(l);
    if (header_.empty()) {
      std::set<std::string> seen;
      for (auto& h : f) {
        h = unquote(h);
        if (h.empty()) throw InputError(path, line, "", "the header names an empty column");
        if (!seen.insert(h).second) throw InputError(path, line, h, "the header names this column twice");
      }
      header_ = std::move(f);
      headerLine_ = line;
      continue;
    }
    if (f.size() != header_.size())
      throw InputError(path, line, "", "the row has " + std::to_string(f.size()) + " fields, the header " +
                                           std::to_string(header_.size()));
    rows_.emplace_back(line, std::move(f));
  }
  if (header_.empty()) throw InputError(path, 0, "", "no header line (the names of the columns)");
}

int MeasurementCsv::column(const std::string& name) const {
  for (std::size_t k = 0; k < header_.size(); ++k)
    if (header_[k] == name) return static_cast<int>(k);
  return -1;
}

std::string MeasurementCsv::headerList() const {
  std::string s;
  for (const auto& h : header_) s += (s.empty() ? "" : ", ") + h;
  return s;
}

std::vector<double> MeasurementCsv::numbers(int k) const {
  std::vector<double> v;
  v.reserve(rows_.size());
  for (const auto& [line, fields] : rows_) {
    double x = 0;
    const std::string& f = fields[static_cast<std::size_t>(k)];
    if (!parseNumber(f, x)) throw InputError(path_, line, header_[k], "value '" + f + "' is not a number");
    if (!std::isfinite(x)) throw InputError(path_, line, header_[k], "value '" + f + "' must be a finite number");
    v.push_back(x);
  }
  return v;
}

}  // namespace lg::calib
