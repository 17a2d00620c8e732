// The one drop-case reader (sim/io/drop_case.cpp): the keys of a scene's [[case]], which a study's
// [[case]] and a calibration's [[measurement]] read the same way (tests/optim/study_test.cpp and
// tests/calib/calibration_test.cpp check those two files with it). Tables inline as raw TOML.
#include "tests/sim/scene_support.hpp"  // sim headers, then Catch (see there)

#include "sim/io/drop_case.hpp"
#include "sim/io/toml_reader.hpp"

namespace {

// The main gear declares spin-up (its tyre has mu_x) and a lift element; the seed gear's tyre has no mu_x.
const lg::Scene& mainGear() {
  static const lg::Scene s = lg::loadScene(lgtest::sourcePath("data/main_gear.toml"));
  return s;
}
const lg::Scene& seedGear() {
  static const lg::Scene s = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  return s;
}

lg::DropCase read(const std::string& text, lg::DropCase base, bool fresh, const lg::Scene& scene = mainGear()) {
  const toml::table t = lg::parseToml(text, "t.toml");
  const lg::TomlReader r(t, "t.toml", "case[0]");
  lg::readDropCase(r, scene, base, fresh);
  return base;
}

std::string error(const std::string& text, bool fresh = true, const lg::Scene& scene = mainGear()) {
  try {
    read(text, lg::DropCase{}, fresh, scene);
  } catch (const lg::InputError& e) {
    return e.what();
  }
  return "(no error)";
}

}  // namespace

TEST_CASE("drop case reader: a new case from the keys is the case the scene file declares", "[drop_case]") {
  const lg::DropCase& declared = lgtest::findCase(mainGear(), "limit-spinup");
  const lg::DropCase c = read("sink_speed = 3.05\nlift_ratio = 1.0\nforward_speed = 60.0\n", lg::DropCase{}, true);
  CHECK(c.sinkSpeed == declared.sinkSpeed);
  CHECK(c.liftRatio == declared.liftRatio);
  CHECK(c.forwardSpeed == declared.forwardSpeed);
  CHECK(c.duration == declared.duration);
  CHECK(c.duration == 0.8);
  CHECK(c.dropHeight == 0);
  CHECK(c.masses.empty());
}

TEST_CASE("drop case reader: a drop from a height is released at rest and runs 0.8 s past its fall", "[drop_case]") {
  const double h = 0.45, g = mainGear().gravity;
  const lg::DropCase c = read("drop_height = 0.45\nlift_ratio = 0.0\n", lg::DropCase{}, true);
  CHECK(c.sinkSpeed == 0);
  CHECK(c.dropHeight == h);
  // free fall from rest: t_f = sqrt(2 h / g), touchdown at sqrt(2 g h)
  CHECK(c.duration == Approx(0.8 + std::sqrt(2 * h / g)).epsilon(1e-15));
  CHECK(lg::touchdownSpeed(c, g) == Approx(std::sqrt(2 * g * h)).epsilon(1e-15));
}

TEST_CASE("drop case reader: keys over a scene case replace those values alone", "[drop_case]") {
  const lg::DropCase& base = lgtest::findCase(mainGear(), "reserve-spinup");
  const lg::DropCase c = read("forward_speed = 40.0\n[masses]\nairframe = 5000.0\n", base, false);
  CHECK(c.sinkSpeed == base.sinkSpeed);
  CHECK(c.liftRatio == base.liftRatio);
  CHECK(c.duration == base.duration);
  CHECK(c.forwardSpeed == 40.0);
  REQUIRE(c.masses.size() == 1);
  CHECK(c.masses.at("airframe") == 5000.0);
  // a new drop height is a new fall: its duration follows it unless the table gives one
  const lg::DropCase d = read("drop_height = 0.2\nduration = 1.5\n", base, false);
  CHECK(d.duration == 1.5);
  CHECK(d.sinkSpeed == base.sinkSpeed);  // released at the case's sink speed
}

TEST_CASE("drop case reader: a bad value is one error naming the file, the line, the key and the rule", "[drop_case]") {
  struct Bad {
    std::string text, message;
    bool fresh = true;
  };
  const Bad bad[] = {
      {"lift_ratio = 1.0\nsink_speed = 0.0\n", "t.toml:2: key 'case[0].sink_speed': value 0 must be > 0 [m/s]"},
      {"sink_speed = 35.0\n", "t.toml:1: key 'case[0].sink_speed': value 35 m/s is above 10 m/s"},
      {"sink_speed = 3.0\nlift_ratio = 2.0\n", "t.toml:2: key 'case[0].lift_ratio': value 2 is above 1.5"},
      {"sink_speed = 3.0\nforward_speed = 200.0\n",
       "t.toml:2: key 'case[0].forward_speed': value 200 m/s is not a landing speed (at most 150 m/s)"},
      {"sink_speed = 3.0\nforward_speed = -1.0\n", "t.toml:2: key 'case[0].forward_speed': value -1 must be >= 0"},
      {"sink_speed = 3.0\nduration = 0.0\n", "t.toml:2: key 'case[0].duration'"},
      {"sink_speed = 3.0\n[masses]\nnobody = 3.0\n", "t.toml:3: key 'case[0].masses.nobody': 'nobody' is not a body of the scene"},
      {"lift_ratio = 1.0\n", "t.toml:1: key 'case[0].sink_speed': missing required number"},
      {"drop_height = 0.3\nlift_ratio = 1.0\n",
       "t.toml:1: key 'case[0].drop_height': the gear never reaches the ground: with lift_ratio 1 >= 1 it does not fall"},
  };
  for (const auto& b : bad) {
    INFO(b.text);
    const std::string e = error(b.text, b.fresh);
    CHECK(e.rfind(b.message, 0) == 0);
  }
  // the seed gear's tyre declares no mu_x: no forward speed, not even 0
  CHECK(error("sink_speed = 3.0\nforward_speed = 0.0\n", true, seedGear()) ==
        "t.toml:2: key 'case[0].forward_speed': no tyre of this scene declares the longitudinal friction coefficient mu_x");
}
