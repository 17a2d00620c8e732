// The catalogue of per-case drop-test metrics by name, shared by study constraints, the certification
// matrix and the reports: one place that says what "stroke_margin" means and in which unit.
#pragma once

#include <limits>

#include <string>
#include <vector>

#include "sim/drop_test.hpp"

namespace lg {

struct MetricInfo {
  const char* name;         // as written in study files: "stroke_margin"
  const char* unit;         // SI unit for headers: "m", "N", "-", "J", "m/s"
  const char* description;  // for people
  double scale;             // [unit] a typical size, to scale a constraint whose bound is 0
  double least = 0;         // [unit] the smallest value the metric can take (-inf: no bound): a bound
  double most = kInf;       // [unit] ... and the largest; "max" below 'least' can never hold
  static constexpr double kInf = std::numeric_limits<double>::infinity();
};

// Every metric a study constraint or the certification matrix can name, in a fixed order.
const std::vector<MetricInfo>& metricCatalogue();
// The entry of 'name', or nullptr.
const MetricInfo* findMetric(const std::string& name);
// "peak_load, load_factor, ..." for messages.
std::string metricNames();
// The value of a metric of one case (NaN where the scene lacks what it measures, e.g. stroke_margin
// without a bottoming stop).
double metricValue(const CaseMetrics& m, const std::string& name);

}  // namespace lg
