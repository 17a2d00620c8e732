// Orifices by direction (a check valve) in the shock absorber (sim/forces/shock_absorber.hpp): the
// extension law against the closed form, the two-orifice law unchanged to the bit without the keys or
// with the compression's values, a drop whose compression is the plain gear's and whose rebound is
// damped harder, the damping term and Jet derivatives, and bad input.
#include "sim/core/jet.hpp"
#include "sim/io/overrides.hpp"
#include "tests/sim/bad_input_support.hpp"
#include "tests/sim/engine_support.hpp"

#include <catch2/catch.hpp>  // after the sim headers (see scene_support.hpp)

namespace {

// The telescopic gear (vertical strut: the rod and wheel moving up compress it) with extra strut keys.
lg::Scene telescopicWith(const std::string& keys) {
  const std::string text = lgtest::readFile(lgtest::sourcePath("data/telescopic_gear.toml"));
  const std::string at = "xi2 = 1.6\n";
  REQUIRE(text.find(at) != std::string::npos);
  return lg::parseScene(lgtest::replacedText(text, at, at + keys), lgtest::sourcePath("data/telescopic_gear.toml"));
}

// The strut's outputs (s, s', p_1, P_a, P_gas, P_friction, P_orifice1, P_orifice2) and its damping term at
// the touchdown positions with the rod and wheel moving at 'sdot' along the strut (any scalar model).
template <class S> std::vector<S> strutOutputs(const lg::Scene& sc, const lg::Model<S>& m, double sdot,
                                               lg::DampingTerm<S>* term = nullptr) {
  lg::VecX<S> y = sc.initial.y.template cast<S>();
  const int N = m.nBodies();
  for (const char* b : {"rod", "wheel"}) y[7 * N + 6 * m.bodyIndex(b) + 1] = S(sdot);
  lg::Workspace<S> w(m);
  lg::kinematics(m, y, w);
  const auto& sa = std::get<lg::ShockAbsorber<S>>(m.forces[sc.roles.struts.at(0)].type);
  std::vector<S> out(sa.outputNames().size());
  sa.outputs(w.kins(), out.data());
  if (term) sa.damping(w.kins(), term);
  return out;
}

}  // namespace

