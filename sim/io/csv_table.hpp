// A numeric CSV file as every program reads it (a scene's tyre and metering-pin tables, a calibration's
// measured drops): a header of column names, then one row of numbers per sample, comma separated;
// blank lines and lines starting with '#' are skipped; a header name may carry its unit in brackets,
// "stroke[m]" or "stroke [m]" (the form the programs write), and is found by its bare name.
//
// Every fault is one lg::InputError naming the CSV file, the line and the column (the key): a header
// missing or after the numbers, a semicolon- or tab-separated file, a name twice, a row with too few or
// too many fields, a field that is not a finite number, a line over 64 KiB. A table that a scene names
// adds the scene's key to the rule ("the table of force[3].load_table in gear.toml").
#pragma once

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace lg {

class CsvTable {
 public:
  // Reads the whole file; 'what' names it in messages ("measurement file", "table"); 'example' is a
  // header that fits ("deflection,load"), quoted where the header is missing; 'context' ends every
  // rule, e.g. " (the table of force[3].load_table in gear.toml)".
  CsvTable(const std::string& path, const std::string& what, const std::string& example,
           const std::string& context = "");
  const std::string& path() const { return path_; }
  // The index of a column by its bare name ("stroke" finds "stroke" and "stroke[m]"), -1 if absent.
  int column(const std::string& name) const;
  // "time_s, Fz_N, stroke_m" for messages.
  std::string headerList() const;
  int headerLine() const { return headerLine_; }
  std::size_t rows() const { return rows_.size(); }
  int rowLine(std::size_t i) const { return rows_[i].first; }
  // The values of column k, one per row, each a finite number (errors name the row's line and the column).
  std::vector<double> numbers(int k) const;
  // The same column required by name: an error at the header naming the columns there are.
  std::vector<double> numbers(const std::string& name) const;
  // An error at row i's line (i < 0: the header's) and column 'name', with the context appended.
  [[noreturn]] void fail(long i, const std::string& name, const std::string& rule) const;

  static constexpr std::size_t kMaxLine = 65536;  // [characters] a longer line is no table row

 private:
  std::string path_, what_, example_, context_;
  std::vector<std::string> header_;
  int headerLine_ = 0;
  std::vector<std::pair<int, std::vector<std::string>>> rows_;  // (line, fields)
};

}  // namespace lg
