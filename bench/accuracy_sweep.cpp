// accuracy_sweep [--threads N] [--worst K] [--accuracies A,B,...] [--gear FILE ...]: how `--accuracy` holds off the shipped
// cases. The seed, nose, telescopic, main and friction gears (the last two also at their forward speed, the
// friction gear with every friction on one slide; none of them calibrated the mapping but the seed gear), each as shipped and with one parameter changed (the main orifice f1 x 0.6
// and x 1.6, the gas pressure p01 x 0.5 and x 2, the tyre stiffness K x 0.5 and x 2 where the tyre
// declares K, the airframe's mass x 0.7, the strut friction mu 0 and 0.15), dropped at 1.5, 2.5 and
// 3.5 m/s with lift ratios 0 and 1 (the main gear also at its forward speed of 60 m/s: wheel spin-up and its
// drag load), at accuracies 1e-2, 1e-3 and 1e-4 (or those given), against dopri5 at rtol 1e-10: the
// largest relative error of the promised metrics over the accuracy, per run, the worst K of them, the
// cases run again (a flat peak, two close peaks) and the evaluations. Prints figures; never a test (about
// 25 s: the references dominate). Each run also shows its energy balance error over the accuracy (energy/A).
// Run from the project root.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "sim/drop/accuracy.hpp"
#include "sim/drop/run.hpp"
#include "sim/io/overrides.hpp"
#include "sim/io/scene.hpp"
#include "sim/scene/parameters.hpp"

