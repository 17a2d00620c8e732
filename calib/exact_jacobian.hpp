// The exact Jacobian of a calibration's residuals: forward-mode derivatives through the drop test
// (ceres::Jet, sim/drop/gradient.hpp's caseHistoryGradient), the default of every fit.
//
// A residual is w (y(t_i - t_shift; x) - y_i). For a sample after touchdown (t_s = t_i - t_shift > 0):
//   dr/dx_j       = w dy/dx_j (t_s)            the history's derivative at the fixed time t_s
//   dr/dt_shift   = -w dy/dt (t_s)             the rate along the integrator's dense output
// (0 for a sample past the case's end, which is clamped there). Before touchdown (t_s <= 0) every
// channel keeps its touchdown value y(0), and the travel is h = V t_s + (1 - L) g t_s^2 / 2:
//   dr/dx_j       = w dy(0)/dx_j  (+ w t_s for h when x_j is the case's sink speed V,
//                                   - w g t_s^2 / 2 for h when x_j is its lift ratio L)
//   dr/dt_shift   = -w (V + (1 - L) g t_s) for h, 0 for the others.
// The residuals themselves are the plain double run's (simulateMeasurement), so that they are the same
// bits with either Jacobian. These are the derivatives of the residuals as the adaptive run computes
// them (its step sizes, chosen on values, are constants to them); a sample at an event's time takes
// the left side's (the state jumps there). Measurements run in parallel, each into its own slot: the
// same result for any thread count.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "calib/residuals.hpp"

namespace lg::calib {

class ExactDerivatives final : public ResidualJacobian {
 public:
  ExactDerivatives(const Calibration& c, int threads, std::function<bool()> stop = {})
      : c_(c), threads_(threads), stop_(std::move(stop)) {}
  std::string source() const override;
  void evaluate(const Point& p, bool jacobians, std::vector<MeasurementEval>& out) const override;

 private:
  void evaluateOne(const Point& p, std::size_t m, bool jacobians, MeasurementEval& e) const;
  const Calibration& c_;
  int threads_;
  std::function<bool()> stop_;
};

}  // namespace lg::calib
