// Drop-test results as text, shared by every program: a case's time histories as CSV (units in the
// header), summary.json and summary.csv. Pictures: sim/io/plots.hpp. Writing: sim/io/files.hpp.
#pragma once

#include <string>
#include <vector>

#include "sim/drop_test.hpp"
#include "sim/io/json.hpp"

namespace lg {

// "t[s],P_y[N],h[m],..." for a recorded case.
std::string historyHeader(const CaseResult& r);
// The CSV of a recorded case: the header, then one row per sample (10 significant digits; round-off-
// sized values, below 1e-12 of their column's largest, written as 0).
std::string historyCsv(const CaseResult& r);
// One case's metrics as a JSON object (README "Metrics").
std::string metricsJson(const CaseMetrics& m, const std::string& indent = "  ");
// summary.json: the scene and every case's metrics.
std::string summaryJson(const Scene& scene, const std::vector<CaseResult>& results);
// summary.csv: one row per case, units in the header.
std::string summaryCsv(const std::vector<CaseResult>& results);

}  // namespace lg
