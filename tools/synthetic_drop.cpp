// synthetic_drop SCENE --case NAME --out FILE [--set PATH=VALUE]... [--channel NAME:CSV_COLUMN[:SIGMA]]...
//                [--rate HZ] [--start T] [--end T] [--touchdown T] [--seed S] [--digits N]
// Writes a measurement CSV of a scene's drop as a rig would record it (calib/synthetic.hpp): samples at
// a fixed rate in the rig's clock (touchdown at --touchdown), each channel with Gaussian noise of its
// sigma [its SI unit] from a fixed seed. The shipped calibration example's data were made with it
// (studies/seed_gear_calibration.cfg says how). Exit status: 0 written, 1 the drop failed or the file
// could not be written, 2 bad input.
#include <cstdio>
#include <iostream>

#include "apps/cli.hpp"
#include "calib/synthetic.hpp"
#include "sim/io/files.hpp"
#include "sim/io/overrides.hpp"
#include "sim/io/toml_reader.hpp"

namespace {

// "P_y:Fz_N:500" -> channel P_y in column Fz_N with sigma 500 (the sigma optional).
lg::calib::SyntheticChannel parseChannel(const std::string& text) {
  lg::calib::SyntheticChannel c;
  const auto a = text.find(':');
  const auto b = a == std::string::npos ? std::string::npos : text.find(':', a + 1);
  c.name = text.substr(0, a);
  c.csvColumn = a == std::string::npos ? c.name : text.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
  if (b != std::string::npos) {
    try {
      std::size_t used = 0;
      c.sigma = std::stod(text.substr(b + 1), &used);
      if (used != text.size() - b - 1 || !(c.sigma >= 0)) throw std::invalid_argument("");
    } catch (const std::exception&) {
      throw lg::InputError("command line", 0, "--channel", "'" + text + "': the sigma must be a number >= 0");
    }
  }
  if (c.name.empty() || c.csvColumn.empty() || c.csvColumn.find(',') != std::string::npos)
    throw lg::InputError("command line", 0, "--channel", "'" + text + "' must read NAME:CSV_COLUMN[:SIGMA], e.g. P_y:Fz_N:500");
  return c;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"A scene's drop sampled like a rig's measurement, with noise from a fixed seed (a CSV for calibrate)"};
  lg::cli::addVersion(app, "synthetic_drop");
  std::string scenePath, caseName, out;
  std::vector<std::string> sets, channels;
  lg::calib::SyntheticSpec spec;
  long long seed = 1;
  app.add_option("scene", scenePath, "scene file")->required();
  app.add_option("--case", caseName, "the scene case dropped")->required();
  app.add_option("--out", out, "the CSV to write")->required();
  app.add_option("--set", sets, "override a parameter of the scene, PATH=VALUE in SI units (repeatable)");
  app.add_option("--channel", channels, "NAME:CSV_COLUMN[:SIGMA]: a history channel, its CSV column and its noise [SI unit]")
      ->required();
  app.add_option("--rate", spec.rate, "samples per second [Hz] (default 2000)")->check(CLI::PositiveNumber);
  app.add_option("--start", spec.start, "the first sample in the rig's clock [s] (default 0)");
  app.add_option("--end", spec.end, "the last sample at most, in the rig's clock [s] (default 0.5)");
  app.add_option("--touchdown", spec.touchdown, "the touchdown in the rig's clock [s] (default 0)");
  app.add_option("--digits", spec.digits, "significant digits written (default 17: exact)")->check(CLI::Range(1, 17));
  app.add_option("--seed", seed, "seed of the noise (default 1)")->check(CLI::Range(0LL, 9223372036854775807LL));
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;
  lg::Scene scene;
  try {
    std::vector<lg::ParameterOverride> overrides;
    for (const auto& s : sets) overrides.push_back(lg::parseOverride(s));
    scene = lg::applyOverrides(lg::loadScene(scenePath), overrides);
    bool found = false;
    for (const auto& c : scene.cases)
      if (c.name == caseName) {
        spec.dropCase = c;
        found = true;
      }
    if (!found) throw lg::InputError("command line", 0, "--case", "'" + caseName + "' is not a case of the scene");
    for (const auto& c : channels) spec.channels.push_back(parseChannel(c));
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  spec.seed = static_cast<std::uint64_t>(seed);
  try {
    lg::writeFileAtomic(out, lg::calib::syntheticCsv(scene, spec));
  } catch (const std::invalid_argument& e) {
    std::cerr << "error: command line: " << e.what() << "\n";
    return lg::cli::kUsage;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  std::printf("wrote %s\n", out.c_str());
  return lg::cli::kOk;
}
