// Calibration files (TOML, ".cfg" or ".toml"): a gear's model fitted to measured drop tests. The file
// names a scene, the measured drops (a CSV each, the scene case or the inline case it was dropped in,
// which CSV column holds which history channel, a weight or the noise sigma per channel, a known or a
// fitted touchdown time) and the parameters to fit (scene parameters by path, with bounds). `calibrate`
// runs it (calib/fit.hpp). docs/calibration.md has the format; in short:
//
//   scene = "../data/seed_gear.toml"          # relative to the calibration file
//   [solver]        integrator, rtol, atol, step    # into the scene's [solver], as in a study
//   [[measurement]] name = "drop_3p05", file = "rig/drop_3p05.csv", case = "limit" (or sink_speed,
//                   lift_ratio, duration, masses), columns = { t = "time_s", P_y = "Fz_N", s = "stroke_m" },
//                   weights = { P_y = 1e-3 } | sigma = { P_y = 500.0, s = 2e-4 }, t_shift = "fit" | 0.0123,
//                   t_shift_range = [-0.01, 0.01]
//   [[parameter]]   path = "strut.f1", lower = 3e-5, upper = 1.6e-4, initial = 7e-5
//   [fit]           jacobian = "exact" | "central", loss = "none" | "huber" | "cauchy" | "soft_l1" | "arctan", loss_scale = 1, max_iterations,
//                   jacobian_step, shift_step, function_tolerance, parameter_tolerance, gradient_tolerance,
//                   identifiability
//
// Time: a sample at measured time t compares with the simulation at t - t_shift (t_shift: the
// measured time of touchdown). Before touchdown the gear falls freely: every channel keeps its value
// at touchdown except the travel h = V t + (1 - L) g t^2 / 2 (t < 0).
//
// The parser validates at the edge: every error is an lg::InputError naming the file (the calibration
// file, or the measurement's CSV for its rows), the line, the key and the rule.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "sim/drop/run.hpp"
#include "sim/io/overrides.hpp"
#include "sim/scene/parameters.hpp"

namespace lg::calib {

// One fitted scene parameter between bounds.
struct FitParameter {
  std::string path;      // "strut.f1"
  Parameter parameter;   // resolved in the scene
  std::string unit;      // SI unit ("m^2")
  double lower = 0, upper = 0;  // [unit]
  double initial = 0;    // [unit] default: the scene's value
  double scale = 1;      // [unit] the fit works in x / scale: |initial|, or upper - lower when initial is 0
  int line = 0;          // its [[parameter]] table
};

// One measured channel: a CSV column compared with a history column of the simulation.
struct Channel {
  std::string name;       // history column of the scene ("P_y", "s", "h", "delta", "p_1", "F_bottoming", ...)
  std::string unit;       // its SI unit
  std::string csvColumn;  // the CSV header's name for it
  int historyColumn = -1; // index into historyColumns(scene)
  double weight = 0;      // [1/unit] residual = weight (simulated - measured); 0: compared, not fitted
  double sigma = std::numeric_limits<double>::quiet_NaN();  // [unit] when given (weight = 1/sigma)
  bool fitted() const { return weight > 0; }
};

// The touchdown time in the measurement's clock: simulated time = measured time - t_shift.
struct TimeShift {
  bool fit = false;
  double value = 0;             // [s] the known value, or the fit's start (the middle of the range)
  double lower = 0, upper = 0;  // [s] the range of a fitted shift (lower = upper = value when known)
};

struct Measurement {
  std::string name;          // unique; a file stem of the outputs
  std::string file;          // the CSV's path (resolved against the calibration file's folder)
  int line = 0;              // its [[measurement]] table
  DropCase dropCase;         // the drop it was measured in
  int sceneCase = -1;        // index into Scene::cases when it is a scene case as is (case parameters reach it)
  std::vector<Channel> channels;
  std::vector<double> t;                 // [s] measured times, strictly increasing
  std::vector<std::vector<double>> y;    // per channel: the measured values [unit], one per time
  TimeShift shift;
  // Residuals of this measurement: (fitted channels) x (samples), channel by channel.
  std::size_t residuals() const;
};

enum class Loss { None, Huber, Cauchy, SoftL1, Arctan };
const char* lossName(Loss l);

struct FitSettings {
  bool exactJacobian = true;          // "jacobian": "exact" (forward mode, exact_jacobian.hpp) or "central"
  Loss loss = Loss::None;
  double lossScale = 1;               // [-] in units of the weighted residual
  int maxIterations = 50;
  double jacobianStep = 1e-4;         // [-] relative step h of the central differences (of the parameter's scale)
  double shiftStep = 1e-5;            // [s] step of the central differences in t_shift
  double functionTolerance = 1e-9;    // Ceres: |d cost| / cost (at the noise's cost: about 1e-3 sd)
  double parameterTolerance = 1e-10;  // Ceres: |dx| / (|x| + tol), x scaled by each parameter's scale
  double gradientTolerance = 1e-14;   // Ceres: max-norm of the projected gradient
  double identifiability = 1e-6;      // smallest reciprocal condition number of the column-scaled Jacobian
  double confidence = 0.95;           // of the intervals
};

struct Calibration {
  std::string file;       // as given (messages)
  std::string name;       // "name" key, default: the file stem
  std::string sceneFile;  // resolved
  std::string sceneDir;   // its folder (relative tables)
  Scene scene;            // with the calibration's [solver]
  std::vector<FitParameter> parameters;
  std::vector<Measurement> measurements;
  FitSettings fit;
  // Fitted values: the parameters, then one t_shift per measurement that fits it.
  std::size_t unknowns() const;
  std::size_t residuals() const;  // over every measurement
};

// Parses and validates a calibration file and reads its measurements; throws lg::InputError. 'sets'
// (the command line's --set) override parameters of the scene before anything reads it.
Calibration loadCalibration(const std::string& path, const std::vector<ParameterOverride>& sets = {});
Calibration parseCalibration(const std::string& text, const std::string& file, const std::string& baseDir = ".",
                             const std::vector<ParameterOverride>& sets = {});

}  // namespace lg::calib
