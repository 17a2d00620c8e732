// Exact derivatives of drop-test metrics (sim/drop/gradient.cpp) against central finite differences of
// the double runs, for each kind of parameter (orifice area, gas pressure and volume, polytropic
// exponent, tyre stiffness, a mass, the sink speed, the lift ratio, a stop length) on the seed gear's
// light, limit, reserve and free-drop cases and on the telescopic gear; an event whose time moves with
// the design; the kink flags on designs built to sit on a kink; independence of the pass width.
//
// The reference: at dopri5 rtol 1e-10 both the Jet run and the differences approach the exact
// sensitivities, but a difference of two adaptive runs now and then carries a jump of the step
// sequence; the median of the central differences at relative steps 3e-3, 1e-3 and 3e-4 is immune
// to one such outlier. Errors are relative to max(|derivative|, the derivative of an elasticity of 1e-3,
// with the metric's typical size for one near 0), so that a metric that hardly depends on a parameter is
// not judged on its noise.
#include "tests/sim/scene_support.hpp"  // sim headers, then Catch (see there)

#include <algorithm>
#include <cstdio>
#include <string_view>

#include "sim/drop/accuracy.hpp"  // withSolver
#include "sim/drop/gradient.hpp"
#include "sim/scene/parameters.hpp"

namespace {

// The scene at rtol 1e-10, in space: central differences at relative steps of 1e-4 .. 3e-3 need metrics
// smooth between neighbouring designs, which the 3-D run's are to about 1e-12 here and the planar model's
// only to about 5e-10 (the adaptive steps' sequence; README: Planar models). The planar model's exact
// derivatives are checked against these below.
lg::Scene tightScene(toml::table doc) {
  doc = lgtest::spatialDoc(doc);
  doc.insert_or_assign("solver", toml::table{{"integrator", "dopri5"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  return lgtest::build(doc);
}

std::vector<double> metricsAt(const lg::Scene& sc, const lg::DropCase& c, const lg::Parameter& p, double v) {
  lg::Scene s = sc;
  REQUIRE_FALSE(lg::applyParameters(s, {p}, {v}));
  lg::DropCase d = c;  // a case parameter of this case moves its own field only
  if (p.kind == lg::Parameter::Kind::Case && s.cases[p.index].name == c.name)
    (p.key == "sink_speed" ? d.sinkSpeed : d.liftRatio) = v;
  const lg::CaseMetrics m = lg::runCase(s, d).metrics;
  REQUIRE(m.ok);
  std::vector<double> f;
  for (const auto& info : lg::gradientMetrics()) f.push_back(lg::metricValue(m, info.name));
  return f;
}

// The median of central differences of every gradient metric at three relative steps ('scale' sets the
// step of a parameter whose value is 0): 1e-3, 3e-4, 1e-4. A late metering-pin sample bends the peak strut
// force enough that a step of 3e-3 is 5e-3 off (the differences converge to the exact derivative as the
// step shrinks: 2.4391e7, 2.4504e7, 2.45214e7, 2.45230e7, 2.452315e7 at 3e-3 .. 3e-5, exact 2.452313e7).
// The time of the peak is smooth in the design to its Newton step's round-off (drop_observer.hpp,
// correctPeakTime): located on values alone, to about 1e-9 s, its differences were 1e-3 off at a step of
// 1e-3 and needed larger steps and a looser bound.
std::vector<double> referenceDerivatives(const lg::Scene& sc, const lg::DropCase& c, const lg::Parameter& p, double scale) {
  const double x = lg::parameterValue(sc, p), base = std::max(std::abs(x), scale);
  const double steps[3] = {1e-3, 3e-4, 1e-4};
  std::vector<std::vector<double>> est;
  for (double h : steps) {
    const auto a = metricsAt(sc, c, p, x + h * base), b = metricsAt(sc, c, p, x - h * base);
    std::vector<double> d(a.size());
    for (size_t i = 0; i < a.size(); ++i) d[i] = (a[i] - b[i]) / (2 * h * base);
    est.push_back(d);
  }
  std::vector<double> out(est[0].size());
  for (size_t i = 0; i < out.size(); ++i) {
    std::vector<double> v{est[0][i], est[1][i], est[2][i]};
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
      const double floor = 1e-3 * std::max(std::abs(md.value), lg::findMetric(md.metric)->scale) / std::max(std::abs(x), scale);
      const double err = std::abs(md.d[j] - fd[i]) / std::max({std::abs(fd[i]), floor, 1e-300});
      INFO(label << ": d " << md.metric << " / d " << ps[j].path << " exact " << md.d[j] << " differences " << fd[i]);
      CHECK(err <= 1e-4);
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

// The shipped planar model's exact derivatives against the same scene's in space (both exact, of two runs
// whose steps differ): every metric a smooth derivative, each parameter kind, two cases.
TEST_CASE("gradient: a planar model's exact derivatives are those of its scene in space", "[gradient][planar]") {
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  doc.insert_or_assign("solver", toml::table{{"integrator", "dopri5"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  const lg::Scene planar = lgtest::build(doc), space = tightScene(doc);
  REQUIRE(planar.model.settings.planar());
  REQUIRE_FALSE(space.model.settings.planar());
  const std::vector<std::string> model{"strut.f1", "strut.p01", "strut.Omega0", "strut.n", "tyre.K", "airframe.mass"};
  double worst = 0;
  int compared = 0;
  for (const char* name : {"light", "limit"}) {
    std::vector<std::string> paths = model;
    paths.push_back(std::string(name) + ".sink_speed");
    std::vector<lg::Parameter> pp, ps;
    for (const auto& path : paths) {
      pp.push_back(lg::resolveParameter(planar, path));
      ps.push_back(lg::resolveParameter(space, path));
    }
    const lg::CaseGradient a = lg::caseGradient(planar, lgtest::findCase(planar, name), pp);
    const lg::CaseGradient b = lg::caseGradient(space, lgtest::findCase(space, name), ps);
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    REQUIRE(a.metrics.size() == b.metrics.size());
    for (size_t i = 0; i < a.metrics.size(); ++i) {
      const auto &ma = a.metrics[i], &mb = b.metrics[i];
      if (std::isnan(ma.value) || !ma.smooth || !mb.smooth) continue;
      for (size_t j = 0; j < paths.size(); ++j) {
        const double x = lg::parameterValue(space, ps[j]);
        const double floor = 1e-3 * std::max(std::abs(mb.value), lg::findMetric(mb.metric)->scale) / std::max(std::abs(x), 1e-300);
        const double err = std::abs(ma.d[j] - mb.d[j]) / std::max({std::abs(mb.d[j]), floor, 1e-300});
        INFO(name << ": d " << ma.metric << " / d " << paths[j] << " planar " << ma.d[j] << " in space " << mb.d[j]);
        CHECK(err <= 1e-4);  // (measured 4.9e-5 over 182 derivatives)
        worst = std::max(worst, err);
        ++compared;
      }
    }
  }
  std::printf("gradient: %d derivatives of the planar seed gear within %.1e of the 3-D model's\n", compared, worst);
}

TEST_CASE("gradient: the telescopic gear against central differences", "[gradient]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/telescopic_gear.toml"));
  Tally tally;
  compare("telescopic limit", sc, lgtest::findCase(sc, "limit"),
          {"shock.f1", "shock.p01", "tyre.K", "airframe.mass", "limit.sink_speed"}, tally);
  std::printf("gradient: %d derivatives of the telescopic gear within %.1e (t_peak %.1e)\n", tally.compared, tally.worst,
              tally.worstPeakTime);
}

// The elastic extension stop (a pad, k 2e6 N/m, c 5e3 N s/m): the gear hangs on it at the release
// (sim/drop/hang.hpp), its overtravel moving with k, c's pad carries nothing at rest, and the gas preload; the
// derivatives pass through that fixed point and its projection. On the limit drop at contact and on a drop
// from 0.2 m (the fall's start moves with the hang too): 70 derivatives, measured within 4.4e-5.
TEST_CASE("gradient: the elastic extension stop and the hang on it against central differences", "[gradient][stop_pad]") {
  toml::table doc = lgtest::shippedDoc("data/telescopic_gear.toml");
  toml::table& stop = lgtest::element(doc, "stop", "extension");
  stop.insert_or_assign("stiffness", 2.0e6);
  stop.insert_or_assign("damping", 5.0e3);
  doc.insert_or_assign("case", toml::array{toml::table{{"name", "limit"}, {"sink_speed", 3.05}, {"lift_ratio", 1.0}},
                                           toml::table{{"name", "fall"}, {"drop_height", 0.2}, {"sink_speed", 1.0}, {"lift_ratio", 0.5}}});
  const lg::Scene sc = tightScene(doc);
  Tally tally;
  compare("pad limit", sc, lgtest::findCase(sc, "limit"), {"extension.stiffness", "extension.damping", "shock.p01"}, tally);
  // (On the fall the pad's damping moves the tyre margin by 4e-6 m over a 100 % change: below what the
  // differences resolve at rtol 1e-10, 1.04e-4 of the floor. Its stiffness and the preload are compared.)
  compare("pad fall", sc, lgtest::findCase(sc, "fall"), {"extension.stiffness", "shock.p01"}, tally);
  std::printf("gradient: %d derivatives of the gear on a pad within %.1e (t_peak %.1e)\n", tally.compared, tally.worst,
              tally.worstPeakTime);
}

// The two-stage gas spring (data/nose_gear.toml): the second chamber's precharge, volume and exponent
// through the engagement event (its time moves with them) on the limit and reserve drops, where the
// second stage engages. (The other parameter kinds are the seed gear's above: on this scene the early
// orifice peak's time moves so little with p01 that its differences, at the 1e-9 s the peak is located
// to, are no sharper than 5e-4.)
TEST_CASE("gradient: the nose gear's second gas chamber against central differences", "[gradient][gas_spring]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/nose_gear.toml"));
  Tally tally;
  for (const char* name : {"limit", "reserve"})
    compare(std::string("nose ") + name, sc, lgtest::findCase(sc, name), {"strut.p02", "strut.Omega02", "strut.n2"}, tally);
  std::printf("gradient: %d derivatives of the nose gear within %.1e (t_peak %.1e)\n", tally.compared, tally.worst,
              tally.worstPeakTime);
}

// Table values as parameters: samples of the metering pin f_1(s) (the interpolant carries their
// derivatives), early, mid and late in the stroke, on the limit and reserve drops.
TEST_CASE("gradient: the metering pin's samples against central differences", "[gradient][metering_pin]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/seed_gear_metering_pin.toml"));
  Tally tally;
  for (const char* name : {"limit", "reserve"})
    compare(std::string("metering pin ") + name, sc, lgtest::findCase(sc, name),
            {"strut.f1_table[2]", "strut.f1_table[8]", "strut.f1_table[16]", "strut.f1_table[24]"}, tally);
  CHECK(tally.compared > 80);
  std::printf("gradient: %d derivatives in the metering pin's samples within %.1e (t_peak %.1e)\n", tally.compared,
              tally.worst, tally.worstPeakTime);
}

// The samples of a check valve's extension table f_1e(s) (seed gear, inline table over the stroke):
// they act in the rebound only, so the rebound velocity and the energies carry their derivatives.
TEST_CASE("gradient: the extension table's samples against central differences", "[gradient][check_valve]") {
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  toml::table table{{"stroke", toml::array{0.0, 0.04, 0.08, 0.12, 0.16}}, {"area", toml::array{6.0e-5, 5.0e-5, 4.5e-5, 4.0e-5, 3.5e-5}}};
  lgtest::element(doc, "force", "strut").insert_or_assign("f1_extension_table", table);
  const lg::Scene sc = tightScene(doc);
  Tally tally;
  compare("extension table limit", sc, lgtest::findCase(sc, "limit"),
          {"strut.f1_extension_table[1]", "strut.f1_extension_table[2]", "strut.f1_extension_table[3]"}, tally);
  CHECK(tally.compared > 20);
  std::printf("gradient: %d derivatives in the extension table's samples within %.1e\n", tally.compared, tally.worst);
}

namespace {
// The interior local maxima of P_y(t) of a recorded run, in time order.
std::vector<double> loadHumps(const lg::Scene& sc, const lg::DropCase& c) {
  lg::CaseOptions o;
  o.record = true;
  const lg::CaseResult r = lg::runCase(sc, c, o);
  const int col = r.column("P_y");
  std::vector<double> humps;
  for (size_t i = 1; i + 1 < r.samples.size(); ++i) {
    const double a = r.samples[i - 1].values[col], b = r.samples[i].values[col], d = r.samples[i + 1].values[col];
    if (b > a && b >= d && b > 1000) humps.push_back(b);
  }
  return humps;
}
lg::Scene withValue(const lg::Scene& sc, const std::string& path, double v) {
  lg::Scene s = sc;
  REQUIRE_FALSE(lg::applyParameters(s, {lg::resolveParameter(sc, path)}, {v}));
  return s;
}
}  // namespace

// An event whose time moves with the design: the reserve drop onto the bottoming stop (a plastic
// impact). Were the event time's derivative dropped, the metrics after the impact would miss its
// motion; they agree with the differences.
TEST_CASE("gradient: through a plastic impact whose time moves with the design", "[gradient][events]") {
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  lgtest::element(doc, "force", "strut").insert_or_assign("Omega0", 1.6e-3);
  lgtest::element(doc, "force", "strut").insert_or_assign("p01", 1.0e6);
  const lg::Scene sc = tightScene(doc);
  lg::DropCase c = lgtest::findCase(sc, "reserve");
  c.liftRatio = 0;
  REQUIRE(lg::runCase(sc, c).metrics.bottomed);
  Tally tally;
  compare("bottoming reserve", sc, c, {"strut.f1", "strut.Omega0", "airframe.mass", "reserve.sink_speed"}, tally);
  CHECK(tally.compared > 30);
  std::printf("gradient: %d derivatives through the bottoming impact within %.1e (t_peak %.1e)\n", tally.compared,
              tally.worst, tally.worstPeakTime);
}

TEST_CASE("gradient: the kinks are named, with the side computed", "[gradient][kinks]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  const lg::Parameter f1 = lg::resolveParameter(sc, "strut.f1"), omega0 = lg::resolveParameter(sc, "strut.Omega0");
  SECTION("a strut that sticks before a metric is reached") {
    // regularised friction: the stick is the regularised law's, noted; exact Coulomb: an event, no note
    const lg::Scene reg = lgtest::build(lgtest::referenceDoc("data/seed_gear.toml"));
    const lg::CaseGradient g = lg::caseGradient(reg, lgtest::findCase(reg, "limit"), {f1});
    CHECK(g.find("peak_load")->smooth);  // reached at 0.059 s, before the strut comes to rest
    CHECK_FALSE(g.find("stroke")->smooth);
    CHECK(g.find("stroke")->note.rfind("a strut sticks from t = 0.19", 0) == 0);
    const lg::CaseGradient gc = lg::caseGradient(sc, lgtest::findCase(sc, "limit"), {f1});
    CHECK(gc.find("stroke")->smooth);
    CHECK(gc.find("stroke")->note.empty());
  }
  SECTION("bottoming begins at the design") {
    // The reserve drop's largest gas volume that keeps clear of the bottoming stop, by bisection.
    double lo = 1.3e-3, hi = 1.8e-3;
    REQUIRE_FALSE(lg::runCase(withValue(sc, "strut.Omega0", lo), lgtest::findCase(sc, "reserve")).metrics.bottomed);
    REQUIRE(lg::runCase(withValue(sc, "strut.Omega0", hi), lgtest::findCase(sc, "reserve")).metrics.bottomed);
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (lg::runCase(withValue(sc, "strut.Omega0", mid), lgtest::findCase(sc, "reserve")).metrics.bottomed ? hi : lo) = mid;
    }
    const lg::Scene edge = withValue(sc, "strut.Omega0", lo);
    const lg::CaseGradient g = lg::caseGradient(edge, lgtest::findCase(edge, "reserve"), {omega0});
    const auto* s = g.find("stroke");
    INFO(s->note);
    CHECK_FALSE(s->smooth);
    // The bisection ends within round-off of the edge, so the run may land on either side of it (the
    // derivative run's value part differs from the double run's in round-off): the note names the side.
    if (g.values.bottomed)
      CHECK(s->note.find("bottoming begins at this design; the derivative is the bottomed side's") != std::string::npos);
    else
      CHECK(s->note.find("short of its bottoming stop: bottoming begins near this design; the derivative is the side that "
                         "does not bottom") != std::string::npos);
    CHECK_FALSE(g.find("peak_load")->smooth);
  }
  SECTION("two maxima of P_y of equal height") {
    // The reserve drop's two humps (orifice first, gas spring later): the orifice area at which they are
    // equal, by bisection on their difference.
    const lg::DropCase& c = lgtest::findCase(sc, "reserve");
    auto gap = [&](double p) {
      const auto h = loadHumps(withValue(sc, "strut.f1", p), c);
      REQUIRE(h.size() >= 2);
      return h[0] - h[1];
    };
    double lo = 7e-5, hi = 1e-4;
    REQUIRE(gap(lo) > 0);
    REQUIRE(gap(hi) < 0);
    for (int i = 0; i < 40; ++i) {
      const double mid = 0.5 * (lo + hi);
      (gap(mid) > 0 ? lo : hi) = mid;
    }
    const lg::Scene equal = withValue(sc, "strut.f1", lo);
    const lg::CaseGradient g = lg::caseGradient(equal, lgtest::findCase(equal, "reserve"), {f1});
    const auto* peak = g.find("peak_load");
    INFO(peak->note);
    CHECK_FALSE(peak->smooth);
    CHECK(peak->note.rfind("two maxima of P_y within 0", 0) == 0);
    CHECK_FALSE(g.find("t_peak")->smooth);
    CHECK_FALSE(g.find("tyre_deflection")->smooth);  // one tyre: its largest deflection is the largest load
    // away from the kink the same metric is smooth
    CHECK(lg::caseGradient(sc, c, {f1}).find("peak_load")->smooth);
  }
}

// The Rosenbrock path in Jet: ros34pw2's stages, its W solves and its dense output (the velocities on
// the continuous extension, tableaus.hpp) carry the derivatives as dopri5's do. Every smooth metric of
// the seed gear's limit drop at ros34pw2 rtol 1e-7 against the same scene's exact derivatives at dopri5
// rtol 1e-10, with the floor of compare() above. Measured over 52 derivatives: worst 2.1e-5 (the strut
// efficiency in tyre.K), the time of the peak 7.7e-5 (in p01); at rtol 1e-6, P_a,max in f1 9.6e-5.
TEST_CASE("gradient: ros34pw2's exact derivatives agree with dopri5's at a tight tolerance", "[gradient][ros34pw2]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  const lg::DropCase& c = lgtest::findCase(sc, "limit");
  std::vector<lg::Parameter> ps;
  for (const char* path : {"strut.f1", "strut.p01", "tyre.K", "limit.sink_speed"}) ps.push_back(lg::resolveParameter(sc, path));
  const lg::CaseGradient ref = lg::caseGradient(lg::withSolver(sc, lg::IntegratorKind::DormandPrince, 1e-10), c, ps);
  const lg::CaseGradient ros = lg::caseGradient(lg::withSolver(sc, lg::IntegratorKind::Ros34pw2, 1e-7), c, ps);
  REQUIRE(ref.ok);
  REQUIRE(ros.ok);
  double worst = 0, worstPeakTime = 0;
  std::string where;
  int compared = 0;
  for (size_t i = 0; i < ref.metrics.size(); ++i) {
    const auto &a = ros.metrics[i], &r = ref.metrics[i];
    if (std::isnan(r.value) || !r.smooth || !a.smooth) continue;
    const bool peakTime = r.metric == "t_peak";  // (the most sensitive metric, as in compare())
    for (size_t j = 0; j < ps.size(); ++j) {
      const double x = lg::parameterValue(sc, ps[j]);
      const double floor = 1e-3 * std::max(std::abs(r.value), lg::findMetric(r.metric)->scale) / std::abs(x);
      const double err = std::abs(a.d[j] - r.d[j]) / std::max({std::abs(r.d[j]), floor, 1e-300});
      INFO(r.metric << " / " << ps[j].path << ": ros34pw2 " << a.d[j] << ", dopri5 " << r.d[j]);
      CHECK(err <= (peakTime ? 1.5e-4 : 4e-5));
      if (peakTime) {
        worstPeakTime = std::max(worstPeakTime, err);
      } else if (err > worst) {
        worst = err;
        where = r.metric + " / " + ps[j].path;
      }
      ++compared;
    }
  }
  std::printf("gradient: ros34pw2 at rtol 1e-7, %d derivatives within %.1e of dopri5's at 1e-10 (worst %s; t_peak %.1e)\n",
              compared, worst, where.c_str(), worstPeakTime);
  CHECK(compared >= 30);
}

TEST_CASE("gradient: the derivatives do not depend on the pass width", "[gradient]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  std::vector<lg::Parameter> ps;
  for (const char* path : {"strut.f1", "strut.p01", "tyre.K", "limit.sink_speed", "airframe.mass"})
    ps.push_back(lg::resolveParameter(sc, path));
  const lg::DropCase& c = lgtest::findCase(sc, "limit");
  const lg::CaseGradient g4 = lg::caseGradient(sc, c, ps, 4), g2 = lg::caseGradient(sc, c, ps, 2),
                         g1 = lg::caseGradient(sc, c, ps, 1);
  double worst = 0;
  for (size_t i = 0; i < g4.metrics.size(); ++i)
    for (size_t j = 0; j < ps.size() && !std::isnan(g4.metrics[i].value); ++j)  // (NaN: a metric the scene has not)
      for (const auto* g : {&g2, &g1}) {
        const double a = g4.metrics[i].d[j], b = g->metrics[i].d[j];
        worst = std::max(worst, std::abs(a - b) / std::max(std::abs(a), 1e-300));
        CHECK(g->metrics[i].value == g4.metrics[i].value);
      }
  std::printf("gradient: pass widths 1, 2, 4 agree to %.1e\n", worst);
  CHECK(worst <= 1e-12);
}

// ---- time histories at fixed times (the calibration's exact Jacobian) ----------------------------
namespace {

// The recorded rows of a double run at 'times' with parameter p at v.
std::vector<std::vector<double>> rowsAt(const lg::Scene& sc, const lg::DropCase& c, const lg::Parameter& p, double v,
                                        const std::vector<double>& times) {
  lg::Scene s = sc;
  REQUIRE_FALSE(lg::applyParameters(s, {p}, {v}));
  lg::DropCase d = c;
  if (p.kind == lg::Parameter::Kind::Case && s.cases[p.index].name == c.name)
    (p.key == "sink_speed" ? d.sinkSpeed : d.liftRatio) = v;
  lg::CaseOptions o;
  o.record = true;
  o.outputTimes = times;
  const lg::CaseResult r = lg::runCase(s, d, o);
  REQUIRE(r.metrics.ok);
  REQUIRE(r.samples.size() == times.size());
  std::vector<std::vector<double>> out;
  for (const auto& row : r.samples) out.push_back(row.values);
  return out;
}

}  // namespace

// Every column at 61 fixed times (t = 0 included) against the median of central differences of the
// double runs' rows at relative steps 1e-3, 3e-4 and 1e-4, each error relative to the column's largest derivative over the
// run (a value near a zero crossing is not judged on its own size); the rates in time against the
// model's own velocities (s against the strut's s_dot output, a state velocity, not a difference).
TEST_CASE("history gradient: time histories at fixed times against central differences, rates against s_dot",
          "[gradient][history]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/seed_gear.toml"));
  const lg::DropCase& c = lgtest::findCase(sc, "limit");
  std::vector<double> times;
  for (int k = 0; k <= 60; ++k) times.push_back(0.005 * k);
  std::vector<lg::Parameter> ps;
  for (const char* path : {"strut.f1", "strut.p01", "tyre.K", "limit.sink_speed", "airframe.mass"})
    ps.push_back(lg::resolveParameter(sc, path));
  const lg::HistoryGradient g = lg::caseHistoryGradient(sc, c, ps, times, true);
  REQUIRE(g.ok);
  REQUIRE(g.value.size() == times.size());
  const auto cols = lg::historyColumns(sc);
  const std::vector<std::vector<double>> base = rowsAt(sc, c, ps[0], lg::parameterValue(sc, ps[0]), times);
  double worstValue = 0, worst = 0;  // values relative to the column's largest over the run
  for (size_t k = 0; k + 1 < cols.size(); ++k) {  // the last column, the constraint violation, has no derivative
    double top = 0;
    for (size_t r = 0; r < times.size(); ++r) top = std::max(top, std::abs(base[r][k]));
    for (size_t r = 0; r < times.size(); ++r)
      if (top > 0) worstValue = std::max(worstValue, std::abs(g.value[r][k] - base[r][k]) / top);
  }
  int compared = 0;
  for (size_t j = 0; j < ps.size(); ++j) {
    const double x = lg::parameterValue(sc, ps[j]);
    std::vector<std::vector<std::vector<double>>> est;  // [step][row][column]
    for (double h : {1e-3, 3e-4, 1e-4}) {  // a history's second derivatives are larger than a metric's
      const auto a = rowsAt(sc, c, ps[j], x + h * x, times), b = rowsAt(sc, c, ps[j], x - h * x, times);
      std::vector<std::vector<double>> d(times.size(), std::vector<double>(cols.size()));
      for (size_t r = 0; r < times.size(); ++r)
        for (size_t k = 0; k < cols.size(); ++k) d[r][k] = (a[r][k] - b[r][k]) / (2 * h * x);
      est.push_back(d);
    }
    for (size_t k = 0; k + 1 < cols.size(); ++k) {
      // The column's scale: its largest derivative over the run, at least an elasticity of 1e-6 of its
      // largest value (a column the parameter does not reach is judged against that).
      double big = 0, top = 0;
      for (size_t r = 0; r < times.size(); ++r) {
        big = std::max(big, std::abs(g.d[r][k][j]));
        top = std::max(top, std::abs(g.value[r][k]));
      }
      big = std::max(big, 1e-6 * top / std::abs(x));
      if (big == 0) continue;  // a column that is 0 throughout (a stop that never acts)
      for (size_t r = 0; r < times.size(); ++r) {
        // Central differences converge as h^2 (the histories' curvature near the stick at s' = 0 is
        // large): Richardson's extrapolation of the two smaller steps, unless the median of the three
        // is closer (a jump of the step sequence in one of them).
        std::vector<double> v{est[0][r][k], est[1][r][k], est[2][r][k]};
        const double richardson = est[2][r][k] + (est[2][r][k] - est[1][r][k]) / 8;
        std::sort(v.begin(), v.end());
        const double ref = std::abs(g.d[r][k][j] - richardson) < std::abs(g.d[r][k][j] - v[1]) ? richardson : v[1];
        const double err = std::abs(g.d[r][k][j] - ref) / big;
        INFO(cols[k].name << " at t = " << times[r] << " d/d " << ps[j].path << ": exact " << g.d[r][k][j] << ", differences "
                          << ref << " (" << est[0][r][k] << ", " << est[1][r][k] << ", " << est[2][r][k] << ")");
        CHECK(err < 2e-6);
        worst = std::max(worst, err);
        ++compared;
      }
    }
  }
  // Rates: ds/dt along the dense output against the strut's s_dot, relative to the largest |s_dot|.
  int s = -1, sdot = -1;
  for (size_t k = 0; k < cols.size(); ++k) {
    if (cols[k].name == "s") s = static_cast<int>(k);
    if (cols[k].name == "s_dot") sdot = static_cast<int>(k);
  }
  REQUIRE(s >= 0);
  REQUIRE(sdot >= 0);
  double worstRate = 0, vmax = 0;
  for (size_t r = 1; r < times.size(); ++r) vmax = std::max(vmax, std::abs(g.value[r][sdot]));
  for (size_t r = 1; r < times.size(); ++r)
    worstRate = std::max(worstRate, std::abs(g.rate[r][s] - g.value[r][sdot]) / vmax);
  CHECK(g.rate[0][s] == 0);  // the row at t = 0 precedes the first step
  CHECK(worstRate < 1e-8);
  std::printf("history gradient: values to %.1e of the plain run, %d derivatives within %.1e of the differences, ds/dt "
              "within %.1e of s_dot\n", worstValue, compared, worst, worstRate);
  CHECK(worstValue < 5e-12);
}

