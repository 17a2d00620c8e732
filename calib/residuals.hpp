// The residuals of a calibration and their Jacobian.
//
// A measurement's residuals are weight (simulated - measured) at every sample of every fitted channel,
// channel by channel; the simulated values are rows of the drop test at exactly the samples' times
// (CaseOptions::outputTimes, on the integrator's dense output), t_sim = t - t_shift, and before
// touchdown (t_sim < 0) the free fall: every channel at its touchdown value, h = V t + (1 - L) g t^2 / 2.
//
// Derivatives come from one place, a ResidualJacobian: it evaluates every measurement at a point,
// residuals and (when asked) their Jacobian with respect to the physical parameters and the
// measurement's own t_shift. CentralDifferences is the one implemented: central differences in the
// physical parameters (relative step h of each parameter's scale) and in t_shift (step dt), one-sided
// second-order differences where a central step would leave the bounds; its 1 + 2 (p + shift) runs per
// measurement go over the threads, each into its own slot, so the result is the same for any thread
// count. ExactDerivatives (exact_jacobian.hpp, the default) differentiates the drop test itself
// (ceres::Jet through the run); the fit takes either (FitSettings::jacobian, or FitOptions::jacobian).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "calib/calibration.hpp"

namespace lg::calib {

// A point of the fit: the parameters' values [their units] and each measurement's t_shift [s] (its
// known value where it is not fitted).
struct Point {
  std::vector<double> x;
  std::vector<double> shift;
};
// The starting point: the parameters' initial values, each shift's known value or the middle of its range.
Point initialPoint(const Calibration& c);

// The scene of a design: the parameters set to x as data and the scene's rules checked (sim/scene/parameters.hpp).
// Returns why the scene rejects it, or nothing.
std::optional<std::string> designScene(const Calibration& c, const std::vector<double>& x, Scene& out);

// The simulation's output rows for a measurement at a t_shift [s]: times (t = 0 first when a sample
// precedes touchdown, then one per later sample, the last clamped to the case's end) and, per sample,
// the index of its row.
struct SampleRows {
  std::vector<double> times;
  std::vector<std::size_t> row;
};
SampleRows sampleRows(const Measurement& m, double shift, double duration);

// The simulated channels of a measurement at its samples: y[channel][sample], every channel (fitted or
// compared only).
struct Simulated {
  bool ok = false;
  std::string message;  // why not
  std::vector<std::vector<double>> y;
};
// Simulates measurement k of c in the design scene with the given t_shift [s]. 'stop' (Ctrl-C) is polled.
Simulated simulateMeasurement(const Calibration& c, std::size_t k, const Scene& design, double shift,
                              const std::function<bool()>& stop = {});

// The weighted residuals of the fitted channels: weight (simulated - measured), channel by channel.
Eigen::VectorXd weightedResiduals(const Measurement& m, const Simulated& s);

// One measurement at a point.
struct MeasurementEval {
  bool ok = false;
  std::string message;     // why not
  Eigen::VectorXd r;       // weighted residuals [-]
  Eigen::MatrixXd J;       // dr/dx [1/unit of each parameter]: residuals x parameters (with jacobians)
  Eigen::VectorXd Jshift;  // dr/dt_shift [1/s] (with jacobians, when its shift is fitted)
};

// Where the residuals and their derivatives come from (see the header comment).
class ResidualJacobian {
 public:
  virtual ~ResidualJacobian() = default;
  // For the reports: "central differences, relative step h = 0.0001 (t_shift: 1e-05 s)".
  virtual std::string source() const = 0;
  // Every measurement of the calibration at p: out[k] for measurement k. Identical for any thread count.
  virtual void evaluate(const Point& p, bool jacobians, std::vector<MeasurementEval>& out) const = 0;
  // For the error of the Jacobian at p (the identifiability test, fit.hpp): a second Jacobian of the same
  // scheme with other steps, whose difference to evaluate()'s estimates the error. An exact Jacobian
  // has no error to estimate and returns false.
  virtual bool secondJacobian(const Point&, std::vector<MeasurementEval>&) const { return false; }
};

class CentralDifferences final : public ResidualJacobian {
 public:
  CentralDifferences(const Calibration& c, int threads, std::function<bool()> stop = {})
      : c_(c), threads_(threads), stop_(std::move(stop)) {}
  std::string source() const override;
  void evaluate(const Point& p, bool jacobians, std::vector<MeasurementEval>& out) const override;
  // Central differences with twice the steps.
  bool secondJacobian(const Point& p, std::vector<MeasurementEval>& out) const override;

 private:
  void run(const Point& p, bool jacobians, double stepFactor, std::vector<MeasurementEval>& out) const;
  const Calibration& c_;
  int threads_;
  std::function<bool()> stop_;
};

}  // namespace lg::calib
