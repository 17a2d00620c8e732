// calibrate CALIB [--out DIR] [--threads N] [--set PATH=VALUE]... [--plots] [--quiet]
// Fits a gear's model to measured drop tests with Ceres (calib/fit.hpp) and writes DIR/result.json,
// report.md, calibrated.toml, histories_<measurement>.csv (calib/report.hpp). Exit status (apps/cli.hpp):
// 0 fitted, 1 the parameters are not identifiable (everything written, no uncertainties), the fit could
// not start or an output could not be written, 2 bad input (nothing written), 130 interrupted by Ctrl-C
// (nothing written).
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>

#include "apps/cli.hpp"
#include "sim/io/provenance.hpp"
#include "calib/calibration.hpp"
#include "calib/fit.hpp"
#include "calib/report.hpp"
#include "sim/io/files.hpp"
#include "sim/io/overrides.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Fit a gear's model to measured drop tests with Ceres, with uncertainties (docs/calibrate.md, docs/calibration.md)"};
  lg::cli::addVersion(app, "calibrate");
  std::string calibPath, outDir;
  std::vector<std::string> sets;
  int threads = 0;
  bool plots = false, quiet = false;
  lg::cli::addInputFile(app, "calibration", calibPath, "calibration file (TOML, .cfg or .toml): scene, measurements, parameters");
  lg::cli::addText(app, "--out", outDir, "output directory (default: <calibration stem>-calibration in the current directory)");
  lg::cli::addThreads(app, threads, "the simulations of the measurements and of the Jacobian's columns");
  lg::cli::addTexts(app, "--set", sets, "override a parameter of the scene, PATH=VALUE in SI units (repeatable)");
  app.add_flag("--plots", plots, "draw the report's pictures with gnuplot (the scripts are written regardless)");
  app.add_flag("--quiet", quiet, "no progress line or summary");
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;
  lg::cli::installInterruptHandler();  // from here on Ctrl-C means exit status 130

  lg::calib::Calibration calib;
  try {
    std::vector<lg::ParameterOverride> overrides;
    for (const auto& s : sets) overrides.push_back(lg::parseOverride(s));
    calib = lg::calib::loadCalibration(calibPath, overrides);
  } catch (const lg::InputError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  if (outDir.empty()) outDir = lg::safeFileStem(std::filesystem::path(calibPath).stem().string()) + "-calibration";
  try {
    lg::prepareOutputDir(outDir);  // before any work: a directory that takes no file fails now
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  threads = lg::cli::resolveThreads(threads);
  const bool tty = !quiet && isatty(fileno(stderr));
  const auto t0 = std::chrono::steady_clock::now();
  auto elapsed = [&] { return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); };

  lg::calib::FitOptions fo;
  fo.threads = threads;
  fo.stop = [] { return lg::cli::interrupted(); };
  if (tty)
    fo.progress = [&](int iteration, double cost) {
      std::fprintf(stderr, "\r  iteration %3d   cost %-12.6g   elapsed %7.1f s   ", iteration, cost, elapsed());
      std::fflush(stderr);
    };
  lg::calib::FitResult r;
  try {
    r = lg::calib::runFit(calib, fo);
  } catch (const std::exception& e) {
    if (tty) std::fprintf(stderr, "\n");
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  if (tty) std::fprintf(stderr, "\n");
  if (r.interrupted) {  // a fit cut short has no optimum and no uncertainties to report
    std::cerr << "calibrate: interrupted, nothing written\n";
    return lg::cli::kInterrupted;
  }
  lg::calib::CalibrationFiles files;
  try {
    std::vector<lg::InputFile> inputs{{"calibration", calibPath, ""}};
    for (const auto& f : lg::sceneInputs(calib.scene)) inputs.push_back(f);
    for (const auto& m : calib.measurements) inputs.push_back({"measurement", m.file, ""});
    const lg::Provenance provenance = lg::makeProvenance("calibrate", argc, argv, inputs);
    files = lg::calib::writeCalibration(calib, r, outDir, plots, &provenance);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  for (const auto& w : r.warnings) std::cerr << "calibrate: warning: " << w << "\n";
  for (const auto& w : files.warnings) std::cerr << "calibrate: warning: " << w << "\n";
  if (!r.ident.identifiable) std::cerr << "calibrate: " << r.ident.message << "\n";
  if (!quiet) {
    std::printf("%s: %s after %d iterations (Ceres: %s), %zu measurement(s), %zu fitted samples, %zu unknowns, %.1f s\n",
                calib.name.c_str(), r.ident.identifiable ? (r.converged ? "converged" : "stopped") : "NOT IDENTIFIABLE",
                r.iterations, r.termination.c_str(), calib.measurements.size(), r.residuals, r.unknowns, elapsed());
    std::printf("  Jacobian: %s\n", r.jacobianSource.c_str());
    std::printf("  covariance: ceres::Covariance scaled by the residual variance estimated from the fit, s^2 = %.4g "
                "(%zu degrees of freedom)\n",
                r.s2, r.dof);
    std::printf("%s", lg::calib::parameterTable(r).c_str());
    std::printf("  wrote %s/{report.md,result.json,calibrated.toml,histories_*.csv}\n", outDir.c_str());
  }
  return r.ident.identifiable ? lg::cli::kOk : lg::cli::kFailed;
}