// An output time exactly on the plastic impact onto the bottoming stop: the row is the left limit (before
// the jump), and so are its derivatives. The stroke there shows the difference: on the right side s
// stays at S_max (derivative 0 in f1), on the left s(t_e) = S_max - s'(t_e-) dt_e (its derivative
// -s'(t_e-) dt_e/df1, not 0). The reference is the one-sided difference with the step that moves the
// impact later (the perturbed runs are still before it at t_e), extrapolated to second order.
TEST_CASE("history gradient: an output time on an impact takes the left side, not the jump", "[gradient][history][events]") {
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  lgtest::element(doc, "force", "strut").insert_or_assign("Omega0", 1.6e-3);
  lgtest::element(doc, "force", "strut").insert_or_assign("p01", 1.0e6);
  const lg::Scene sc = tightScene(doc);
  lg::DropCase c = lgtest::findCase(sc, "reserve");
  c.liftRatio = 0;
  // The impact's time: the first step row with the stop's force.
  lg::CaseOptions o;
  o.record = true;
  const lg::CaseResult run = lg::runCase(sc, c, o);
  const int fb = run.column("F_bottoming"), s = run.column("s"), sdot = run.column("s_dot");
  REQUIRE(fb >= 0);
  double te = -1;
  for (const auto& row : run.samples)
    if (row.values[fb] != 0) {
      te = row.t;
      break;
    }
  REQUIRE(te > 0);
  const std::vector<double> times{0.5 * te, te};
  const lg::Parameter f1 = lg::resolveParameter(sc, "strut.f1");
  const lg::HistoryGradient g = lg::caseHistoryGradient(sc, c, {f1}, times, true);
  REQUIRE(g.ok);
  const double x = lg::parameterValue(sc, f1);
  // The impact's time moves with f1: find the direction that delays it.
  auto impactTime = [&](double v) {
    lg::Scene s2 = sc;
    REQUIRE_FALSE(lg::applyParameters(s2, {f1}, {v}));
    const lg::CaseResult r = lg::runCase(s2, c, o);
    for (const auto& row : r.samples)
      if (row.values[fb] != 0) return row.t;
    return -1.0;
  };
  const double h = 1e-4 * x;
  const double dir = impactTime(x + h) > te ? 1.0 : -1.0;
  REQUIRE(impactTime(x + dir * h) > te);
  REQUIRE(impactTime(x + 2 * dir * h) > te);
  const double y0 = rowsAt(sc, c, f1, x, times)[1][s], y1 = rowsAt(sc, c, f1, x + dir * h, times)[1][s],
               y2 = rowsAt(sc, c, f1, x + 2 * dir * h, times)[1][s];
  const double left = dir * (-3 * y0 + 4 * y1 - y2) / (2 * h);  // second-order one-sided
  const double rateLeft = g.value[1][sdot];
  std::printf("history gradient: on the impact at t = %.6f s, ds/df1 exact %.8g, left-side differences %.8g (%.1e; s' "
              "before the jump %.4g m/s, s at the row %.9f, the right side's derivative 0)\n", te, g.d[1][s][0], left,
              std::abs(g.d[1][s][0] - left) / std::abs(left), rateLeft, g.value[1][s]);
  CHECK(rateLeft > 0.1);  // the row is before the jump: the strut still moves
  CHECK(std::abs(g.d[1][s][0]) > 10);  // not the right side's 0
  CHECK(g.d[1][s][0] == Approx(left).epsilon(1e-6));
  CHECK(g.rate[1][s] == Approx(rateLeft).epsilon(1e-6));
}