namespace {

struct Gear {
  const char* scene;
  const char* strut;         // the shock absorber's name
  const char* tyre;          // the tyre's name, or nullptr where its K is not a scalar
  double forwardSpeed = 0;   // [m/s] > 0: each drop also at this forward speed (a tyre with mu_x: spin-up)
};

struct Variant {
  std::string name;
  std::vector<lg::ParameterOverride> sets;
};

double number(const lg::Scene& sc, const std::string& path) {
  return lg::parameterValue(sc, lg::resolveParameter(sc, path, "accuracy_sweep"));
}

std::vector<Variant> variants(const lg::Scene& sc, const Gear& g) {
  const std::string s = g.strut;
  std::vector<Variant> v{{"as shipped", {}}};
  auto scaled = [&](const std::string& path, double f, const std::string& label) {
    v.push_back({label, {{path, number(sc, path) * f}}});
  };
  scaled(s + ".f1", 0.6, "f1 x 0.6");
  scaled(s + ".f1", 1.6, "f1 x 1.6");
  scaled(s + ".p01", 0.5, "p01 x 0.5");
  scaled(s + ".p01", 2.0, "p01 x 2");
  if (g.tyre) {
    scaled(std::string(g.tyre) + ".K", 0.5, "K x 0.5");
    scaled(std::string(g.tyre) + ".K", 2.0, "K x 2");
  }
  scaled("airframe.mass", 0.7, "mass x 0.7");
  v.push_back({"mu 0", {{s + ".mu", 0.0}}});
  v.push_back({"mu 0.15", {{s + ".mu", 0.15}}});
  return v;
}

struct Row {
  double ratio;  // worst error / accuracy
  std::string gear, variant, metric;
  double accuracy;
  std::string caseName, rerun;
  long evaluations;
  double energy;  // the run's energy balance error / accuracy
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"How --accuracy holds off the shipped cases: five gears, ten variants, six drops, three "
               "accuracies against dopri5 at rtol 1e-10 (run from the project root)"};
  lg::cli::addVersion(app, "accuracy_sweep");
  int threads = 0, worst = 20;
  std::vector<double> accuracies{1e-2, 1e-3, 1e-4};
  lg::cli::addThreads(app, threads, "the cases");
  lg::cli::addInteger(app, "--worst", worst, "runs listed, worst first (default 20)", 1, 100000);
  std::vector<std::string> only;
  app.add_option("--gear", only, "only this scene (repeatable; default: every gear)");
  app.add_option("--accuracies", accuracies, "accuracies to sweep (default 1e-2,1e-3,1e-4)")
      ->delimiter(',')
      ->check(CLI::Range(lg::kAccuracyMin, lg::kAccuracyMax));
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;
  const std::vector<Gear> gears{{"data/seed_gear.toml", "strut", "tyre"},
                                {"data/nose_gear.toml", "strut", "tyre"},
                                {"data/telescopic_gear.toml", "shock", "tyre"},
                                {"data/main_gear.toml", "strut", nullptr, 60.0},
                                {"data/friction_gear.toml", "shock", "tyre", 60.0}};
  auto casesOf = [](const Gear& g) {
    std::vector<lg::DropCase> cases;
    std::vector<double> forward{0.0};
    if (g.forwardSpeed > 0) forward.push_back(g.forwardSpeed);
    for (double Vx : forward) {
      for (double V : {1.5, 2.5, 3.5})
        for (double L : {0.0, 1.0}) {
          lg::DropCase c;
          char name[48];
          if (Vx > 0) std::snprintf(name, sizeof name, "V%g_L%g_Vx%g", V, L, Vx);
          else std::snprintf(name, sizeof name, "V%g_L%g", V, L);
          c.name = name;
          c.sinkSpeed = V;
          c.liftRatio = L;
          c.forwardSpeed = Vx;
          cases.push_back(c);
        }
    }
    return cases;
  };
  std::vector<Row> rows;
  std::vector<long> evaluations(accuracies.size(), 0);
  std::vector<int> reruns(accuracies.size(), 0), failed(accuracies.size(), 0);
  try {
    for (const Gear& g : gears) {
      if (!only.empty() && std::find(only.begin(), only.end(), std::string(g.scene)) == only.end()) continue;
      const lg::Scene base = lg::loadScene(g.scene);
      const std::vector<lg::DropCase> cases = casesOf(g);
      for (const Variant& v : variants(base, g)) {
        const lg::Scene sc = lg::applyOverrides(base, v.sets);
        const auto ref = lg::runCases(lg::withSolver(sc, lg::IntegratorKind::DormandPrince, 1e-10), cases, threads);
        for (size_t a = 0; a < accuracies.size(); ++a) {
          const auto res = lg::runCases(lg::withAccuracy(sc, accuracies[a]), cases, threads);
          for (size_t k = 0; k < cases.size(); ++k) {
            const lg::CaseMetrics &m = res[k].metrics, &r = ref[k].metrics;
            if (!m.ok || !r.ok) {
              ++failed[a];
              std::printf("failed: %s, %s, %s at %g: %s\n", g.scene, v.name.c_str(), cases[k].name.c_str(), accuracies[a],
                          (m.ok ? r.message : m.message).c_str());
              continue;
            }
            const lg::MetricErrors e = lg::metricErrors(m, r);
            const std::pair<double, const char*> all[] = {
                {e.peakLoad, "peak load"},   {e.tPeak, "t_peak"},         {e.stroke, "stroke"},
                {e.travel, "h_max"},         {e.tyreDeflection, "tyre"}, {e.efficiency, "efficiency"},
                {e.strutForce, "P_a,max"},   {e.dragPeak, "drag peak"}};
            const auto* w = std::max_element(std::begin(all), std::end(all));
            char rerun[32] = "";
            if (std::isfinite(m.accuracy_rerun)) std::snprintf(rerun, sizeof rerun, "%.3g", m.accuracy_rerun);
            rows.push_back({w->first / accuracies[a], g.scene, v.name, w->second, accuracies[a], cases[k].name, rerun,
                            m.rhs_evaluations, m.energy_balance_error / accuracies[a]});
            evaluations[a] += m.rhs_evaluations;
            reruns[a] += std::isfinite(m.accuracy_rerun) ? 1 : 0;
          }
        }
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s (run from the project root)\n", e.what());
    return 2;
  }
  std::stable_sort(rows.begin(), rows.end(), [](const Row& x, const Row& y) { return x.ratio > y.ratio; });
  std::printf("%zu runs; the worst %d (largest metric error over the accuracy):\n", rows.size(),
              std::min<int>(worst, static_cast<int>(rows.size())));
  std::printf("%8s  %-26s %-11s %-8s %-12s %-10s %-9s %-11s %s\n", "err/A", "scene", "variant", "accuracy", "case",
              "metric", "rerun at", "evaluations", "energy/A");
  for (int i = 0; i < worst && i < static_cast<int>(rows.size()); ++i) {
    const Row& r = rows[i];
    std::printf("%8.3f  %-26s %-11s %-8g %-12s %-10s %-9s %-11ld %.3g\n", r.ratio, r.gear.c_str(), r.variant.c_str(),
                r.accuracy, r.caseName.c_str(), r.metric.c_str(), r.rerun.empty() ? "-" : r.rerun.c_str(), r.evaluations,
                r.energy);
  }
  for (size_t a = 0; a < accuracies.size(); ++a)
    std::printf("accuracy %g: %ld evaluations, %d case(s) run again, %d failed\n", accuracies[a], evaluations[a],
                reruns[a], failed[a]);
  return 0;
}
