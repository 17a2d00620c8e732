// The shock-absorber element (sim/forces/shock_absorber.hpp): its law against method.md (through the
// reference's independent StrutLaw), the metering pin f_1(s) table and the atmospheric-pressure option.
#include "scene_support.hpp"  // sim headers, then Catch (see there)
#include <cstdio>

#include "reference/reduced_seed_gear.hpp"
#include "sim/io/overrides.hpp"
#include "sim/scene/parameters.hpp"
#include "reference/reduced_telescopic.hpp"

using lgtest::relDiff;

namespace {

// The strut's output channels of a scene at the initial positions with the rod (and wheel) moved by
// 'ds' along the (vertical) strut axis and moving at 'sdot' (telescopic gear: B moves up = compression).
struct StrutOut {
  double s, sdot, Pa;
};
StrutOut telescopicStrut(const lg::Scene& sc, double ds, double sdot) {
  const auto& m = sc.model;
  lg::State<double> st = sc.initial;
  const int N = m.nBodies();
  for (const char* b : {"rod", "wheel"}) {
    const int i = m.bodyIndex(b);
    st.y[7 * i + 1] += ds;
    st.y[7 * N + 6 * i + 1] = sdot;
  }
  lg::Workspace<double> w(m);
  lg::kinematics(m, st.y, w);
  const int f = sc.roles.struts.at(0);
  const auto& sa = std::get<lg::ShockAbsorber<double>>(m.forces[f].type);
  std::vector<double> out(sa.outputNames().size());
  sa.outputs(w.kins(), out.data());
  return {out[0], out[1], out[3]};
}

ref::StrutLaw telescopicLaw() {
  const ref::TelescopicParams p;
  return ref::TelescopicModel(p, 0, 0).strut();
}

}  // namespace

TEST_CASE("shock-absorber force follows method.md", "[shock_absorber]") {
  // With p_atm = 0 (the article) and with p_atm on: gas (p_1 - p_atm) F, friction mu (p_1 - p_atm) F sgn.
  const double pAtm = GENERATE(0.0, 101325.0);
  toml::table doc = lgtest::referenceDoc("data/telescopic_gear.toml");  // the law's regularised friction
  lgtest::element(doc, "force", "shock").insert_or_assign("p_atm", pAtm);
  const lg::Scene sc = lgtest::build(doc);
  ref::StrutLaw law = telescopicLaw();
  law.pAtm = pAtm;
  for (double s : {0.0, 0.03, 0.1, 0.19})
    for (double v : {-2.0, -0.01, -1e-4, 0.0, 1e-4, 1e-3, 0.5, 3.0}) {
      const StrutOut o = telescopicStrut(sc, s, v);
      INFO("p_atm = " << pAtm << ", s = " << s << ", sdot = " << v);
      CHECK(o.s == Approx(s).margin(1e-15));
      CHECK(o.sdot == Approx(v).margin(1e-15));
      CHECK(relDiff(o.Pa, law.force(s, v).Pa) < 1e-12);
    }
}

