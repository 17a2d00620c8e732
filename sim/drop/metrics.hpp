// The catalogue of per-case drop-test metrics by name, shared by study constraints, the certification
// matrix, sensitivity, the derivatives and the reports: one declaration per metric says its name, its
// field in summary.json, its unit, what it means, its typical size, its range and where its value is
// read (docs/metrics.md lists them in the same order, and a test holds the two together).
#pragma once

#include <limits>

#include <string>
#include <vector>

#include "sim/drop/case.hpp"

namespace lg {

struct MetricInfo {
  static constexpr double kInf = std::numeric_limits<double>::infinity();
  const char* name = "";         // as written in study files: "stroke_margin"
  const char* field = "";        // its field in summary.json, result.json, compliance.json: "stroke_margin_m"
  const char* unit = "-";        // SI unit for headers: "m", "N", "-", "J", "m/s"
  const char* description = "";  // for people
  double scale = 1;              // [unit] a typical size, to scale a constraint whose bound is 0
  double least = 0;              // [unit] the smallest value the metric can take (-inf: no bound): a bound
  double most = kInf;            // [unit] ... and the largest; "max" below 'least' can never hold
  // Its value in a case's metrics (NaN where the scene lacks what it measures).
  double (*value)(const CaseMetrics&) = nullptr;
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