// Extension areas and coefficients (f1_extension = f1/2, xi1_extension 2.4, f2_extension = 1.5 f2,
// xi2_extension 0.9): each orifice's force is xi rho F^3 s'|s'| / (2 f^2) with the compression's values
// for s' > 0 and the extension's for s' < 0, to 1e-14 relative (measured 0: the same operations); in
// compression the outputs
// are the plain strut's bit for bit, and a check valve given the compression's own values is the plain
// strut's in both directions. The damping term c = dP_a/ds' against central differences on each side
// (1e-7; measured 2.9e-9), and the Jet derivatives of P_a in f1_extension and xi1_extension against
// central differences (1e-8; measured 2.0e-11, 2.6e-10).
TEST_CASE("check valve: orifice forces by direction against the closed form", "[shock_absorber][check_valve]") {
  const lg::Scene plain = telescopicWith("");
  const lg::Scene valve = telescopicWith("f1_extension = 2.5e-5\nxi1_extension = 2.4\nf2_extension = 6.0e-5\nxi2_extension = 0.9\n");
  const lg::Scene same = telescopicWith("f1_extension = 5.0e-5\nxi1_extension = 1.6\nf2_extension = 4.0e-5\nxi2_extension = 1.6\n");
  const auto& sa = std::get<lg::ShockAbsorber<double>>(valve.model.forces[valve.roles.struts.at(0)].type);
  REQUIRE(sa.checkValve);
  REQUIRE(sa.declaresReboundOrifice());
  const double F = M_PI * sa.D * sa.D / 4, F2 = M_PI * (sa.D2 * sa.D2 - sa.D * sa.D) / 4, rho = sa.rho;
  double worst = 0, worstDt = 0;
  for (double v : {0.8, 0.05, -0.05, -0.8}) {
    INFO("s' = " << v);
    const auto o = strutOutputs(valve, valve.model, v), p = strutOutputs(plain, plain.model, v),
               q = strutOutputs(same, same.model, v);
    REQUIRE(std::abs(o[1] - v) < 1e-12);
    const bool ext = v < 0;
    const double a1 = ext ? 2.5e-5 : 5.0e-5, x1 = ext ? 2.4 : 1.6, a2 = ext ? 6.0e-5 : 4.0e-5, x2 = ext ? 0.9 : 1.6;
    const double s2 = o[1] * std::abs(o[1]);
    const double P1 = x1 * rho * F * F * F * s2 / (2 * a1 * a1), P2 = x2 * rho * F2 * F2 * F2 * s2 / (2 * a2 * a2);
    worst = std::max({worst, lgtest::relDiff(o[6], P1), lgtest::relDiff(o[7], P2)});
    CHECK(lgtest::relDiff(o[6], P1) < 1e-14);
    CHECK(lgtest::relDiff(o[7], P2) < 1e-14);
    CHECK(o[6] * v > 0);  // dissipating on both sides
    for (size_t k = 0; k < o.size(); ++k) {
      if (!ext) CHECK(o[k] == p[k]);
      CHECK(q[k] == p[k]);
    }
    // Damping term on this side.
    lg::DampingTerm<double> dt;
    strutOutputs(valve, valve.model, v, &dt);
    const double h = 1e-6 * std::abs(v);
    const double fd = (strutOutputs(valve, valve.model, v + h)[3] - strutOutputs(valve, valve.model, v - h)[3]) / (2 * h);
    worstDt = std::max(worstDt, lgtest::relDiff(dt.c, fd));
    CHECK(lgtest::relDiff(dt.c, fd) < 1e-7);
  }
  // Jet derivatives in the extension's area and coefficient.
  using J = ceres::Jet<double, 2>;
  lg::Model<J> mj = valve.model.cast<J>();
  auto& sj = std::get<lg::ShockAbsorber<J>>(mj.forces[valve.roles.struts.at(0)].type);
  REQUIRE(sj.parameter("f1_extension") == &sj.f1e);
  REQUIRE(sj.parameter("xi1_extension") == &sj.xi1e);
  sj.f1e.v[0] = 1.0;
  sj.xi1e.v[1] = 1.0;
  const J Pa = strutOutputs(valve, mj, -0.8)[3];
  auto PaWith = [&](double df, double dx) {
    lg::Model<double> m = valve.model;
    auto& s = std::get<lg::ShockAbsorber<double>>(m.forces[valve.roles.struts.at(0)].type);
    s.f1e += df;
    s.xi1e += dx;
    return strutOutputs(valve, m, -0.8)[3];
  };
  const double dF = (PaWith(1e-10, 0) - PaWith(-1e-10, 0)) / 2e-10, dX = (PaWith(0, 1e-6) - PaWith(0, -1e-6)) / 2e-6;
  lgtest::report("check valve: closed form %.1e, damping term %.1e, Jet dP/df1e %.1e, dP/dxi1e %.1e", worst, worstDt,
                 lgtest::relDiff(Pa.v[0], dF), lgtest::relDiff(Pa.v[1], dX));
  CHECK(lgtest::relDiff(Pa.v[0], dF) < 1e-8);
  CHECK(lgtest::relDiff(Pa.v[1], dX) < 1e-8);
  // Without its extension keys a compression value moved by a design moves the extension too.
  CHECK(std::get<lg::ShockAbsorber<double>>(plain.model.forces[plain.roles.struts.at(0)].type).checkValve == false);
}

// The seed gear with a check valve: given the compression's own values, every metric of every case is
// the plain gear's bit for bit; with the extension damped harder (xi1_extension = xi2_extension = 4.8,
// three times xi1, xi2), the limit drop's peak load and its time are the plain gear's bit for bit (the
// compression uses the compression law) and so is the largest stroke (located on the compression's
// dense output), the rebound velocity lower (measured 1.658 -> 1.476 m/s), the energy balance below 1e-6
// (measured 2.3e-7).
TEST_CASE("check valve in a drop: the compression unchanged, the rebound damped harder", "[shock_absorber][check_valve]") {
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  auto& st = lgtest::element(doc, "force", "strut");
  st.insert_or_assign("f1_extension", 7.0e-5);
  st.insert_or_assign("xi1_extension", 1.6);
  st.insert_or_assign("f2_extension", 5.0e-5);
  st.insert_or_assign("xi2_extension", 1.6);
  const lg::Scene same = lgtest::build(doc);
  const auto a = lg::runCases(seed, seed.cases, 2), b = lg::runCases(same, same.cases, 2);
  for (size_t i = 0; i < a.size(); ++i) {
    INFO(a[i].metrics.name);
    CHECK(a[i].metrics.peak_load_N == b[i].metrics.peak_load_N);
    CHECK(a[i].metrics.stroke_max_m == b[i].metrics.stroke_max_m);
    CHECK(a[i].metrics.rebound_velocity_mps == b[i].metrics.rebound_velocity_mps);
    CHECK(a[i].metrics.energy_dissipated_J == b[i].metrics.energy_dissipated_J);
    CHECK(a[i].metrics.steps == b[i].metrics.steps);
  }
  st.insert_or_assign("xi1_extension", 4.8);
  st.insert_or_assign("xi2_extension", 4.8);
  const lg::Scene hard = lgtest::build(doc);
  const auto p = lg::runCase(seed, lgtest::findCase(seed, "limit")).metrics;
  const auto h = lg::runCase(hard, lgtest::findCase(hard, "limit")).metrics;
  REQUIRE(h.ok);
  lgtest::report("check valve limit drop: peak %.6f / %.6f N, s_max rel. %.1e, rebound %.4f -> %.4f m/s, E_bal %.1e", p.peak_load_N,
                 h.peak_load_N, lgtest::relDiff(h.stroke_max_m, p.stroke_max_m), p.rebound_velocity_mps, h.rebound_velocity_mps,
                 h.energy_balance_error);
  CHECK(h.peak_load_N == p.peak_load_N);
  CHECK(h.t_peak_s == p.t_peak_s);
  // The step that holds the stroke's turn also holds the start of the extension, whose law its dense output
  // sees (measured 7.9e-14 on the shipped planar seed gear; 0 in space, where that step ends at the turn).
  CHECK(lgtest::relDiff(h.stroke_max_m, p.stroke_max_m) < 1e-12);
  CHECK(h.rebound_velocity_mps < p.rebound_velocity_mps);
  CHECK(h.energy_balance_error < 1e-6);
}

