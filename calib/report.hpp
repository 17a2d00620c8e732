// The outputs of a calibration (fit.hpp), written atomically and free of timings and thread counts, so
// that the same input writes the same bytes:
//   result.json              the unknowns (initial, fitted, standard deviation, interval, bounds), the
//                            correlation matrix, s^2, Ceres's summary, identifiability, per measurement and
//                            channel the residual statistics before and after the fit
//   report.md                the same for people, with the pictures
//   histories_<meas>.csv     per sample: t, t - t_shift, and per channel measured, initial, fitted and the
//                            residual (fitted - measured), units in the header
//   calibrated.toml          the scene with the fitted values (runnable; inline drops added as cases)
//   plots/plots.gp, <meas>.png  measured against simulated before and after, and the residuals
#pragma once

#include <string>
#include <vector>

#include "calib/calibration.hpp"
#include "calib/fit.hpp"
#include "sim/io/provenance.hpp"

namespace lg::calib {

std::string resultJson(const Calibration& c, const FitResult& r);
std::string historiesCsv(const Calibration& c, const FitResult& r, std::size_t m);
// The scene document with the fitted values, its tables' paths made to resolve from outDir.
std::string calibratedToml(const Calibration& c, const FitResult& r, const std::string& outDir);
// note: empty when the pictures were drawn, else why not (said in the report instead of them).
std::string reportMarkdown(const Calibration& c, const FitResult& r, const std::string& note);
// The terminal's table of the unknowns.
std::string parameterTable(const FitResult& r);

struct CalibrationFiles {
  std::vector<std::string> written;   // relative to the output directory
  std::vector<std::string> warnings;  // for the terminal (gnuplot)
};
// Writes every output into 'dir' (created and tested before the fit by the caller); plots = false skips
// gnuplot (the scripts are written regardless). Throws std::runtime_error when a file cannot be written.
// 'provenance' (optional) heads result.json, report.md and calibrated.toml (sim/io/provenance.hpp).
CalibrationFiles writeCalibration(const Calibration& c, const FitResult& r, const std::string& dir, bool plots,
                                  const Provenance* provenance = nullptr);

}  // namespace lg::calib