// The peak drag load of wheel spin-up (data/main_gear.toml at 60 m/s) as a metric with its derivatives:
// against central differences in the tyre's friction coefficient and damping and the leg's fore-aft
// spring; a scene without a drag load has no such metric (NaN, never 0).
TEST_CASE("gradient: the peak drag of wheel spin-up against central differences", "[gradient][tyre]") {
  const lg::Scene sc = tightScene(lgtest::shippedDoc("data/main_gear.toml"));
  const lg::DropCase& c = lgtest::findCase(sc, "limit-spinup");
  std::vector<lg::Parameter> ps;
  for (const char* path : {"tyre.mu_x", "tyre.c", "fore_aft_spring.k"}) ps.push_back(lg::resolveParameter(sc, path));
  const lg::CaseGradient g = lg::caseGradient(sc, c, ps);
  REQUIRE(g.ok);
  const auto* drag = g.find("drag_peak");
  REQUIRE(drag);
  INFO(drag->note);
  CHECK(drag->value > 1e4);
  CHECK(drag->value == lg::metricValue(g.values, "drag_peak"));
  const auto metrics = lg::gradientMetrics();
  const size_t at = std::find_if(metrics.begin(), metrics.end(), [](const auto& m) { return m.name == "drag_peak"; }) -
                    metrics.begin();
  double worst = 0;
  for (size_t j = 0; j < ps.size(); ++j) {
    const double fd = referenceDerivatives(sc, c, ps[j], 0.0)[at];
    const double err = std::abs(drag->d[j] - fd) / std::abs(fd);
    INFO(ps[j].path << ": exact " << drag->d[j] << ", differences " << fd);
    CHECK(err < 2e-6);  // achieved 3.3e-7
    worst = std::max(worst, err);
  }
  std::printf("gradient: the peak drag's derivatives within %.1e of the differences\n", worst);
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  CHECK(std::isnan(lg::caseGradient(seed, lgtest::findCase(seed, "limit"), {lg::resolveParameter(seed, "tyre.K")})
                       .find("drag_peak")
                       ->value));
}

