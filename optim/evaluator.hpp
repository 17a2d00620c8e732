// Evaluating one design of a study on the simulator: edit the scene document, rebuild the scene,
// run the cases (OpenMP through lg::runCases), reduce the per-case metrics to the objective and the
// constraints in a fixed order (so results are bitwise identical for any thread count).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "optim/optimizer.hpp"
#include "optim/study.hpp"

namespace lg::optim {

struct EvaluatorOptions {
  int threads = 1;                 // OpenMP threads over the cases
  std::function<bool()> stop;      // polled by the simulator (Ctrl-C); null = never
  bool record = false;             // keep time histories (reports)
};

// The scene document with the variables set to x (physical units).
toml::table designDocument(const Study& s, const std::vector<double>& x);
// The drop cases of a design: scene cases re-read from the design's scene, new cases as given.
std::vector<DropCase> designCases(const Study& s, const Scene& designScene);

// Names and scales of the constraints a study declares, in the order of Evaluation::constraints:
// stroke [m], tyre_deflection [m], static_stroke_low/high [m], bottoming [0/1], rebound [m].
std::vector<std::string> constraintNames(const Study& s);
std::vector<double> constraintScales(const Study& s);

// Objective and constraints from per-case metrics (pure; the reduction order is the case order).
// 'tyreDeltaMax' [m] is the scene tyre's delta_max (used by tyre_deflection_max = "delta_max").
Evaluation reduceMetrics(const Study& s, std::vector<CaseMetrics> cases, double tyreDeltaMax, double staticStroke);

// The full evaluation of a design; never throws. 'results' (optional) receives the case results.
Evaluation evaluateDesign(const Study& s, const std::vector<double>& x, const EvaluatorOptions& o,
                          std::vector<CaseResult>* results = nullptr);

// The study as an optimisation Problem.
Problem makeProblem(const Study& s, const EvaluatorOptions& o);

// delta_max [m] of the scene's first tyre (NaN if none).
double sceneTyreDeltaMax(const Scene& scene);

}  // namespace lg::optim
