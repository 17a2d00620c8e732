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

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;
using namespace lg::optim;

namespace {

const std::string kScene = std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml";

fs::path tempDir() {
  const fs::path d = fs::temp_directory_path() / ("lg_study_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string write(const std::string& name, const std::string& text) {
  const fs::path p = tempDir() / name;
  std::ofstream(p) << text;
  return p.string();
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
         "[constraints]\n"                       // 10
         "stroke_max = 0.15\n"                   // 11
         "tyre_deflection_max = \"delta_max\"\n" // 12
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
  REQUIRE(s.cases.size() == 2);
  CHECK(s.cases[0].fromScene);
  CHECK(s.cases[0].dropCase.sinkSpeed == 3.05);
  CHECK_FALSE(s.cases[1].fromScene);
  CHECK(s.cases[1].dropCase.sinkSpeed == 3.3);
  CHECK(s.cases[1].dropCase.duration == 0.8);
  CHECK(s.constraints.tyreDeflectionFromScene);
  CHECK(s.algorithm.name == "LN_BOBYQA");
  CHECK(s.algorithm.maxeval == 10);
  CHECK(s.algorithm.seed == 3u);
  CHECK_FALSE(nativeConstraints(s.algorithm.name));
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
  SECTION("unknown algorithm") {
    expectError("algo.cfg", study(v, "[algorithm]\nname = \"LN_COBYLAX\"\n"), 18, "algorithm.name", "not an NLopt");
  }
  SECTION("gradient algorithm") {
    expectError("grad.cfg", study(v, "[algorithm]\nname = \"LD_MMA\"\n"), 18, "algorithm.name", "gradients");
  }
  SECTION("missing scene file") {
    std::string t = study(v);
    t.replace(0, t.find('\n'), "scene = \"no/such/scene.toml\"");
    expectError("scene.cfg", t, 1, "scene", "does not exist");
  }
  SECTION("unknown key") {
    expectError("key.cfg", study(v + "lowr = 1\n"), 17, "variable[0].lowr", "unknown key");
    expectError("key2.cfg", study(v, "[constraints2]\n"), 17, "constraints2", "unknown key");
  }
  SECTION("wrong type") {
    expectError("type.cfg", study("path = \"strut.f1\"\nlower = \"small\"\nupper = 1.6e-4\n"), 15, "variable[0].lower",
                "must be a number");
    expectError("type2.cfg", study(v, "[algorithm]\nmaxeval = 1.5\n"), 18, "algorithm.maxeval", "integer");
  }
  SECTION("bad objective and constraints") {
    std::string t = study(v);
    t.replace(t.find("min_peak_load"), 13, "min_weight");
    expectError("obj.cfg", t, 9, "objective.kind", "min_weight");
    std::string u = study(v);
    u.replace(u.find("\"delta_max\""), 11, "\"dmax\"");
    expectError("tyre.cfg", u, 12, "constraints.tyre_deflection_max", "dmax");
  }
  SECTION("unknown scene case") {
    std::string t = study(v);
    t.replace(t.find("\"limit\""), 7, "\"limmit\"");
    expectError("case.cfg", t, 3, "case[0].name", "not a case of the scene");
  }
  SECTION("TOML syntax") { expectError("syntax.cfg", study(v + "upper = = 3\n"), 17, "", "TOML syntax"); }
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
