// Stiffness detection and the hand-over to ros34pw2 (sim/engine/integration/stiffness.hpp, Settings::stiffSwitchRtol).
#include "tests/sim/engine_support.hpp"  // sim headers, then Catch (see there)
#include "tests/sim/scene_support.hpp"

#include <cmath>

#include "sim/drop/accuracy.hpp"

namespace {

// One case of a scene at accuracy 1e-3, with the hand-over (a) and with dopri5 to the end (b), and their
// worst metric errors against dopri5 at rtol 1e-10.
struct WithAndWithout {
  lg::CaseMetrics a, b;
  double ea = 0, eb = 0;
};
WithAndWithout runWithAndWithout(const lg::Scene& sc, const lg::DropCase& c) {
  const auto ref = lg::runCase(lg::withSolver(sc, lg::IntegratorKind::DormandPrince, 1e-10), c).metrics;
  lg::Scene acc = sc;
  lg::applyAccuracy(acc.model.settings, 1e-3);
  lg::Scene alone = acc;
  alone.model.settings.stiffSwitchRtol = 0;  // dopri5 to the end
  WithAndWithout r{lg::runCase(acc, c).metrics, lg::runCase(alone, c).metrics};
  REQUIRE(ref.ok);
  REQUIRE(r.a.ok);
  REQUIRE(r.b.ok);
  r.ea = lg::metricErrors(r.a, ref).max();
  r.eb = lg::metricErrors(r.b, ref).max();
  return r;
}

}  // namespace

TEST_CASE("stiffness test: h rho of a linear step is h |lambda|, 15 steps at the bound mark it stiff and 6 below reset the count",
          "[stiffness]") {
  // On y' = lambda y, f(y1) - f(y*) = lambda (y1 - y*) exactly, whatever y1 and y*.
  const double lambda = -4.0e4, h = 1e-4;
  lg::VecX<double> y1(2), ys(2), f1(2), f6(2);
  y1 << 0.3, -1.2;
  ys << 0.1, 0.7;
  f1 = lambda * y1;
  f6 = lambda * ys;
  lg::StiffnessTest t;
  CHECK(std::abs(t.observe(h, y1, ys, f1, f6, 2) - h * std::abs(lambda)) < 1e-12);
  for (int k = 0; k < 13; ++k) t.observe(h, y1, ys, f1, f6, 2);
  CHECK_FALSE(t.stiff);  // 14 at the bound
  for (int k = 0; k < 5; ++k) t.observe(1e-6, y1, ys, f1, f6, 2);  // h rho = 0.04: 5 below do not reset
  t.observe(h, y1, ys, f1, f6, 2);
  CHECK(t.stiff);  // the 15th
  lg::StiffnessTest u;
  for (int k = 0; k < 14; ++k) u.observe(h, y1, ys, f1, f6, 2);
  for (int k = 0; k < 6; ++k) u.observe(1e-6, y1, ys, f1, f6, 2);  // 6 below: the count starts again
  for (int k = 0; k < 14; ++k) u.observe(h, y1, ys, f1, f6, 2);
  CHECK_FALSE(u.stiff);
}

TEST_CASE("accuracy 1e-3 on a stiff drop: dopri5 hands over to ros34pw2 and keeps the promise at a fifteenth of the work",
          "[stiffness][accuracy]") {
  // The main gear dropped at 2 m/s without forward speed: its tyre's longitudinal friction is regularised
  // over eps = kappa_0 * 1 m/s, a damper of mu_x P_t / eps (some 4e5 N s/m) on the wheel's contact point,
  // lambda about -4e4 1/s. dopri5 alone is held at its stability bound (steps of about 1e-4 s).
  lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/main_gear.toml"));
  lg::DropCase c = sc.cases.at(0);
  c.name = "no-forward-speed";
  c.forwardSpeed = 0;
  c.sinkSpeed = 2.0;
  const auto [a, b, ea, eb] = runWithAndWithout(sc, c);
  lgtest::report("stiff drop at accuracy 1e-3: switched at %.5f s, %ld evaluations (error %.2e); dopri5 alone %ld (%.2e)",
                 a.stiff_from_s, a.rhs_evaluations, ea, b.rhs_evaluations, eb);
  CHECK(a.stiff_switch);
  CHECK(std::isfinite(a.stiff_from_s));
  CHECK(a.stiff_from_s > 0.005);  // after touchdown, when the tyre's friction comes in
  CHECK(a.stiff_from_s < 0.02);
  CHECK(std::isnan(b.stiff_from_s));
  CHECK(a.rhs_evaluations * 10 < b.rhs_evaluations);
  CHECK(ea <= 1e-3);
  CHECK(eb <= 1e-3);
}

