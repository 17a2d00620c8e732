// Writing work-precision results (sim/drop/accuracy.hpp): a CSV table, a terminal table, and per case a
// gnuplot picture of the errors of peak load, stroke and travel against the time per drop.
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "sim/drop/work_precision.hpp"

namespace lg {

// Written atomically; throws std::runtime_error if it cannot be written.
void writeWorkPrecisionCsv(const std::vector<WorkPrecisionPoint>& points, const std::string& path);
void printWorkPrecisionTable(const std::vector<WorkPrecisionPoint>& points, std::FILE* out);
// DIR/work_precision_<case>.{dat,gp,png} (the case name as a safe file stem, every file written
// atomically; throws std::runtime_error if one cannot be written); returns false with a reason if gnuplot cannot draw (the data
// and scripts are written anyway).
bool writeWorkPrecisionPlots(const Scene& scene, const std::vector<WorkPrecisionPoint>& points,
                             const std::string& outDir, std::string* why);

}  // namespace lg
