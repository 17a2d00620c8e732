// simulate SCENE [--case NAME]... [--out DIR] [--plots] [--threads N] [--integrator NAME] [--rtol X]
//          [--atol X] [--step H] [--set PATH=VALUE]... [--sink-speeds LIST] [--lift-ratios LIST]
//          [--duration T] [--output-interval DT] [--accuracy A] [--gradient PATHS] [--corner NAME]...
//          [--work-precision] [--quiet]
// Runs drop cases of a scene and writes DIR/<case>.csv, DIR/summary.json, DIR/summary.csv (and plots);
// or, with --work-precision, the error of every integrator over a range of tolerances against the
// scene's own tight run (DIR/work_precision.csv and, with --plots, DIR/work_precision_<case>.png).
// Exit status: 0 done, 1 a case failed or an output could not be written, 2 bad input (nothing
// written), 130 interrupted (nothing written).
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <mutex>

#include "apps/cli.hpp"
#include "sim/io/provenance.hpp"
#include "sim/drop/accuracy.hpp"
#include "sim/io/files.hpp"
#include "sim/io/overrides.hpp"
#include "sim/io/plots.hpp"
#include "sim/io/results.hpp"
#include "sim/io/toml_reader.hpp"  // lg::fmt
#include "sim/io/work_precision.hpp"
#include "sim/drop/metrics.hpp"
#include "sim/scene/parameters.hpp"
#include "sim/scene/check.hpp"