TEST_CASE("a drop that is not stiff is not switched: the accuracy setting's run equals dopri5's bit for bit",
          "[stiffness][accuracy]") {
  // The seed gear's free drop never reaches the bound. (Its drops with lift do, once the gear has come to
  // rest on its tyre after the rebound, at 0.40 .. 0.44 s: the settling strut's orifice damping; there the
  // hand-over saves 14 % of the evaluations, the compression's metrics already found by dopri5.)
  lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  lg::applyAccuracy(sc.model.settings, 1e-3);
  lg::Scene alone = sc;
  alone.model.settings.stiffSwitchRtol = 0;
  for (const char* name : {"free-drop"}) {
    const lg::DropCase& c = lgtest::findCase(sc, name);
    const auto a = lg::runCase(sc, c).metrics, b = lg::runCase(alone, c).metrics;
    INFO(name);
    CHECK(std::isnan(a.stiff_from_s));
    CHECK(a.steps == b.steps);
    CHECK(a.rhs_evaluations == b.rhs_evaluations);
    CHECK(a.peak_load_N == b.peak_load_N);
    CHECK(a.t_peak_s == b.t_peak_s);
    CHECK(a.stroke_max_m == b.stroke_max_m);
  }
}

TEST_CASE("the hand-over is a trial judged by cost: lost when ros34pw2's evaluations per second exceed dopri5's, "
          "retried only at 1.5 times the lost rate, kept when cheaper",
          "[stiffness]") {
  lg::StiffHandOver ho;
  double t = 0;
  long e = 0;
  auto dopri = [&](int steps, double h, int evalsPerStep) {
    for (int k = 0; k < steps; ++k) {
      t += h;
      e += evalsPerStep;
      ho.dopriStep(t, e);
    }
  };
  auto ros = [&](int steps, double h, int evalsPerStep) {
    bool lost = false;
    for (int k = 0; k < steps; ++k) {
      t += h;
      e += evalsPerStep;
      lost = ho.rosStep(t, e);
      if (lost) CHECK(k == steps - 1);  // decided on the 20th step, not before
    }
    return lost;
  };
  dopri(15, 2e-3, 6);
  CHECK_FALSE(ho.tryStiff(t, e, 2e-3));  // 15 steps seen: no window of 15 spans yet
  dopri(1, 2e-3, 6);                     // D = 6 / 2e-3 = 3000 1/s
  REQUIRE(ho.tryStiff(t, e, 2e-3));
  CHECK(ho.dopriRate == Approx(3000).epsilon(1e-12));
  CHECK(ho.hDopri == 2e-3);
  CHECK(ros(20, 1e-3, 4));  // R = 4000 1/s > D: lost
  CHECK(ho.lostRate == Approx(4000).epsilon(1e-12));
  CHECK_FALSE(ho.rosStep(t, e));  // no trial running any more
  dopri(16, 1e-3, 6);             // D = 6000 1/s = 1.5 R: not yet
  CHECK_FALSE(ho.tryStiff(t, e, 1e-3));
  dopri(16, 0.9e-3, 6);  // D = 6667 1/s > 1.5 R: tried again
  REQUIRE(ho.tryStiff(t, e, 0.9e-3));
  CHECK_FALSE(ros(20, 1e-3, 4));  // R = 4000 < D: kept
  CHECK_FALSE(ros(50, 1e-3, 40));  // and kept to the end, whatever it costs later
}

TEST_CASE("accuracy 1e-3 where the stiffness test fires but ros34pw2 costs more: the trial is handed back, "
          "the run costs about what dopri5 alone costs and keeps the promise",
          "[stiffness][accuracy]") {
  // The main gear's limit case with spin-up: dopri5 near 2.5 ms is at its stability bound from the
  // orifice damping, but ros34pw2 at rtol A/6 is held by accuracy near 1.1 ms: when it kept the run from
  // 0.12 s it cost 60 % more (2849 evaluations in 572 steps, against dopri5 alone's 1776 in 248).
  lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/main_gear.toml"));
  const lg::DropCase& c = lgtest::findCase(sc, "limit-spinup");
  const auto [a, b, ea, eb] = runWithAndWithout(sc, c);
  lgtest::report("limit-spinup at accuracy 1e-3: %d trial(s) handed back, %ld evaluations (error %.2e); dopri5 alone %ld (%.2e)",
                 a.stiff_handbacks, a.rhs_evaluations, ea, b.rhs_evaluations, eb);
  CHECK(a.stiff_handbacks >= 1);
  CHECK(std::isnan(a.stiff_from_s));              // dopri5 to the end
  CHECK(a.rhs_evaluations * 20 <= b.rhs_evaluations * 21);  // within 5 % (1825 against 1776: the trial's cost)
  CHECK(b.stiff_handbacks == 0);
  CHECK(ea <= 1e-3);
  CHECK(ea <= 2 * eb);  // the trial does not spoil the accuracy (1.65e-5 against 1.54e-5)
}
