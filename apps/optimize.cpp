// optimize STUDY [--out DIR] [--threads N] [--maxeval N] [--set PATH=VALUE]... [--resume] [--plots] [--quiet]
// Runs an NLopt design study (optim/study.hpp) and writes DIR/history.csv, result.json, best.toml,
// report.md. Exit status: 0 done, 1 an output could not be written, 2 bad input (nothing written),
// 130 interrupted by Ctrl-C (the best design so far written).
#include <unistd.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "apps/cli.hpp"
#include "sim/io/provenance.hpp"
#include "optim/report.hpp"
#include "optim/study.hpp"
#include "sim/io/overrides.hpp"
#include "sim/io/plots.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Design study of a gear scene with NLopt (docs/optimize.md, docs/study.md)"};
  lg::cli::addVersion(app, "optimize");
  std::string studyPath, outDir;
  std::vector<std::string> sets;
  int threads = 0, maxeval = -1;
  bool quiet = false, resume = false, plots = false;
  lg::cli::addInputFile(app, "study", studyPath, "study file (TOML, .cfg or .toml)");
  lg::cli::addText(app, "--out", outDir, "output directory (default: <study stem>-out in the current directory)");
  lg::cli::addThreads(app, threads, "the cases of a design");
  lg::cli::addInteger(app, "--maxeval", maxeval, "override [algorithm] maxeval: evaluations at most (1 .. 1e8)", 1, 100000000,
                      "for no limit, maxeval = 0 in the study's [algorithm], beside another stopping rule");
  lg::cli::addTexts(app, "--set", sets, "override a parameter of the study's scene, PATH=VALUE in SI units (repeatable)");
  app.add_flag("--resume", resume, "reuse the evaluations of DIR/history.csv (same bits of the variables)");
  app.add_flag("--plots", plots, "draw the report's pictures with gnuplot (the data and scripts are written regardless)");
  app.add_flag("--quiet", quiet, "no progress line or summary");
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;

  lg::optim::Study study;
  try {
    std::vector<lg::ParameterOverride> overrides;
    for (const auto& s : sets) overrides.push_back(lg::parseOverride(s));
    study = lg::optim::loadStudy(studyPath, overrides);
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  if (outDir.empty()) outDir = lg::safeFileStem(std::filesystem::path(studyPath).stem().string()) + "-out";
  threads = std::min(lg::cli::resolveThreads(threads), std::max(1, study.steeringCases()));

  lg::cli::installInterruptHandler();
  const bool tty = !quiet && isatty(fileno(stderr));
  if (!quiet) std::printf("%s: drop-test solver %s\n", study.name.c_str(), study.solverChoice.c_str());
  const bool maximize = study.objective.kind == lg::optim::ObjectiveKind::MaxEfficiency;

  std::vector<lg::InputFile> inputs{{"study", studyPath, ""}};
  for (const auto& f : lg::sceneInputs(study.scene)) inputs.push_back(f);
  const lg::Provenance provenance = lg::makeProvenance("optimize", argc, argv, inputs);
  lg::optim::RunOptions ro;
  ro.provenance = &provenance;
  ro.outDir = outDir;
  ro.threads = threads;
  ro.maxeval = maxeval;
  ro.resume = resume;
  ro.plots = plots;
  ro.stop = [] { return lg::cli::interrupted(); };
  double best = NAN;
  double lastPrint = -1;
  ro.progress = [&](const lg::optim::EvaluationRecord& r, double elapsed) {
    if (r.feasible && (std::isnan(best) || (maximize ? r.evaluation.objective > best : r.evaluation.objective < best)))
      best = r.evaluation.objective;
    if (!tty || elapsed - lastPrint < 0.1) return;
    lastPrint = elapsed;
    std::fprintf(stderr, "\r  eval %5d   best feasible %-12s  elapsed %7.1f s   ", r.index,
                 std::isnan(best) ? "-" : (std::to_string(best)).c_str(), elapsed);
    std::fflush(stderr);
  };

  lg::optim::StudyResult res;
  try {
    res = lg::optim::runStudy(study, ro);
  } catch (const std::exception& e) {
    if (tty) std::fprintf(stderr, "\n");
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  if (tty) std::fprintf(stderr, "\n");
  for (const auto& w : res.warnings) std::cerr << "optimize: warning: " << w << "\n";
  const auto& o = res.opt;
  if (!quiet && o.history.empty()) std::printf("%s: %s\n", study.name.c_str(), o.reason.c_str());
  if (!quiet && !o.history.empty()) {
    std::printf("%s: %s after %d evaluations (%d simulated)\n", study.name.c_str(), o.reason.c_str(), o.evaluations,
                o.simulations);
    std::printf("  objective %s: baseline %.6g -> best %.6g (%s, evaluation %d)\n",
                maximize ? "(max efficiency)" : "(min peak load, N)", o.initial.objective, o.best.objective,
                o.feasible ? "feasible" : "NOT feasible", o.bestIndex);
    if (study.certification)
      std::printf("  certification matrix (%s, %s): %s\n", study.certification->basisName.c_str(),
                  study.certificationRole == lg::optim::CaseRole::Check ? "checked" : "constraining the design",
                  res.certified ? "PASS" : "FAIL");
    if (!study.corners.empty())
      std::printf("  envelope: %zu points; steering cases %s, checks %s\n", study.corners.size(),
                  study.envelope.robust() ? "at every point" : "at the nominal point",
                  study.envelope.checksAtCorners ? "at every point" : "at the nominal point");
    if (const auto& b = res.robustness; b.robust) {
      if (b.nominalRun)
        std::printf("  price of robustness: the nominal study's optimum %.6g -> %.6g at the nominal point (%+.3g %%); it "
                    "breaks %d constraints at the corners, most %s\n",
                    b.nominalObjective, b.atNominal, 100 * (b.atNominal - b.nominalObjective) / b.nominalObjective,
                    b.nominalViolated, b.nominalWorst.empty() ? "none" : b.nominalWorst.c_str());
      for (const auto& a : b.active) std::printf("  active: %s (g = %.3g)\n", a.constraint.c_str(), a.g);
    }
    std::printf("  check cases: %s\n", res.checksWithinLimits ? "within their limits"
                                                               : "some exceed a limit (warnings above, report.md)");
    for (size_t i = 0; i < study.variables.size(); ++i)
      std::printf("  %-16s %.6g -> %.6g\n", study.variables[i].path.c_str(), o.x0[i], o.x[i]);
    std::printf("  wrote %s/{history.csv,result.json,best.toml,report.md}\n", outDir.c_str());
  }
  return o.interrupted && lg::cli::interrupted() ? lg::cli::kInterrupted : lg::cli::kOk;
}
