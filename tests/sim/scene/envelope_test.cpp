// The servicing and temperature envelope (sim/scene/envelope.hpp, sim/io/scene_envelope.cpp): its corners, the
// gas law and the other factors at each against their closed forms, the nominal point's bits, a cornered
// run against the same values written into the scene by hand, and the bad inputs of [envelope].
#include "tests/sim/bad_input_support.hpp"  // sim headers, then Catch (see there)

#include <cstring>
#include <set>

#include "sim/io/overrides.hpp"
#include "sim/scene/parameters.hpp"

namespace {

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

lg::Scene seed() { return lgtest::build(lgtest::shippedDoc("data/seed_gear.toml")); }

const lg::ShockAbsorber<double>& strutOf(const lg::Model<double>& m, const std::string& name = "strut") {
  return std::get<lg::ShockAbsorber<double>>(m.forces[m.forceIndex(name)].type);
}

// The seed gear with its [envelope] replaced by 'table' (TOML lines; empty: none).
lg::Scene withEnvelope(const std::string& table, const std::string& scene = "data/seed_gear.toml") {
  toml::table doc = lgtest::shippedDoc(scene);
  doc.erase("envelope");
  if (!table.empty()) doc.insert("envelope", toml::parse(table));
  return lgtest::build(doc);
}

}  // namespace

TEST_CASE("envelope: the corners are the full factorial of the declared extremes, named, nominal first", "[envelope]") {
  const lg::Scene sc = seed();
  REQUIRE(sc.envelope.declared);
  const auto corners = sc.envelope.corners();
  REQUIRE(corners.size() == 17);  // 2^4 corners and the nominal point
  CHECK(corners[0].name == "nominal");
  CHECK(corners[0].at == sc.envelope.nominal());
  CHECK(corners[0].at.temperature == 288.15);
  CHECK(corners[1].name == "cold-lowcharge-lowoil-smallorifice");
  CHECK(corners[16].name == "hot-highcharge-highoil-largeorifice");
  // the extremes: -40 C, charge -5 %, gas volume +1 % (low oil), orifices -2 %
  CHECK(corners[1].at.temperature == Approx(233.15).epsilon(1e-15));
  CHECK(corners[1].at.charge == -0.05);
  CHECK(corners[1].at.gasVolume == 0.01);
  CHECK(corners[1].at.orifice == -0.02);
  CHECK(corners[16].at.temperature == Approx(323.15).epsilon(1e-15));
  CHECK(corners[16].at.gasVolume == -0.01);
  std::set<std::string> names;
  for (const auto& c : corners) names.insert(c.name);
  CHECK(names.size() == corners.size());
  // a fifth factor doubles them; an absolute oil tolerance names the same factor
  const lg::Scene five = withEnvelope("landing_temperature_C = [-40.0, 50.0]\ncharge_tolerance = 0.05\n"
                                      "oil_level_tolerance = 1.0e-5\norifice_tolerance = 0.02\ntyre_stiffness_tolerance = 0.1\n");
  const auto c5 = five.envelope.corners();
  REQUIRE(c5.size() == 33);
  CHECK(c5[1].name == "cold-lowcharge-lowoil-smallorifice-softtyre");
  CHECK(c5[1].at.oilLevel == -1.0e-5);
  CHECK(c5[1].at.tyreStiffness == -0.1);
  // a declared list replaces the factorial
  const lg::Scene listed = withEnvelope("[[corner]]\nname = \"cold-day\"\ntemperature_C = -30.0\ncharge = -0.03\n"
                                        "[[corner]]\nname = \"hot-day\"\ntemperature_C = 45.0\n");
  const auto cl = listed.envelope.corners();
  REQUIRE(cl.size() == 3);
  CHECK(cl[1].name == "cold-day");
  CHECK(cl[1].at.temperature == Approx(243.15).epsilon(1e-15));
  CHECK(cl[1].at.charge == -0.03);
  CHECK(cl[2].at.charge == 0.0);
  // without factors: the nominal point only
  CHECK(withEnvelope("service_temperature_C = 20.0\n").envelope.corners().size() == 1);
}

