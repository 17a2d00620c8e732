// Work-precision data (error against time per drop) of any scene, each setting measured against the
// scene's own tight-tolerance run: the data the accuracy calibration (sim/drop/accuracy.hpp) was read off.
#pragma once

#include <string>
#include <vector>

#include "sim/drop/accuracy.hpp"

namespace lg {

// One point of a work-precision diagram: a setting (integrator and rtol, or the step of a fixed-step
// method), its errors against the reference on one case, and what it cost.
struct WorkPrecisionPoint {
  std::string caseName;
  std::string integrator;
  double tolerance = 0;    // rtol (adaptive) or step [s] (fixed-step)
  bool ok = true;
  std::string message;
  MetricErrors errors;
  double timePerDrop = 0;  // [s] median wall time of one drop, single thread
  long steps = 0, rhsEvaluations = 0;
};

struct WorkPrecisionOptions {
  double referenceRtol = 1e-10;  // the scene's own tight run: dopri5 at this rtol (atol = rtol / 100)
  int repetitions = 5;           // timed runs per point (median)
  bool fast = false;             // fewer settings (tests)
};

// Every integrator over a range of tolerances on each case, against the scene's own reference run.
std::vector<WorkPrecisionPoint> workPrecision(const Scene& scene, const std::vector<DropCase>& cases,
                                              const WorkPrecisionOptions& opt = {});

}  // namespace lg
