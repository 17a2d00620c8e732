// Running a study with its outputs in DIR:
//   history.csv  one line per evaluation, flushed as it finishes: eval, variables (physical units),
//                objective, each constraint g_j (<= 0 is feasible), feasible (0/1), reason
//   result.json  best design, objective, constraints, every case of the study (steering and checks) for
//                baseline and best with its limits and verdict, the certification verdict, evaluations,
//                wall time, NLopt result code and a human reason
//   best.toml    the scene with the best variables (runnable with `simulate` and `certify`)
//   report.md    tables and gnuplot pictures (plots/*.png; skipped, and said so, without gnuplot)
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "optim/evaluator.hpp"
#include "optim/optimizer.hpp"
#include "optim/study.hpp"
#include "sim/io/json.hpp"
#include "sim/io/provenance.hpp"

namespace lg::optim {

using lg::jsonNumber;

struct RunOptions {
  std::string outDir = "study-out";
  int threads = 1;          // OpenMP threads over the cases of one design
  int maxeval = -1;         // >= 0 overrides [algorithm] maxeval
  bool resume = false;      // reuse DIR/history.csv evaluations (cache by exact bits of x)
  bool plots = true;        // run gnuplot for report.md
  std::function<bool()> stop;                                 // Ctrl-C flag
  std::function<void(const EvaluationRecord&, double elapsed_s)> progress;  // after each evaluation
  const Provenance* provenance = nullptr;  // heads result.json, report.md and best.toml (sim/io/provenance.hpp)
};

// What a robust study's constraints at the corners cost, and where they bind (Study::envelope).
struct Robustness {
  bool robust = false;             // the study ran its steering cases at the corners
  int points = 0;                  // points of the envelope (nominal and corners)
  struct Active {
    std::string constraint;        // the item's name ("stroke_margin_min@cert-reserve@cold-...")
    std::string caseName, corner;  // its case and point
    double g = 0;                  // [metric's unit] g_j at the best design (<= 0 holds)
  };
  std::vector<Active> active;      // the constraints within 1e-3 of their scale of binding at the best design
  double atNominal = std::numeric_limits<double>::quiet_NaN();  // the robust optimum's objective at the nominal
                                   // point (its objective where the study's is the worst corner's)
  bool nominalRun = false;         // the nominal variant was run (nominal_study)
  double nominalObjective = std::numeric_limits<double>::quiet_NaN();  // its optimum's objective
  bool nominalFeasible = false;
  std::vector<double> nominalX;    // its optimum (physical)
  int nominalEvaluations = 0;
  int nominalViolated = 0;         // the robust study's constraints the nominal optimum breaks at the corners
  std::string nominalWorst;        // the one it breaks most (scaled), and its g [metric's unit]
  double nominalWorstG = std::numeric_limits<double>::quiet_NaN();
};

struct StudyResult {
  OptimizationResult opt;
  // Every case of the study (Study::cases order: steering, then checks), re-simulated for the baseline
  // and the best design, and judged against its limits (matrix cases: the rules'; other cases: the
  // stroke and tyre limits and the study's constraints on them).
  std::vector<CaseMetrics> baselineCases, bestCases;
  std::vector<CaseVerdict> baselineVerdicts, bestVerdicts;
  bool certified = false;        // the best design passes every matrix case (false without a matrix)
  bool checksWithinLimits = true;  // the best design's check cases are within their limits
  std::string bestToml;          // the text written to best.toml
  bool gnuplot = false;          // pictures were made
  std::vector<std::string> warnings;
  Robustness robustness;
};

// Runs the study and writes DIR; throws only for I/O errors (std::runtime_error).
StudyResult runStudy(const Study& s, const RunOptions& o);

// The limits a case of the study is judged against in the report (not the constraints NLopt sees:
// those are Study::items).
std::vector<Limit> reportLimits(const Study& s, int caseIndex);

// History file (CSV).
std::string historyHeader(const Study& s);
std::string historyLine(const Study& s, const EvaluationRecord& r);
// Reads a history written for the same study header; returns the evaluations by bits of x.
// A missing file gives an empty cache; a different header gives an empty cache and a warning.
EvaluationCache readHistory(const std::string& path, const Study& s, std::string* warning = nullptr);

// best.toml text: the design's document, relative table paths rewritten to stay valid from outDir.
std::string bestSceneText(const Study& s, const std::vector<double>& x, const std::string& outDir);

}  // namespace lg::optim