TEST_CASE("metering pin: a table f_1(s) drives the main orifice", "[shock_absorber][metering_pin]") {
  const lg::Scene pin = lg::loadScene(lgtest::sourcePath("data/seed_gear_metering_pin.toml"));
  const auto& sa = std::get<lg::ShockAbsorber<double>>(pin.model.forces[pin.roles.struts.at(0)].type);
  REQUIRE(sa.f1Table);
  // The table holds f_1(s) = 6e-5 + 2e-5 cos(pi s / 0.16) on a uniform grid from 0 to S_max.
  CHECK(sa.f1Table->xMin() == 0.0);
  CHECK(sa.f1Table->xMax() == Approx(0.16).epsilon(1e-12));
  for (size_t i = 0; i < sa.f1Table->xs().size(); ++i)
    CHECK(sa.mainOrifice(sa.f1Table->xs()[i]) == Approx(sa.f1Table->ys()[i]).epsilon(1e-12));
  double errInner = 0, errEnd = 0;
  for (double s = 0; s <= 0.16; s += 0.0013) {
    const double e = relDiff(sa.mainOrifice(s), 6e-5 + 2e-5 * std::cos(M_PI * s / 0.16));
    (s < 0.005 || s > 0.155 ? errEnd : errInner) = std::max(s < 0.005 || s > 0.155 ? errEnd : errInner, e);
  }
  std::printf("metering pin table vs its formula: max rel. error %.1e inside, %.1e in the end intervals\n", errInner, errEnd);
  // Catmull-Rom: third order inside; at the ends Ceres repeats the end sample, so the end slopes are
  // one-sided (the formula's are 0) and the first and last intervals are less accurate.
  CHECK(errInner < 2e-5);
  CHECK(errEnd < 5e-4);
  // The shipped variant is the seed gear with f1 replaced by the table, nothing else.
  {
    toml::table a = lgtest::shippedDoc("data/seed_gear.toml"), b = lgtest::shippedDoc("data/seed_gear_metering_pin.toml");
    lgtest::element(a, "force", "strut").erase("f1");
    lgtest::element(b, "force", "strut").erase("f1_table");
    a["scene"].as_table()->erase("name");
    b["scene"].as_table()->erase("name");
    CHECK(lg::toTomlString(a) == lg::toTomlString(b));
  }
  // Every case runs and closes its energy balance.
  const auto results = lg::runCases(pin, pin.cases, 2);
  for (const auto& r : results) {
    const auto& m = r.metrics;
    std::printf("metering pin %-10s peak %.1f N  s_max %.5f m  eta %.4f  eta_s %.4f  E_bal %.2e\n", m.name.c_str(),
                m.peak_load_N, m.stroke_max_m, m.efficiency, m.strut_efficiency, m.energy_balance_error);
    INFO(m.name << ": " << m.message);
    REQUIRE(m.ok);
    CHECK(m.energy_balance_error < 1e-3);
    CHECK(m.stroke_max_m < 0.16);
  }
}

TEST_CASE("metering pin: a constant table reproduces the constant orifice", "[shock_absorber][metering_pin]") {
  // The Catmull-Rom interpolant of constant data is that constant only up to rounding (its cubic
  // coefficients are sums like 2p - 5p + 4p - p), so the two runs differ from the first step at the
  // 1e-16 level. The adaptive step control amplifies such differences into a different step sequence
  // (its error estimate is a cancelling sum), and the two runs then differ by the integration error of
  // whatever depends on the discretisation (at the shipped rtol 1e-6: 2e-9 in the absorbed energy,
  // through the located tyre lift-off). With rtol 1e-9 every figure agrees to 1e-9 or better, except
  // the time of the peak: near a smooth maximum P(t) = P* - P''(t - t*)^2/2 values within rounding
  // (k ulp) cannot be told apart over |t - t*| < sqrt(2 k eps P*/P''), about 1e-9 s here (P*/P'' ~
  // (0.03 s)^2), so it is compared in absolute time, to 1e-8 s (steps are ~1e-4 s).
  lgtest::TempDir dir("pin");
  {
    std::string csv = "stroke,area\n";
    for (int i = 0; i <= 16; ++i) csv += std::to_string(0.01 * i) + ",7.0e-5\n";
    lgtest::writeFile(dir / "constant.csv", csv);
  }
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  doc["solver"].as_table()->insert_or_assign("rtol", 1e-9);
  doc["solver"].as_table()->insert_or_assign("atol", 1e-11);
  const lg::Scene constant = lgtest::build(doc);
  auto& strut = lgtest::element(doc, "force", "strut");
  strut.erase("f1");
  strut.insert_or_assign("f1_table", dir / "constant.csv");
  const lg::Scene table = lgtest::build(doc);
  REQUIRE(std::get<lg::ShockAbsorber<double>>(table.model.forces[table.roles.struts.at(0)].type).f1Table);
  for (const char* name : {"limit", "free-drop"}) {
    const auto a = lg::runCase(constant, lgtest::findCase(constant, name)).metrics;
    const auto b = lg::runCase(table, lgtest::findCase(table, name)).metrics;
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    double worst = 0;
    for (auto [x, y] : {std::pair{a.peak_load_N, b.peak_load_N}, {a.stroke_max_m, b.stroke_max_m}, {a.h_max_m, b.h_max_m},
                        {a.tyre_deflection_max_m, b.tyre_deflection_max_m}, {a.efficiency, b.efficiency},
                        {a.strut_efficiency, b.strut_efficiency}, {a.strut_force_max_N, b.strut_force_max_N},
                        {a.energy_absorbed_J, b.energy_absorbed_J}})
      worst = std::max(worst, relDiff(y, x));
    const double dt = std::abs(a.t_peak_s - b.t_peak_s);
    std::printf("constant table vs f1 = 7e-5 (rtol 1e-9), %-9s largest relative difference %.2e, |dt_peak| %.1e s\n", name,
                worst, dt);
    CHECK(worst < 1e-9);
    CHECK(dt < 1e-8);
  }
}

