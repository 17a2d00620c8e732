// Writing drop-test results: per-case CSV time histories and summary.json (pictures: sim/io/plots.hpp).
#pragma once

#include <string>
#include <vector>

#include "sim/drop_test.hpp"
#include "sim/io/json.hpp"

namespace lg {

// Column names of a case's CSV for this scene: only what the scene declares.
std::vector<std::string> historyColumns(const Scene& scene);
void writeHistoryCsv(const Scene& scene, const CaseResult& r, const std::string& path);
std::string metricsJson(const CaseMetrics& m, const std::string& indent = "  ");
void writeSummaryJson(const Scene& scene, const std::vector<CaseResult>& results, const std::string& path);

}  // namespace lg
