// The metric catalogue (sim/drop/metrics.cpp): one declaration per metric. Each entry's field is the
// summary.json field that the results writer gives its value, and docs/metrics.md lists the same
// metrics, in the same order, with the same fields.
#include "tests/sim/scene_support.hpp"  // sim headers, then Catch (see there)
#include "docs_support.hpp"   // docsText: README.md and docs/

#include <map>
#include <regex>
#include <set>

#include "sim/drop/metrics.hpp"
#include "sim/io/results.hpp"

namespace {

// A case whose every number differs from every other, with a longitudinal tyre (the drag metrics exist).
lg::CaseMetrics distinctMetrics() {
  lg::CaseMetrics m;
  m.longitudinal = true;
  double v = 1.25;
  for (double* x : {&m.sink_speed_mps, &m.lift_ratio, &m.forward_speed_mps, &m.drag_peak_N, &m.t_drag_peak_s,
                    &m.springback_peak_N, &m.t_springback_s, &m.drag_at_peak_N, &m.mass_kg, &m.peak_load_N, &m.t_peak_s,
                    &m.t_peak_condition, &m.second_peak_gap, &m.t_second_peak_s, &m.load_factor, &m.inertia_load_factor,
                    &m.stroke_max_m, &m.stroke_margin_m, &m.h_max_m, &m.tyre_deflection_max_m, &m.tyre_margin_m,
                    &m.efficiency, &m.strut_efficiency, &m.strut_force_max_N, &m.energy_absorbed_J, &m.energy_to_absorb_J,
                    &m.energy_dissipated_J, &m.energy_balance_error, &m.constraint_violation_max, &m.rebound_velocity_mps})
    *x = (v += 1.0);
  return m;
}

// The "field": number pairs of a metrics JSON object (one per line, as the writer prints them).
std::map<std::string, double> jsonNumbers(const std::string& json) {
  std::map<std::string, double> out;
  const std::regex line("\"([a-zA-Z0-9_]+)\": (-?[0-9.eE+-]+),?\n");
  for (std::sregex_iterator it(json.begin(), json.end(), line), end; it != end; ++it)
    out[(*it)[1]] = std::stod((*it)[2]);
  return out;
}

}  // namespace

TEST_CASE("metric catalogue: every entry whole, names and fields unique", "[metrics]") {
  std::set<std::string> names, fields;
  for (const auto& info : lg::metricCatalogue()) {
    INFO(info.name);
    CHECK(std::string(info.name).size() > 0);
    CHECK(std::string(info.field).size() > 0);
    CHECK(std::string(info.description).size() > 10);
    CHECK(info.scale > 0);
    CHECK(info.least < info.most);
    REQUIRE(info.value != nullptr);
    CHECK(names.insert(info.name).second);
    CHECK(fields.insert(info.field).second);
    CHECK(lg::findMetric(info.name) == &info);
  }
  CHECK(names.size() == 18);
  CHECK(lg::findMetric("no_such_metric") == nullptr);
  CHECK(std::isnan(lg::metricValue(distinctMetrics(), "no_such_metric")));
}

TEST_CASE("metric catalogue: each metric's value is its field's in summary.json", "[metrics]") {
  const lg::CaseMetrics m = distinctMetrics();
  const auto json = jsonNumbers(lg::metricsJson(m));
  REQUIRE(json.size() > 20);
  for (const auto& info : lg::metricCatalogue()) {
    INFO(info.name << " (" << info.field << ")");
    REQUIRE(json.count(info.field) == 1);
    CHECK(lg::metricValue(m, info.name) == json.at(info.field));  // the same number, not a neighbour's
  }
  // Without a longitudinal tyre the drag metrics do not exist: NaN, never a stale number.
  lg::CaseMetrics plain = m;
  plain.longitudinal = false;
  for (const char* n : {"drag_peak", "springback_peak", "drag_at_peak", "drag_ratio"})
    CHECK(std::isnan(lg::metricValue(plain, n)));
  CHECK(lg::metricValue(plain, "peak_load") == m.peak_load_N);
}

TEST_CASE("metric catalogue: docs/metrics.md lists the same metrics in the same order with the same fields",
          "[metrics][docs]") {
  const std::string page = lgtest::readFile(lgtest::sourcePath("docs/metrics.md"));
  const std::regex row("\n\\| `([a-z_]+)` \\| `([a-zA-Z_]+)` \\|");
  std::vector<std::pair<std::string, std::string>> documented;
  for (std::sregex_iterator it(page.begin(), page.end(), row), end; it != end; ++it)
    documented.emplace_back((*it)[1], (*it)[2]);
  std::vector<std::pair<std::string, std::string>> declared;
  for (const auto& info : lg::metricCatalogue()) declared.emplace_back(info.name, info.field);
  CHECK(documented == declared);
}