// At a corner of the servicing and temperature envelope (sim/scene/envelope.hpp): the design's parameters and
// the envelope's own quantities (temperature, charge, gas volume, orifice tolerance) against central
// differences, the scene's point at the seed gear's worst corner for the reserve drop's stroke; a case
// that carries the corner itself (certify, robust studies) gives the same derivatives, bit for bit.
TEST_CASE("gradient: at a corner of the envelope, design and envelope quantities against central differences",
          "[gradient][envelope]") {
  lg::Scene sc = tightScene(lgtest::shippedDoc("data/seed_gear.toml"));
  REQUIRE(sc.envelope.declared);
  const std::vector<lg::EnvelopeCorner> corners = sc.envelope.corners();
  const lg::EnvelopeCorner* cold = nullptr;
  for (const auto& c : corners)
    if (c.name == "cold-lowcharge-lowoil-largeorifice") cold = &c;
  REQUIRE(cold != nullptr);
  sc.envelope.point = cold->at;
  Tally tally;
  const lg::DropCase& reserve = lgtest::findCase(sc, "reserve");
  compare("seed reserve at " + cold->name, sc, reserve,
          {"strut.f1", "strut.p01", "strut.Omega0", "envelope.temperature_C", "envelope.charge", "envelope.gas_volume",
           "envelope.orifice"},
          tally);
  CHECK(tally.compared > 40);
  // the same corner carried by the case
  lg::Scene nominal = sc;
  nominal.envelope.point = nominal.envelope.nominal();
  lg::DropCase atCorner = reserve;
  atCorner.corner = *cold;
  std::vector<lg::Parameter> ps;
  for (const char* path : {"strut.f1", "envelope.temperature_C"}) ps.push_back(lg::resolveParameter(nominal, path));
  const lg::CaseGradient a = lg::caseGradient(sc, reserve, ps), b = lg::caseGradient(nominal, atCorner, ps);
  REQUIRE(a.ok);
  REQUIRE(b.ok);
  for (size_t i = 0; i < a.metrics.size(); ++i)
    for (size_t j = 0; j < ps.size(); ++j)
      if (!std::isnan(a.metrics[i].value)) CHECK(a.metrics[i].d[j] == b.metrics[i].d[j]);
  std::printf("gradient: %d derivatives at the envelope's corner %s within %.1e of the differences\n", tally.compared,
              cold->name.c_str(), tally.worst);
}