namespace {

constexpr int kMaxCases = 10000;   // cases of one run (a matrix, the corners): beyond it, an error, not a crash
constexpr int kMaxRows = 1000000;  // rows of one case's history at --output-interval

struct Options {
  std::string scene, outDir = "out", integrator, sinkSpeeds, liftRatios;
  std::vector<std::string> cases, sets, gradient, corners;
  bool plots = false, quiet = false, workPrecision = false;
  int threads = 0;
  double rtol = 0, atol = 0, step = 0, duration = 0.8, outputInterval = 0, accuracy = 0;
};

// The scene with the command line's overrides and the cases to run; throws lg::InputError.
std::vector<lg::DropCase> atCorners(const Options& o, const lg::Scene& scene, const std::vector<lg::DropCase>& cases);

lg::Scene loadInputs(const Options& o, const CLI::App& app, std::vector<lg::DropCase>& cases) {
  std::vector<lg::ParameterOverride> sets;
  for (const auto& s : o.sets) sets.push_back(lg::parseOverride(s));
  lg::Scene scene = lg::applyOverrides(lg::loadScene(o.scene), sets);
  // Solver overrides: the one rule of a study's or a calibration's [solver] (sim/drop/accuracy.hpp).
  // (each number is > 0 and finite already: its declaration in addOptions states the rule)
  lg::SolverOverrides so;
  if (!o.integrator.empty()) {
    lg::IntegratorKind kind;
    lg::integratorFromName(o.integrator, kind);  // (one of the names: addChoice)
    so.integrator = kind;
  }
  if (app.count("--rtol")) so.rtol = o.rtol;
  if (app.count("--atol")) so.atol = o.atol;
  if (app.count("--step")) so.step = o.step;
  if (app.count("--accuracy")) so.accuracy = o.accuracy;
  if (const auto problem = lg::solverOverridesProblem(so, "--"))
    throw lg::InputError("command line", 0, problem->first, problem->second);
  lg::applySolverOverrides(scene.model.settings, so);
  if (o.workPrecision && !o.gradient.empty())
    throw lg::InputError("command line", 0, "--gradient", "--work-precision runs no gradient: give one or the other");
  // The cases: a sink-speed / lift matrix, the named scene cases, or every case of the scene.
  const bool matrix = !o.sinkSpeeds.empty() || !o.liftRatios.empty();
  if (!matrix && app.count("--duration"))
    throw lg::InputError("command line", 0, "--duration", "sets the duration of a matrix's cases: give --sink-speeds too");
  if (matrix) {
    if (!o.cases.empty())
      throw lg::InputError("command line", 0, "--case", "give either --case or a matrix (--sink-speeds, --lift-ratios)");
    if (o.sinkSpeeds.empty()) throw lg::InputError("command line", 0, "--sink-speeds", "a matrix needs its sink speeds");
    if (!(o.duration <= lg::TomlReader::kMaxDuration))
      throw lg::InputError("command line", 0, "--duration", "value " + lg::fmt(o.duration) + " s must be <= " +
                                                              lg::fmt(lg::TomlReader::kMaxDuration) + " s (a drop test lasts seconds)");
    const auto V = lg::parseValueList(o.sinkSpeeds, "--sink-speeds", true);
    for (double v : V)
      if (const std::string rule = lg::sinkSpeedRule(v); !rule.empty())
        throw lg::InputError("command line", 0, "--sink-speeds", rule);
    const auto L = o.liftRatios.empty() ? std::vector<double>{0.0} : lg::parseValueList(o.liftRatios, "--lift-ratios", false);
    for (double l : L)
      if (const std::string rule = lg::liftRatioRule(l); !rule.empty()) throw lg::InputError("command line", 0, "--lift-ratios", rule);
    for (double l : L)
      if (l > 0 && scene.roles.lifts.empty())
        throw lg::InputError("command line", 0, "--lift-ratios", "value " + lg::fmt(l) + ": the scene declares no lift element");
    if (static_cast<double>(V.size()) * static_cast<double>(L.size()) > kMaxCases)
      throw lg::InputError("command line", 0, "--lift-ratios",
                           "the matrix has " + std::to_string(V.size() * L.size()) + " cases (sink speeds x lift ratios), more than " +
                               std::to_string(kMaxCases) + ": run it in parts");
    cases = lg::caseMatrix(V, L, o.duration);
  } else if (o.cases.empty()) {
    cases = scene.cases;
  } else {
    for (const auto& n : o.cases) {
      auto it = std::find_if(scene.cases.begin(), scene.cases.end(), [&](const auto& c) { return c.name == n; });
      if (it == scene.cases.end()) {
        std::string known;
        for (const auto& c : scene.cases) known += (known.empty() ? "" : ", ") + c.name;
        throw lg::InputError("command line", 0, "--case", "value '" + n + "' is no case of the scene " + o.scene + " (cases: " + known + ")");
      }
      cases.push_back(*it);
    }
  }
  if (cases.empty()) throw lg::InputError(o.scene, 0, "case", "the scene declares no [[case]] to run");
  if (!o.corners.empty()) cases = atCorners(o, scene, cases);
  if (static_cast<double>(cases.size()) > kMaxCases)
    throw lg::InputError("command line", 0, "--corner",
                         std::to_string(cases.size()) + " cases at the corners, more than " + std::to_string(kMaxCases) + ": name fewer");
  if (o.outputInterval > 0)
    for (const auto& c : cases) {
      const double rows = c.duration / o.outputInterval + 1;
      if (rows > kMaxRows)
        throw lg::InputError("command line", 0, "--output-interval",
                             "value " + lg::fmt(o.outputInterval) + " s gives " + lg::fmt(rows) + " rows over case '" + c.name +
                                 "' (" + lg::fmt(c.duration) + " s), more than " + std::to_string(kMaxRows) + " per case");
      if (o.outputInterval > c.duration)
        std::fprintf(stderr, "simulate: warning: --output-interval %s s is longer than case '%s' (%s s): one row, at t = 0\n",
                     lg::fmt(o.outputInterval).c_str(), c.name.c_str(), lg::fmt(c.duration).c_str());
    }
  return scene;
}

// Each case at each corner of --corner (a name of the scene's envelope, or "all": the nominal point and
// every corner), named "<case>@<corner>"; throws lg::InputError.
std::vector<lg::DropCase> atCorners(const Options& o, const lg::Scene& scene, const std::vector<lg::DropCase>& cases) {
  if (!scene.envelope.declared)
    throw lg::InputError("command line", 0, "--corner", "the scene has no [envelope] table (docs/certification.md, \"The servicing and "
                                                        "temperature envelope\")");
  const std::vector<lg::EnvelopeCorner> all = scene.envelope.corners();
  std::vector<lg::EnvelopeCorner> chosen;
  for (const std::string& name : o.corners) {
    if (name == "all") {
      chosen.insert(chosen.end(), all.begin(), all.end());
      continue;
    }
    auto it = std::find_if(all.begin(), all.end(), [&](const auto& c) { return c.name == name; });
    if (it == all.end()) {
      std::string known;
      for (const auto& c : all) known += (known.empty() ? "" : ", ") + c.name;
      throw lg::InputError("command line", 0, "--corner",
                           "value '" + name.substr(0, 80) + "' is no point of the scene's envelope (" + known + ", or all)");
    }
    chosen.push_back(*it);
  }
  std::vector<lg::DropCase> out;
  for (const auto& c : cases)
    for (const auto& k : chosen) {
      lg::DropCase d = c;
      d.corner = k;
      d.name += "@" + k.name;
      if (std::none_of(out.begin(), out.end(), [&](const auto& e) { return e.name == d.name; })) out.push_back(d);
    }
  return out;
}

// The parameters of --gradient, resolved in the scene (after --set); throws lg::InputError.
std::vector<lg::Parameter> gradientParameters(const Options& o, const lg::Scene& scene) {
  std::vector<lg::Parameter> out;
  for (const auto& list : o.gradient) {
    size_t start = 0;
    while (start <= list.size()) {
      const auto comma = list.find(',', start);
      const std::string path = list.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (path.empty())
        throw lg::InputError("command line", 0, "--gradient",
                             "value '" + list + "' has an empty path: PATH[,PATH...], e.g. strut.f1,tyre.K");
      try {
        out.push_back(lg::resolveParameter(scene, path, "command line"));
        lg::checkGradientParameter(out.back(), "command line");
      } catch (const lg::InputError& e) {
        throw lg::InputError("command line", 0, "--gradient", "'" + path + "': " + e.rule());
      }
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return out;
}

struct Gradients {
  std::vector<lg::CaseGradient> cases;
  std::vector<std::string> units;
};

// Writes every output file (atomically); throws std::runtime_error on the first that fails.
void writeOutputs(const Options& o, const lg::Scene& scene, const std::vector<lg::CaseResult>& results, bool gnuplot,
                  const Gradients* g, const lg::Provenance& provenance) {
  namespace fs = std::filesystem;
  for (const auto& r : results) {
    const std::string stem = lg::safeFileStem(r.metrics.name);
    lg::writeFileAtomic((fs::path(o.outDir) / (stem + ".csv")).string(), lg::historyCsv(r));
    if (!o.plots) continue;
    lg::CaseFigure f;
    char title[256];
    std::snprintf(title, sizeof title, "%s: %s, V = %.3f m/s, L = %.3g, W = %.0f kg", scene.name.c_str(),
                  r.metrics.name.c_str(), r.metrics.sink_speed_mps, r.metrics.lift_ratio, r.metrics.mass_kg);
    f.title = title;
    f.run = &r;
    f.limits = lg::sceneLimits(scene);
    f.drawElementsOf(scene);
    std::string why;
    if (!lg::drawCaseFigure(f, o.outDir, stem, gnuplot, &why) && gnuplot)
      std::cerr << "plot of " << r.metrics.name << " skipped: " << why << "\n";
  }
  lg::writeFileAtomic((fs::path(o.outDir) / "summary.json").string(),
                      lg::stampJson(lg::summaryJson(scene, results, g ? &g->cases : nullptr, g ? &g->units : nullptr), &provenance));
  if (g) lg::writeFileAtomic((fs::path(o.outDir) / "gradient.csv").string(), lg::gradientCsv(g->cases, g->units));
  lg::writeFileAtomic((fs::path(o.outDir) / "summary.csv").string(), lg::summaryCsv(results));
}

void printTable(const std::vector<lg::CaseResult>& results) {
  std::printf("%-10s %12s %9s %7s %9s %9s %9s %7s %7s %10s %6s %9s  %s\n", "case", "peak P_y[N]", "t_peak[s]", "n_y",
              "s_max[m]", "h_max[m]", "delta[m]", "eta", "eta_s", "E_err", "steps", "time[ms]", "limits");
  for (const auto& r : results) {
    const auto& m = r.metrics;
    const std::string lim = !m.ok ? "FAILED: " + m.message : m.withinLimits() ? "ok" : "EXCEEDED: " + m.limitViolations();
    std::printf("%-10s %12.1f %9.5f %7.3f %9.5f %9.5f %9.5f %7.4f %7.4f %10.2e %6ld %9.3f  %s\n", m.name.c_str(),
                m.peak_load_N, m.t_peak_s, m.load_factor, m.stroke_max_m, m.h_max_m, m.tyre_deflection_max_m,
                m.efficiency, m.strut_efficiency, m.energy_balance_error, m.steps, 1e3 * m.wall_time_s, lim.c_str());
  }
  for (const auto& r : results) {
    const auto& m = r.metrics;
    const std::string back = m.stiff_handbacks == 0 ? ""
                             : " (" + std::to_string(m.stiff_handbacks) + " earlier trial(s) cost more and went back to dopri5)";
    if (std::isfinite(m.stiff_from_s))
      std::printf("%s: stiff from t = %.5f s (dopri5 at its stability bound): ros34pw2 from there%s\n", m.name.c_str(),
                  m.stiff_from_s, back.c_str());
    else if (m.stiff_handbacks > 0)
      std::printf("%s: dopri5 at its stability bound, but ros34pw2 cost more on %d trial(s): dopri5 throughout\n",
                  m.name.c_str(), m.stiff_handbacks);
    if (std::isfinite(m.accuracy_rerun))
      std::printf("%s: %s: run again at accuracy %.3g for its time\n", m.name.c_str(), m.accuracy_rerun_reason.c_str(),
                  m.accuracy_rerun);
    if (m.ok && m.longitudinal)
      std::printf("%s: drag at V_x = %.1f m/s: spin-up %.1f kN at %.4f s, spring-back %.1f kN at %.4f s, P_x/P_y at P_y,max %.3f\n",
                  m.name.c_str(), m.forward_speed_mps, m.drag_peak_N / 1e3, m.t_drag_peak_s, m.springback_peak_N / 1e3,
                  m.t_springback_s, m.peak_load_N > 0 ? m.drag_at_peak_N / m.peak_load_N : NAN);
  }
}

// The derivatives of the peak load and the stroke per case, for the terminal (all in gradient.csv).
void printGradients(const Gradients& g) {
  if (g.cases.empty()) return;
  const auto& params = g.cases.front().parameters;
  std::printf("%-10s %-14s", "case", "metric");
  for (size_t j = 0; j < params.size(); ++j)
    std::printf(" %22s", ("d/d" + params[j] + "[" + g.units[j] + "]").c_str());
  std::printf("\n");
  for (const auto& c : g.cases) {
    if (!c.ok) {
      std::printf("%-10s FAILED: %s\n", c.caseName.c_str(), c.message.c_str());
      continue;
    }
    for (const char* metric : {"peak_load", "stroke"}) {
      const auto* m = c.find(metric);
      std::printf("%-10s %-14s", c.caseName.c_str(), (std::string(metric) + "[" + lg::findMetric(metric)->unit + "]").c_str());
      for (double d : m->d) std::printf(" %22.6g", d);
      std::printf("%s\n", m->smooth ? "" : "  (one-sided: see note)");
    }
  }
}

// simulate --work-precision: single thread, so that the times are per drop on one core.
int workPrecision(const Options& o, const lg::Scene& scene, const std::vector<lg::DropCase>& cases) {
  if (!o.quiet)
    std::fprintf(stderr, "work-precision of %s: %zu case(s), every integrator, against dopri5 at rtol 1e-10\n",
                 scene.name.c_str(), cases.size());
  const auto points = lg::workPrecision(scene, cases);
  if (lg::cli::interrupted()) {
    std::cerr << "interrupted: nothing written\n";
    return lg::cli::kInterrupted;
  }
  std::string why;
  bool drawn = false;
  try {
    lg::writeWorkPrecisionCsv(points, o.outDir + "/work_precision.csv");
    drawn = o.plots && lg::writeWorkPrecisionPlots(scene, points, o.outDir, &why);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  if (o.plots && !drawn) std::cerr << "plots skipped: " << why << "\n";
  if (!o.quiet) {
    lg::printWorkPrecisionTable(points, stdout);
    std::printf("wrote %s/work_precision.csv%s\n", o.outDir.c_str(), drawn ? " and work_precision_<case>.png" : "");
  }
  return lg::cli::kOk;  // a setting that failed is a row of the table (FAILED), not a failure of the command
}

// The command line's options into o.
void addOptions(CLI::App& app, Options& o) {
  namespace cli = lg::cli;
  cli::addInputFile(app, "scene", o.scene, "scene file (TOML)");
  cli::addTexts(app, "--case", o.cases, "case to run (repeatable; default: every case of the scene)");
  cli::addText(app, "--out", o.outDir, "output directory (default: out)");
  app.add_flag("--plots", o.plots, "draw one figure per case with gnuplot");
  cli::addThreads(app, o.threads, "the cases");
  app.add_flag("--quiet", o.quiet, "no progress and no table on the terminal");
  cli::addChoice(app, "--integrator", o.integrator, "override the scene's integrator: " + lg::integratorNames(),
                 lg::integratorList());
  cli::addNumber(app, "--rtol", o.rtol, "override the relative tolerance of the adaptive integrators (atol = rtol/100 unless --atol)", true);
  cli::addNumber(app, "--atol", o.atol, "override the absolute tolerance of the adaptive integrators", true);
  cli::addNumber(app, "--step", o.step, "override the step of the fixed-step integrators (first trial step of the adaptive ones) [s]", true, "s");
  cli::addTexts(app, "--set", o.sets, "override a scene parameter, PATH=VALUE in SI units (repeatable), e.g. strut.f1=8e-5");
  cli::addText(app, "--sink-speeds", o.sinkSpeeds, "run a matrix instead of the scene's cases: sink speeds [m/s], a,b,c or start:step:stop");
  cli::addText(app, "--lift-ratios", o.liftRatios, "the matrix's lift ratios, a,b,c or start:step:stop (default 0)");
  cli::addNumber(app, "--duration", o.duration, "the matrix cases' duration [s] (default 0.8)", true, "s");
  cli::addNumber(app, "--output-interval", o.outputInterval, "CSV rows every DT seconds from the dense output (default: one per step) [s]", true, "s");
  cli::addTexts(app, "--gradient", o.gradient, "derivatives of every metric with respect to these parameters, PATH[,PATH...] "
                                            "(exact, forward mode): into summary.json and gradient.csv");
  cli::addNumber(app, "--accuracy", o.accuracy,
                 "relative accuracy of the reported metrics (1e-5 .. 1e-1): chooses integrator and tolerances", true);
  cli::addTexts(app, "--corner", o.corners, "run each case at this point of the scene's [envelope] (repeatable; \"all\": "
                                       "the nominal point and every corner), named <case>@<corner>");
  app.add_flag("--work-precision", o.workPrecision,
               "run every integrator over a range of tolerances against the scene's own tight run; write the table "
               "(and with --plots the pictures) of error against time per drop (one core)");
}

// Every case in parallel over 'threads' (results in the cases' order), with progress on a terminal for
// runs longer than a second; Ctrl-C stops every case at its next step.
std::vector<lg::CaseResult> runCases(const Options& o, const lg::Scene& scene, const std::vector<lg::DropCase>& cases,
                                     int threads) {
  const bool tty = !o.quiet && isatty(STDERR_FILENO);
  const auto start = std::chrono::steady_clock::now();
  std::atomic<int> done{0};
  std::mutex mu;
  auto lastPrint = start;
  lg::CaseOptions opt;
  opt.record = true;
  opt.outputInterval = o.outputInterval;
  opt.stop = [&]() {
    if (lg::cli::interrupted()) return true;
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
  return results;
}

// The exact derivatives of every case's metrics by 'params' (none without them), in parallel.
Gradients caseGradients(const lg::Scene& scene, const std::vector<lg::DropCase>& cases,
                        const std::vector<lg::Parameter>& params, int threads) {
  Gradients gradients;
  if (params.empty()) return gradients;
  for (const auto& p : params) gradients.units.push_back(lg::parameterUnit(scene, p));
  gradients.cases.resize(cases.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(threads)
  for (int i = 0; i < static_cast<int>(cases.size()); ++i)
    if (!lg::cli::interrupted()) gradients.cases[i] = lg::caseGradient(scene, cases[i], params);
  return gradients;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Drop-test simulator: runs the drop cases of a gear scene"};
  lg::cli::addVersion(app, "simulate");
  Options o;
  addOptions(app, o);
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;

  lg::Scene scene;
  std::vector<lg::DropCase> cases;
  std::vector<lg::Parameter> gradientParams;
  try {
    scene = loadInputs(o, app, cases);
    gradientParams = gradientParameters(o, scene);
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  try {
    lg::prepareOutputDir(o.outDir);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  const int threads = lg::cli::resolveThreads(o.threads);
  lg::cli::installInterruptHandler();
  if (o.workPrecision) return workPrecision(o, scene, cases);

  const lg::Provenance provenance = lg::makeProvenance("simulate", argc, argv, lg::sceneInputs(scene));
  const std::vector<lg::CaseResult> results = runCases(o, scene, cases, threads);
  const Gradients gradients = caseGradients(scene, cases, gradientParams, threads);
  if (lg::cli::interrupted()) {
    std::cerr << "interrupted: nothing written\n";
    return lg::cli::kInterrupted;
  }

  int failed = 0;
  for (const auto& r : results)
    if (!r.metrics.ok) {
      ++failed;
      std::cerr << "case " << r.metrics.name << " failed: " << r.metrics.message << "\n";
    }
  const bool gnuplot = o.plots && lg::haveGnuplot();
  if (o.plots && !gnuplot) std::cerr << "plots skipped: gnuplot is not installed (scripts/setup.sh installs gnuplot-nox)\n";
  try {
    writeOutputs(o, scene, results, gnuplot, gradientParams.empty() ? nullptr : &gradients, provenance);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  if (!o.quiet) {
    printTable(results);
    if (!gradientParams.empty()) printGradients(gradients);
    std::printf("wrote %s/summary.json, summary.csv%s and %zu case file(s)%s\n", o.outDir.c_str(),
                gradientParams.empty() ? "" : ", gradient.csv", results.size(), gnuplot ? " with plots" : "");
  }
  return failed ? lg::cli::kFailed : lg::cli::kOk;
}
