// Stiffness detection for the Dormand-Prince pair (Hairer, Norsett & Wanner, Solving ODEs I, IV.2 and
// their code dopri5): the step's last two stages are both at c = 1, the 6th at y* = y_n + h sum_j a_6j k_j,
// the 7th (FSAL) at y_n+1, so
//
//   h rho = h |f(y_n+1) - f(y*)| / |y_n+1 - y*|
//
// estimates h times the dominant eigenvalue of the Jacobian along the step. Where it is at the boundary
// of the method's stability region (|h lambda| about 3.3 on the negative real axis; the test takes 3.25),
// the step size is set by stability, not accuracy. 15 such accepted steps with fewer than 6 others
// between any two of them mark the run as stiff: from then on an implicit method is cheaper. A drop is
// mildly stiff where the orifice damping dominates (lambda about -1.6e3 1/s, caps dopri5 near 2 ms), and
// very stiff where a tyre's longitudinal friction is regularised at zero forward speed (mu_x P_t / eps
// over the wheel's effective mass, some 4e4 1/s: steps of 8e-5 s, ten thousand a drop).
#pragma once

#include <cmath>

#include "sim/core/math.hpp"

namespace lg {

struct StiffnessTest {
  static constexpr double kBound = 3.25;  // [-] h rho at or above it: a step at the stability bound
  static constexpr int kStiffSteps = 15;  // such steps that mark the run stiff
  static constexpr int kReset = 6;        // steps below the bound in a row that clear the count
  int atBound = 0, below = 0;
  bool stiff = false;

  // One accepted step of size h: f1 = f(y1), f6 = f(y*) over the first n components. Returns h rho.
  template <class S>
  double observe(double h, const VecX<S>& y1, const VecX<S>& yStar, const VecX<S>& f1, const VecX<S>& f6, int n) {
    double num = 0, den = 0;
    for (int i = 0; i < n; ++i) {
      const double df = value(f1[i]) - value(f6[i]), dy = value(y1[i]) - value(yStar[i]);
      num += df * df;
      den += dy * dy;
    }
    const double hRho = den > 0 ? h * std::sqrt(num / den) : 0.0;
    if (hRho > kBound) {
      below = 0;
      if (++atBound >= kStiffSteps) stiff = true;
    } else if (++below >= kReset) {
      atBound = 0;
    }
    return hRho;
  }
};

}  // namespace lg