TEST_CASE("atmospheric pressure: off by default, changes the static force by p_atm F", "[shock_absorber][p_atm]") {
  const lg::Scene base = lgtest::build(lgtest::referenceDoc("data/telescopic_gear.toml"));
  CHECK(std::get<lg::ShockAbsorber<double>>(base.model.forces[base.roles.struts.at(0)].type).pAtm == 0.0);
  const double pAtm = 101325.0;
  toml::table doc = lgtest::referenceDoc("data/telescopic_gear.toml");
  lgtest::element(doc, "force", "shock").insert_or_assign("p_atm", pAtm);
  const lg::Scene atm = lgtest::build(doc);
  const ref::TelescopicParams p;
  const double F = M_PI * p.D * p.D / 4;
  for (double s : {0.0, 0.05, 0.15}) {
    const double diff = telescopicStrut(base, s, 0.0).Pa - telescopicStrut(atm, s, 0.0).Pa;
    INFO("s = " << s);
    CHECK(diff == Approx(pAtm * F).epsilon(1e-12));
  }
  // A drop with p_atm on still closes its energy balance and agrees with the reference.
  ref::TelescopicParams q = p;
  q.pAtm = pAtm;
  const auto c = lgtest::findCase(atm, "limit");
  const auto m = lg::runCase(atm, c).metrics;
  const auto r = ref::simulateTelescopic(q, c.sinkSpeed, c.liftRatio, c.duration);
  std::printf("p_atm %.0f Pa: peak %.1f N (reference %.1f N, rel. diff %.1e), s_max %.5f m, E_bal %.2e\n", pAtm,
              m.peak_load_N, r.peakLoad, relDiff(m.peak_load_N, r.peakLoad), m.stroke_max_m, m.energy_balance_error);
  REQUIRE(m.ok);
  CHECK(m.energy_balance_error < 1e-3);
  CHECK(relDiff(m.peak_load_N, r.peakLoad) < 5e-3);
  CHECK(relDiff(m.stroke_max_m, r.strokeMax) < 5e-3);
  CHECK(relDiff(m.h_max_m, r.hMax) < 5e-3);
  // Less gas force: a deeper stroke than without p_atm.
  CHECK(m.stroke_max_m > lg::runCase(base, lgtest::findCase(base, "limit")).metrics.stroke_max_m);
}

