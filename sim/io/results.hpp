// Writing drop-test results: per-case CSV time histories, summary.json, gnuplot plots.
#pragma once

#include <string>
#include <vector>

#include "sim/drop_test.hpp"

namespace lg {

// Column names of a case's CSV for this scene: only what the scene declares.
std::vector<std::string> historyColumns(const Scene& scene);
void writeHistoryCsv(const Scene& scene, const CaseResult& r, const std::string& path);
std::string metricsJson(const CaseMetrics& m, const std::string& indent = "  ");
void writeSummaryJson(const Scene& scene, const std::vector<CaseResult>& results, const std::string& path);
// Plots with gnuplot (P_y(t), s(t), h(t), work diagram P_y(h)); returns false with a reason if it
// cannot (gnuplot missing).
bool writePlots(const Scene& scene, const CaseResult& r, const std::string& csvPath, const std::string& outDir,
                std::string* why);
// JSON string escaping.
std::string jsonString(const std::string& s);
// A number as JSON (finite numbers with 17 significant digits; others as null).
std::string jsonNumber(double v);

}  // namespace lg
