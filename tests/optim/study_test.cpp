// Study files: every bad input is an InputError naming file, line and key; `optimize` exits 2 and
// writes nothing.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "optim/evaluator.hpp"
#include "optim/study.hpp"

#include "files_support.hpp"  // TempDir, readFile, writeFile

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;
using namespace lg::optim;

namespace {

// This test process's temporary directory (removed when it exits).
fs::path tempDir() {
  static const lgtest::TempDir dir("study_test");
  return dir.path;
}

// The seed gear without its [envelope]: the studies below test the mechanics of cases, roles and
// constraints on the eight cases of the scene and its matrix (the envelope's corners: the robust study's
// test and tests/optim/study_run_test.cpp).
std::string nominalSeedScene() {
  std::string text = lgtest::readFile(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml");
  text = text.substr(0, text.find("# ---- servicing and temperature envelope"));
  const std::string p = (tempDir() / "seed_gear.toml").string();
  lgtest::writeFile(p, text);
  return p;
}
const std::string kScene = nominalSeedScene();

std::string write(const std::string& name, const std::string& text) {
  const std::string p = (tempDir() / name).string();
  lgtest::writeFile(p, text);
  return p;
}

// A valid study; 'extra' is appended (lines 14 on).
std::string study(const std::string& variable, const std::string& extra = "") {
  return "scene = \"" + kScene + "\"\n"          // 1
         "[[case]]\n"                            // 2
         "name = \"limit\"\n"                    // 3
         "[[case]]\n"                            // 4
         "name = \"hard\"\n"                     // 5
         "sink_speed = 3.3\n"                    // 6
         "lift_ratio = 1.0\n"                    // 7
         "[objective]\n"                         // 8
         "kind = \"min_peak_load\"\n"            // 9
         "[[constraint]]\n"                      // 10
         "metric = \"stroke_margin\"\n"          // 11
         "min = 0.01\n"                          // 12
         "[[variable]]\n"                        // 13
         + variable + extra;                     // 14...
}

void expectError(const std::string& file, const std::string& text, int line, const std::string& key,
                 const std::string& words) {
  const std::string path = write(file, text);
  try {
    (void)loadStudy(path);
    FAIL("no InputError for " << file);
  } catch (const lg::InputError& e) {
    INFO(e.what());
    CHECK(e.file() == path);
    CHECK(e.line() == line);
    CHECK(e.key() == key);
    CHECK(std::string(e.what()).find(words) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("study: a valid file parses with defaults from the scene", "[optim][study]") {
  const std::string path =
      write("good.cfg", study("path = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\nlog = true\n",
                              "[[variable]]\npath = \"tyre.K\"\nlower = 5e5\nupper = 1.2e6\ninitial = 9e5\n"
                              "[algorithm]\nname = \"LN_BOBYQA\"\nmaxeval = 10\nseed = 3\n"));
  const Study s = loadStudy(path);
  REQUIRE(s.variables.size() == 2);
  CHECK(s.variables[0].initial == 7.0e-5);  // the scene's value
  CHECK(s.variables[0].log);
  CHECK(s.variables[1].initial == 9e5);
  // the study's two cases (objective, the default role), then the matrix's and the scene's others as checks
  REQUIRE(s.cases.size() == 2 + 3 + 4);
  CHECK(s.steeringCases() == 2);
  CHECK(s.cases[0].dropCase.name == "limit");
  CHECK(s.cases[0].origin == CaseOrigin::Scene);
  CHECK(s.cases[0].role == CaseRole::Objective);
  CHECK(s.cases[0].dropCase.sinkSpeed == 3.05);
  CHECK(s.cases[1].origin == CaseOrigin::Study);
  CHECK(s.cases[1].dropCase.sinkSpeed == 3.3);
  CHECK(s.cases[1].dropCase.duration == 0.8);
  const std::vector<std::string> checks{"cert-limit-landing", "cert-limit-takeoff", "cert-reserve", "light", "medium",
                                        "reserve", "free-drop"};
  for (size_t i = 0; i < checks.size(); ++i) {
    CHECK(s.cases[2 + i].dropCase.name == checks[i]);
    CHECK(s.cases[2 + i].role == CaseRole::Check);
  }
  CHECK(s.certificationRole == CaseRole::Check);  // no [certification] in the study: the matrix is reported
  // one constraint on each steering case
  REQUIRE(s.constraints.size() == 1);
  CHECK(s.constraints[0].metric == "stroke_margin");
  CHECK_FALSE(s.constraints[0].upper);
  CHECK(s.constraints[0].bound == 0.01);
  REQUIRE(s.items.size() == 2);
  CHECK(s.items[0].name == "stroke_margin_min@limit");
  CHECK(s.items[1].name == "stroke_margin_min@hard");
  CHECK(s.algorithm.name == "LN_BOBYQA");
  CHECK(s.algorithm.maxeval == 10);
  CHECK(s.algorithm.seed == 3u);
  CHECK_FALSE(nativeConstraints(s.algorithm.name));
}

// The shipped main study: the matrix's limit cases are the objective, its reserve case and limits
// constrain the design, the scene's own cases are checks.
// The robust main study: its three matrix cases at the nominal point and the 16 corners of the envelope
// ("<case>@<corner>"), the objective cases' corner copies constraining, every limit at every point; the
// checks at every point too.
TEST_CASE("study: the robust main study runs every matrix case at every corner of the envelope", "[optim][study][envelope]") {
  const Study s = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak.cfg");
  REQUIRE(s.corners.size() == 17);
  CHECK(s.envelope.constraintsAtCorners);
  CHECK_FALSE(s.envelope.objectiveWorst);
  REQUIRE(s.steeringCases() == 51);
  CHECK(s.cases[0].dropCase.name == "cert-limit-landing");
  CHECK(s.cases[0].role == CaseRole::Objective);
  CHECK(s.cases[0].corner == "nominal");
  CHECK(s.cases[1].dropCase.name == "cert-limit-landing@cold-lowcharge-lowoil-smallorifice");
  CHECK(s.cases[1].role == CaseRole::Constraint);
  CHECK(s.cases[1].baseRole == CaseRole::Objective);
  CHECK(s.cases[1].dropCase.corner->at.temperature == Approx(233.15).epsilon(1e-15));
  int objective = 0;
  for (const auto& c : s.cases) objective += c.role == CaseRole::Objective ? 1 : 0;
  CHECK(objective == 2);  // the two limit drops, nominal
  CHECK(s.cases.size() == 51 + 5 * 17);
  CHECK(s.items.size() == 153);
  bool found = false;
  for (const auto& it : s.items) found = found || it.name == "stroke_margin_min@cert-reserve@cold-lowcharge-lowoil-largeorifice";
  CHECK(found);
  // a robust design cannot choose its servicing; a worst-corner objective needs aggregate "worst"
  const std::string head = "scene = \"" + std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml\"\n";
  CHECK_THROWS_WITH(parseStudy(head + "[[variable]]\npath = \"envelope.charge\"\nlower = -0.1\nupper = 0.1\n"
                               "[[case]]\nname = \"limit\"\n[envelope]\nconstraints = \"corners\"\n[algorithm]\nmaxeval = 5\n",
                               "s.cfg"),
                    Catch::Contains("a robust design cannot choose its servicing"));
  CHECK_THROWS_WITH(parseStudy(head + "[[variable]]\npath = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n"
                               "[[case]]\nname = \"limit\"\n[objective]\naggregate = \"weighted_sum\"\n"
                               "[envelope]\nobjective = \"worst\"\n[algorithm]\nmaxeval = 5\n",
                               "s.cfg"),
                    Catch::Contains("needs [objective] aggregate = \"worst\""));
  CHECK_THROWS_WITH(parseStudy(head + "[[variable]]\npath = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n"
                               "[[case]]\nname = \"limit\"\n[envelope]\nconstraints = \"every\"\n[algorithm]\nmaxeval = 5\n",
                               "s.cfg"),
                    Catch::Contains("s.cfg:9: key 'envelope.constraints': value 'every' must be \"corners\" or \"nominal\""));
  // a key of the scene's envelope overridden in the study: its errors name the study's line
  CHECK_THROWS_WITH(parseStudy(head + "[[variable]]\npath = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n"
                               "[[case]]\nname = \"limit\"\n[envelope]\ncharge_tolerance = 2.0\n[algorithm]\nmaxeval = 5\n",
                               "s.cfg"),
                    Catch::Contains("s.cfg:9: key 'envelope.charge_tolerance': value 2 must be below 1"));
  // and a study's override reaches the corners: a narrower temperature range, the same 17 points
  const Study narrow = parseStudy(head + "[[variable]]\npath = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n"
                                  "[[case]]\nname = \"limit\"\n[envelope]\nlanding_temperature_C = [-20.0, 40.0]\n"
                                  "[algorithm]\nmaxeval = 5\n", "s.cfg");
  REQUIRE(narrow.corners.size() == 17);
  CHECK(narrow.corners[1].at.temperature == Approx(253.15).epsilon(1e-15));
}

TEST_CASE("study: the main study is constrained by the certification matrix", "[optim][study]") {
  std::string text = lgtest::readFile(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak_nominal.cfg");
  text.replace(text.find("constraints = \"nominal\""), 23, "constraints = \"nominal\"\nchecks = \"nominal\"");
  const Study s = parseStudy(text, "nominal.cfg", std::string(LG_SOURCE_DIR) + "/studies");
  REQUIRE(s.certification);
  CHECK(s.certification->basisName == "part25");
  CHECK(s.certificationRole == CaseRole::Constraint);
  const std::vector<std::pair<std::string, CaseRole>> expected{
      {"cert-limit-landing", CaseRole::Objective}, {"cert-limit-takeoff", CaseRole::Objective},
      {"cert-reserve", CaseRole::Constraint},      {"light", CaseRole::Check},
      {"medium", CaseRole::Check},                 {"limit", CaseRole::Check},
      {"reserve", CaseRole::Check},                {"free-drop", CaseRole::Check}};
  REQUIRE(s.cases.size() == expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    INFO(expected[i].first);
    CHECK(s.cases[i].dropCase.name == expected[i].first);
    CHECK(s.cases[i].role == expected[i].second);
  }
  // W made up through the airframe: 4250 kg on the unit at the takeoff weight (gear bodies 70 kg)
  CHECK(s.cases[1].dropCase.masses.at("airframe") == 4250.0 - 70.0);
  CHECK(s.cases[1].dropCase.sinkSpeed == 1.83);
  // the rules' limits on every matrix case: load factor (ultimate in the reserve case), stroke margin, tyre
  const std::vector<std::string> names{"load_factor_max@cert-limit-landing", "stroke_margin_min@cert-limit-landing",
                                       "tyre_margin_min@cert-limit-landing", "load_factor_max@cert-limit-takeoff",
                                       "stroke_margin_min@cert-limit-takeoff", "tyre_margin_min@cert-limit-takeoff",
                                       "load_factor_max@cert-reserve", "stroke_margin_min@cert-reserve",
                                       "tyre_margin_min@cert-reserve"};
  REQUIRE(s.items.size() == names.size());
  for (size_t i = 0; i < names.size(); ++i) CHECK(s.items[i].name == names[i]);
  CHECK(s.constraints[s.items[0].spec].bound == 2.5);
  CHECK(s.constraints[s.items[1].spec].bound == 0.01);
  CHECK(s.constraints[s.items[2].spec].bound == 0.0);
  CHECK(s.constraints[s.items[6].spec].bound == Approx(3.75).epsilon(1e-15));
  // best.toml keeps the matrix
  CHECK(designDocument(s, s.variables.empty() ? std::vector<double>{} : std::vector<double>(
                                                    {7e-5, 5e-5, 3e6, 1.3e-3, 8e5}))["certification"]["basis"]
            .value_or(std::string()) == "part25");
}

// Each role and each constraint kind on synthetic metrics (an analytic problem: the answer is known).
TEST_CASE("study: roles and constraint kinds reduce as documented", "[optim][study]") {
  const std::string v = "path = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n";
  const std::string extra =
      "[[case]]\nname = \"soft\"\nrole = \"constraint\"\nsink_speed = 1.0\nlift_ratio = 1.0\n"
      "[[case]]\nname = \"medium\"\nrole = \"check\"\n"
      "[[constraint]]\nmetric = \"load_factor\"\nmax = 2.0\ncases = \"objective\"\n"
      "[[constraint]]\nmetric = \"efficiency\"\nmin = 0.7\nmax = 0.9\ncases = [\"soft\"]\n"
      "[[constraint]]\nmetric = \"tyre_deflection\"\nmax = 0.09\ncases = \"constraint\"\n";
  Study s = loadStudy(write("roles.cfg", study(v, extra)));
  REQUIRE(s.steeringCases() == 3);  // limit, hard (objective), soft (constraint); medium is a check
  CHECK(s.cases[2].dropCase.name == "soft");
  CHECK(s.cases[3].dropCase.name == "medium");
  CHECK(s.cases[3].role == CaseRole::Check);
  const std::vector<std::string> names{"stroke_margin_min@limit", "stroke_margin_min@hard", "stroke_margin_min@soft",
                                       "load_factor_max@limit",   "load_factor_max@hard",   "efficiency_max@soft",
                                       "efficiency_min@soft",     "tyre_deflection_max@soft"};
  REQUIRE(s.items.size() == names.size());
  for (size_t i = 0; i < names.size(); ++i) CHECK(s.items[i].name == names[i]);
  auto metrics = [](const std::string& n, double peak, double eta, double ng, double margin, double tyre) {
    lg::CaseMetrics m;
    m.name = n;
    m.peak_load_N = peak;
    m.efficiency = eta;
    m.load_factor = ng;
    m.stroke_margin_m = margin;
    m.tyre_deflection_max_m = tyre;
    return m;
  };
  // a check case that fails its simulation changes nothing; the constraint case never enters the objective
  std::vector<lg::CaseMetrics> cases{metrics("limit", 80e3, 0.70, 2.1, 0.020, 0.08),
                                     metrics("hard", 90e3, 0.65, 1.9, 0.005, 0.09),
                                     metrics("soft", 200e3, 0.95, 5.0, 0.050, 0.10)};
  lg::CaseMetrics broken = metrics("medium", NAN, NAN, NAN, NAN, NAN);
  broken.ok = false;
  cases.push_back(broken);
  Evaluation e = reduceMetrics(s, cases, NAN);
  REQUIRE(e.ok);
  CHECK(e.objective == 90e3);  // worst objective case: max peak of limit and hard, not soft's 200 kN
  const std::vector<double> g{0.01 - 0.020, 0.01 - 0.005, 0.01 - 0.050, 2.1 - 2.0, 1.9 - 2.0, 0.95 - 0.9, 0.7 - 0.95,
                              0.10 - 0.09};
  REQUIRE(e.constraints.size() == g.size());
  for (size_t i = 0; i < g.size(); ++i) CHECK(e.constraints[i] == Approx(g[i]).margin(1e-15));
  CHECK_FALSE(isFeasible(e));
  // weighted sum over the objective cases, and the efficiency objective's worst = the smallest
  s.objective.aggregate = Aggregate::WeightedSum;
  CHECK(reduceMetrics(s, cases, NAN).objective == 80e3 + 90e3);
  s.objective.kind = ObjectiveKind::MaxEfficiency;
  s.objective.aggregate = Aggregate::Worst;
  CHECK(reduceMetrics(s, cases, NAN).objective == 0.65);
  // a steering case that fails makes the evaluation fail, with its reason
  cases[2].ok = false;
  cases[2].message = "contact solve failed";
  e = reduceMetrics(s, cases, NAN);
  CHECK_FALSE(e.ok);
  CHECK(e.message == "case 'soft': contact solve failed");
}

TEST_CASE("study: bad files name file, line and key", "[optim][study]") {
  const std::string v = "path = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n";  // lines 14-16
  SECTION("unknown parameter path") {
    expectError("path.cfg", study("path = \"strut.f9\"\nlower = 1\nupper = 2\n"), 14, "variable[0].path", "strut.f9");
  }
  SECTION("reversed bounds") {
    expectError("bounds.cfg", study("path = \"strut.f1\"\nlower = 1e-4\nupper = 5e-5\n"), 16, "variable[0].upper",
                "greater than lower");
  }
  SECTION("initial outside the bounds") {
    expectError("initial.cfg", study(v + "initial = 2e-4\n"), 17, "variable[0].initial", "must lie in");
  }
  SECTION("scene value outside the bounds without initial") {
    expectError("default.cfg", study("path = \"strut.f1\"\nlower = 1e-4\nupper = 2e-4\n"), 14, "variable[0].path",
                "outside");
  }
  SECTION("a metric the scene does not measure") {
    expectError("drag.cfg", study(v, "[[constraint]]\nmetric = \"drag_peak\"\nmax = 5e4\n"), 18, "constraint[1].metric",
                "'drag_peak' needs a tyre with a longitudinal force (mu_x: wheel spin-up) in the scene");
  }
  SECTION("unknown algorithm") {
    expectError("algo.cfg", study(v, "[algorithm]\nname = \"LN_COBYLAX\"\n"), 18, "algorithm.name", "not an NLopt");
  }
  SECTION("gradient algorithm") {
    expectError("grad.cfg", study(v, "[algorithm]\nname = \"LD_TNEWTON\"\n"), 18, "algorithm.name",
                "not one of the gradient algorithms supported");
    expectError("lbfgs.cfg", study(v, "[algorithm]\nname = \"LD_LBFGS\"\n"), 18, "algorithm.name", "bounds only");
    expectError("mlsl.cfg", study(v, "[algorithm]\nname = \"GD_MLSL\"\nlocal = \"LN_BOBYQA\"\n"), 19, "algorithm.local",
                "must be a gradient algorithm");
    expectError("static.cfg",
                study(v, "[[constraint]]\nmetric = \"static_stroke\"\nmax = 0.1\n[algorithm]\nname = \"LD_SLSQP\"\n"), 21,
                "algorithm.name", "static_stroke constraint has none");
  }
  SECTION("missing scene file") {
    std::string t = study(v);
    t.replace(0, t.find('\n'), "scene = \"no/such/scene.toml\"");
    expectError("scene.cfg", t, 1, "scene", "no/such/scene.toml': no such file (the path is relative to the study file)");
  }
  SECTION("unknown key") {
    expectError("key.cfg", study(v + "lowr = 1\n"), 17, "variable[0].lowr", "unknown key");
    expectError("key2.cfg", study(v, "[constraint2]\n"), 17, "constraint2", "unknown key");
  }
  SECTION("wrong type") {
    expectError("type.cfg", study("path = \"strut.f1\"\nlower = \"small\"\nupper = 1.6e-4\n"), 15, "variable[0].lower",
                "must be a number");
    expectError("type2.cfg", study(v, "[algorithm]\nmaxeval = 1.5\n"), 18, "algorithm.maxeval", "integer");
  }
  SECTION("a bound that breaks the parameter's own rule") {
    expectError("neg.cfg", study("path = \"strut.f1\"\nlower = -1e-5\nupper = 1.6e-4\ninitial = 7e-5\n"), 15,
                "variable[0].lower", "value -1e-05 breaks the rule of strut.f1: ");
    // a rule that ties it to another value is the study's to cross (an infeasible design, not bad input)
    const Study s = loadStudy(write("cross.cfg", study("path = \"strut.Omega0\"\nlower = 1e-4\nupper = 2e-3\n")));
    CHECK(s.variables[0].lower == 1e-4);
  }
  SECTION("bad objective and constraints") {
    std::string t = study(v);
    t.replace(t.find("min_peak_load"), 13, "min_weight");
    expectError("obj.cfg", t, 9, "objective.kind", "min_weight");
    std::string u = study(v);
    u.replace(u.find("\"stroke_margin\""), 15, "\"stroke_margn\"");
    expectError("metric.cfg", u, 11, "constraint[0].metric", "stroke_margn");
    std::string w = study(v);
    w.insert(w.find("[[constraint]]"), "aggregate = \"max\"\n");
    expectError("agg2.cfg", w, 10, "objective.aggregate", "\"worst\"");
    expectError("bound.cfg", study(v, "[[constraint]]\nmetric = \"efficiency\"\n"), 18, "constraint[1].metric",
                "give a bound");
    expectError("minmax.cfg", study(v, "[[constraint]]\nmetric = \"efficiency\"\nmin = 0.9\nmax = 0.8\n"), 20,
                "constraint[1].max", "greater than min");
    // a bound of the wrong sign, or beyond what the metric can take, can never hold: refused, not run
    expectError("sign.cfg", study(v, "[[constraint]]\nmetric = \"stroke\"\nmax = -0.15\n"), 19, "constraint[1].max",
                "value -0.15 m can never hold: stroke is >= 0 (a margin is stroke_margin, with min = ...)");
    expectError("sign2.cfg", study(v, "[[constraint]]\nmetric = \"tyre_deflection\"\nmax = -0.15\n"), 19,
                "constraint[1].max", "value -0.15 m can never hold: tyre_deflection is >= 0 (a margin is tyre_margin");
    expectError("sign3.cfg", study(v, "[[constraint]]\nmetric = \"static_stroke\"\nmax = -0.01\n"), 19,
                "constraint[1].max", "value -0.01 m can never hold: static_stroke is >= 0");
    expectError("above.cfg", study(v, "[[constraint]]\nmetric = \"efficiency\"\nmin = 1.2\n"), 19, "constraint[1].min",
                "value 1.2 can never hold: efficiency is <= 1");
    expectError("check.cfg",
                study(v, "[[constraint]]\nmetric = \"peak_load\"\nmax = 9e4\ncases = [\"free-drop\"]\n"), 20,
                "constraint[1].cases", "check case");
    expectError("sel.cfg", study(v, "[[constraint]]\nmetric = \"peak_load\"\nmax = 9e4\ncases = \"constraint\"\n"), 20,
                "constraint[1].cases", "selects no case");
    expectError("static.cfg", study(v, "[[constraint]]\nmetric = \"static_stroke\"\nmax = 0.1\ncases = \"objective\"\n"),
                20, "constraint[1].cases", "figure of the design");
    std::string old = study(v);
    old.replace(old.find("[[constraint]]"), 14, "[constraints]");
    expectError("old.cfg", old, 10, "constraints", "[[constraint]]");
  }
  SECTION("bad roles and matrix cases") {
    expectError("role.cfg", study(v, "[[case]]\nname = \"medium\"\nrole = \"steer\"\n"), 19, "case[2].role",
                "\"objective\", \"constraint\" or \"check\"");
    expectError("noobj.cfg",
                "scene = \"" + kScene + "\"\n[[case]]\nname = \"limit\"\nrole = \"check\"\n[[variable]]\n" + v, 0,
                "case", "no objective case");
    expectError("certover.cfg", study(v, "[[case]]\nname = \"cert-reserve\"\nsink_speed = 4.0\n"), 19,
                "case[2].sink_speed", "certification matrix");
    expectError("certrole.cfg", study(v, "[certification]\nrole = \"objective\"\n"), 18, "certification.role",
                "cannot be the objective");
    expectError("certkey.cfg", study(v, "[certification]\nlimit_load_factor = -1\n"), 18,
                "certification.limit_load_factor", "> 0");
    expectError("sink.cfg", study(v, "[[case]]\nname = \"zero\"\nsink_speed = 0.0\nlift_ratio = 1\n"), 19,
                "case[2].sink_speed", "must be > 0");
  }
  SECTION("unknown scene case") {
    std::string t = study(v);
    t.replace(t.find("\"limit\""), 7, "\"limmit\"");
    expectError("case.cfg", t, 3, "case[0].name", "not a case of the scene or of its certification matrix");
  }
  SECTION("TOML syntax") {
    expectError("syntax.cfg", study(v + "upper = = 3\n"), 17, "upper", "TOML syntax");
    expectError("syntax2.cfg", study(v + "log true\n"), 17, "log", "TOML syntax");
  }
  SECTION("bad solver settings") {
    expectError("solver1.cfg", study(v, "[solver]\nintegrator = \"rk5\"\n"), 18, "solver.integrator", "ros34pw2");
    expectError("solver2.cfg", study(v, "[solver]\nrtol = -1e-4\n"), 18, "solver.rtol", "> 0");
    expectError("solver3.cfg", study(v, "[solver]\norder = 3\n"), 18, "solver.order", "unknown key");
  }
}

// A study's [solver] goes into the scene it runs: the baseline, every design and best.toml (the design
// document) use its integrator and tolerances; without it the scene's own settings stand.
TEST_CASE("study: [solver] sets the integrator of every design", "[optim][study]") {
  const std::string v = "path = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n";
  const Study plain = loadStudy(write("plain.cfg", study(v)));
  CHECK(plain.scene.model.settings.integrator == lg::IntegratorKind::DormandPrince);
  CHECK(plain.scene.model.settings.rtol == 1e-6);
  const Study fast = loadStudy(write("fast.cfg", study(v, "[solver]\nintegrator = \"ros34pw2\"\nrtol = 1e-4\n")));
  CHECK(fast.scene.model.settings.integrator == lg::IntegratorKind::Ros34pw2);
  CHECK(fast.scene.model.settings.rtol == 1e-4);
  CHECK(fast.scene.model.settings.atol == Approx(1e-6).epsilon(1e-12));
  const toml::table design = designDocument(fast, {8e-5});
  CHECK(design["solver"]["integrator"].value_or(std::string()) == "ros34pw2");
  CHECK(design["solver"]["rtol"].value_or(0.0) == 1e-4);
  CHECK(design["force"][2]["f1"].value_or(0.0) == 8e-5);
}

TEST_CASE("study: optimize exits with status 2 on a bad file and writes nothing", "[optim][study]") {
  const std::string path = write("cli_bad.cfg", study("path = \"strut.f1\"\nlower = 1e-4\nupper = 5e-5\n"));
  const fs::path out = tempDir() / "cli_out";
  fs::remove_all(out);
  const std::string cmd = std::string(LG_BIN_DIR) + "/optimize '" + path + "' --out '" + out.string() + "' --quiet 2>'" +
                          (tempDir() / "cli_err.txt").string() + "'";
  const int rc = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(rc));
  CHECK(WEXITSTATUS(rc) == 2);
  CHECK_FALSE(fs::exists(out));
  std::ifstream err(tempDir() / "cli_err.txt");
  std::string msg((std::istreambuf_iterator<char>(err)), std::istreambuf_iterator<char>());
  CHECK(msg.find("cli_bad.cfg:16: key 'variable[0].upper'") != std::string::npos);
}

// Without a [solver] of its own a study keeps the scene's setting where that is accurate enough for its
// stopping tolerances (a tenth of xtol_rel / ftol_rel), else it runs at the accuracy they need; it says
// which. A [solver] accuracy chooses integrator and tolerances, and excludes integrator, rtol and atol.
TEST_CASE("study: the drop-test solver is accurate enough for the study's tolerances, and says which",
          "[optim][study][accuracy]") {
  const std::string v = "path = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n";
  // The shipped scene (dopri5, rtol 1e-6: metrics to about 1e-5) meets xtol_rel 1e-4's need of 1e-5.
  const Study plain = loadStudy(write("acc_plain.cfg", study(v)));
  CHECK(plain.accuracyNeeded == 1e-5);
  CHECK(plain.scene.model.settings.integrator == lg::IntegratorKind::DormandPrince);
  CHECK(plain.solverChoice == "dopri5, rtol 1e-06: the scene's [solver], metrics to about 1e-05, within the 1e-05 that "
                              "the study's xtol_rel / ftol_rel of 0.0001 needs");
  // A loose scene (ros34pw2 at rtol 1e-2, beyond the calibration's kRosRtolMax) is tightened to the
  // accuracy the study needs.
  std::string scene;
  {
    std::ifstream in(kScene);
    scene.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  }
  const auto at = scene.find("integrator = \"dopri5\"");
  REQUIRE(at != std::string::npos);
  scene.replace(at, 21, "integrator = \"ros34pw2\"");
  const auto rt = scene.find("rtol = 1e-6");
  REQUIRE(rt != std::string::npos);
  scene.replace(rt, 11, "rtol = 1e-2");
  const std::string loose = write("loose_scene.toml", scene);
  auto onLoose = [&](const std::string& extra) {
    std::string text = study(v, extra);
    text.replace(text.find(kScene), kScene.size(), loose);
    return text;
  };
  const Study tightened = loadStudy(write("acc_loose.cfg", onLoose("[algorithm]\nxtol_rel = 1e-3\n")));
  CHECK(tightened.accuracyNeeded == 1e-4);
  CHECK(tightened.scene.model.settings.integrator == lg::IntegratorKind::DormandPrince);
  CHECK(tightened.scene.model.settings.rtol == 5e-5);
  CHECK(tightened.scene.model.settings.accuracy == 1e-4);
  CHECK(tightened.solverChoice == "accuracy 0.0001 (dopri5, rtol 5e-05): the 0.0001 that the study's xtol_rel / "
                                  "ftol_rel of 0.001 needs (the scene's ros34pw2, rtol 0.01 gives an accuracy the calibration "
                                  "does not cover)");
  const toml::table design = designDocument(tightened, {8e-5});  // best.toml runs the same way
  CHECK(design["solver"]["accuracy"].value_or(0.0) == 1e-4);
  CHECK_FALSE(design["solver"]["integrator"]);
  // The study's own [solver] stands, and the report says whether it is accurate enough.
  const Study own = loadStudy(write("acc_own.cfg", onLoose("[solver]\naccuracy = 1e-3\n[algorithm]\nxtol_rel = 1e-3\n")));
  CHECK(own.scene.model.settings.integrator == lg::IntegratorKind::DormandPrince);
  CHECK(own.scene.model.settings.rtol == 5e-4);
  CHECK(own.solverChoice.find("the study's [solver], metrics to about 0.001, NOT within the 0.0001") != std::string::npos);
  expectError("acc_both.cfg", onLoose("[solver]\naccuracy = 1e-3\nrtol = 1e-4\n"), 19, "solver.rtol",
              "give either accuracy or rtol");
  expectError("acc_range.cfg", onLoose("[solver]\naccuracy = 0.5\n"), 18, "solver.accuracy", "between 1e-05 and 0.1");
}

TEST_CASE("study cases: a study's [[case]] reads a drop by the scene's keys and rules", "[study]") {
  const std::string head = "scene = \"" + std::string(LG_SOURCE_DIR) +
                           "/data/seed_gear.toml\"\n[[variable]]\npath = \"strut.f1\"\nlower = 3e-5\nupper = 1.6e-4\n";
  // a new case released from a height: at rest, 0.8 s past its fall (sim/io/drop_case.hpp)
  const Study s = parseStudy(head + "[[case]]\nname = \"from-height\"\ndrop_height = 0.3\nlift_ratio = 0.0\n", "s.cfg");
  REQUIRE(s.cases.size() > 1);
  const lg::DropCase& d = s.cases[0].dropCase;
  CHECK(d.name == "from-height");
  CHECK(s.cases[0].origin == CaseOrigin::Study);
  CHECK(d.dropHeight == 0.3);
  CHECK(d.sinkSpeed == 0);
  CHECK(d.duration == Approx(0.8 + std::sqrt(2 * 0.3 / s.scene.gravity)).epsilon(1e-15));
  // the scene's rules, in the scene's words, at the study's line
  CHECK_THROWS_WITH(parseStudy(head + "[[case]]\nname = \"x\"\nsink_speed = 0.0\nlift_ratio = 0.0\n", "s.cfg"),
                    Catch::StartsWith("s.cfg:8: key 'case[0].sink_speed': value 0 must be > 0 [m/s]"));
  CHECK_THROWS_WITH(parseStudy(head + "[[case]]\nname = \"x\"\nsink_speed = 3.0\nlift_ratio = 0.0\nforward_speed = 5.0\n", "s.cfg"),
                    "s.cfg:10: key 'case[0].forward_speed': no tyre of this scene declares the longitudinal friction "
                    "coefficient mu_x");
  // a matrix case's numbers come from [certification], a forward speed among them
  CHECK_THROWS_WITH(parseStudy(head + "[[case]]\nname = \"cert-reserve\"\nforward_speed = 1.0\n", "s.cfg"),
                    Catch::StartsWith("s.cfg:8: key 'case[0].forward_speed': 'cert-reserve' is a case of the certification matrix"));
}
