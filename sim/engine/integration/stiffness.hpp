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
//
// Being at the stability bound does not make the implicit method cheaper: where dopri5 is held near
// 3.25 / 1.6e3 s by the orifice damping, ros34pw2 (order 3, at a tolerance three times tighter) may be
// held by accuracy to half that step. So the hand-over is a trial, judged by cost (StiffHandOver):
//
//   D = dopri5's evaluations per simulated second over its last 15 steps, when the test fires;
//   R = ros34pw2's over its first 20 steps after the hand-over;
//   R > D: ros34pw2 costs more, dopri5 takes the run back at the step it had; it tries again only when
//          its D exceeds 1.5 R (it has become stiffer than when ros34pw2 lost), and R is measured anew;
//   R <= D: ros34pw2 keeps the run to its end.
//
// Counts of evaluations and simulated time, never wall time: the same run takes the same decisions.
#pragma once

#include <array>
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

// The cost-judged hand-over between dopri5 and ros34pw2 (the comment at the top).
struct StiffHandOver {
  static constexpr int kDopriWindow = 15;  // dopri5's steps over which D is measured (the test's own count)
  static constexpr int kTrialSteps = 20;   // ros34pw2's steps over which R is measured
  static constexpr double kRetry = 1.5;    // D over the last lost trial's R before dopri5 tries again

  std::array<double, kDopriWindow + 1> tRing{};  // [s] end times of dopri5's last steps (a ring)
  std::array<long, kDopriWindow + 1> eRing{};    // evaluations at those ends
  int seen = 0;                                  // dopri5 steps recorded since the start or the last hand-back
  double dopriRate = 0;  // [1/s] D when ros34pw2 took over
  double lostRate = 0;   // [1/s] R of the last trial that was handed back (0: none)
  double hDopri = 0;     // [s] dopri5's step when it handed over (it resumes with it)
  double trialT0 = 0;    // [s] where the trial began
  long trialE0 = 0;      // evaluations there
  int trialSteps = -1;   // ros34pw2's steps into the trial; -1: no trial running

  // After each accepted dopri5 step (the run's end time t, its evaluation count so far).
  void dopriStep(double t, long evals) {
    const int i = seen++ % (kDopriWindow + 1);
    tRing[i] = t;
    eRing[i] = evals;
  }
  // The stiffness test fired: is a trial worth it? (D now, against the last lost trial's R.)
  bool tryStiff(double t, long evals, double h) {
    if (seen <= kDopriWindow) return false;
    const int oldest = seen % (kDopriWindow + 1);
    const double span = t - tRing[oldest];
    const double D = span > 0 ? double(evals - eRing[oldest]) / span : INFINITY;
    if (lostRate > 0 && D <= kRetry * lostRate) return false;
    dopriRate = D;
    hDopri = h;
    trialT0 = t;
    trialE0 = evals;
    trialSteps = 0;
    return true;
  }
  // After each accepted ros34pw2 step: true when the trial has just been lost (dopri5 takes the run back).
  bool rosStep(double t, long evals) {
    if (trialSteps < 0 || ++trialSteps < kTrialSteps) return false;
    trialSteps = -1;
    const double span = t - trialT0;
    const double R = span > 0 ? double(evals - trialE0) / span : INFINITY;
    if (R <= dopriRate) return false;
    lostRate = R;
    seen = 0;
    return true;
  }
};

}  // namespace lg