TEST_CASE("envelope: the gas law and the tolerances at every corner, one and two stages, oil expansion", "[envelope]") {
  const lg::Scene sc = seed();
  const lg::ShockAbsorber<double>& s0 = strutOf(sc.model);
  const double Ts = 288.15;
  for (const auto& c : sc.envelope.corners()) {
    INFO(c.name);
    lg::Model<double> m = sc.model;
    lg::applyEnvelope(sc.envelope, m, c.at);
    const auto& s = strutOf(m);
    const double T = c.at.temperature;
    // a fixed gas mass at a fixed extended volume: p01(T) = p01 (1 + c) T / T_s
    CHECK(s.p01 == Approx(s0.p01 * (1 + c.at.charge) * T / Ts).epsilon(1e-15));
    CHECK(s.Omega0 == Approx(s0.Omega0 * (1 + c.at.gasVolume)).epsilon(1e-15));
    CHECK(s.f1 == Approx(s0.f1 * (1 + c.at.orifice)).epsilon(1e-15));
    CHECK(s.f2 == Approx(s0.f2 * (1 + c.at.orifice)).epsilon(1e-15));
    CHECK(s.rho == s0.rho);  // no oil expansion declared
  }
  // the nominal point: every value the same bits
  lg::Model<double> m = sc.model;
  lg::applyEnvelope(sc.envelope, m, sc.envelope.nominal());
  CHECK(sameBits(strutOf(m).p01, s0.p01));
  CHECK(sameBits(strutOf(m).Omega0, s0.Omega0));
  CHECK(sameBits(strutOf(m).f1, s0.f1));

  // oil expansion: V_T = V_s - beta V_oil (T - T_s), p01(T) = p_s (T / T_s) V_s / V_T, rho / (1 + beta dT)
  const lg::Scene oil = withEnvelope("landing_temperature_C = [-40.0, 50.0]\noil_expansion = 7.0e-4\noil_volume = 1.0e-3\n"
                                     "gas_volume_tolerance = 0.01\n");
  for (const auto& c : oil.envelope.corners()) {
    INFO(c.name);
    lg::Model<double> mo = oil.model;
    lg::applyEnvelope(oil.envelope, mo, c.at);
    const double T = c.at.temperature, Vs = 1.3e-3 * (1 + c.at.gasVolume), VT = Vs - 7e-4 * 1e-3 * (T - Ts);
    CHECK(strutOf(mo).Omega0 == Approx(VT).epsilon(1e-14));
    CHECK(strutOf(mo).p01 == Approx(3.0e6 * T / Ts * Vs / VT).epsilon(1e-14));
    CHECK(strutOf(mo).rho == Approx(850.0 / (1 + 7e-4 * (T - Ts))).epsilon(1e-14));
  }
  // cold, 40 C below the service temperature: 1.3e-3 + 7e-4 1e-3 55 = 1.3385e-3 m^3 of gas
  lg::Model<double> cold = oil.model;
  lg::applyEnvelope(oil.envelope, cold, oil.envelope.corners()[1].at);
  CHECK(strutOf(cold).Omega0 == Approx(1.3e-3 * 1.01 + 3.85e-5).epsilon(1e-14));

  // two stages: both charges follow T / T_s, the second chamber's volume stays
  const lg::Scene nose = withEnvelope("landing_temperature_C = [-40.0, 50.0]\ncharge_tolerance = 0.05\n", "data/nose_gear.toml");
  const auto& n0 = std::get<lg::ShockAbsorber<double>>(nose.model.forces[nose.roles.struts[0]].type);
  REQUIRE(n0.twoStage);
  for (const auto& c : nose.envelope.corners()) {
    INFO(c.name);
    lg::Model<double> mn = nose.model;
    lg::applyEnvelope(nose.envelope, mn, c.at);
    const auto& n = std::get<lg::ShockAbsorber<double>>(mn.forces[nose.roles.struts[0]].type);
    const double k = (1 + c.at.charge) * c.at.temperature / Ts;
    CHECK(n.p01 == Approx(n0.p01 * k).epsilon(1e-15));
    CHECK(n.p02 == Approx(n0.p02 * k).epsilon(1e-15));
    CHECK(n.Omega02 == n0.Omega02);
  }
}

