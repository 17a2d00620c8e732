// simulate SCENE [--case NAME]... [--out DIR] [--plots] [--threads N] [--integrator NAME] [--rtol X]
//          [--atol X] [--step H] [--accuracy A] [--work-precision] [--quiet]
// Runs drop cases of a scene and writes DIR/<case>.csv, DIR/summary.json (and plots); or, with
// --work-precision, the error of every integrator over a range of tolerances against the scene's own
// tight run (DIR/work_precision.csv and, with --plots, DIR/work_precision_<case>.png).
#include <CLI/CLI.hpp>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <thread>

#include "sim/accuracy.hpp"
#include "sim/io/results.hpp"
#include "sim/io/work_precision.hpp"
#include "sim/io/toml_reader.hpp"  // lg::fmt

int main(int argc, char** argv) {
  CLI::App app{"Drop-test simulator: runs the drop cases of a gear scene"};
  std::string scenePath, outDir = "out";
  std::vector<std::string> caseNames;
  bool plots = false, quiet = false;
  int threads = 0;
  std::string integrator;
  double rtol = 0, atol = 0, step = 0;
  app.add_option("scene", scenePath, "scene file (TOML)")->required();
  app.add_option("--case", caseNames, "case to run (repeatable; default: every case of the scene)");
  app.add_option("--out", outDir, "output directory (default: out)");
  app.add_flag("--plots", plots, "draw P_y(t), s(t), h(t) and the work diagram P_y(h) with gnuplot");
  app.add_option("--threads", threads, "threads for running cases in parallel (default: all cores)");
  app.add_flag("--quiet", quiet, "no progress and no table on the terminal");
  app.add_option("--integrator", integrator, "override the scene's integrator: dopri5, ros34pw2, ros2, rk4, euler");
  app.add_option("--rtol", rtol, "override the relative tolerance of the adaptive integrators (atol = rtol/100 unless --atol)");
  app.add_option("--atol", atol, "override the absolute tolerance of the adaptive integrators");
  app.add_option("--step", step, "override the step of the fixed-step integrators (first trial step of the adaptive ones) [s]");
  // Accuracy on demand and work-precision (sim/accuracy.hpp).
  double accuracy = 0;
  bool workPrecision = false;
  app.add_option("--accuracy", accuracy,
                 "relative accuracy of the reported metrics (1e-5 .. 1e-1): chooses integrator and tolerances");
  app.add_flag("--work-precision", workPrecision,
               "run every integrator over a range of tolerances against the scene's own tight run; write the table "
               "(and with --plots the pictures) of error against time per drop");
  CLI11_PARSE(app, argc, argv);

  lg::Scene scene;
  std::vector<lg::DropCase> cases;
  try {
    scene = lg::loadScene(scenePath);
    // Solver overrides from the command line, checked like the scene's own keys.
    lg::Settings& cfg = scene.model.settings;
    auto positive = [](const char* flag, double v) {
      if (!(v > 0) || !std::isfinite(v))
        throw lg::InputError("command line", 0, flag, "value " + lg::fmt(v) + " must be > 0");
    };
    if (!integrator.empty() && !lg::integratorFromName(integrator, cfg.integrator))
      throw lg::InputError("command line", 0, "--integrator",
                           "value '" + integrator + "' must be one of " + lg::integratorNames());
    if (app.count("--rtol")) {
      positive("--rtol", rtol);
      cfg.rtol = rtol;
      cfg.atol = rtol * 1e-2;
    }
    if (app.count("--atol")) {
      positive("--atol", atol);
      cfg.atol = atol;
    }
    if (app.count("--step")) {
      positive("--step", step);
      cfg.step = step;
    }
    if (app.count("--accuracy")) {
      if (const std::string rule = lg::accuracyRule(accuracy); !rule.empty())
        throw lg::InputError("command line", 0, "--accuracy", "value " + lg::fmt(accuracy) + " " + rule);
      for (const char* flag : {"--integrator", "--rtol", "--atol"})
        if (app.count(flag))
          throw lg::InputError("command line", 0, flag, "--accuracy chooses integrator and tolerances: give one or the other");
      lg::applyAccuracy(cfg, accuracy);
    }
    if (caseNames.empty()) cases = scene.cases;
    for (const auto& n : caseNames) {
      auto it = std::find_if(scene.cases.begin(), scene.cases.end(), [&](const auto& c) { return c.name == n; });
      if (it == scene.cases.end()) {
        std::string known;
        for (const auto& c : scene.cases) known += (known.empty() ? "" : ", ") + c.name;
        throw lg::InputError(scenePath, 0, "case", "no case named '" + n + "' (cases: " + known + ")");
      }
      cases.push_back(*it);
    }
    if (cases.empty()) throw lg::InputError(scenePath, 0, "case", "the scene declares no [[case]] to run");
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  if (workPrecision) {  // single thread: the times are per drop on one core
    std::error_code wec;
    std::filesystem::create_directories(outDir, wec);
    if (wec) {
      std::cerr << "error: cannot create output directory " << outDir << ": " << wec.message() << "\n";
      return 1;
    }
    if (!quiet) std::fprintf(stderr, "work-precision of %s: %zu case(s), every integrator, against dopri5 at rtol 1e-10\n",
                             scene.name.c_str(), cases.size());
    const auto points = lg::workPrecision(scene, cases);
    lg::writeWorkPrecisionCsv(points, outDir + "/work_precision.csv");
    std::string why;
    const bool drawn = plots && lg::writeWorkPrecisionPlots(scene, points, outDir, &why);
    if (plots && !drawn) std::cerr << "plots skipped: " << why << "\n";
    if (!quiet) {
      lg::printWorkPrecisionTable(points, stdout);
      std::printf("wrote %s/work_precision.csv%s\n", outDir.c_str(), drawn ? " and work_precision_<case>.png" : "");
    }
    return 0;
  }

  // Progress on a terminal for runs longer than a second.
  const bool tty = !quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  std::atomic<int> done{0};
  std::mutex mu;
  auto lastPrint = start;
  lg::CaseOptions opt;
  opt.record = true;
  opt.stop = [&]() {
    if (!tty) return false;
    std::lock_guard<std::mutex> lock(mu);
    const auto now = std::chrono::steady_clock::now();
    if (std::chrono::duration<double>(now - start).count() > 1.0 &&
        std::chrono::duration<double>(now - lastPrint).count() > 0.25) {
      lastPrint = now;
      std::fprintf(stderr, "\r  running %zu case(s): %d done, %.1f s elapsed", cases.size(), done.load(),
                   std::chrono::duration<double>(now - start).count());
    }
    return false;
  };
  std::vector<lg::CaseResult> results(cases.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int i = 0; i < static_cast<int>(cases.size()); ++i) {
    results[i] = lg::runCase(scene, cases[i], opt);
    ++done;
  }
  if (tty && std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() > 1.0)
    std::fprintf(stderr, "\r%60s\r", "");

  std::error_code ec;
  std::filesystem::create_directories(outDir, ec);
  if (ec) {
    std::cerr << "error: cannot create output directory " << outDir << ": " << ec.message() << "\n";
    return 1;
  }
  int failed = 0;
  for (const auto& r : results) {
    lg::writeHistoryCsv(scene, r, outDir + "/" + r.metrics.name + ".csv");
    if (!r.metrics.ok) {
      ++failed;
      std::cerr << "case " << r.metrics.name << " failed: " << r.metrics.message << "\n";
    }
    if (plots) {
      std::string why;
      if (!lg::writePlots(scene, r, outDir + "/" + r.metrics.name + ".csv", outDir, &why))
        std::cerr << "plots skipped: " << why << "\n";
    }
  }
  lg::writeSummaryJson(scene, results, outDir + "/summary.json");
  if (!quiet) {
    std::printf("%-10s %12s %9s %7s %9s %9s %9s %7s %7s %10s %6s %9s\n", "case", "peak P_y[N]", "t_peak[s]", "n_y",
                "s_max[m]", "h_max[m]", "delta[m]", "eta", "eta_s", "E_err", "steps", "time[ms]");
    for (const auto& r : results) {
      const auto& m = r.metrics;
      std::printf("%-10s %12.1f %9.5f %7.3f %9.5f %9.5f %9.5f %7.4f %7.4f %10.2e %6ld %9.3f%s\n", m.name.c_str(),
                  m.peak_load_N, m.t_peak_s, m.load_factor, m.stroke_max_m, m.h_max_m, m.tyre_deflection_max_m,
                  m.efficiency, m.strut_efficiency, m.energy_balance_error, m.steps, 1e3 * m.wall_time_s,
                  m.ok ? "" : "  FAILED");
    }
    std::printf("wrote %s/summary.json and %zu case file(s)%s\n", outDir.c_str(), results.size(),
                plots ? " with plots" : "");
  }
  return failed ? 1 : 0;
}
