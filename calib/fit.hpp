// Fitting a calibration (calibration.hpp) with Ceres, and what the fit says about its parameters.
//
// The unknowns are the parameters (Ceres sees each divided by its scale, so that all are of order 1,
// between its bounds) and each fitted t_shift [s]. Each measurement is one ceres::CostFunction over its
// residuals (with a robust loss, one per residual, the loss acting on each), and all of them read one
// evaluation of every measurement made when Ceres announces a new point (ceres::EvaluationCallback):
// the measurements are simulated in parallel there (residuals.hpp), Ceres itself runs single-threaded,
// so the fit is the same for any thread count. Levenberg-Marquardt with dense QR.
//
// At the optimum: identifiability (identifiability.hpp) and, when the parameters are identifiable, the
// covariance: ceres::Covariance (dense SVD) of the weighted residuals, scaled by the residual variance
// estimated from the fit, s^2 = sum(r^2) / (m - n) (m residuals, n unknowns; with a robust loss
// s = 1.4826 median |r|, which the outliers do not inflate); standard deviations, correlations and
// intervals x +- t(1 - (1 - confidence)/2, m - n) sd follow from it.
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "calib/calibration.hpp"
#include "calib/identifiability.hpp"
#include "calib/residuals.hpp"

namespace lg::calib {

// Residual statistics of one channel [its unit]: r = simulated - measured over every sample.
struct ChannelStats {
  double mean = 0, rms = 0, maxAbs = 0;
  double tMaxAbs = 0;  // [s] measured time of the largest |r|
  // [-] lag-1 autocorrelation of r about its mean: sum (r_i - m)(r_i+1 - m) / sum (r_i - m)^2; near 0 for
  // independent noise, near 1 where the residual is a slow misfit the noise model does not describe
  double lag1 = std::numeric_limits<double>::quiet_NaN();
};

struct MeasurementFit {
  Simulated before, after;                  // the channels at the initial and the fitted point
  std::vector<ChannelStats> statsBefore, statsAfter;  // per channel
};

struct FitResult {
  bool interrupted = false;
  std::string jacobianSource;   // ResidualJacobian::source()
  std::string termination;      // Ceres: "CONVERGENCE", "NO_CONVERGENCE", ...
  std::string ceresMessage;     // Ceres's own words
  bool converged = false;
  int iterations = 0;
  int evaluations = 0;          // points at which every measurement was simulated (with or without the Jacobian)
  double initialCost = 0, finalCost = 0;  // Ceres's cost: sum of rho(r^2) / 2
  std::size_t residuals = 0, unknowns = 0, dof = 0;
  double s2 = 0;                // residual variance estimated from the fit: sum(r^2) / (m - n) (robust loss: (1.4826 median |r|)^2)
  // Unknowns: the parameters, then each fitted t_shift.
  std::vector<std::string> names, units;
  std::vector<double> initial, value, sd, lo, hi;
  std::vector<double> lower, upper;
  std::vector<bool> atBound;
  double t = 0;                 // Student-t quantile of the intervals
  bool covariance = false;      // standard deviations and correlations computed
  std::string covarianceMessage;
  Eigen::MatrixXd cov, corr;    // in the unknowns' units
  Identifiability ident;
  Point start, fitted;
  std::vector<MeasurementFit> measurements;
  std::vector<std::string> warnings;
};

struct FitOptions {
  int threads = 1;
  // Where the residuals' Jacobian comes from (residuals.hpp); null: the calibration's choice
  // (FitSettings::exactJacobian: ExactDerivatives, else CentralDifferences) on 'threads'.
  const ResidualJacobian* jacobian = nullptr;
  std::function<bool()> stop;                              // Ctrl-C: the fit stops, interrupted = true
  std::function<void(int iteration, double cost)> progress;  // after each Ceres iteration
};

// A fit that cannot start (the initial design fails to simulate a measurement).
class FitError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Runs the fit; throws FitError when the initial point cannot be evaluated.
FitResult runFit(const Calibration& c, const FitOptions& o);

// Residual statistics of each channel of measurement m for simulated values s.
std::vector<ChannelStats> channelStats(const Measurement& m, const Simulated& s);

}  // namespace lg::calib
