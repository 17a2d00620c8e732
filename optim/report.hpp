// Running a study with its outputs in DIR:
//   history.csv  one line per evaluation, flushed as it finishes: eval, variables (physical units),
//                objective, each constraint g_j (<= 0 is feasible), feasible (0/1), reason
//   result.json  best design, objective, constraints, per-case metrics of best and baseline,
//                evaluations, wall time, NLopt result code and a human reason
//   best.toml    the scene with the best variables (runnable with `simulate`)
//   report.md    tables and gnuplot pictures (plots/*.png; skipped, and said so, without gnuplot)
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "optim/evaluator.hpp"
#include "optim/optimizer.hpp"
#include "optim/study.hpp"

namespace lg::optim {

struct RunOptions {
  std::string outDir = "study-out";
  int threads = 1;          // OpenMP threads over the cases of one design
  int maxeval = -1;         // >= 0 overrides [algorithm] maxeval
  bool resume = false;      // reuse DIR/history.csv evaluations (cache by exact bits of x)
  bool plots = true;        // run gnuplot for report.md
  std::function<bool()> stop;                                 // Ctrl-C flag
  std::function<void(const EvaluationRecord&, double elapsed_s)> progress;  // after each evaluation
};

struct StudyResult {
  OptimizationResult opt;
  std::vector<CaseMetrics> baselineCases, bestCases;  // re-simulated, record = false
  std::string bestToml;                               // the text written to best.toml
  bool gnuplot = false;                               // pictures were made
  std::vector<std::string> warnings;
};

// Runs the study and writes DIR; throws only for I/O errors (std::runtime_error).
StudyResult runStudy(const Study& s, const RunOptions& o);

// History file (CSV).
std::string historyHeader(const Study& s);
std::string historyLine(const EvaluationRecord& r);
// Reads a history written for the same study header; returns the evaluations by bits of x.
// A missing file gives an empty cache; a different header gives an empty cache and a warning.
EvaluationCache readHistory(const std::string& path, const Study& s, std::string* warning = nullptr);

// best.toml text: the design's document, relative table paths rewritten to stay valid from outDir.
std::string bestSceneText(const Study& s, const std::vector<double>& x, const std::string& outDir);

// JSON number: %.17g (exact round trip), null when not finite.
std::string jsonNumber(double v);

}  // namespace lg::optim
