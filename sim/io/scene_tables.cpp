// The scene's tables, read and checked for the parser (sim/io/scene_builder.hpp): the two columns of a
// CSV file through fast-cpp-csv-parser, a path relative to the scene's folder, a strut's metering-pin
// table (stroke, area) from a CSV file or inline in the scene, with its rules (at least 4 rows, stroke
// increasing and uniformly spaced, every area > 0), and a tyre's load-deflection curve.

// A false positive of GCC in inlined library code: fast-cpp-csv-parser's bounded file-name copy.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-truncation"
#endif
#include <csv.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/io/scene_builder.hpp"

namespace lg::detail {

// Reads the two columns 'cx', 'cy' of a CSV table with a header through fast-cpp-csv-parser.
void readColumns(const std::string& path, const TomlReader& r, const std::string& key, const char* cx, const char* cy,
                 std::vector<double>& x, std::vector<double>& y) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    r.fail(key, "cannot read table '" + path + "': " + (std::filesystem::exists(path, ec) ? "not a regular file" : "no such file"));
  try {
    io::CSVReader<2, io::trim_chars<' ', '\t'>, io::no_quote_escape<','>, io::throw_on_overflow, io::single_and_empty_line_comment<'#'>> in(path);
    in.read_header(io::ignore_no_column, cx, cy);
    double a, b;
    while (in.read_row(a, b)) {
      x.push_back(a);
      y.push_back(b);
    }
  } catch (const std::exception& e) {
    r.fail(key, "cannot read table '" + path + "': " + e.what());
  }
}

// A path of the scene relative to its folder.
std::string scenePath(const TomlReader& r, const std::string& key, const std::string& baseDir) {
  std::filesystem::path tp(r.string(key));
  if (tp.is_relative()) tp = std::filesystem::path(baseDir) / tp;
  return tp.string();
}

// A table's samples checked: at least 4, stroke increasing and uniformly spaced, every area > 0.
std::shared_ptr<const Table1D> checkedTable(std::vector<double> x, std::vector<double> y, const std::string& source,
                                            const TomlReader& r, const std::string& key, int firstRow) {
  if (x.size() < 4) r.fail(key, "table '" + source + "' needs at least 4 rows of (stroke, area)");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  if (!(dx > 0)) r.fail(key, "table '" + source + "': stroke must increase");
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      r.fail(key, "table '" + source + "': stroke must be uniformly spaced (row " + std::to_string(i + firstRow) + ")");
    if (!(y[i] > 0))
      r.fail(key, "table '" + source + "': area " + fmt(y[i]) + " at row " + std::to_string(i + firstRow) + " must be > 0");
  }
  return std::make_shared<Table1D>(std::move(x), std::move(y), source);
}

// Reads a two-column CSV table (header "stroke,area" or any two names) through fast-cpp-csv-parser.
std::shared_ptr<const Table1D> readTable(const std::string& path, const TomlReader& r, const std::string& key) {
  std::vector<double> x, y;
  readColumns(path, r, key, "stroke", "area", x, y);
  return checkedTable(std::move(x), std::move(y), path, r, key, 2);
}

// An inline table: { stroke = [...] [m], area = [...] [m^2] } (what best.toml and calibrated.toml write
// when a table's samples are design parameters).
std::shared_ptr<const Table1D> inlineTable(const toml::table& t, const TomlReader& r, const std::string& key) {
  for (auto&& [k, v] : t)
    if (k.str() != "stroke" && k.str() != "area")
      r.fail(key + "." + std::string(k.str()), "unknown key (an inline table has stroke = [...] and area = [...])");
  std::vector<double> col[2];
  const char* names[2] = {"stroke", "area"};
  for (int c = 0; c < 2; ++c) {
    const toml::array* a = t[names[c]].as_array();
    if (!a) r.fail(key + "." + names[c], "must be an array of numbers");
    for (const auto& e : *a) col[c].push_back(r.toNumber(e, key + "." + names[c]));
  }
  if (col[0].size() != col[1].size())
    r.fail(key, "stroke has " + std::to_string(col[0].size()) + " samples and area " + std::to_string(col[1].size()) +
                    ": they must pair up");
  return checkedTable(std::move(col[0]), std::move(col[1]), "inline", r, key, 1);
}

// A tyre's load-deflection curve: CSV "deflection,load" [m, N], uniformly spaced from deflection 0 with
// load 0, the load rising.
std::shared_ptr<const CurveTable> readCurve(const std::string& path, const TomlReader& r, const std::string& key) {
  std::vector<double> x, y;
  readColumns(path, r, key, "deflection", "load", x, y);
  if (x.size() < 4) r.fail(key, "table '" + path + "' needs at least 4 rows of (deflection, load)");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  if (!(dx > 0)) r.fail(key, "table '" + path + "': deflection must increase");
  if (x.front() != 0.0 || y.front() != 0.0)
    r.fail(key, "table '" + path + "': the first row must be deflection 0 with load 0 (got " + fmt(x.front()) + ", " +
                    fmt(y.front()) + "): the tyre touches the ground unloaded");
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      r.fail(key, "table '" + path + "': row " + std::to_string(i + 2) + " must hold finite numbers");
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      r.fail(key, "table '" + path + "': deflection must be uniformly spaced (row " + std::to_string(i + 2) + ")");
    if (i > 0 && !(y[i] > y[i - 1]))
      r.fail(key, "table '" + path + "': load " + fmt(y[i]) + " N at row " + std::to_string(i + 2) +
                      " must be larger than the row before's " + fmt(y[i - 1]) + " N (a tyre's load rises with its deflection)");
  }
  return std::make_shared<CurveTable>(std::move(x), std::move(y), path);
}

}  // namespace lg::detail
