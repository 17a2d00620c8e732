// Accuracy versus time on the seed gear's limit case: time per simulation for each solver and
// integrator setting against its peak-load error (reference: the independent reduced-coordinate model
// at rtol 1e-10). Prints the data of an accuracy-versus-time plot; single thread.
// Usage: bench_drop [SCENE] [--plot DIR]   (--plot: DIR/accuracy_vs_time.{dat,gp,png} drawn by gnuplot)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "reference/reduced_seed_gear.hpp"
#include "sim/drop_test.hpp"

namespace {

struct Setting {
  std::string label;
  lg::MultiplierSolver solver;
  lg::IntegratorKind integrator;
  double tol;  // rtol (adaptive) or step (fixed)
};

double timeCase(const lg::Scene& sc, const lg::DropCase& c, int reps, lg::CaseMetrics& m) {
  std::vector<double> t;
  for (int i = 0; i < reps; ++i) {
    const auto a = std::chrono::steady_clock::now();
    m = lg::runCase(sc, c).metrics;
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  std::string scenePath = "data/seed_gear.toml", plotDir;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--plot" && i + 1 < argc) plotDir = argv[++i];
    else scenePath = a;
  }
  std::map<std::string, std::string> curves;  // setting -> "time err" lines
  lg::Scene base = lg::loadScene(scenePath);
  const lg::DropCase limit = *std::find_if(base.cases.begin(), base.cases.end(), [](auto& c) { return c.name == "limit"; });
  const ref::ReducedResult refr = ref::simulateSeedGear(ref::SeedGearParams{}, limit.sinkSpeed, limit.liftRatio, limit.duration, 1e-10);
  std::printf("# limit case (V = %.2f m/s, L = %.1f, %.1f s); reference peak P_y = %.3f N (reduced model, rtol 1e-10)\n",
              limit.sinkSpeed, limit.liftRatio, limit.duration, refr.peakLoad);
  std::printf("# %-30s %9s %8s %8s %12s %12s\n", "setting", "tol/step", "steps", "rhs", "time [ms]", "peak err [%]");
  std::vector<Setting> settings;
  for (double r : {1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8})
    settings.push_back({"dopri5 direct", lg::MultiplierSolver::Direct, lg::IntegratorKind::DormandPrince, r});
  for (double r : {1e-1, 1e-2, 1e-3, 1e-4})
    settings.push_back({"ros2 direct", lg::MultiplierSolver::Direct, lg::IntegratorKind::Ros2, r});
  for (double r : {1e-1, 3e-2, 1e-2, 3e-3, 2e-3, 1e-3, 1e-4, 1e-5})
    settings.push_back({"ros34pw2 direct", lg::MultiplierSolver::Direct, lg::IntegratorKind::Ros34pw2, r});
  for (double h : {1e-3, 5e-4, 2e-4, 1e-4})
    settings.push_back({"rk4 direct", lg::MultiplierSolver::Direct, lg::IntegratorKind::RK4, h});
  for (double h : {1e-4, 3e-5, 1e-5})
    settings.push_back({"euler direct", lg::MultiplierSolver::Direct, lg::IntegratorKind::SemiImplicitEuler, h});
  for (double r : {1e-3, 1e-5})
    settings.push_back({"dopri5 gauss-seidel", lg::MultiplierSolver::GaussSeidel, lg::IntegratorKind::DormandPrince, r});
  settings.push_back({"rk4 gauss-seidel", lg::MultiplierSolver::GaussSeidel, lg::IntegratorKind::RK4, 2e-4});
  for (const Setting& s : settings) {
    lg::Scene sc = base;
    auto& cfg = sc.model.settings;
    cfg.solver = s.solver;
    cfg.integrator = s.integrator;
    if (s.integrator == lg::IntegratorKind::DormandPrince || lg::isRosenbrock(s.integrator)) {
      cfg.rtol = s.tol;
      cfg.atol = s.tol * 1e-2;
    } else {
      cfg.step = s.tol;
    }
    lg::CaseMetrics m;
    const double t = timeCase(sc, limit, s.integrator == lg::IntegratorKind::SemiImplicitEuler ? 3 : 9, m);
    const double err = 100.0 * std::abs(m.peak_load_N - refr.peakLoad) / refr.peakLoad;
    std::printf("  %-30s %9.0e %8ld %8ld %12.3f %12.2e%s\n", s.label.c_str(), s.tol, m.steps, m.rhs_evaluations, 1e3 * t,
                err, m.ok ? "" : ("  FAILED: " + m.message).c_str());
    if (m.ok) curves[s.label] += std::to_string(1e3 * t) + " " + std::to_string(std::max(err, 1e-9)) + "\n";
  }
  if (!plotDir.empty()) {  // the accuracy-versus-time picture, one curve per setting
    std::filesystem::create_directories(plotDir);
    const std::string dat = plotDir + "/accuracy_vs_time.dat", gp = plotDir + "/accuracy_vs_time.gp";
    std::ofstream d(dat), g(gp);
    std::string plot;
    int index = 0;
    for (const auto& [label, lines] : curves) {
      d << "# " << label << "\n" << lines << "\n\n";
      plot += (plot.empty() ? "plot " : ", ") + std::string("'accuracy_vs_time.dat' index ") + std::to_string(index++) +
              " using 1:2 with linespoints title '" + label + "'";
    }
    g << "set terminal pngcairo size 900,600\nset output 'accuracy_vs_time.png'\nset logscale xy\nset format y \"%g\"\nset format x \"%g\"\n"
         "set xlabel 'time per limit-case simulation [ms]'\nset ylabel 'peak-load error [%]'\n"
         "set title 'Seed gear, limit case: accuracy versus time (one core)'\nset grid\nset key outside right\n"
      << plot << "\n";
    g.close();
    d.close();
    const std::string cmd = "cd '" + plotDir + "' && gnuplot accuracy_vs_time.gp 2>/dev/null";
    std::printf("# plot: %s/accuracy_vs_time.png%s\n", plotDir.c_str(),
                std::system(cmd.c_str()) == 0 ? "" : " (gnuplot failed or missing: data and script written)");
  }
  // Stage profiles: the default setting, and the cheapest setting that reaches 0.1 %.
  for (int which = 0; which < 2; ++which) {
    lg::Scene sc = base;
    sc.model.settings.profile = true;
    if (which == 1) {
      sc.model.settings.integrator = lg::IntegratorKind::Ros34pw2;
      sc.model.settings.rtol = 3e-3;
      sc.model.settings.atol = 3e-5;
    }
    const lg::Model<double> m = lg::caseModel(sc, limit);
    lg::State<double> s = lg::caseState(sc, m, limit);
    lg::Workspace<double> w(m);
    const auto a = std::chrono::steady_clock::now();
    lg::RunStatus st = lg::simulate(m, s, w, limit.duration);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
    std::printf("# stage profile, %s (rtol %.0e): %ld steps, %ld rhs, %.3f ms (timers on)\n",
                which == 0 ? "default settings, dopri5" : "ros34pw2", sc.model.settings.rtol, st.steps, w.rhsEvaluations, 1e3 * total);
    for (int k = 0; k < lg::kStageCount; ++k)
      std::printf("  %-16s %9.3f ms %8ld calls\n", lg::stageName(k), 1e3 * w.timer.seconds[k], w.timer.calls[k]);
  }
  return 0;
}
