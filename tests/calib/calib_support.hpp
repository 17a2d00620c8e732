// Helpers of the calibration tests: synthetic measurements of the seed gear written into a temporary
// folder with a calibration file beside them, and running the programs.
//
// Include order: the project headers pull in glog (through Ceres), whose CHECK macro replaces Catch's if
// it comes later; Catch is included here after them.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "calib/calibration.hpp"
#include "files_support.hpp"
#include "calib/fit.hpp"
#include "calib/synthetic.hpp"
#include "sim/io/overrides.hpp"

#include <catch2/catch.hpp>

namespace calibtest {

using lgtest::binPath;
using lgtest::readFile;
using lgtest::sourcePath;
using lgtest::TempDir;
using lgtest::writeFile;
inline std::string q(const std::string& s) { return "'" + s + "'"; }

// The seed gear with parameters changed (PATH=VALUE).
inline lg::Scene seedGear(const std::vector<lg::ParameterOverride>& sets = {}) {
  return lg::applyOverrides(lg::loadScene(sourcePath("data/seed_gear.toml")), sets);
}

// A short limit drop (3.05 m/s, L = 1) as an inline case: the tests' drops last 0.35 s.
inline lg::DropCase shortLimitDrop(double duration = 0.35) {
  lg::DropCase c;
  c.name = "short_limit";
  c.sinkSpeed = 3.05;
  c.liftRatio = 1.0;
  c.duration = duration;
  return c;
}

// A measurement CSV of the seed gear with 'truth' set: P_y (Fz_N), s (stroke_m), h (travel_m) at 2 kHz
// from 'start' to 'end' [s] in the rig's clock, touchdown at 'touchdown'; noise sigma (500 N, 2e-4 m,
// 2e-4 m) times 'noise' from 'seed'.
inline std::string limitCsv(const std::vector<lg::ParameterOverride>& truth, double touchdown, double noise,
                            std::uint64_t seed, double start = 0, double end = 0.3) {
  lg::calib::SyntheticSpec spec;
  spec.dropCase = shortLimitDrop();
  spec.channels = {{"P_y", "Fz_N", 500 * noise}, {"s", "stroke_m", 2e-4 * noise}, {"h", "travel_m", 2e-4 * noise}};
  spec.rate = 2000;
  spec.start = start;
  spec.end = end;
  spec.touchdown = touchdown;
  spec.seed = seed;
  return lg::calib::syntheticCsv(seedGear(truth), spec);
}

// A calibration file on the seed gear (by its absolute path) with one measurement of 'csvName' in the
// short inline limit drop; 'measurementExtra' lines go into the [[measurement]] table, 'rest' after it.
inline std::string calibText(const std::string& csvName, const std::string& measurementExtra, const std::string& rest) {
  return "scene = \"" + sourcePath("data/seed_gear.toml") + "\"\n"
         "[[measurement]]\n"
         "file = \"" + csvName + "\"\n"
         "sink_speed = 3.05\n"
         "lift_ratio = 1.0\n"
         "duration = 0.35\n"
         "columns = { t = \"time_s\", P_y = \"Fz_N\", s = \"stroke_m\", h = \"travel_m\" }\n" +
         measurementExtra + "\n" + rest;
}

inline std::string parameter(const std::string& path, double lower, double upper) {
  std::ostringstream o;
  o.precision(17);
  o << "[[parameter]]\npath = \"" << path << "\"\nlower = " << lower << "\nupper = " << upper << "\n";
  return o.str();
}

// Runs a program of build/bin with arguments (after the shell commands 'prefix'); returns its exit status,
// its output in 'out'.
inline int run(const std::string& program, const std::string& args, std::string& out, const std::string& prefix = "") {
  TempDir log("log");
  const std::string cmd = prefix + q(binPath(program)) + " " + args + " > " + q(log / "log.txt") + " 2>&1";
  const int st = std::system(cmd.c_str());
  out = readFile(log / "log.txt");
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// The index of an unknown by name in a fit result.
inline std::size_t unknown(const lg::calib::FitResult& r, const std::string& name) {
  for (std::size_t i = 0; i < r.names.size(); ++i)
    if (r.names[i] == name) return i;
  FAIL("no unknown " << name);
  return 0;
}

}  // namespace calibtest
