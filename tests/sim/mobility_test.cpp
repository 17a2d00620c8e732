// A body's prismatic or fixed joint to the ground, eliminated into the body's mobility (Model::finalize,
// BodyKin::invMassTimes) instead of being enforced by its rows: the same motion, with fewer rows.
#include "tests/sim/engine_support.hpp"  // sim headers, then Catch (see there)
#include "tests/sim/scene_support.hpp"

TEST_CASE("a guide to the ground eliminated into the body's mobility gives the motion of its rows",
          "[engine][mobility]") {
  for (const char* file : {"data/seed_gear.toml", "data/telescopic_gear.toml"}) {
    toml::table doc = lgtest::shippedDoc(file);
    doc["solver"].as_table()->insert_or_assign("rtol", 1e-9);
    doc["solver"].as_table()->insert_or_assign("atol", 1e-11);
    const lg::Scene eliminated = lgtest::build(doc);
    lg::Scene rows = eliminated;
    rows.model.settings.eliminateGroundJoints = false;
    rows.model.finalize();
    rows.initial = lg::State<double>(rows.model);
    rows.initial.y = eliminated.initial.y;
    INFO(file);
    CHECK(rows.model.nRows == eliminated.model.nRows + 5);  // the rig's prismatic joint
    const auto a = lg::runCase(eliminated, lgtest::findCase(eliminated, "limit")).metrics;
    const auto b = lg::runCase(rows, lgtest::findCase(rows, "limit")).metrics;
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    double worst = 0;
    for (auto [x, y] : {std::pair{a.peak_load_N, b.peak_load_N}, {a.stroke_max_m, b.stroke_max_m}, {a.h_max_m, b.h_max_m},
                        {a.tyre_deflection_max_m, b.tyre_deflection_max_m}, {a.efficiency, b.efficiency},
                        {a.energy_absorbed_J, b.energy_absorbed_J}})
      worst = std::max(worst, lgtest::relDiff(x, y));
    lgtest::report("%s: eliminated rig (%d rows) against its rows (%d rows): largest relative difference %.1e",
                   file, eliminated.model.nRows, rows.model.nRows, worst);
    // Measured 3e-11 (seed gear), 0 (telescopic gear): the two runs differ by round-off from the start (other
    // rows, other sums), which moves the located stick/slip events by about 1e-12 s.
    CHECK(worst < 1e-10);
    CHECK(a.energy_balance_error < 1e-6);
  }
}
