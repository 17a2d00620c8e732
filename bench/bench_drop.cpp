// Accuracy versus time on a scene's limit case (default: the seed gear): time per drop for each solver and
// integrator setting against its peak-load error, the reference being the scene's own tight run (dopri5
// at rtol 1e-10). Prints the data of an accuracy-versus-time plot, the stage profiles of the default
// setting and of the fastest setting at 0.1 %, and as its last line
//   target 0.1 %: <time> ms (<integrator> rtol <x>, error <e> %)
// for the fastest setting at or below 0.1 % peak-load error (the settings close to the fastest timed again in
// interleaved rounds, the smallest median chosen). Single thread (run it on one core).
// Usage: bench_drop [SCENE] [--case NAME] [--plot DIR] [--specialist PROGRAM] [--help] [--version]
//   --plot DIR          DIR/accuracy_vs_time.{dat,gp,png} drawn by gnuplot
//   --specialist PROG   also runs PROG --case <case> --rtol 1e-3 (the hand-derived reduced model of the seed
//                       gear, kept outside the repository and built by the user) in the same go, and prints its
//                       time per drop and the ratio of ours at 0.1 % to it; then five paired rounds (ours at
//                       0.1 %, then the specialist) and the medians of their times and of their ratios
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "sim/drop/accuracy.hpp"
#include "sim/io/files.hpp"
#include "sim/io/plots.hpp"
#include "sim/io/scene.hpp"

namespace {

struct Setting {
  std::string label;
  lg::MultiplierSolver solver;
  lg::IntegratorKind integrator;
  double tol;          // rtol (adaptive) or step (fixed)
  double maxStep = 0;  // [s] 0: the scene's
};

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.size() % 2 ? v[v.size() / 2] : 0.5 * (v[v.size() / 2 - 1] + v[v.size() / 2]);
}
constexpr int kPairedRounds = 5;
constexpr double kCandidateSpread = 1.5;  // settings this close to the fastest single timing are timed again
constexpr int kSelectRounds = 5;          // in this many interleaved rounds

