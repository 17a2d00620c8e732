// The scene parser (sim/io/scene.cpp): the shipped scenes load; bad input gives lg::InputError naming
// the file, the line and the key, and `simulate` on such a file exits with status 2 without writing.
#include "scene_support.hpp"  // sim headers, then Catch (see there)

#include <sys/wait.h>

#include <cstdlib>

namespace {

// 1-based line of the first occurrence of 'needle' in 'text' (0 if absent).
int lineOf(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  if (pos == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

// Replaces the first occurrence of 'from' (which must exist) by 'to'.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  return text.replace(pos, from.size(), to);
}

struct BadScene {
  std::string what;      // what is wrong
  std::string text;      // the scene
  std::string marker;    // text starting on the line the error must name (the table's header for a missing key)
  std::string key;       // what the message must name as the key
  std::string rule;      // a word of the rule
};

int runSimulate(const std::string& scene, const std::string& out, const std::string& errFile) {
  const std::string cmd = "'" + lgtest::binPath("simulate") + "' '" + scene + "' --out '" + out + "' --quiet --threads 1 2>'" +
                          errFile + "' >/dev/null";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

}  // namespace

TEST_CASE("shipped scenes load", "[scene]") {
  for (const char* f : {"data/seed_gear.toml", "data/telescopic_gear.toml", "data/seed_gear_metering_pin.toml"}) {
    INFO(f);
    const lg::Scene sc = lg::loadScene(lgtest::sourcePath(f));
    CHECK(sc.roles.airframe == "airframe");
    CHECK(sc.roles.tyres.size() == 1);
    CHECK(sc.roles.struts.size() == 1);
    CHECK(sc.roles.stops.size() == 2);
    CHECK(sc.roles.lifts.size() == 1);
    CHECK(!sc.cases.empty());
  }
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  CHECK(seed.model.nBodies() == 5);
  double G = 0;
  for (const auto& b : seed.model.bodies) G += b.mass;
  CHECK(G == Approx(4050.0));
  // Rows: revolute 5 + 5, spherical 3 + 3, sliding 4, two stops, the strut's friction lock (exact
  // Coulomb friction); the rig's prismatic joint to the ground is eliminated into the airframe's
  // mobility (translation along y), its 5 rows not built.
  CHECK(seed.model.nRows == 5 + 5 + 3 + 3 + 4 + 2 + 1);
  CHECK(seed.model.mobility[seed.model.bodyIndex("airframe")] == lg::kTranslation);
  const lg::Scene tele = lg::loadScene(lgtest::sourcePath("data/telescopic_gear.toml"));
  CHECK(tele.model.nBodies() == 4);
  // Rows: fixed 6 + prismatic 5 (strut) + revolute 5, two stops, the friction lock, the rig eliminated;
  // 24 coordinates - 5 (rig) - 16 bilateral rows = 3 degrees of freedom: airframe height, stroke, wheel spin.
  CHECK(tele.model.nRows == 6 + 5 + 5 + 2 + 1);
}

TEST_CASE("bad input names file, line and key, and simulate exits with 2 and writes nothing", "[scene][input]") {
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string pin = lgtest::readFile(lgtest::sourcePath("data/seed_gear_metering_pin.toml"));
  const std::string leverMass = "mass = 16.0\n";
  std::vector<BadScene> bad = {
      {"missing key", replaced(seed, leverMass, ""), "[[body]]\nname = \"lever\"", "body[1].mass", "missing"},
      {"unknown key", replaced(seed, leverMass, leverMass + "colour = \"red\"\n"), "colour", "body[1].colour", "unknown key"},
      {"negative area", replaced(seed, "f1 = 7.0e-5", "f1 = -7.0e-5"), "f1 = -7.0e-5", "force[2].f1", "> 0"},
      {"negative mass", replaced(seed, "mass = 20.0", "mass = -20.0"), "mass = -20.0", "body[0].mass", "> 0"},
      {"zero inertia", replaced(seed, "inertia = [0.45, 0.45, 0.80]", "inertia = [0.45, 0.0, 0.80]"), "inertia = [0.45, 0.0",
       "body[0].inertia", "> 0"},
      {"p_atm not below p01", replaced(seed, "mu = 0.05", "p_atm = 4.0e6\nmu = 0.05"), "p_atm = 4.0e6", "force[2].p_atm",
       "< p01"},
      {"joint naming an unknown body", replaced(seed, "body1 = \"wheel\"", "body1 = \"wheels\""), "body1 = \"wheels\"",
       "joint[1].body1", "not a body"},
      {"stop violated at t = 0", replaced(seed, "max_distance = 0.60", "max_distance = 0.59"), "[[stop]]\nname = \"extension\"",
       "stop.extension", "violate"},
      {"joint violated at t = 0",
       seed + "\n[[joint]]\nname = \"guide\"\ntype = \"point_on_plane\"\nbody1 = \"wheel\"\nbody2 = \"ground\"\n"
              "point = [-0.40, 0.30, 0.0]\nplane_point = [0.0, 0.0, 0.05]\nnormal = [0.0, 0.0, 1.0]\n",
       "[[joint]]\nname = \"guide\"", "joint.guide", "violate"},
      {"missing table", replaced(pin, "tables/metering_pin.csv", "tables/no_such_pin.csv"), "f1_table", "force[2].f1_table",
       "cannot read"},
      {"unreadable table", replaced(pin, "tables/metering_pin.csv", "garbled.csv"), "f1_table", "force[2].f1_table",
       "cannot read"},
      {"TOML syntax error", replaced(seed, "mass = 12.0", "mass = 12.0.0"), "mass = 12.0.0", "mass", "TOML"},
      {"TOML syntax error, unclosed array", replaced(seed, "point = [-0.20, 0.45, 0.0]\n", "point = [-0.20, 0.45, 0.0\n"),
       "[[joint]]\nname = \"b\"", "point", "TOML"},  // noticed on the next header, named by the open array
  };
  lgtest::TempDir dir("bad");
  lgtest::writeFile(dir / "garbled.csv", "stroke,area\n0.0,8e-5\n0.05,seven\n0.1,6e-5\n0.16,4e-5\n");
  for (size_t i = 0; i < bad.size(); ++i) {
    const BadScene& b = bad[i];
    const std::string file = dir / ("bad" + std::to_string(i) + ".toml");
    lgtest::writeFile(file, b.text);
    const int line = lineOf(b.text, b.marker);
    REQUIRE(line > 0);
    INFO(b.what);
    std::string msg;
    try {
      lg::loadScene(file);
      FAIL("no InputError for: " << b.what);
    } catch (const lg::InputError& e) {
      msg = e.what();
    }
    INFO("message: " << msg);
    CHECK(msg.find(file + ":" + std::to_string(line) + ":") != std::string::npos);
    CHECK(msg.find("'" + b.key + "'") != std::string::npos);
    CHECK(msg.find(b.rule) != std::string::npos);
    // The program: exit status 2, the message on stderr, nothing written.
    const std::string out = dir / ("out" + std::to_string(i));
    const int rc = runSimulate(file, out, dir / "stderr.txt");
    CHECK(rc == 2);
    CHECK(!std::filesystem::exists(out));
    CHECK(lgtest::readFile(dir / "stderr.txt").find(msg) != std::string::npos);
  }
}

TEST_CASE("simulate: a missing scene file or an unknown case is bad input too", "[scene][input]") {
  lgtest::TempDir dir("bad2");
  const std::string out = dir / "out";
  CHECK(runSimulate(dir / "no_such_scene.toml", out, dir / "err.txt") == 2);
  CHECK(lgtest::readFile(dir / "err.txt").find("no_such_scene.toml") != std::string::npos);
  CHECK(!std::filesystem::exists(out));
  const std::string cmd = "'" + lgtest::binPath("simulate") + "' '" + lgtest::sourcePath("data/seed_gear.toml") +
                          "' --case nonesuch --out '" + out + "' --quiet 2>'" + (dir / "err.txt") + "'";
  const int st = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(st) == 2);
  CHECK(lgtest::readFile(dir / "err.txt").find("nonesuch") != std::string::npos);
  CHECK(!std::filesystem::exists(out));
}