// The extension table's samples as design parameters ("strut.f1_extension_table[k]"), like the
// metering pin's: paths, values and units; a sample set as data runs the bits of the scene edited by
// --set (which writes a CSV table inline); the sample acts on the rebound only; a design with a sample
// <= 0 is rejected by the scene's rule, named by its key.
TEST_CASE("check valve: the extension table's samples are design parameters", "[shock_absorber][check_valve][parameters]") {
  lgtest::TempDir dir("check_valve_table");
  lgtest::writeFile((dir.path / "extension.csv").string(), "stroke,area\n0.0,6.0e-5\n0.04,5.0e-5\n0.08,4.5e-5\n0.12,4.0e-5\n0.16,3.5e-5\n");
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  lgtest::element(doc, "force", "strut").insert_or_assign("f1_extension_table", (dir.path / "extension.csv").string());
  const lg::Scene valve = lgtest::build(doc);
  const auto& sa = std::get<lg::ShockAbsorber<double>>(valve.model.forces[valve.roles.struts.at(0)].type);
  REQUIRE(sa.f1eTable);
  REQUIRE(sa.f1eValues.size() == 5);
  const lg::Parameter p = lg::resolveParameter(valve, "strut.f1_extension_table[2]");
  CHECK(lg::parameterValue(valve, p) == sa.f1eTable->ys()[2]);  // the CSV reader's bits of 4.5e-5
  CHECK(lg::parameterValue(valve, p) == Approx(4.5e-5));
  CHECK(lg::unitOfKey(p.key) == "m^2");
  for (const char* bad : {"strut.f1_extension_table[5]", "strut.f1_extension_table[]", "strut.f1_extension_table"}) {
    INFO(bad);
    CHECK_THROWS_AS(lg::resolveParameter(valve, bad), lg::InputError);
  }
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  CHECK_THROWS_AS(lg::resolveParameter(seed, "strut.f1_extension_table[0]"), lg::InputError);
  // As data and as text (--set inlines the CSV): the same bits; the compression untouched.
  lg::Scene asData = valve;
  REQUIRE_FALSE(lg::applyParameters(asData, {lg::resolveParameter(valve, "strut.f1_extension_table[3]")}, {2.0e-5}));
  const lg::Scene asText = lg::applyOverrides(valve, {{"strut.f1_extension_table[3]", 2.0e-5}});
  const lg::DropCase& c = lgtest::findCase(valve, "limit");
  const lg::CaseMetrics a = lg::runCase(asData, c).metrics, b = lg::runCase(asText, c).metrics, base = lg::runCase(valve, c).metrics;
  REQUIRE(a.ok);
  CHECK(a.rebound_velocity_mps == b.rebound_velocity_mps);
  CHECK(a.energy_dissipated_J == b.energy_dissipated_J);
  CHECK(a.peak_load_N == base.peak_load_N);  // the compression's law
  CHECK(a.rebound_velocity_mps < base.rebound_velocity_mps);  // a narrower orifice in extension
  // A sample <= 0 is the scene's rule, named by its key.
  lg::Scene bad = valve;
  const auto why = lg::applyParameters(bad, {lg::resolveParameter(valve, "strut.f1_extension_table[1]")}, {-1e-6});
  REQUIRE(why);
  CHECK(why->find("f1_extension_table[1]") != std::string::npos);
  CHECK(why->find("must be > 0") != std::string::npos);
}

