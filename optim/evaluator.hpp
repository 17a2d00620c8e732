// Evaluating one design of a study on the simulator: set the variables in the scene's model as data
// (sim/scene/parameters.hpp; no text edited or parsed), check the scene's rules, run the steering cases (OpenMP through lg::runCases; cases that differ only by name run once),
// reduce the per-case metrics to the objective and the constraints in a fixed order (so results are
// bitwise identical for any thread count).
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
  bool checks = false;             // also run the check cases (reports: every case of the study)
};

// A design's per-case metrics, in the order of Study::cases: the study's EvaluationDetail.
struct CaseDetail : EvaluationDetail {
  std::vector<CaseMetrics> cases;
};
// The per-case metrics an evaluation carries (empty when it carries none: cached, or failed before a run).
const std::vector<CaseMetrics>& caseMetricsOf(const Evaluation& e);

// The scene document with the variables set to x (physical units): best.toml's text.
toml::table designDocument(const Study& s, const std::vector<double>& x);
// The drop cases of a design, in the order of Study::cases: the steering cases, and with 'checks' the
// check cases too. Scene cases are re-read from the design's scene, matrix cases get W made up on it.
std::vector<DropCase> designCases(const Study& s, const Scene& designScene, bool checks);

// Names and scales of the scalar constraints g_j (Study::items), in the order of Evaluation::constraints.
std::vector<std::string> constraintNames(const Study& s);
std::vector<double> constraintScales(const Study& s);

// Objective and constraints from the metrics of the cases (at least the steering ones, in study order)
// and the static stroke [m] (NaN when not needed); pure, the reduction order is the case order.
Evaluation reduceMetrics(const Study& s, std::vector<CaseMetrics> cases, double staticStroke);

// The full evaluation of a design; never throws. 'results' (optional) receives the case results.
Evaluation evaluateDesign(const Study& s, const std::vector<double>& x, const EvaluatorOptions& o,
                          std::vector<CaseResult>* results = nullptr);

// The same with the derivatives of the objective, its terms and every constraint with respect to the
// variables (sim/drop/gradient.hpp: exact, forward mode; the values are the Jet run's, equal to the
// double run's to round-off). Needs no static_stroke constraint.
Evaluation evaluateDesignGradient(const Study& s, const std::vector<double>& x, const EvaluatorOptions& o);

// The study as an optimisation Problem (with derivatives unless it constrains the static stroke).
Problem makeProblem(const Study& s, const EvaluatorOptions& o);

}  // namespace lg::optim