TEST_CASE("envelope: the nominal point runs the same bits as the scene without one, and a corner as its values by hand",
          "[envelope]") {
  const lg::Scene with = seed(), without = withEnvelope("");
  REQUIRE_FALSE(without.envelope.declared);
  const lg::DropCase& reserve = lgtest::findCase(with, "reserve");
  const lg::CaseMetrics a = lg::runCase(with, reserve).metrics, b = lg::runCase(without, reserve).metrics;
  CHECK(sameBits(a.peak_load_N, b.peak_load_N));
  CHECK(sameBits(a.stroke_max_m, b.stroke_max_m));
  CHECK(sameBits(a.energy_balance_error, b.energy_balance_error));
  CHECK(a.steps == b.steps);
  // the worst corner for the stroke, and the same values written into a scene without an envelope
  lg::DropCase atCold = reserve;
  for (const auto& c : with.envelope.corners())
    if (c.name == "cold-lowcharge-lowoil-largeorifice") atCold.corner = c;
  REQUIRE(atCold.corner);
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  doc.erase("envelope");
  toml::table& strut = lgtest::element(doc, "force", "strut");
  strut.insert_or_assign("p01", 3.0e6 * 0.95 * 233.15 / 288.15);
  strut.insert_or_assign("Omega0", 1.3e-3 * 1.01);
  strut.insert_or_assign("f1", 7.0e-5 * 1.02);
  strut.insert_or_assign("f2", 5.0e-5 * 1.02);
  const lg::CaseMetrics c = lg::runCase(with, atCold).metrics, d = lg::runCase(lgtest::build(doc), reserve).metrics;
  REQUIRE(c.ok);
  CHECK(c.stroke_max_m == Approx(d.stroke_max_m).epsilon(1e-9));
  CHECK(c.peak_load_N == Approx(d.peak_load_N).epsilon(1e-9));
  // the cold, under-charged strut with low oil strokes further: 16.4 mm of the seed's 24.2 mm margin are left
  CHECK(c.stroke_margin_m < a.stroke_margin_m - 0.005);
  CHECK(c.stroke_margin_m == Approx(0.016447).margin(5e-6));
}

TEST_CASE("envelope: envelope.<key> parameters set the scene's point and are checked", "[envelope]") {
  lg::Scene sc = seed();
  const lg::Parameter t = lg::resolveParameter(sc, "envelope.temperature_C");
  CHECK(t.kind == lg::Parameter::Kind::Envelope);
  CHECK(lg::parameterValue(sc, t) == Approx(15.0).epsilon(1e-14));
  CHECK(lg::unitOfKey("temperature_C") == "C");
  CHECK_FALSE(lg::applyParameters(sc, {t}, {-40.0}));
  CHECK(sc.envelope.point.temperature == Approx(233.15).epsilon(1e-15));
  const auto why = lg::applyParameters(sc, {t}, {-300.0});
  REQUIRE(why);
  CHECK(why->find("below absolute zero") != std::string::npos);
  CHECK_THROWS_WITH(lg::resolveParameter(sc, "envelope.pressure"), Catch::Contains("has no quantity 'pressure'"));
  CHECK_THROWS_WITH(lg::resolveParameter(withEnvelope(""), "envelope.charge"), Catch::Contains("has no [envelope] table"));
  // --set writes the point into the document: the rebuilt scene runs there
  const lg::Scene set = lg::applyOverrides(seed(), {{"envelope.charge", -0.05}});
  CHECK(set.envelope.point.charge == -0.05);
}