// Median wall time of one drop over at least 'reps' runs (and at least 0.2 s of runs, for the fast ones).
double timeCase(const lg::Scene& sc, const lg::DropCase& c, int reps, lg::CaseMetrics& m) {
  std::vector<double> t;
  double spent = 0;
  while (static_cast<int>(t.size()) < reps || (spent < 0.2 && t.size() < 1000)) {
    const auto a = std::chrono::steady_clock::now();
    m = lg::runCase(sc, c).metrics;
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
    spent += t.back();
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

lg::Scene configured(const lg::Scene& base, const Setting& s) {
  lg::Scene sc = lg::withSolver(base, s.integrator, s.tol);
  sc.model.settings.solver = s.solver;
  if (s.maxStep > 0) sc.model.settings.maxStep = s.maxStep;
  return sc;
}

// A POSIX shell single-quoted word.
std::string shellWord(const std::string& s) {
  std::string q = "'";
  for (char c : s) q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

// Runs the specialist program and returns its "time/run" in seconds (0 if it could not be read).
double runSpecialist(const std::string& program, const std::string& caseName, std::string& peakLine) {
  const std::string cmd = shellWord(program) + " --case " + shellWord(caseName) + " --rtol 1e-3 2>/dev/null";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return 0;
  char line[512];
  double us = 0;
  while (std::fgets(line, sizeof line, p)) {
    const std::string l(line);
    double peak = 0;
    if (l.rfind("peak P_y", 0) == 0 && std::sscanf(l.c_str(), "peak P_y %lf", &peak) == 1) {
      char buf[64];
      std::snprintf(buf, sizeof buf, "peak P_y %.2f N", peak);
      peakLine = buf;
    }
    if (l.rfind("time/run", 0) == 0) {
      double v = 0;
      char unit[8] = {0};
      if (std::sscanf(l.c_str(), "time/run %lf %7s", &v, unit) == 2)
        us = std::string(unit) == "ms" ? 1e3 * v : (std::string(unit) == "s" ? 1e6 * v : v);
    }
  }
  pclose(p);
  return 1e-6 * us;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Accuracy versus time of a scene's drop case (one core): every solver and integrator setting "
               "against the scene's own tight run; last line: the fastest setting at 0.1 % peak-load error"};
  lg::cli::addVersion(app, "bench_drop");
  std::string scenePath = "data/seed_gear.toml", plotDir, caseName = "limit", specialist;
  app.add_option("scene", scenePath, "scene file (TOML; default data/seed_gear.toml, from the project root)");
  app.add_option("--case", caseName, "the case to measure (default limit)");
  app.add_option("--plot", plotDir, "also write DIR/accuracy_vs_time.{dat,gp,png} (gnuplot)");
  app.add_option("--specialist", specialist,
                 "run PROGRAM --case <case> --rtol 1e-3 (the hand-derived reduced model of the seed gear) in the same "
                 "go and print its time per drop and the ratio of ours at 0.1 % to it");
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;
  lg::Scene base;
  try {
    base = lg::loadScene(scenePath);
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  const auto it = std::find_if(base.cases.begin(), base.cases.end(), [&](auto& c) { return c.name == caseName; });
  if (it == base.cases.end()) {
    std::string known;
    for (const auto& c : base.cases) known += (known.empty() ? "" : ", ") + c.name;
    std::fprintf(stderr, "error: %s: key 'case': no case named '%s' (cases: %s)\n", scenePath.c_str(), caseName.c_str(),
                 known.c_str());
    return lg::cli::kUsage;
  }
  if (!plotDir.empty()) {
    try {
      lg::prepareOutputDir(plotDir);
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      return lg::cli::kFailed;
    }
  }
  const lg::DropCase drop = *it;
  const lg::CaseMetrics ref = lg::runCase(lg::withSolver(base, lg::IntegratorKind::DormandPrince, 1e-10), drop).metrics;
  std::printf("# %s, case %s (V = %.2f m/s, L = %.2f, %.2f s); reference: its own run, dopri5 rtol 1e-10: peak P_y = %.4f N\n",
              base.name.c_str(), drop.name.c_str(), drop.sinkSpeed, drop.liftRatio, drop.duration, ref.peak_load_N);
  std::printf("# %-34s %9s %8s %8s %12s %12s %12s\n", "setting", "tol/step", "steps", "rhs", "time [ms]", "peak err [%]",
              "max err [%]");
  const auto D = lg::MultiplierSolver::Direct;
  std::vector<Setting> settings;
  for (double r : {1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8})
    settings.push_back({"dopri5 direct", D, lg::IntegratorKind::DormandPrince, r});
  for (double r : {1e-1, 1e-2, 1e-3, 1e-4}) settings.push_back({"ros2 direct", D, lg::IntegratorKind::Ros2, r});
  for (double r : {1e-1, 3e-2, 1e-2, 3e-3, 2e-3, 1e-3, 1e-4, 1e-5})
    settings.push_back({"ros34pw2 direct", D, lg::IntegratorKind::Ros34pw2, r});
  for (double r : {1e-2, 5e-3, 3e-3, 2e-3, 1e-3})
    settings.push_back({"ros34pw2 direct, max step 0.05 s", D, lg::IntegratorKind::Ros34pw2, r, 0.05});
  for (double h : {1e-3, 5e-4, 2e-4, 1e-4}) settings.push_back({"rk4 direct", D, lg::IntegratorKind::RK4, h});
  for (double h : {1e-4, 3e-5, 1e-5}) settings.push_back({"euler direct", D, lg::IntegratorKind::SemiImplicitEuler, h});
  for (double r : {1e-3, 1e-5})
    settings.push_back({"dopri5 gauss-seidel", lg::MultiplierSolver::GaussSeidel, lg::IntegratorKind::DormandPrince, r});
  settings.push_back({"rk4 gauss-seidel", lg::MultiplierSolver::GaussSeidel, lg::IntegratorKind::RK4, 2e-4});

  std::map<std::string, std::string> curves;  // setting -> "time err" lines
  const Setting* best = nullptr;
  double bestTime = 0, bestErr = 0;
  struct Within {
    const Setting* setting;
    double err, time;  // [%], [s] (its first timing)
  };
  std::vector<Within> within;  // the settings at or below 0.1 %
  for (const Setting& s : settings) {
    const lg::Scene sc = configured(base, s);
    lg::CaseMetrics m;
    const double t = timeCase(sc, drop, s.integrator == lg::IntegratorKind::SemiImplicitEuler ? 3 : 9, m);
    const double err = 100.0 * std::abs(m.peak_load_N - ref.peak_load_N) / ref.peak_load_N;
    const double maxErr = 100.0 * lg::metricErrors(m, ref).max();
    std::printf("  %-34s %9.0e %8ld %8ld %12.3f %12.2e %12.2e%s\n", s.label.c_str(), s.tol, m.steps, m.rhs_evaluations,
                1e3 * t, err, maxErr, m.ok ? "" : ("  FAILED: " + m.message).c_str());
    if (m.ok) curves[s.label] += std::to_string(1e3 * t) + " " + std::to_string(std::max(err, 1e-9)) + "\n";
    if (m.ok && err <= 0.1) within.push_back({&s, err, t});
  }
  // The fastest setting at 0.1 %. One timing per setting is not enough to choose: on a shared machine a
  // spike of a fifth moved the choice from ros34pw2 rtol 1e-2 (244 evaluations) to rtol 2e-3 (341). Every
  // setting within kCandidateSpread of the fastest single timing is timed again in kSelectRounds
  // interleaved rounds (each round runs every candidate once, in a rotated order), and the smallest
  // median over the rounds wins: its time is that median.
  if (!within.empty()) {
    double fastest = within[0].time;
    for (const Within& w : within) fastest = std::min(fastest, w.time);
    std::vector<Within> cand;
    for (const Within& w : within)
      if (w.time <= kCandidateSpread * fastest) cand.push_back(w);
    std::vector<std::vector<double>> rounds(cand.size());
    for (int r = 0; r < kSelectRounds && cand.size() > 1; ++r)
      for (size_t j = 0; j < cand.size(); ++j) {
        const size_t k = (j + static_cast<size_t>(r)) % cand.size();
        lg::CaseMetrics m;
        rounds[k].push_back(timeCase(configured(base, *cand[k].setting), drop, 9, m));
      }
    if (cand.size() > 1)
      std::printf("# fastest at 0.1 %%: %zu settings within %.1f times the fastest timing, each timed again in %d "
                  "interleaved rounds (medians):\n", cand.size(), kCandidateSpread, kSelectRounds);
    for (size_t j = 0; j < cand.size(); ++j) {
      const Within& w = cand[j];
      const double t = cand.size() > 1 ? median(rounds[j]) : w.time;
      if (cand.size() > 1)
        std::printf("#   %-34s %9.0e %12.3f ms  error %.3f %%\n", w.setting->label.c_str(), w.setting->tol, 1e3 * t,
                    w.err);
      if (!best || t < bestTime) {
        best = w.setting;
        bestTime = t;
        bestErr = w.err;
      }
    }
  }
  if (!plotDir.empty()) {  // the accuracy-versus-time picture, one curve per setting
    std::filesystem::create_directories(plotDir);
    std::ostringstream d, g;
    std::string plot;
    int index = 0;
    for (const auto& [label, lines] : curves) {
      d << "# " << label << "\n" << lines << "\n\n";
      plot += (plot.empty() ? "plot " : ", ") + std::string("'accuracy_vs_time.dat' index ") + std::to_string(index++) +
              " using 1:2 with linespoints title " + lg::gnuplotQuoted(label);
    }
    g << "set terminal pngcairo size 900,600 noenhanced\nset output 'accuracy_vs_time.png'\nset logscale xy\n"
         "set format y \"%g\"\nset format x \"%g\"\nset xlabel 'time per drop [ms]'\nset ylabel 'peak-load error [%]'\n"
         "set title "
      << lg::gnuplotQuoted(base.name + ", case " + drop.name + ": accuracy versus time (one core)")
      << "\nset grid\nset key outside right\n" << plot << "\n";
    std::string why;
    try {
      lg::writeFileAtomic(plotDir + "/accuracy_vs_time.dat", d.str());
      lg::writeFileAtomic(plotDir + "/accuracy_vs_time.gp", g.str());
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      return lg::cli::kFailed;
    }
    const bool drawn = lg::runGnuplot(plotDir, "accuracy_vs_time", &why);
    std::printf("# plot: %s/accuracy_vs_time.png%s\n", plotDir.c_str(),
                drawn ? "" : (" (not drawn: " + why + "; data and script written)").c_str());
  }
  // Stage profiles: the scene's own setting, and the fastest at 0.1 %.
  for (int which = 0; which < 2; ++which) {
    if (which == 1 && !best) break;
    lg::Scene sc = which == 0 ? base : configured(base, *best);
    sc.model.settings.profile = true;
    const lg::Model<double> m = lg::caseModel(sc, drop);
    lg::State<double> s = lg::caseState(sc, m, drop);
    lg::Workspace<double> w(m);
    const auto a = std::chrono::steady_clock::now();
    const lg::RunStatus st = lg::simulate(m, s, w, drop.duration);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
    std::printf("# stage profile, %s %s %.0e: %ld steps, %ld rhs, %ld projections, %ld events, %.3f ms (timers on, no observer)\n",
                which == 0 ? "the scene's setting," : "fastest at 0.1 %,", lg::integratorName(sc.model.settings.integrator).c_str(),
                sc.model.settings.rtol, st.steps, w.rhsEvaluations, st.projections, st.events, 1e3 * total);
    for (int k = 0; k < lg::kStageCount; ++k)
      std::printf("  %-16s %9.3f ms %8ld calls\n", lg::stageName(k), 1e3 * w.timer.seconds[k], w.timer.calls[k]);
  }
  if (!specialist.empty()) {
    std::string peak;
    const double ts = runSpecialist(specialist, drop.name, peak);
    if (ts > 0) {
      std::printf("# specialist (%s, DP5 rtol 1e-3), same run: %.1f us per drop (%s); ours at 0.1 %%: %.0f times that\n",
                  specialist.c_str(), 1e6 * ts, peak.c_str(), best ? bestTime / ts : 0.0);
      // Paired rounds: the fastest setting at 0.1 % and the specialist one after the other, five times, so
      // that each ratio is taken while the machine runs at one speed (on a shared machine the times of one
      // program move by half from minute to minute, the ratio much less).
      if (best) {
        const lg::Scene sc = configured(base, *best);
        std::vector<double> ours, theirs, ratios;
        for (int r = 0; r < kPairedRounds; ++r) {
          lg::CaseMetrics m;
          ours.push_back(timeCase(sc, drop, 9, m));
          theirs.push_back(runSpecialist(specialist, drop.name, peak));
          if (theirs.back() > 0) ratios.push_back(ours.back() / theirs.back());
          std::printf("#   round %d: ours %.3f ms, specialist %.1f us, ratio %.1f\n", r + 1, 1e3 * ours.back(),
                      1e6 * theirs.back(), theirs.back() > 0 ? ours.back() / theirs.back() : 0.0);
        }
        if (!ratios.empty())
          std::printf("# paired rounds: ours %.3f ms, specialist %.1f us, ratio %.1f (medians of %d rounds)\n",
                      1e3 * median(ours), 1e6 * median(theirs), median(ratios), kPairedRounds);
      }
    } else {
      std::printf("# specialist %s: no time/run in its output\n", specialist.c_str());
    }
  }
  if (best)
    std::printf("target 0.1 %%: %.3f ms (%s rtol %g%s, error %.3f %%)\n", 1e3 * bestTime,
                lg::integratorName(best->integrator).c_str(), best->tol, best->maxStep > 0 ? ", max step 0.05 s" : "", bestErr);
  else
    std::printf("target 0.1 %%: not reached by any setting\n");
  return 0;
}
