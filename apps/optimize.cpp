// optimize STUDY [--out DIR] [--threads N] [--maxeval N] [--resume] [--no-plots] [--quiet]
// Runs an NLopt design study (optim/study.hpp) and writes DIR/history.csv, result.json, best.toml,
// report.md. Exit status: 0 done (also after Ctrl-C, with the best design so far), 2 bad input
// (nothing written), 1 other errors.
#include <unistd.h>

#include <atomic>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include <omp.h>

#include <CLI/CLI.hpp>

#include "optim/report.hpp"
#include "optim/study.hpp"

namespace {
volatile std::sig_atomic_t gInterrupted = 0;
extern "C" void onSigint(int) { gInterrupted = 1; }
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Design study of a gear scene with NLopt (see optim/study.hpp for the study file)"};
  std::string studyPath, outDir;
  int threads = 0, maxeval = -1;
  bool quiet = false, resume = false, noPlots = false;
  app.add_option("study", studyPath, "study file (TOML, .cfg or .toml)")->required();
  app.add_option("--out", outDir, "output directory (default: <study stem>-out in the current directory)");
  app.add_option("--threads", threads, "OpenMP threads over the cases of a design (default: min(cases, cores))")
      ->check(CLI::Range(1, 1024));
  app.add_option("--maxeval", maxeval, "override [algorithm] maxeval")->check(CLI::Range(0, 100000000));
  app.add_flag("--resume", resume, "reuse the evaluations of DIR/history.csv (same bits of the variables)");
  app.add_flag("--no-plots", noPlots, "skip gnuplot (data and script are still written)");
  app.add_flag("--quiet", quiet, "no progress line or summary");
  CLI11_PARSE(app, argc, argv);

  lg::optim::Study study;
  try {
    study = lg::optim::loadStudy(studyPath);
  } catch (const lg::InputError& e) {
    std::cerr << "optimize: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "optimize: " << studyPath << ": " << e.what() << "\n";
    return 2;
  }
  if (outDir.empty()) outDir = std::filesystem::path(studyPath).stem().string() + "-out";
  if (threads <= 0) threads = std::max(1, std::min<int>(static_cast<int>(study.cases.size()), omp_get_num_procs()));

  std::signal(SIGINT, onSigint);
  const bool tty = !quiet && isatty(fileno(stderr));
  const bool maximize = study.objective.kind == lg::optim::ObjectiveKind::MaxEfficiency;

  lg::optim::RunOptions ro;
  ro.outDir = outDir;
  ro.threads = threads;
  ro.maxeval = maxeval;
  ro.resume = resume;
  ro.plots = !noPlots;
  ro.stop = [] { return gInterrupted != 0; };
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
    std::cerr << "optimize: " << e.what() << "\n";
    return 1;
  }
  if (tty) std::fprintf(stderr, "\n");
  for (const auto& w : res.warnings) std::cerr << "optimize: warning: " << w << "\n";
  if (!quiet) {
    const auto& o = res.opt;
    std::printf("%s: %s after %d evaluations (%d simulated)\n", study.name.c_str(), o.reason.c_str(), o.evaluations,
                o.simulations);
    std::printf("  objective %s: baseline %.6g -> best %.6g (%s, evaluation %d)\n",
                maximize ? "(max efficiency)" : "(min peak load, N)", o.initial.objective, o.best.objective,
                o.feasible ? "feasible" : "NOT feasible", o.bestIndex);
    if (study.certification)
      std::printf("  certification matrix (%s, %s): %s\n", study.certification->basisName.c_str(),
                  study.certificationRole == lg::optim::CaseRole::Check ? "checked" : "constraining the design",
                  res.certified ? "PASS" : "FAIL");
    std::printf("  check cases: %s\n", res.checksWithinLimits ? "within their limits"
                                                               : "some exceed a limit (warnings above, report.md)");
    for (size_t i = 0; i < study.variables.size(); ++i)
      std::printf("  %-16s %.6g -> %.6g\n", study.variables[i].path.c_str(), o.x0[i], o.x[i]);
    std::printf("  wrote %s/{history.csv,result.json,best.toml,report.md}\n", outDir.c_str());
  }
  return 0;
}
