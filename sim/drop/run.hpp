// Drop tests of a gear scene: one case is one run of the engine from touchdown, with the outputs
// seed-gear.md asks for (time histories, peaks, efficiencies, energy balance) and the limits a
// loads engineer checks (sim/drop/case.hpp: the case's vocabulary).
#pragma once

#include <string>
#include <vector>

#include "sim/drop/case.hpp"

namespace lg {

// Runs a case. A run whose settings came from an accuracy (Settings::accuracy) and whose peak turns out
// flatter than the calibration's, or to have a twin of nearly its height (sim/drop/accuracy.hpp), is run
// again at the tighter accuracy that its peak's time needs (two close peaks: until a run orders them,
// nextAccuracy); the result is the last run's (CaseMetrics::accuracy_rerun says so).
CaseResult runCase(const Scene& scene, const DropCase& c, const CaseOptions& opt = {});

// Runs several cases (OpenMP, one case per thread); results identical to a serial run.
std::vector<CaseResult> runCases(const Scene& scene, const std::vector<DropCase>& cases, int threads,
                                 const CaseOptions& opt = {});

// Static stroke: the strut stroke after settling under 1 g without lift from rest (seconds of
// simulated time, friction included), for the first strut. Returns NaN and sets 'message' on failure.
double staticStroke(const Scene& scene, std::string* message = nullptr, double duration = 3.0);

}  // namespace lg
