// The certification matrix (sim/drop/certification.cpp) and `certify` (apps/certify.cpp): the cases each
// basis generates against hand-computed numbers (certification.md), the limits and verdicts, and the
// program's outputs and exit statuses.
#include "tests/sim/scene_support.hpp"  // sim headers, then Catch (see there)
#include "docs_support.hpp"   // docsText: README.md and docs/

#include <sys/wait.h>

#include <cstdlib>

#include "sim/drop/certification.hpp"
#include "sim/io/compliance.hpp"
#include "sim/io/dossier.hpp"

namespace {

// The seed gear with its [certification] table replaced by 'table' (TOML lines).
lg::Scene withCertification(const std::string& table) {
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  doc.erase("certification");
  doc.insert("certification", toml::parse(table));
  return lgtest::build(doc);
}

int certify(const std::string& args, const std::string& errFile) {
  const std::string cmd = "'" + lgtest::binPath("certify") + "' " + args + " --quiet >/dev/null 2>'" + errFile + "'";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

std::string q(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST_CASE("certification: Part 25 and CS-25 generate the limit, takeoff and reserve drops", "[certification]") {
  const lg::Scene sc = lgtest::build(lgtest::shippedDoc("data/seed_gear.toml"));
  REQUIRE(sc.certification);
  const lg::Certification& c = *sc.certification;
  REQUIRE(c.cases.size() == 3);
  struct Expected {
    const char* name;
    lg::CertKind kind;
    double V, W;
  } expected[] = {{"cert-limit-landing", lg::CertKind::Limit, 3.05, 4050},
                  {"cert-limit-takeoff", lg::CertKind::Limit, 1.83, 4250},
                  {"cert-reserve", lg::CertKind::Reserve, 3.66, 4050}};
  for (size_t i = 0; i < 3; ++i) {
    INFO(expected[i].name);
    CHECK(c.cases[i].name == expected[i].name);
    CHECK(c.cases[i].kind == expected[i].kind);
    CHECK(c.cases[i].sinkSpeed == expected[i].V);
    CHECK(c.cases[i].liftRatio == 1.0);
    CHECK(c.cases[i].mass == expected[i].W);
    CHECK(c.cases[i].duration == 0.8);
    // W reaches the model through the airframe: the gear's other bodies weigh 70 kg
    const lg::DropCase d = lg::certDropCase(sc, c, c.cases[i]);
    CHECK(d.masses.at("airframe") == expected[i].W - 70.0);
    CHECK(lg::caseMass(sc, d) == expected[i].W);
  }
  CHECK(c.limitGroundFactor() == 2.5);
  CHECK(c.strokeMargin == 0.01);
  // CS-25 writes 3.7 m/s for the reserve drop; a takeoff mass defaults to the landing mass
  const lg::Scene cs = withCertification("basis = \"cs25\"\nlanding_mass = 4050.0\nlimit_load_factor = 2.0\n");
  CHECK(cs.certification->cases[2].sinkSpeed == 3.7);
  CHECK(cs.certification->cases[1].mass == 4050.0);
  CHECK(cs.certification->liftRatio == 1.0);
  CHECK(cs.certification->reserveLiftRatio == 1.0);
}

TEST_CASE("certification: Part 23 sink speeds from the wing loading, clamped at both ends", "[certification]") {
  // V = 4.4 (W/S)^(1/4) ft/s, W/S in lb/ft^2 = 0.204816 x kg/m^2, clamped to 7 .. 10 ft/s; reserve 1.2 V
  struct Row {
    double ws, V;
  } rows[] = {{20.0, 7.0 * 0.3048},                   // 4.096 lb/ft^2: 6.26 ft/s, clamped up to 7 ft/s
              {80.0, 8.852504236999334 * 0.3048},     // 16.385 lb/ft^2
              {300.0, 10.0 * 0.3048}};                // 61.44 lb/ft^2: 12.3 ft/s, clamped down to 10 ft/s
  for (const Row& r : rows) {
    INFO("W/S " << r.ws << " kg/m^2");
    CHECK(lg::part23SinkSpeed(r.ws) == Approx(r.V).epsilon(1e-14));
    const lg::Scene sc = withCertification("basis = \"part23\"\nlanding_mass = 4050.0\nwing_loading = " +
                                           std::to_string(r.ws) + "\nlimit_load_factor = 3.0\n");
    const lg::Certification& c = *sc.certification;
    REQUIRE(c.cases.size() == 2);
    CHECK(c.cases[0].name == "cert-limit");
    CHECK(c.cases[0].sinkSpeed == Approx(r.V).epsilon(1e-14));
    CHECK(c.cases[0].liftRatio == Approx(2.0 / 3.0).epsilon(1e-15));  // at most, and by default, 2/3
    CHECK(c.cases[1].name == "cert-reserve");
    CHECK(c.cases[1].kind == lg::CertKind::Reserve);
    CHECK(c.cases[1].sinkSpeed == Approx(1.2 * r.V).epsilon(1e-14));
    CHECK(c.cases[1].liftRatio == 1.0);
    CHECK(c.limitGroundFactor() == Approx(3.0 - 2.0 / 3.0).epsilon(1e-15));  // n_g = n - L
  }
  // Part 23's floors, n >= 2.67 and n_g >= 2.0, reported for the unit
  const lg::Scene low = withCertification("basis = \"cs23\"\nlanding_mass = 4050.0\nwing_loading = 80.0\nlimit_load_factor = 2.6\n");
  const auto items = lg::unitItems(*low.certification);
  REQUIRE(items.size() == 2);
  CHECK_FALSE(items[0].pass);  // 2.6 < 2.67
  CHECK_FALSE(items[1].pass);  // 2.6 - 2/3 = 1.93 < 2.0
  const lg::Scene ok = withCertification("basis = \"part23\"\nlanding_mass = 4050.0\nwing_loading = 80.0\nlimit_load_factor = 2.7\n");
  const auto okItems = lg::unitItems(*ok.certification);
  CHECK(okItems[0].pass);
  CHECK(okItems[1].pass);
}

TEST_CASE("certification: a custom matrix takes its cases as written", "[certification]") {
  const lg::Scene sc = withCertification(
      "basis = \"custom\"\nlimit_load_factor = 2.2\nstroke_margin = 0.005\ntyre_limit = 0.09\n"
      "[[case]]\nname = \"rig-1\"\nkind = \"limit\"\nsink_speed = 2.9\nlift_ratio = 0.8\nmass = 4100.0\n"
      "[[case]]\nname = \"rig-2\"\nkind = \"reserve\"\nsink_speed = 3.5\nlift_ratio = 1.0\nmass = 4000.0\nduration = 1.0\n");
  const lg::Certification& c = *sc.certification;
  REQUIRE(c.cases.size() == 2);
  CHECK(c.cases[0].sinkSpeed == 2.9);
  CHECK(c.cases[0].liftRatio == 0.8);
  CHECK(c.cases[0].mass == 4100.0);
  CHECK(c.cases[1].kind == lg::CertKind::Reserve);
  CHECK(c.cases[1].duration == 1.0);
  // the limits: load factor (ultimate 1.5 x 2.2 for the reserve case), stroke margin, tyre limit as a number
  const auto lim = lg::caseLimits(c, c.cases[1], sc);
  REQUIRE(lim.size() == 3);
  CHECK(lim[0].metric == "load_factor");
  CHECK(lim[0].bound == Approx(3.3).epsilon(1e-15));
  CHECK(lim[1].metric == "stroke_margin");
  CHECK(lim[1].bound == 0.005);
  CHECK(lim[2].metric == "tyre_deflection");
  CHECK(lim[2].bound == 0.09);
}

TEST_CASE("certification: verdicts name every limit a case breaks", "[certification]") {
  const lg::Scene sc = lgtest::build(lgtest::shippedDoc("data/seed_gear.toml"));
  const lg::Certification& c = *sc.certification;
  lg::CaseMetrics m;
  m.name = "cert-limit-landing";
  m.load_factor = 2.4;
  m.stroke_margin_m = 0.02;
  m.tyre_margin_m = 0.01;
  m.compression_ended = true;
  const auto limits = lg::caseLimits(c, c.cases[0], sc);
  CHECK(lg::assessCase("certification", c.cases[0], m, limits).pass);
  m.load_factor = 2.6;            // above n_g,lim = 2.5
  m.stroke_margin_m = 0.005;      // inside the 10 mm margin
  m.compression_ended = false;
  const lg::CaseVerdict v = lg::assessCase("certification", c.cases[0], m, limits);
  CHECK_FALSE(v.pass);
  REQUIRE(v.reasons.size() == 3);
  CHECK(v.reasons[0] == "load_factor 2.6 > 2.5 (design limit load factor n_g)");
  CHECK(v.reasons[1] == "stroke_margin 0.005 < 0.01 m (stroke margin to the bottoming stop >= 0.01 m)");
  CHECK(v.reasons[2].find("the compression did not end within 0.8 s") == 0);
  // the reserve case is held to ultimate, 1.5 x the limit load
  m.load_factor = 3.7;
  m.stroke_margin_m = 0.02;
  m.compression_ended = true;
  CHECK(lg::assessCase("certification", c.cases[2], m, lg::caseLimits(c, c.cases[2], sc)).pass);
  m.load_factor = 3.8;
  CHECK_FALSE(lg::assessCase("certification", c.cases[2], m, lg::caseLimits(c, c.cases[2], sc)).pass);
}

TEST_CASE("certify: exit 0 when the matrix passes, 1 when a case fails, 2 on bad input", "[certification][cli]") {
  lgtest::TempDir dir("certify");
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  SECTION("the seed gear passes; the report shows the matrix and the checks") {
    const std::string out = dir / "pass";
    CHECK(certify(q(lgtest::sourcePath("data/seed_gear.toml")) + " --out " + q(out), dir / "err.txt") == 0);
    const std::string json = lgtest::readFile(out + "/compliance.json");
    CHECK(json.find("\"pass\": true,\n  \"checks_pass\": false") != std::string::npos);  // the free drop's tyre
    for (const char* n : {"cert-limit-landing", "cert-limit-takeoff", "cert-reserve", "light", "free-drop"})
      CHECK(json.find(std::string("{\"name\": \"") + n + "\"") != std::string::npos);
    const std::string md = lgtest::readFile(out + "/compliance.md");
    CHECK(md.find("**Verdict: PASS**") != std::string::npos);
    CHECK(md.find("| cert-reserve | reserve | 3.660 | 1 | 4050 |") != std::string::npos);
    CHECK(md.find("| free-drop | check | 2.500 | 0 | 4050 |") != std::string::npos);
    CHECK(md.find("**FAIL**: tyre_margin") != std::string::npos);
  }
  SECTION("a design limit below the limit drop's load factor fails") {
    const std::string file = dir / "strict.toml";
    lgtest::writeFile(file, [&] {
      std::string t = seed;
      t.replace(t.find("limit_load_factor = 2.5"), 23, "limit_load_factor = 2.0");
      return t;
    }());
    const std::string out = dir / "fail";
    CHECK(certify(q(file) + " --out " + q(out), dir / "err.txt") == 1);
    const std::string md = lgtest::readFile(out + "/compliance.md");
    CHECK(md.find("**Verdict: FAIL**") != std::string::npos);
    CHECK(md.find("load_factor 2.1717") != std::string::npos);  // exact Coulomb friction (2.1716 regularised)
    // --basis replaces the table's basis: CS-25's reserve drop at 3.7 m/s
    const std::string cs = dir / "cs25";
    CHECK(certify(q(file) + " --basis cs25 --out " + q(cs), dir / "err.txt") == 1);
    CHECK(lgtest::readFile(cs + "/compliance.json").find("\"sink_speed_mps\": 3.7") != std::string::npos);
  }
  SECTION("bad input: exit 2, a message, nothing written") {
    const std::string noTable = dir / "plain.toml";
    lgtest::writeFile(noTable, seed.substr(0, seed.find("# ---- certification matrix")));
    struct Bad {
      std::string args, words;
    } bad[] = {{q(noTable), "has no [certification] table"},
               {q(lgtest::sourcePath("data/seed_gear.toml")) + " --basis part24", "'--basis': value 'part24' must be part25, cs25, part23, cs23 or custom"},
               {q(lgtest::sourcePath("data/seed_gear.toml")) + " --basis part23", "needs the wing loading"},
               {q(dir / "missing.toml"), "cannot read the scene file: no such file"}};
    for (const Bad& b : bad) {
      INFO(b.args);
      const std::string out = dir / "bad_out";
      CHECK(certify(b.args + " --out " + q(out), dir / "err.txt") == 2);
      CHECK_FALSE(std::filesystem::exists(out));
      const std::string err = lgtest::readFile(dir / "err.txt");
      CHECK(err.rfind("error: ", 0) == 0);
      CHECK(err.find(b.words) != std::string::npos);
    }
  }
}

// certify over the seed gear's envelope: every case at the nominal point and its 16 corners, the same
// bytes on 1 and 2 threads; the worst corner of the reserve drop's stroke margin named; --nominal runs
// the nominal point alone. The docs' example output is this run's.
TEST_CASE("certify: the envelope's every corner, the worst named, the same bytes on 1 and 2 threads",
          "[certification][envelope]") {
  const lgtest::TempDir dir("certify_envelope");
  const std::string scene = lgtest::sourcePath("data/seed_gear.toml");
  REQUIRE(certify(q(scene) + " --out " + q(dir / "t1") + " --threads 1", dir / "err1.txt") == 0);
  REQUIRE(certify(q(scene) + " --out " + q(dir / "t2") + " --threads 2", dir / "err2.txt") == 0);
  // (the provenance block names each run's own command line and date)
  const std::string j1 = lgtest::withoutProvenance(lgtest::readFile(dir / "t1/compliance.json")),
                    j2 = lgtest::withoutProvenance(lgtest::readFile(dir / "t2/compliance.json"));
  CHECK(j1 == j2);
  CHECK(j1.find("provenance") == std::string::npos);
  CHECK(lgtest::withoutProvenance(lgtest::readFile(dir / "t1/compliance.md")) ==
        lgtest::withoutProvenance(lgtest::readFile(dir / "t2/compliance.md")));
  CHECK(lgtest::readFile(dir / "t1/compliance.md") != lgtest::readFile(dir / "t2/compliance.md"));
  CHECK(j1.find("\"drops\": 136") != std::string::npos);
  CHECK(j1.find("\"name\": \"cold-lowcharge-lowoil-largeorifice\", \"temperature_C\": -40") != std::string::npos);
  CHECK(j1.find("{\"metric\": \"stroke_margin\", \"relation\": \">=\", \"limit\": 0.01, \"unit\": \"m\", \"worst_corner\": "
                "\"cold-lowcharge-lowoil-largeorifice\", \"value\": 0.0164") != std::string::npos);
  // --nominal: no envelope section
  REQUIRE(certify(q(scene) + " --nominal --out " + q(dir / "n"), dir / "err3.txt") == 0);
  CHECK(lgtest::readFile(dir / "n/compliance.json").find("\"envelope\"") == std::string::npos);
  // the docs' example: the terminal lines of this run (the wall time aside)
  const std::string cmd = "'" + lgtest::binPath("certify") + "' " + q(scene) + " --out " + q(dir / "t3") + " --threads 2 > " +
                          q(dir / "out.txt");
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::string readme = lgtest::docsText();  // README.md and docs/
  std::istringstream out(lgtest::readFile(dir / "out.txt"));
  int lines = 0;
  for (std::string line; std::getline(out, line);) {
    if (line.rfind("wrote ", 0) == 0) continue;  // (the output folder differs)
    if (line.rfind("envelope: 17 points", 0) == 0) line = line.substr(0, line.find(" in "));  // (wall time)
    INFO(line);
    CHECK(readme.find(line) != std::string::npos);
    ++lines;
  }
  CHECK(lines == 15);
}

// Spin-up in the matrix: the main gear's scene cases drop at 60 m/s forward, so its matrix does too
// (certification forward_speed, default the scene's). The matrix's reserve drop is `simulate`'s drop at
// the same mass and forward speed, bit for bit; the drag at the vertical peak is the history's P_x at
// t_peak; without a forward speed the drop is milder (the verdict was judged on the milder drop).
TEST_CASE("certification: spin-up in the matrix at the scene's forward speed, the drag at the vertical peak",
          "[certification][tyre]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/main_gear.toml"));
  REQUIRE(sc.certification);
  const lg::Certification& c = *sc.certification;
  CHECK(c.forwardSpeed == 60.0);
  CHECK(c.forwardSpeedSource == "the scene's own cases' (the largest)");
  const lg::CertCase* reserve = c.findCase("cert-reserve");
  REQUIRE(reserve);
  CHECK(reserve->forwardSpeed == 60.0);
  const lg::Compliance comp = lg::assessCompliance(sc, c, 2);
  const lg::CaseMetrics& m = comp.cases[2].metrics;
  REQUIRE(m.longitudinal);
  lg::DropCase d;
  d.name = "by-hand";
  d.sinkSpeed = 3.66;
  d.liftRatio = 1.0;
  d.forwardSpeed = 60.0;
  d.duration = c.duration;
  d.masses["airframe"] = 4050.0 - (lg::caseMass(sc, lg::DropCase{}) - sc.model.bodies[sc.model.bodyIndex("airframe")].mass);
  CHECK(lg::caseMass(sc, d) == Approx(4050.0).epsilon(1e-15));
  lg::CaseOptions opt;
  opt.record = true;
  const lg::CaseResult byHand = lg::runCase(sc, d, opt);
  CHECK(byHand.metrics.peak_load_N == m.peak_load_N);
  CHECK(byHand.metrics.load_factor == m.load_factor);
  CHECK(byHand.metrics.drag_peak_N == m.drag_peak_N);
  CHECK(m.drag_peak_N > 30e3);  // spin-up
  CHECK(m.springback_peak_N > 0);
  // the drag at the vertical peak: the history's P_x at t_peak (the dense output there)
  lg::CaseOptions at;
  at.outputTimes = {m.t_peak_s};
  at.record = true;
  const lg::CaseResult row = lg::runCase(sc, d, at);
  REQUIRE(row.samples.size() == 1);
  const int px = row.column("P_x");
  REQUIRE(px >= 0);
  CHECK(m.drag_at_peak_N == Approx(row.samples[0].values[px]).margin(1e-9 * m.peak_load_N));
  CHECK(lg::metricValue(m, "drag_ratio") == m.drag_at_peak_N / m.peak_load_N);
  // the spin-up drop is the harder one: without a forward speed the matrix's n_g was 7 % lower
  lg::DropCase still = d;
  still.forwardSpeed = 0;
  const double calm = lg::runCase(sc, still).metrics.load_factor;
  CHECK(m.load_factor > 1.05 * calm);
  std::printf("certification: main gear reserve n_g %.3f with spin-up at 60 m/s, %.3f without; drag peak %.1f kN\n",
              m.load_factor, calm, m.drag_peak_N / 1e3);
}

// The dossier (sim/io/dossier.cpp): compliance.md holds every value of the scene with its unit, each
// case's rule paragraphs for its basis (Part 25, CS-25, Part 23), the derivation of h and W_e by hand,
// the method with each case's energy balance, the assumptions and the notes.
TEST_CASE("certification: the dossier holds the configuration, the rules' paragraphs and the assumptions",
          "[certification][dossier]") {
  const lg::Scene sc = lgtest::build(lgtest::shippedDoc("data/seed_gear.toml"));
  const lg::Compliance c = lg::assessCompliance(sc, *sc.certification, 2, {}, nullptr, false);
  const std::string md = lg::complianceMarkdown(c, ""), json = lg::complianceJson(c);
  // every key of every element, with its value and unit
  int rows = 0;
  for (const char* arr : {"body", "stop", "force"})
    for (const auto& e : *sc.doc[arr].as_array()) {
      const toml::table& t = *e.as_table();
      const std::string name = t["name"].value_or(std::string());
      for (const auto& [k, v] : t) {
        if (k.str() == "name") continue;
        INFO(arr << " " << name << " " << k.str());
        CHECK(md.find("| " + std::string(arr) + " " + name + " | " + std::string(k.str()) + " | ") != std::string::npos);
        ++rows;
      }
    }
  CHECK(rows > 50);
  CHECK(md.find("| force strut | p01 | 3000000 | Pa |") != std::string::npos);
  CHECK(md.find("| force strut | Omega0 | 0.0013 | m^3 |") != std::string::npos);
  CHECK(md.find("| force tyre | K | 800000 | N/m |") != std::string::npos);
  CHECK(json.find("{\"element\": \"force strut\", \"key\": \"f1\", \"value\": \"7e-05\", \"unit\": \"m^2\"}") != std::string::npos);
  // the rules' paragraphs of each basis
  for (const char* p : {"14 CFR 25.473(a)(2)(i)", "14 CFR 25.473(a)(2)(ii)", "14 CFR 25.723(b)", "25.727 before amendment 25-103"})
    CHECK(md.find(p) != std::string::npos);
  const lg::Scene cs = withCertification("basis = \"cs25\"\nlanding_mass = 4050.0\nlimit_load_factor = 2.5\n");
  const lg::Compliance ccs = lg::assessCompliance(cs, *cs.certification, 2);
  CHECK(lg::complianceMarkdown(ccs, "").find("CS 25.723(b) (reserve energy: 3.7 m/s") != std::string::npos);
  const lg::Scene p23 = withCertification("basis = \"part23\"\nlanding_mass = 4050.0\nwing_loading = 80.0\nlimit_load_factor = 2.7\n");
  const lg::Compliance c23 = lg::assessCompliance(p23, *p23.certification, 2);
  const std::string md23 = lg::complianceMarkdown(c23, "");
  CHECK(md23.find("14 CFR 23.473 (n >= 2.67, n_g >= 2.0") != std::string::npos);
  CHECK(md23.find("14 CFR 23.727 (reserve energy") != std::string::npos);
  // h = V^2 / (2 g) and W_e = W [h + (1 - L) d] / (h + d) by hand: L = 1 leaves W h / (h + d)
  const double h = 3.05 * 3.05 / (2 * 9.80665), d = c.cases[0].metrics.h_max_m;
  CHECK(lg::dropHeight(3.05, 9.80665) == Approx(h).epsilon(1e-15));
  CHECK(lg::effectiveMass(4050, 1.0, h, d) == Approx(4050 * h / (h + d)).epsilon(1e-14));
  CHECK(lg::effectiveMass(4050, 0.0, h, d) == Approx(4050).epsilon(1e-15));
  char row[200];
  std::snprintf(row, sizeof row, "| 4050 | 3.05 | 1 | %.4g | %.4g | %.5g | 0 |", h, d, 4050 * h / (h + d));
  CHECK(md.find(row) != std::string::npos);
  // the method with each case's accuracy, the assumptions, the notes
  CHECK(md.find("Integrator: dopri5, rtol 1e-06, atol 1e-08") != std::string::npos);
  char balance[80];
  std::snprintf(balance, sizeof balance, "| cert-reserve | %.3g |", c.cases[2].metrics.energy_balance_error);
  CHECK(md.find(balance) != std::string::npos);
  for (const char* a : {"## Assumptions and exclusions", "\"Must not fail\" in the reserve-energy drop is read as",
                        "The design takeoff mass, 4250 kg", "## Notes to the tables", "n = n_g + L, the inertia load factor"})
    CHECK(md.find(a) != std::string::npos);
}
