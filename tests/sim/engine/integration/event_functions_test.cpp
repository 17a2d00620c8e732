// Event triggering (sim/engine/integration/event_functions.hpp) and the touchdown horizon of the adaptive steps
// (sim/engine/integration/step_context.hpp).
#include "tests/sim/engine_support.hpp"  // sim headers, then Catch (see there)
#include "tests/sim/scene_support.hpp"

#include <cmath>

#include "sim/drop/accuracy.hpp"
#include "sim/engine/integration/step_context.hpp"

// A force event crosses when g changes sign, and a step that ends on g = 0 holds it (the next one, starting
// on 0, does not hold it again). A step landing on a tyre's touchdown to the bit (the touchdown horizon
// below ends the flight's steps there) missed it before: the event's time then carried no derivative, and the
// derivatives of a drop from a height on an elastic stop were 1.1e-4 off (tests/sim/drop/gradient_test.cpp).
TEST_CASE("events: a force event crosses on a sign change, and on a step that ends on zero", "[events]") {
  const lg::Scene sc = lgtest::build(lgtest::shippedDoc("data/telescopic_gear.toml"));
  const lg::Model<double>& m = sc.model;
  const lg::State<double>& s = sc.initial;
  const int e = m.nRows;  // the first force event
  CHECK(lg::eventTriggered(m, s, e, -1.0, 1.0));
  CHECK(lg::eventTriggered(m, s, e, 1.0, -1.0));
  CHECK(lg::eventTriggered(m, s, e, -1e-3, 0.0));
  CHECK(lg::eventTriggered(m, s, e, 1e-3, 0.0));
  CHECK_FALSE(lg::eventTriggered(m, s, e, 0.0, 1e-3));
  CHECK_FALSE(lg::eventTriggered(m, s, e, 0.0, -1e-3));
  CHECK_FALSE(lg::eventTriggered(m, s, e, -1.0, -1e-3));
}

// A drop from rest 0.3 m above the ground at the scene's rtol 1e-6: the flight's steps end on the touchdown
// (its parabola, delta + delta' tau + delta'' tau^2 / 2 = 0), so that no step integrates the contact's first
// instants with the flight's stages: the energy balance closes to 3e-7 (measured 1.4e-7; 9.5e-6 when the
// horizon was -delta/delta' and the last flight step crossed the touchdown by up to 1e-4 s), and the peak
// load agrees with a run at rtol 1e-10 to 1e-6 (measured 1.0e-7; 7.8e-6 before).
TEST_CASE("touchdown horizon: a drop from rest closes its energy balance at the scene's tolerance", "[events][drop_height]") {
  toml::table doc = lgtest::shippedDoc("data/telescopic_gear.toml");
  doc.insert_or_assign("case", toml::array{toml::table{{"name", "fall"}, {"drop_height", 0.3}, {"lift_ratio", 0.0}}});
  const lg::Scene sc = lgtest::build(doc);
  REQUIRE(sc.model.settings.rtol == 1e-6);
  const lg::CaseMetrics a = lg::runCase(sc, sc.cases[0]).metrics;
  const lg::CaseMetrics ref = lg::runCase(lg::withSolver(sc, lg::IntegratorKind::DormandPrince, 1e-10), sc.cases[0]).metrics;
  REQUIRE(a.ok);
  REQUIRE(ref.ok);
  lgtest::report("drop from rest at rtol 1e-6: %d steps, E_bal %.1e, peak %.4f N vs %.4f N (%.1e)", a.steps, a.energy_balance_error,
                 a.peak_load_N, ref.peak_load_N, a.peak_load_N / ref.peak_load_N - 1);
  CHECK(a.energy_balance_error < 3e-7);
  CHECK(std::abs(a.peak_load_N / ref.peak_load_N - 1) < 1e-6);
}
