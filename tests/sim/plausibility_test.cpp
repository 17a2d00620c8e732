// Plausibility (sim/scene/check.cpp): values that are legal numbers but no gear, most often a unit
// mistake, are refused with the file, line, key and rule (exit 2, nothing written): a tyre limit at or
// above its radius, a metering-pin table in mm, a sink speed above 10 m/s (in a scene, a study and on
// the command line), a lift ratio above 1.5; and a run that ends before its compression is EXCEEDED.
#include "bad_input_support.hpp"  // sim headers, then Catch (see there)

#include <fstream>

TEST_CASE("plausibility: unit mistakes in a scene are refused with the rule", "[plausibility][bad-input]") {
  const lgtest::TempDir dir("plausibility");
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string pin = lgtest::readFile(lgtest::sourcePath("data/seed_gear_metering_pin.toml"));
  // the metering pin's table with its strokes in mm
  {
    std::istringstream in(lgtest::readFile(lgtest::sourcePath("data/tables/metering_pin.csv")));
    std::ofstream out(dir / "pin_mm.csv");
    for (std::string line; std::getline(in, line);) {
      if (line.empty() || line[0] == '#' || line.rfind("stroke", 0) == 0) {
        out << line << "\n";
        continue;
      }
      const auto comma = line.find(',');
      out << std::stod(line.substr(0, comma)) * 1000 << line.substr(comma) << "\n";
    }
  }
  auto seedWith = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(seed, from, to); };
  const std::vector<lgtest::BadInput> bad{
      {"a tyre limit in mm", seedWith("delta_max = 0.10               # [m]", "delta_max = 100.0"), "delta_max = 100.0",
       "force[3].delta_max", "is not below the tyre's radius 0.3 m: a deflection limit in mm?"},
      {"a tyre limit at its radius", seedWith("delta_max = 0.10               # [m]", "delta_max = 0.30"), "delta_max = 0.30",
       "force[3].delta_max", "is not below the tyre's radius"},
      {"a sink speed in mm/s", seedWith("sink_speed = 3.05", "sink_speed = 3050.0"), "sink_speed = 3050.0", "case[2].sink_speed",
       "is above 10 m/s, no landing's sink speed"},
      {"a lift ratio of 50", seedWith("lift_ratio = 1.0\n\n[[case]]\nname = \"limit\"", "lift_ratio = 50.0\n\n[[case]]\nname = \"limit\""),
       "lift_ratio = 50.0", "case[1].lift_ratio", "is above 1.5"},
      {"a metering pin in mm", lgtest::replacedText(pin, "\"tables/metering_pin.csv\"", "\"pin_mm.csv\""), "f1_table =",
       "force[2].f1_table", "its stroke column in mm?"},
  };
  lgtest::checkBadInputs(bad, dir);
}

TEST_CASE("plausibility: the command line's matrix, and a run too short for its compression", "[plausibility][cli]") {
  const lgtest::TempDir dir("plausibility_cli");
  const std::string scene = "'" + lgtest::sourcePath("data/seed_gear.toml") + "'";
  auto simulate = [&](const std::string& args) {
    const std::string cmd = "'" + lgtest::binPath("simulate") + "' " + scene + " " + args + " --quiet 2>'" + (dir / "err.txt") +
                            "' >/dev/null";
    const int st = std::system(cmd.c_str());
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  };
  CHECK(simulate("--sink-speeds 3050 --out '" + (dir / "a") + "'") == 2);
  CHECK(lgtest::readFile(dir / "err.txt").rfind("error: command line: key '--sink-speeds': value 3050 m/s is above 10 m/s", 0) == 0);
  CHECK_FALSE(std::filesystem::exists(dir / "a"));
  CHECK(simulate("--sink-speeds 2 --lift-ratios 50 --out '" + (dir / "b") + "'") == 2);
  CHECK(lgtest::readFile(dir / "err.txt").find("key '--lift-ratios': value 50 is above 1.5") != std::string::npos);
  // 10 ms of a drop: the compression is nowhere near its end, and the case says so
  REQUIRE(simulate("--duration 0.01 --sink-speeds 3.05 --lift-ratios 1 --out '" + (dir / "c") + "'") == 0);
  const std::string summary = lgtest::readFile(dir / "c/summary.json");
  CHECK(summary.find("\"within\": false, \"violations\": \"compression not ended") != std::string::npos);
}
