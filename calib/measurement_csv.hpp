// A measurement's CSV file: a header of column names, then one row of numbers per sample (comma
// separated; blank lines and lines starting with '#' skipped; columns the calibration does not name
// may hold anything). Errors are lg::InputError naming the CSV, the line and the column.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace lg::calib {

class MeasurementCsv {
 public:
  // Reads the whole file; throws InputError(path, ...) if it cannot be read, has no header, repeats a
  // header name, or has a row with another number of fields than the header.
  explicit MeasurementCsv(const std::string& path);
  const std::string& path() const { return path_; }
  // The index of a header name, -1 if absent.
  int column(const std::string& name) const;
  // "time_s, Fz_N, stroke_m" for messages.
  std::string headerList() const;
  int headerLine() const { return headerLine_; }
  std::size_t rows() const { return rows_.size(); }
  int rowLine(std::size_t i) const { return rows_[i].first; }
  // The values of column k, one per row, each a finite number (errors name the row's line and the column).
  std::vector<double> numbers(int k) const;

 private:
  std::string path_;
  std::vector<std::string> header_;
  int headerLine_ = 0;
  std::vector<std::pair<int, std::vector<std::string>>> rows_;  // (line, fields)
};

}  // namespace lg::calib