TEST_CASE("check valve: bad input names file, line, key and rule, exit status 2", "[shock_absorber][check_valve][input]") {
  lgtest::TempDir dir("check_valve_bad");
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string at = "xi2 = 1.6\n";
  REQUIRE(seed.find(at) != std::string::npos);
  auto with = [&](const std::string& extra) { return lgtest::replacedText(seed, at, at + extra); };
  const std::string noRebound = lgtest::replacedText(lgtest::replacedText(seed, "f2 = 5.0e-5                    # [m^2] rebound orifice\n", ""),
                                                     at, "");
  lgtest::checkBadInputs(
      {
          {"negative extension coefficient", with("xi1_extension = -1.0\n"), "xi1_extension = -1.0", "force[2].xi1_extension",
           "value -1 must be > 0"},
          {"zero extension area", with("f1_extension = 0.0\n"), "f1_extension = 0.0", "force[2].f1_extension", "value 0 must be > 0"},
          {"area and table", with("f1_extension = 7e-5\nf1_extension_table = \"t.csv\"\n"), "f1_extension = 7e-5",
           "force[2].f1_extension", "give at most one of f1_extension (constant area) and f1_extension_table"},
          {"missing table", with("f1_extension_table = \"no_such.csv\"\n"), "f1_extension_table", "force[2].f1_extension_table",
           "no such file"},
          {"rebound extension without a rebound orifice",
           lgtest::replacedText(noRebound, "xi1 = 1.6\n", "xi1 = 1.6\nf2_extension = 4e-5\n"), "f2_extension = 4e-5",
           "force[2].f2_extension", "needs the rebound orifice f2"},
      },
      dir);
}

// A one-way rebound orifice (f2_direction): its force xi2 rho F2^3 s'|s'| / (2 f2^2) in its own direction
// only, 0 in the other, to the closed form on a single stroke each way; "both" is the plain strut to the bit;
// the damping term against central differences on each side; a drop closes its energy balance.
TEST_CASE("check valve: a one-way rebound orifice against the closed form", "[shock_absorber][check_valve]") {
  const lg::Scene plain = telescopicWith("");
  const lg::Scene both = telescopicWith("f2_direction = \"both\"\n");
  const lg::Scene ext = telescopicWith("f2_direction = \"extension\"\n");
  const lg::Scene comp = telescopicWith("f2_direction = \"compression\"\n");
  const auto& sa = std::get<lg::ShockAbsorber<double>>(ext.model.forces[ext.roles.struts.at(0)].type);
  REQUIRE(sa.f2Direction == -1);
  const double F2 = M_PI * (sa.D2 * sa.D2 - sa.D * sa.D) / 4;
  for (double v : {0.8, 0.05, -0.05, -0.8}) {
    INFO("s' = " << v);
    const auto e = strutOutputs(ext, ext.model, v), c = strutOutputs(comp, comp.model, v), p = strutOutputs(plain, plain.model, v),
               b = strutOutputs(both, both.model, v);
    const double P2 = sa.xi2 * sa.rho * F2 * F2 * F2 * e[1] * std::abs(e[1]) / (2 * sa.f2 * sa.f2);
    CHECK(lgtest::relDiff(v < 0 ? e[7] : c[7], P2) < 1e-14);
    CHECK((v < 0 ? c[7] : e[7]) == 0.0);
    CHECK(e[6] == p[6]);  // the main orifice untouched
    for (size_t k = 0; k < b.size(); ++k) CHECK(b[k] == p[k]);
    lg::DampingTerm<double> dt;
    strutOutputs(ext, ext.model, v, &dt);
    const double h = 1e-6 * std::abs(v);
    const double fd = (strutOutputs(ext, ext.model, v + h)[3] - strutOutputs(ext, ext.model, v - h)[3]) / (2 * h);
    CHECK(lgtest::relDiff(dt.c, fd) < 1e-7);
  }
  const lg::CaseMetrics m = lg::runCase(ext, lgtest::findCase(ext, "limit")).metrics;
  REQUIRE(m.ok);
  CHECK(m.energy_balance_error < 1e-6);
  CHECK_THROWS_WITH(telescopicWith("f2_direction = \"upward\"\n"), Catch::Contains("must be \"both\", \"compression\" or \"extension\""));
}
