// Drop-test results as text, shared by every program: a case's time histories as CSV (units in the
// header), summary.json and summary.csv. Pictures: sim/io/plots.hpp. Writing: sim/io/files.hpp.
#pragma once

#include <string>
#include <vector>

#include "sim/drop/gradient.hpp"
#include "sim/drop/run.hpp"
#include "sim/io/json.hpp"

namespace lg {

// "t[s],P_y[N],h[m],..." for a recorded case.
std::string historyHeader(const CaseResult& r);
// The CSV of a recorded case: the header, then one row per sample (10 significant digits; round-off-
// sized values, below 1e-12 of their column's largest, written as 0).
std::string historyCsv(const CaseResult& r);
// One case's metrics as a JSON object (docs/metrics.md).
std::string metricsJson(const CaseMetrics& m, const std::string& indent = "  ");
// summary.json: the scene and every case's metrics (and their derivatives, when given).
std::string summaryJson(const Scene& scene, const std::vector<CaseResult>& results,
                        const std::vector<CaseGradient>* gradients = nullptr, const std::vector<std::string>* units = nullptr);
// summary.csv: one row per case, units in the header.
std::string summaryCsv(const std::vector<CaseResult>& results);

// The derivatives of every case (simulate --gradient): a JSON object {"parameters": [{path, unit}],
// "cases": {case: {metric: {value, unit, d: {path: d}, smooth, note}}}}, and a CSV with one row per case
// and metric (the metric's unit in its column, the derivatives' "d/d<path>[unit per <parameter unit>]").
std::string gradientJson(const std::vector<CaseGradient>& g, const std::vector<std::string>& units,
                         const std::string& indent = "  ");
std::string gradientCsv(const std::vector<CaseGradient>& g, const std::vector<std::string>& units);

}  // namespace lg