TEST_CASE("envelope: bad [envelope] values name file, line, key and rule", "[envelope][bad-input]") {
  const lgtest::TempDir dir("envelope_bad");
  const std::string base = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  auto envelope = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(base, from, to); };
  std::string noStrut = base;
  {
    // the seed gear without its strut: an envelope has nothing to move
    const auto a = noStrut.find("[[force]]\nname = \"strut\"");
    const auto b = noStrut.find("[[force]]\nname = \"tyre\"");
    REQUIRE(a != std::string::npos);
    noStrut.erase(a, b - a);
  }
  std::string corners = "[envelope]\n";
  for (int i = 0; i <= lg::kMaxCorners; ++i) corners += "[[envelope.corner]]\nname = \"c" + std::to_string(i) + "\"\n";
  std::string many = base.substr(0, base.find("[envelope]")) + corners;
  const std::vector<lgtest::BadInput> bad{
      {"a temperature below absolute zero", envelope("landing_temperature_C = [-40.0, 50.0]", "landing_temperature_C = [-300.0, 50.0]"),
       "landing_temperature_C", "envelope.landing_temperature_C", "at or below absolute zero"},
      {"a range the wrong way round", envelope("landing_temperature_C = [-40.0, 50.0]", "landing_temperature_C = [50.0, -40.0]"),
       "landing_temperature_C", "envelope.landing_temperature_C", "with cold < hot"},
      {"a tolerance of 100 %", envelope("charge_tolerance = 0.05", "charge_tolerance = 1.0"), "charge_tolerance",
       "envelope.charge_tolerance", "must be below 1"},
      {"a tolerance in percent", envelope("orifice_tolerance = 0.02", "orifice_tolerance = 2.0"), "orifice_tolerance",
       "envelope.orifice_tolerance", "must be below 1"},
      {"an oil level that locks the strut", envelope("gas_volume_tolerance = 0.01", "gas_volume_tolerance = 0.04"),
       "gas_volume_tolerance", "envelope.gas_volume_tolerance", "the strut would lock before its stop"},
      {"both oil tolerances", envelope("gas_volume_tolerance = 0.01", "gas_volume_tolerance = 0.01\noil_level_tolerance = 1e-5"),
       "oil_level_tolerance", "envelope.oil_level_tolerance", "give the oil level's tolerance once"},
      {"oil expansion without the oil", envelope("orifice_tolerance = 0.02", "orifice_tolerance = 0.02\noil_expansion = 7e-4"),
       "oil_expansion", "envelope.oil_expansion", "needs the oil volume"},
      {"an unknown key", envelope("orifice_tolerance = 0.02", "orifice_tolerance = 0.02\ntemperature = 15.0"),
       "temperature = 15.0", "envelope.temperature", "unknown key"},
      {"more corners than the cap", many, "[[envelope.corner]]", "envelope.corner", "at most 64"},
      {"an envelope on a scene without gas", noStrut, "[envelope]", "envelope", "the scene has no shock absorber"},
  };
  lgtest::checkBadInputs(bad, dir);
}

// simulate --corner: each case at the named points, "<case>@<corner>" in every output (the file names
// made safe); an unknown corner and a scene without an envelope are refused (exit 2, nothing written).
TEST_CASE("envelope: simulate --corner runs the cases at points of the envelope", "[envelope][cli]") {
  const lgtest::TempDir dir("envelope_cli");
  const std::string scene = lgtest::sourcePath("data/seed_gear.toml");
  auto simulate = [&](const std::string& args) {
    const std::string cmd = "'" + lgtest::binPath("simulate") + "' '" + scene + "' " + args + " --quiet 2>'" +
                            (dir / "err.txt") + "' >/dev/null";
    const int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  };
  REQUIRE(simulate("--case reserve --corner nominal --corner cold-lowcharge-lowoil-largeorifice --out '" + (dir / "a") + "'") == 0);
  const std::string summary = lgtest::readFile(dir / "a/summary.csv");
  CHECK(summary.find("\nreserve@nominal,1,") != std::string::npos);
  CHECK(summary.find("\nreserve@cold-lowcharge-lowoil-largeorifice,1,") != std::string::npos);
  CHECK(std::filesystem::exists(dir / "a/reserve_cold-lowcharge-lowoil-largeorifice.csv"));
  // the nominal point is the scene's own run, to the bit; the corner is --set's at the same values
  REQUIRE(simulate("--case reserve --out '" + (dir / "b") + "'") == 0);
  REQUIRE(simulate("--case reserve --set envelope.temperature_C=-40 --set envelope.charge=-0.05 --set envelope.gas_volume=0.01 "
                   "--set envelope.orifice=0.02 --out '" + (dir / "c") + "'") == 0);
  auto row = [](const std::string& csv, const std::string& name) {
    const auto at = csv.find("\n" + name + ",");
    REQUIRE(at != std::string::npos);
    const auto start = csv.find(',', at + 1), end = csv.find('\n', at + 1);
    std::string r = csv.substr(start, end - start);
    return r.substr(0, r.rfind(','));  // (the wall time last)
  };
  CHECK(row(summary, "reserve@nominal") == row(lgtest::readFile(dir / "b/summary.csv"), "reserve"));
  CHECK(row(summary, "reserve@cold-lowcharge-lowoil-largeorifice") == row(lgtest::readFile(dir / "c/summary.csv"), "reserve"));
  REQUIRE(simulate("--corner all --case limit --out '" + (dir / "d") + "'") == 0);
  const std::string all = lgtest::readFile(dir / "d/summary.csv");
  CHECK(std::count(all.begin(), all.end(), '\n') == 1 + 17);
  CHECK(simulate("--corner freezing --out '" + (dir / "e") + "'") == 2);
  CHECK(lgtest::readFile(dir / "err.txt").find("error: command line: key '--corner': value 'freezing' is no point") == 0);
  CHECK_FALSE(std::filesystem::exists(dir / "e"));
}
