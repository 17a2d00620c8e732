// The scene parser (sim/io/scene.cpp): the shipped scenes load; bad input gives lg::InputError naming
// the file, the line and the key, and `simulate` on such a file exits with status 2 without writing.
#include "tests/sim/bad_input_support.hpp"  // sim headers, then Catch (see there); the bad-input checks

#include <sys/stat.h>
#include <sys/wait.h>

#include <cstdlib>

namespace {
using lgtest::replacedText;
using BadScene = lgtest::BadInput;
}  // namespace

TEST_CASE("shipped scenes load", "[scene]") {
  for (const char* f : {"data/seed_gear.toml", "data/telescopic_gear.toml", "data/seed_gear_metering_pin.toml",
                        "data/main_gear.toml", "data/nose_gear.toml", "data/friction_gear.toml"}) {
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
      {"missing key", replacedText(seed, leverMass, ""), "[[body]]\nname = \"lever\"", "body[1].mass", "missing"},
      {"unknown key", replacedText(seed, leverMass, leverMass + "colour = \"red\"\n"), "colour", "body[1].colour", "unknown key"},
      {"negative area", replacedText(seed, "f1 = 7.0e-5", "f1 = -7.0e-5"), "f1 = -7.0e-5", "force[2].f1", "> 0"},
      {"negative mass", replacedText(seed, "mass = 20.0", "mass = -20.0"), "mass = -20.0", "body[0].mass", "> 0"},
      {"zero inertia", replacedText(seed, "inertia = [0.45, 0.45, 0.80]", "inertia = [0.45, 0.0, 0.80]"), "inertia = [0.45, 0.0",
       "body[0].inertia", "> 0"},
      {"p_atm not below p01", replacedText(seed, "mu = 0.05", "p_atm = 4.0e6\nmu = 0.05"), "p_atm = 4.0e6", "force[2].p_atm",
       "< p01"},
      {"joint naming an unknown body", replacedText(seed, "body1 = \"wheel\"", "body1 = \"wheels\""), "body1 = \"wheels\"",
       "joint[1].body1", "not a body"},
      {"stop violated at t = 0", replacedText(seed, "max_distance = 0.60", "max_distance = 0.59"), "[[stop]]\nname = \"extension\"",
       "stop.extension", "violate"},
      {"joint violated at t = 0",
       seed + "\n[[joint]]\nname = \"guide\"\ntype = \"point_on_plane\"\nbody1 = \"wheel\"\nbody2 = \"ground\"\n"
              "point = [-0.40, 0.30, 0.0]\nplane_point = [0.0, 0.0, 0.05]\nnormal = [0.0, 0.0, 1.0]\n",
       "[[joint]]\nname = \"guide\"", "joint.guide", "violate"},
      {"missing table", replacedText(pin, "tables/metering_pin.csv", "tables/no_such_pin.csv"), "f1_table", "force[2].f1_table",
       "cannot read"},
      {"unreadable table", replacedText(pin, "tables/metering_pin.csv", "garbled.csv"), "f1_table", "force[2].f1_table",
       "cannot read"},
      // physical consistency at touchdown
      {"strut L0 not the attachment distance", replacedText(seed, "mu = 0.05", "mu = 0.05\nL0 = 0.62"),
       "L0 = 0.62", "force[2].L0", "differs from the distance of rod_point and cylinder_point at touchdown, 0.6 m"},
      {"tyre pressed into the ground", replacedText(seed, "radius = 0.30", "radius = 0.32"), "radius = 0.32", "force[3].radius",
       "pressed 0.02 m into the ground"},
      {"gas volume below the swept volume", replacedText(seed, "Omega0 = 1.30e-3", "Omega0 = 1.20e-3"), "Omega0 = 1.20e-3",
       "force[2].Omega0", "must be larger than the volume swept at the bottoming stroke, F S_max = 0.001256637061 m^3"},
      {"bottoming stop not shorter than the extension stop", replacedText(seed, "min_distance = 0.44", "min_distance = 0.60"),
       "min_distance = 0.60", "stop[1].min_distance", "must be shorter than the max_distance 0.6 m"},
      {"zero sink speed", replacedText(seed, "sink_speed = 2.0", "sink_speed = 0.0"), "sink_speed = 0.0", "case[0].sink_speed",
       "must be > 0 [m/s]"},
      {"negative sink speed", replacedText(seed, "sink_speed = 2.0", "sink_speed = -2.0"), "sink_speed = -2.0",
       "case[0].sink_speed", "must be > 0 [m/s]"},
      // the certification matrix
      {"certification without a load factor", replacedText(seed, "limit_load_factor = 2.5", ""), "[certification]",
       "certification.limit_load_factor", "missing"},
      {"unknown basis", replacedText(seed, "basis = \"part25\"", "basis = \"part26\""), "basis = \"part26\"",
       "certification.basis", "\"part25\", \"cs25\", \"part23\", \"cs23\", \"custom\""},
      {"unit mass below the gear's", replacedText(seed, "landing_mass = 4050.0", "landing_mass = 50.0"), "landing_mass = 50.0",
       "certification.landing_mass", "must exceed the mass of the gear's other bodies, 70 kg"},
      {"Part 23 without a wing loading", replacedText(seed, "basis = \"part25\"", "basis = \"part23\""), "[certification]",
       "certification.wing_loading", "needs the wing loading"},
      {"Part 23 lift above 0.667", replacedText(replacedText(seed, "basis = \"part25\"", "basis = \"part23\"\nwing_loading = 150.0"),
                                          "lift_ratio = 1.0\nlimit_load", "lift_ratio = 0.6671\nlimit_load"),
       "lift_ratio = 0.6671", "certification.lift_ratio", "value 0.6671 must be <= 0.667 (Part 23 limit drop: 23.725 takes L \"not more than 0.667\")"},
      {"Part 23 take-off mass below zero",
       replacedText(replacedText(replacedText(seed, "basis = \"part25\"", "basis = \"part23\"\nwing_loading = 150.0"),
                                 "takeoff_mass = 4250.0", "takeoff_mass = -1.0"),
                    "lift_ratio = 1.0\nlimit_load", "lift_ratio = 0.5\nlimit_load"),
       "takeoff_mass = -1.0", "certification.takeoff_mass", "value -1 must be > 0"},
      {"a stroke margin of the whole stroke (0.60 - 0.44 m, rounded either way)",
       replacedText(seed, "stroke_margin = 0.01 ", "stroke_margin = 0.16 "), "stroke_margin = 0.16", "certification.stroke_margin",
       "value 0.16 m must be smaller than the stroke S_max = 0.16 m of strut 'strut'"},
      {"TOML syntax error", replacedText(seed, "mass = 12.0", "mass = 12.0.0"), "mass = 12.0.0", "mass", "TOML"},
      {"TOML syntax error, unclosed array", replacedText(seed, "point = [-0.20, 0.45, 0.0]\n", "point = [-0.20, 0.45, 0.0\n"),
       "[[joint]]\nname = \"b\"", "point", "TOML"},  // noticed on the next header, named by the open array
      {"TOML syntax error, a key without '='", replacedText(seed, "mass = 20.0", "mass 20.0"), "mass 20.0", "mass", "TOML"},
      {"TOML syntax error, unterminated multi-line string",
       replacedText(seed, "name = \"seed_gear\"", "name = \"seed_gear\"\ndescription = \"\"\"a gear"),
       "description = \"\"\"a gear", "description", "never closed"},
      // tables of the wrong kind are errors, never ignored
      {"solver as an array of tables", replacedText(seed, "[solver]", "[[solver]]"), "[[solver]]", "solver",
       "not an array of tables"},
      {"solver as a string",
       "solver = \"dopri5\"\n[[body]]\nname = \"w\"\nmass = 1.0\ninertia = [1.0, 1.0, 1.0]\nposition = [0.0, 0.3, 0.0]\n",
       "solver = \"dopri5\"", "solver", "must be a table [solver]"},
      {"scene as an array of tables", replacedText(seed, "[scene]", "[[scene]]"), "[[scene]]", "scene", "not an array of tables"},
      // counts are whole numbers in range, never truncated
      {"fractional max_steps", replacedText(seed, "atol = 1e-8", "atol = 1e-8\nmax_steps = 10.5"), "max_steps = 10.5",
       "solver.max_steps", "must be a whole number"},
      {"huge max_steps", replacedText(seed, "atol = 1e-8", "atol = 1e-8\nmax_steps = 1e300"), "max_steps = 1e300",
       "solver.max_steps", "must be in [1, 1000000000000]"},
      {"fractional Gauss-Seidel sweeps", replacedText(seed, "atol = 1e-8", "atol = 1e-8\ngauss_seidel_iterations = 0.5"),
       "gauss_seidel_iterations = 0.5", "solver.gauss_seidel_iterations", "must be a whole number"},
      // finite numbers only
      {"NaN in a quaternion", replacedText(seed, "x_axis = [1.0, 0.0, 0.0]", "quaternion = [nan, 0.0, 0.0, 0.0]"),
       "quaternion = [nan", "body[0].quaternion", "must be finite"},
      // a misspelt key is an unknown key, with the allowed ones
      {"misspelt body1", replacedText(seed, "body1 = \"lever\"\nbody2 = \"airframe\"", "bodyl = \"lever\"\nbody2 = \"airframe\""),
       "bodyl = \"lever\"", "joint[0].bodyl", "unknown key (allowed here: axis, body1, body2, name, point, type)"},
      // names become file names and CSV columns
      {"case name with a slash", replacedText(seed, "name = \"light\"", "name = \"a/b\""), "name = \"a/b\"", "case[0].name",
       "must be 1 to 64 letters"},
      {"case name leaving the output directory", replacedText(seed, "name = \"light\"", "name = \"../escaped\""),
       "name = \"../escaped\"", "case[0].name", "must be 1 to 64 letters"},
      {"empty case name", replacedText(seed, "name = \"light\"", "name = \"\""), "name = \"\"", "case[0].name",
       "must be 1 to 64 letters"},
      {"stop name with a comma", replacedText(seed, "name = \"extension\"", "name = \"ext,ension\""), "name = \"ext,ension\"",
       "stop[0].name", "must be 1 to 64 letters"},
      // an over-constrained mechanism names the joint that repeats the others
      {"redundant joint",
       seed + "\n[[joint]]\nname = \"axle2\"\ntype = \"spherical\"\nbody1 = \"wheel\"\nbody2 = \"lever\"\n"
              "point = [-0.40, 0.30, 0.0]\n",
       "[[joint]]\nname = \"axle2\"", "joint.axle2", "over-constrains the mechanism: its row 0 repeats what joint 'g' already holds"},
  };
  lgtest::TempDir dir("bad");
  lgtest::writeFile(dir / "garbled.csv", "stroke,area\n0.0,8e-5\n0.05,seven\n0.1,6e-5\n0.16,4e-5\n");
  lgtest::checkBadInputs(bad, dir);  // the message; the program: exit status 2, the message on stderr, nothing written
}