// The metering pin's samples as design parameters ("strut.f1_table[k]"): the interpolant in any scalar
// performs ceres::CubicInterpolator's operations (the same bits for doubles, so the shipped results
// are unchanged), a sample set as data runs the bits of the scene edited as text (--set inlines the
// table), an inline table is the CSV's, and the paths are checked.
TEST_CASE("metering pin: its samples are design parameters", "[shock_absorber][metering_pin][parameters]") {
  const lg::Scene pin = lg::loadScene(lgtest::sourcePath("data/seed_gear_metering_pin.toml"));
  const auto& sa = std::get<lg::ShockAbsorber<double>>(pin.model.forces[pin.roles.struts.at(0)].type);
  REQUIRE(sa.f1Table);
  REQUIRE(sa.f1Values.size() == 33);
  // (1) The scalar interpolant against Ceres's, bit for bit, over and beyond the table.
  int same = 0;
  for (double s = -0.02; s <= 0.19; s += 0.000173) {
    CHECK(lg::interpolate(*sa.f1Table, sa.f1Values, s) == (*sa.f1Table)(s));
    ++same;
  }
  CHECK(same > 1000);
  // (2) Paths, values and units.
  const lg::Parameter p = lg::resolveParameter(pin, "strut.f1_table[3]");
  CHECK(lg::parameterValue(pin, p) == sa.f1Table->ys()[3]);
  CHECK(lg::unitOfKey(p.key) == "m^2");
  for (const char* bad : {"strut.f1_table[33]", "strut.f1_table[-1]", "strut.f1_table[]", "strut.f1_table[x]", "strut.f1_table"}) {
    INFO(bad);
    CHECK_THROWS_AS(lg::resolveParameter(pin, bad), lg::InputError);
  }
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  CHECK_THROWS_WITH(lg::resolveParameter(seed, "strut.f1_table[0]"), Catch::Contains("no numeric design parameter 'f1_table[0]'"));
  // (3) A narrower pin at mid-stroke as data, and the same by --set (the table written inline): the same bits.
  const double narrow = 0.8 * sa.f1Values[16];
  lg::Scene asData = pin;
  REQUIRE_FALSE(lg::applyParameters(asData, {lg::resolveParameter(pin, "strut.f1_table[16]")}, {narrow}));
  const lg::Scene asText = lg::applyOverrides(pin, {{"strut.f1_table[16]", narrow}});
  const lg::DropCase& c = lgtest::findCase(pin, "limit");
  const lg::CaseMetrics a = lg::runCase(asData, c).metrics, b = lg::runCase(asText, c).metrics,
                        base = lg::runCase(pin, c).metrics;
  CHECK(a.peak_load_N == b.peak_load_N);
  CHECK(a.stroke_max_m == b.stroke_max_m);
  CHECK(a.energy_dissipated_J == b.energy_dissipated_J);
  CHECK(a.stroke_max_m != base.stroke_max_m);  // the sample acts (s = 0.08 m is passed after the peak load)
  // (4) An inline table with the CSV's numbers is the CSV's table, bit for bit.
  toml::table doc = lgtest::shippedDoc("data/seed_gear_metering_pin.toml");
  lg::inlineTables(doc, pin, {"strut.f1_table[0]"});
  REQUIRE(lgtest::element(doc, "force", "strut")["f1_table"].is_table());
  const lg::CaseMetrics inl = lg::runCase(lgtest::build(doc), c).metrics;
  CHECK(inl.peak_load_N == base.peak_load_N);
  CHECK(inl.stroke_max_m == base.stroke_max_m);
  CHECK(lg::getParameter(doc, "strut.f1_table[16]") == sa.f1Values[16]);
  // (5) A design with a sample <= 0 is rejected by the scene's rule, named by its key.
  lg::Scene bad = pin;
  const auto why = lg::applyParameters(bad, {lg::resolveParameter(pin, "strut.f1_table[5]")}, {-1e-6});
  REQUIRE(why);
  CHECK(why->find("f1_table[5]") != std::string::npos);
  CHECK(why->find("must be > 0") != std::string::npos);
}

TEST_CASE("metering pin: inline tables are checked like CSV tables", "[shock_absorber][metering_pin][scene]") {
  const std::string pin = lgtest::readFile(lgtest::sourcePath("data/seed_gear_metering_pin.toml"));
  auto with = [&](const std::string& table) {
    std::string t = pin;
    const std::string key = "f1_table = \"tables/metering_pin.csv\"";
    const auto at = t.find(key);
    REQUIRE(at != std::string::npos);
    return t.replace(at, key.size(), "f1_table = " + table);
  };
  const struct {
    std::string table, message;
  } cases[] = {
      {"{ stroke = [0.0, 0.1, 0.2], area = [1e-4, 1e-4, 1e-4] }", "the table has 3 rows: it needs at least 4 of (stroke, area)"},
      {"{ stroke = [0.0, 0.1, 0.2, 0.3], area = [1e-4, 1e-4, 1e-4] }", "must pair up"},
      {"{ stroke = [0.0, 0.1, 0.25, 0.3], area = [1e-4, 1e-4, 1e-4, 1e-4] }", "uniformly spaced"},
      {"{ stroke = [0.0, 0.1, 0.2, 0.3], area = [1e-4, 0.0, 1e-4, 1e-4] }", "must be > 0"},
      {"{ stroke = [0.0, 0.1, 0.2, 0.3], areas = [1e-4, 1e-4, 1e-4, 1e-4] }", "unknown key"},
      {"{ stroke = [0.0, 0.1, 0.2, 0.3], area = [1e-4, 1e-4, \"x\", 1e-4] }", "f1_table.area"},
  };
  for (const auto& k : cases) {
    INFO(k.table);
    try {
      (void)lg::parseScene(with(k.table), "pin.toml", lgtest::sourcePath("data"));
      FAIL("accepted");
    } catch (const lg::InputError& e) {
      CHECK(std::string(e.what()).find("pin.toml:") == 0);
      CHECK(std::string(e.what()).find(k.message) != std::string::npos);
    }
  }
}
