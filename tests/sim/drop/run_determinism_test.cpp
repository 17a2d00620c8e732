// Determinism of the drop-test layer (sim/drop/run.cpp): the same case twice gives the same bits, and
// running the cases on 1 or 2 threads gives the same bits as well (no shared mutable state, no
// reduction whose order depends on the schedule).
#include <cstring>

#include "sim/drop/run.hpp"
#include "tests/sim/engine_support.hpp"  // includes Catch after the sim headers (see there)

namespace {

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// Every figure of a case's result except the wall time, compared bit for bit. Returns the first
// difference, or "" if none.
std::string difference(const lg::CaseResult& a, const lg::CaseResult& b) {
  const lg::CaseMetrics &x = a.metrics, &y = b.metrics;
  const std::pair<const char*, std::pair<double, double>> figures[] = {
      {"peak_load_N", {x.peak_load_N, y.peak_load_N}},
      {"t_peak_s", {x.t_peak_s, y.t_peak_s}},
      {"load_factor", {x.load_factor, y.load_factor}},
      {"stroke_max_m", {x.stroke_max_m, y.stroke_max_m}},
      {"h_max_m", {x.h_max_m, y.h_max_m}},
      {"tyre_deflection_max_m", {x.tyre_deflection_max_m, y.tyre_deflection_max_m}},
      {"efficiency", {x.efficiency, y.efficiency}},
      {"strut_efficiency", {x.strut_efficiency, y.strut_efficiency}},
      {"energy_absorbed_J", {x.energy_absorbed_J, y.energy_absorbed_J}},
      {"energy_dissipated_J", {x.energy_dissipated_J, y.energy_dissipated_J}},
      {"energy_to_absorb_J", {x.energy_to_absorb_J, y.energy_to_absorb_J}},
      {"stroke_margin_m", {x.stroke_margin_m, y.stroke_margin_m}},
      {"tyre_margin_m", {x.tyre_margin_m, y.tyre_margin_m}},
      {"energy_balance_error", {x.energy_balance_error, y.energy_balance_error}},
      {"constraint_violation_max", {x.constraint_violation_max, y.constraint_violation_max}},
      {"strut_force_max_N", {x.strut_force_max_N, y.strut_force_max_N}},
      {"rebound_velocity_mps", {x.rebound_velocity_mps, y.rebound_velocity_mps}}};
  for (const auto& [name, v] : figures)
    if (!same(v.first, v.second)) return std::string("metric ") + name;
  if (x.name != y.name || x.ok != y.ok || x.message != y.message || x.bottomed != y.bottomed || x.steps != y.steps ||
      x.rhs_evaluations != y.rhs_evaluations)
    return "status, steps or evaluations";
  if (a.samples.size() != b.samples.size()) return "number of samples";
  for (size_t i = 0; i < a.samples.size(); ++i) {
    const lg::Sample &p = a.samples[i], &q = b.samples[i];
    if (!same(p.t, q.t) || p.values.size() != q.values.size()) return "sample " + std::to_string(i);
    for (size_t k = 0; k < p.values.size(); ++k)
      if (!same(p.values[k], q.values[k])) return "sample " + std::to_string(i) + " column " + a.columns[k].name;
  }
  return "";
}

}  // namespace

TEST_CASE("the seed gear limit case is bitwise reproducible", "[drop][determinism]") {
  const lg::Scene sc = lg::loadScene(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml");
  lg::CaseOptions opt;
  opt.record = true;
  const lg::CaseResult a = lg::runCase(sc, sc.cases[2], opt);
  const lg::CaseResult b = lg::runCase(sc, sc.cases[2], opt);
  REQUIRE(a.metrics.ok);
  REQUIRE(a.samples.size() > 100);
  lgtest::report("limit case: %ld steps, %zu samples, peak load %.6f N", a.metrics.steps, a.samples.size(),
                 a.metrics.peak_load_N);
  CHECK(difference(a, b) == "");
}

TEST_CASE("runCases on 1 and 2 threads gives bitwise-identical results", "[drop][determinism]") {
  const lg::Scene sc = lg::loadScene(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml");
  lg::CaseOptions opt;
  opt.record = true;
  const auto one = lg::runCases(sc, sc.cases, 1, opt);
  const auto two = lg::runCases(sc, sc.cases, 2, opt);
  REQUIRE(one.size() == sc.cases.size());
  REQUIRE(two.size() == sc.cases.size());
  for (size_t i = 0; i < one.size(); ++i) {
    INFO("case " << sc.cases[i].name);
    CHECK(one[i].metrics.ok);
    CHECK(difference(one[i], two[i]) == "");
  }
  // The comparison can fail: two different cases differ.
  CHECK(difference(one[0], one[1]) != "");
}
