// Exact derivatives of drop-test metrics (sim/drop_gradient.cpp) against central finite differences of
// the double runs, for each kind of parameter (orifice area, gas pressure and volume, polytropic
// exponent, tyre stiffness, a mass, the sink speed, the lift ratio, a stop length) on the seed gear's
// light, limit, reserve and free-drop cases and on the telescopic gear; an event whose time moves with
// the design; the kink flags on designs built to sit on a kink; independence of the pass width.
//
// The reference: at dopri5 rtol 1e-10 both the Jet run and the differences approach the exact
// sensitivities, but a difference of two adaptive runs now and then carries a jump of the step
// sequence; the median of the central differences at relative steps 3e-3, 1e-3 and 3e-4 is immune
// to one such outlier. Errors are relative to max(|derivative|, the derivative of an elasticity of 1e-3),
// so that a metric that hardly depends on a parameter is not judged on its noise.
#include "scene_support.hpp"  // sim headers, then Catch (see there)

#include <algorithm>
#include <cstdio>

#include "sim/drop_gradient.hpp"
#include "sim/parameters.hpp"

namespace {

lg::Scene tightScene(toml::table doc) {
  doc.insert_or_assign("solver", toml::table{{"integrator", "dopri5"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  return lgtest::build(doc);
}

std::vector<double> metricsAt(const lg::Scene& sc, const lg::DropCase& c, const lg::Parameter& p, double v) {
  lg::Scene s = sc;
  REQUIRE_FALSE(lg::applyParameters(s, {p}, {v}));
  lg::DropCase d = c;
  for (const auto& sc2 : s.cases)
    if (sc2.name == c.name) d = sc2;
  const lg::CaseMetrics m = lg::runCase(s, d).metrics;
  REQUIRE(m.ok);
  std::vector<double> f;
  for (const auto& info : lg::gradientMetrics()) f.push_back(lg::metricValue(m, info.name));
  return f;
}

// The median of central differences of every gradient metric at three steps ('scale' sets the step of a
// parameter whose value is 0).
std::vector<double> referenceDerivatives(const lg::Scene& sc, const lg::DropCase& c, const lg::Parameter& p, double scale) {
  const double x = lg::parameterValue(sc, p), base = std::max(std::abs(x), scale);
  std::vector<std::vector<double>> est;
  for (double h : {3e-3, 1e-3, 3e-4}) {
    const auto a = metricsAt(sc, c, p, x + h * base), b = metricsAt(sc, c, p, x - h * base);
    std::vector<double> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = (a[i] - b[i]) / (2 * h * base);
    est.push_back(d);
  }
  std::vector<double> out(est[0].size());
  for (size_t i = 0; i < out.size(); ++i) {
    std::vector<double> v;
    for (const auto& e : est) v.push_back(e[i]);
    std::sort(v.begin(), v.end());
    out[i] = v[1];
  }
  return out;
}

struct Tally {
  double worst = 0, worstPeakTime = 0;
  int compared = 0;
};

void compare(const std::string& label, const lg::Scene& sc, const lg::DropCase& c, const std::vector<std::string>& paths,
             Tally& tally) {
  std::vector<lg::Parameter> ps;
  for (const auto& path : paths) ps.push_back(lg::resolveParameter(sc, path));
  const lg::CaseGradient g = lg::caseGradient(sc, c, ps);
  REQUIRE(g.ok);
  for (size_t j = 0; j < ps.size(); ++j) {
    const double x = lg::parameterValue(sc, ps[j]);
    const double scale = ps[j].key == "lift_ratio" ? 1.0 : 0.0;
    const auto fd = referenceDerivatives(sc, c, ps[j], scale);
    for (size_t i = 0; i < g.metrics.size(); ++i) {
      const auto& md = g.metrics[i];
      if (std::isnan(md.value)) continue;  // a metric the scene has not (stroke_margin without a stop)
      // A kink at this design (two humps, bottoming's onset, L = 1 for the rebound's derivative in L):
      // one-sided, no central difference to compare with. The stick note speaks of the Coulomb limit, and
      // the differences are the same regularised model's: compared.
      const bool liftPlateau = md.note.find("lift equal to the weight") != std::string::npos;
      const bool stickOnly = md.note.rfind("a strut sticks", 0) == 0;
      if (!md.smooth && !stickOnly && !(liftPlateau && ps[j].key != "lift_ratio" &&
                                        md.note.find("two maxima") == std::string::npos &&
                                        md.note.find("bottoming") == std::string::npos))
        continue;
      const double floor = 1e-3 * std::abs(md.value) / std::max(std::abs(x), scale);
      const double err = std::abs(md.d[j] - fd[i]) / std::max({std::abs(fd[i]), floor, 1e-300});
      INFO(label << ": d " << md.metric << " / d " << ps[j].path << " exact " << md.d[j] << " differences " << fd[i]);
      CHECK(err <= (md.metric == "t_peak" ? 5e-4 : 1e-4));
      (md.metric == "t_peak" ? tally.worstPeakTime : tally.worst) =
          std::max(md.metric == "t_peak" ? tally.worstPeakTime : tally.worst, err);
      ++tally.compared;
    }
  }
}

}  // namespace

TEST_CASE("gradient: every metric against central differences, each parameter kind, four cases", "[gradient]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/seed_gear.toml"));
  Tally tally;
  const std::vector<std::string> model{"strut.f1", "strut.p01", "strut.Omega0", "strut.n", "tyre.K", "airframe.mass",
                                       "bottoming.min_distance"};
  for (const char* name : {"light", "limit", "reserve", "free-drop"}) {
    std::vector<std::string> paths = model;
    paths.push_back(std::string(name) + ".sink_speed");
    if (std::string(name) != "free-drop") paths.push_back(std::string(name) + ".lift_ratio");  // L = 0: a bound
    compare(std::string("seed ") + name, sc, lgtest::findCase(sc, name), paths, tally);
  }
  std::printf("gradient: %d derivatives of the seed gear within %.1e of the differences (t_peak %.1e)\n", tally.compared,
              tally.worst, tally.worstPeakTime);
}

TEST_CASE("gradient: the telescopic gear against central differences", "[gradient]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/telescopic_gear.toml"));
  Tally tally;
  compare("telescopic limit", sc, lgtest::findCase(sc, "limit"),
          {"shock.f1", "shock.p01", "tyre.K", "airframe.mass", "limit.sink_speed"}, tally);
  std::printf("gradient: %d derivatives of the telescopic gear within %.1e (t_peak %.1e)\n", tally.compared, tally.worst,
              tally.worstPeakTime);
}