TEST_CASE("simulate: a missing scene file or an unknown case is bad input too", "[scene][input]") {
  lgtest::TempDir dir("bad2");
  const std::string out = dir / "out";
  CHECK(lgtest::runSimulateOn(dir / "no_such_scene.toml", out, dir / "err.txt") == 2);
  CHECK(lgtest::readFile(dir / "err.txt").find("no_such_scene.toml") != std::string::npos);
  CHECK(!std::filesystem::exists(out));
  const std::string cmd = "'" + lgtest::binPath("simulate") + "' '" + lgtest::sourcePath("data/seed_gear.toml") +
                          "' --case nonesuch --out '" + out + "' --quiet 2>'" + (dir / "err.txt") + "'";
  const int st = std::system(cmd.c_str());
  CHECK(WEXITSTATUS(st) == 2);
  CHECK(lgtest::readFile(dir / "err.txt").find("nonesuch") != std::string::npos);
  CHECK(!std::filesystem::exists(out));
}

TEST_CASE("simulate: a pipe or a directory given as the scene is refused at once, never read", "[scene][input]") {
  lgtest::TempDir dir("bad3");
  const std::string fifo = dir / "scene.fifo";
  REQUIRE(::mkfifo(fifo.c_str(), 0600) == 0);
  const std::string out = dir / "out";
  for (const std::string& scene : {fifo, dir.path.string()}) {
    INFO(scene);
    // 'timeout' guards the test itself: a program that opened the pipe would block here for ever.
    const std::string cmd = "timeout 20 '" + lgtest::binPath("simulate") + "' '" + scene + "' --out '" + out +
                            "' --quiet 2>'" + (dir / "err.txt") + "'";
    const int st = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(st));
    CHECK(WEXITSTATUS(st) == 2);
    CHECK(lgtest::readFile(dir / "err.txt") ==
          "error: " + scene + ": cannot read the scene file: " +
              (scene == fifo ? "not a regular file (a pipe, a socket or a device)\n" : "a directory, not a file\n"));
    CHECK(!std::filesystem::exists(out));
  }
}
