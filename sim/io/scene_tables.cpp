// The scene's tables, read and checked for the parser (sim/io/scene_builder.hpp): the two columns of a
// CSV file (sim/io/csv_table.hpp), a path relative to the scene's folder, a strut's metering-pin table
// (stroke, area) from a CSV file or inline in the scene, with its rules (at least 4 rows, stroke
// increasing and uniformly spaced, every area > 0), and a tyre's load-deflection curve. A fault in a
// CSV file is named at its line and column, with the scene's key that names the file.

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "sim/io/csv_table.hpp"
#include "sim/io/scene.hpp"
#include "sim/io/scene_builder.hpp"

namespace lg::detail {

// The two columns 'cx', 'cy' of the CSV table 'path' that the scene's 'key' names (any other column is
// ignored), with the table's rows for later errors.
ColumnPair readColumns(const std::string& path, const TomlReader& r, const std::string& key, const char* cx, const char* cy) {
  if (const std::string why = fileProblem(path); !why.empty()) r.fail(key, "cannot read table '" + path + "': " + why);
  const std::string context = " (the table of " + r.full(key) + " in " + r.file() + ")";
  auto csv = std::make_shared<CsvTable>(path, "table", std::string(cx) + "," + cy, context);
  ColumnPair p{csv->numbers(cx), csv->numbers(cy), csv, {cx, cy}};
  return p;
}

// A path of the scene relative to its folder.
std::string scenePath(const TomlReader& r, const std::string& key, const std::string& baseDir) {
  std::filesystem::path tp(r.string(key));
  if (tp.is_relative()) tp = std::filesystem::path(baseDir) / tp;
  return tp.string();
}

void ColumnPair::fail(const TomlReader& r, const std::string& key, long row, int column, const std::string& rule) const {
  if (csv) csv->fail(row, names[column], rule);
  r.fail(key + "." + names[column], rule + (row >= 0 ? " (sample " + std::to_string(row + 1) + ")" : ""));
}

// A table's samples checked: at least 4, stroke increasing and uniformly spaced, every area > 0.
std::shared_ptr<const Table1D> checkedTable(ColumnPair t, const std::string& source, const TomlReader& r,
                                            const std::string& key) {
  const auto& x = t.x;
  const auto& y = t.y;
  if (x.size() < 4) t.fail(r, key, -1, 0, "the table has " + std::to_string(x.size()) + " rows: it needs at least 4 of (stroke, area)");
  for (size_t i = 1; i < x.size(); ++i)
    if (!(x[i] > x[i - 1]))
      t.fail(r, key, static_cast<long>(i), 0, "stroke " + fmt(x[i]) + " m must be larger than the row before's " + fmt(x[i - 1]) + " m");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      t.fail(r, key, static_cast<long>(i), 0, "stroke " + fmt(x[i]) + " m: the strokes must be uniformly spaced (" + fmt(dx) + " m apart)");
    if (!(y[i] > 0)) t.fail(r, key, static_cast<long>(i), 1, "area " + fmt(y[i]) + " m^2 must be > 0");
  }
  return std::make_shared<Table1D>(std::move(t.x), std::move(t.y), source);
}

// Reads a two-column CSV table "stroke,area" [m, m^2] (units in brackets allowed: "stroke[m],area[m^2]").
std::shared_ptr<const Table1D> readTable(const std::string& path, const TomlReader& r, const std::string& key) {
  return checkedTable(readColumns(path, r, key, "stroke", "area"), path, r, key);
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
  return checkedTable(ColumnPair{std::move(col[0]), std::move(col[1]), nullptr, {"stroke", "area"}}, "inline", r, key);
}

// A tyre's load-deflection curve: CSV "deflection,load" [m, N], uniformly spaced from deflection 0 with
// load 0, the load rising.
std::shared_ptr<const CurveTable> readCurve(const std::string& path, const TomlReader& r, const std::string& key) {
  ColumnPair t = readColumns(path, r, key, "deflection", "load");
  const auto& x = t.x;
  const auto& y = t.y;
  if (x.size() < 4) t.fail(r, key, -1, 0, "the table has " + std::to_string(x.size()) + " rows: it needs at least 4 of (deflection, load)");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  if (x.front() != 0.0 || y.front() != 0.0)
    t.fail(r, key, 0, x.front() != 0.0 ? 0 : 1,
           "the first row must be deflection 0 with load 0 (got " + fmt(x.front()) + ", " + fmt(y.front()) +
               "): the tyre touches the ground unloaded");
  for (size_t i = 1; i < x.size(); ++i)
    if (!(x[i] > x[i - 1]))
      t.fail(r, key, static_cast<long>(i), 0, "deflection " + fmt(x[i]) + " m must be larger than the row before's " + fmt(x[i - 1]) + " m");
  for (size_t i = 1; i < x.size(); ++i) {
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      t.fail(r, key, static_cast<long>(i), 0, "deflection " + fmt(x[i]) + " m: the deflections must be uniformly spaced (" + fmt(dx) + " m apart)");
    if (!(y[i] > y[i - 1]))
      t.fail(r, key, static_cast<long>(i), 1, "load " + fmt(y[i]) + " N must be larger than the row before's " + fmt(y[i - 1]) +
                                                  " N (a tyre's load rises with its deflection)");
  }
  return std::make_shared<CurveTable>(std::move(t.x), std::move(t.y), path);
}

}  // namespace lg::detail
