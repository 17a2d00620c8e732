// The strut at rest and its servicing chart (sim/drop/servicing.cpp): the static air curve against the
// closed-form polytropic law, the gear's kinematic ratio and static stroke at 1 g by hand on the
// telescopic gear (a vertical strut: r = 1), the compression ratios, and the chart at each ambient
// temperature with its tolerance band.
#include "tests/sim/scene_support.hpp"  // sim headers, then Catch (see there)
#include "docs_support.hpp"   // docsText: README.md and docs/

#include "sim/drop/servicing.hpp"

namespace {

const lg::ShockAbsorber<double>& firstStrut(const lg::Scene& sc) {
  return std::get<lg::ShockAbsorber<double>>(sc.model.forces[sc.roles.struts.at(0)].type);
}

}  // namespace

TEST_CASE("servicing: the static air curve is the closed-form polytropic law at n_s", "[servicing]") {
  for (double ns : {1.0, 1.3}) {
    INFO("n_s = " << ns);
    toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
    doc["envelope"].as_table()->insert_or_assign("static_exponent", ns);
    const lg::Scene sc = lgtest::build(doc);
    const lg::ServicingCurve c = lg::servicingCurve(sc, 4050.0);
    REQUIRE(c.ok);
    const auto& a = firstStrut(sc);
    const double F = M_PI * 0.1 * 0.1 / 4;
    REQUIRE(c.stroke.size() == 101);
    CHECK(c.stroke.back() == Approx(0.16).epsilon(1e-14));
    for (size_t i = 0; i < c.stroke.size(); ++i) {
      const double p = 3.0e6 / std::pow(1 - c.stroke[i] * F / 1.3e-3, ns);
      CHECK(c.pressure[i] == Approx(p).epsilon(1e-13));
      CHECK(c.force[i] == Approx((p - a.pAtm) * F).epsilon(1e-13));
    }
    // the static point: P_a = W g r there, and the volume ratios by hand
    CHECK(c.staticForce == Approx(4050.0 * 9.80665 * c.staticRatio).epsilon(1e-9));
    const double Vs = 1.3e-3 - c.staticStroke * F;
    CHECK(c.extendedToStatic == Approx(1.3e-3 / Vs).epsilon(1e-13));
    CHECK(c.staticToCompressed == Approx(Vs / (1.3e-3 - 0.16 * F)).epsilon(1e-13));
    // the chart: at each ambient temperature the charge scales with T / T_s, the band with +-5 %
    REQUIRE(c.chart.size() == 5);
    CHECK(c.chart.front().temperature == Approx(233.15).epsilon(1e-14));
    CHECK(c.chart[2].temperature == Approx(288.15).epsilon(1e-14));
    for (const auto& ch : c.chart)
      for (size_t i = 0; i < c.extension.size(); ++i) {
        const double p = 3.0e6 * ch.temperature / 288.15 / std::pow(1 - (0.16 - c.extension[i]) * F / 1.3e-3, ns);
        CHECK(ch.pressure[i] == Approx(p - a.pAtm).epsilon(1e-12));
        CHECK(ch.low[i] == Approx(0.95 * p - a.pAtm).epsilon(1e-12));
        CHECK(ch.high[i] == Approx(1.05 * p - a.pAtm).epsilon(1e-12));
      }
    CHECK(c.chart[2].staticExtension == Approx(0.16 - c.staticStroke).epsilon(1e-12));
    // colder gas, less pressure: the strut sits lower (less extension)
    for (size_t k = 1; k < c.chart.size(); ++k) CHECK(c.chart[k].staticExtension > c.chart[k - 1].staticExtension);
  }
}

TEST_CASE("servicing: the telescopic gear's ratio is 1 and its static stroke at 1 g is the hand's", "[servicing]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/telescopic_gear.toml"));
  const auto& a = firstStrut(sc);
  const double W = lg::caseMass(sc, lg::DropCase{});
  const lg::ServicingCurve c = lg::servicingCurve(sc, W);
  REQUIRE(c.ok);
  int measured = 0;
  for (double r : c.ratio)
    if (std::isfinite(r)) {
      CHECK(r == Approx(1.0).margin(1e-7));
      ++measured;
    }
  CHECK(measured > 50);
  // isothermal: (p01 / (1 - s F / Omega0) - p_atm) F = W g
  const double F = a.area();
  const double s = a.Omega0 / F * (1 - a.p01 * F / (W * 9.80665 + a.pAtm * F));
  CHECK(c.staticStroke == Approx(s).epsilon(1e-6));
  std::printf("servicing: telescopic gear, static stroke %.6f m at W = %.0f kg (by hand %.6f m)\n", c.staticStroke, W, s);
  REQUIRE(c.chart.size() == 1);  // no envelope: the service temperature only
}

// The docs' figures for the seed gear ("The servicing chart") are this computation's.
TEST_CASE("servicing: the seed gear's static point and chart as the docs give them", "[servicing][readme]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  const lg::ServicingCurve c = lg::servicingCurve(sc, 4050.0);
  REQUIRE(c.ok);
  char b[400];
  std::snprintf(b, sizeof b,
                "static stroke %.4f m of 0.16 m, P_a %.1f kN (r = %.2f), compression ratios %.2f and %.2f", c.staticStroke,
                c.staticForce / 1e3, c.staticRatio, c.extendedToStatic, c.staticToCompressed);
  const std::string readme = lgtest::docsText();  // README.md and docs/
  INFO(b);
  CHECK(readme.find(b) != std::string::npos);
  REQUIRE(c.chart.size() == 5);
  std::snprintf(b, sizeof b, "at 15 C the strut shows %.2f MPa\nat an extension of %.3f m", c.chart[2].staticPressure / 1e6,
                c.chart[2].staticExtension);
  std::string wanted = b;
  INFO(wanted);
  CHECK(readme.find(wanted) != std::string::npos);
  // the trailing link carries the ground load to the strut through a lever ratio between 2 and 3 there
  CHECK(c.staticRatio > 2.0);
  CHECK(c.staticRatio < 3.0);
}
