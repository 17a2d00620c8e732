// The dense output of an accepted step, y(t) on [t0, t0 + h]: Dormand-Prince's own continuous
// extension (4th order) or a cubic Hermite between the step's ends; and derivativePart, what an
// event-time Newton correction moves.
#pragma once

#include <vector>

#include "sim/core/math.hpp"

namespace lg {

// The derivative part of a scalar (zero for double): what an event-time Newton correction moves.
template <class S> inline S derivativePart(const S& x) { return x - S(value(x)); }

// Dense output over the last accepted step, y(t) for t in [t0, t0 + h].
template <class S> struct DenseOutput {
  enum Kind { Hermite, Dopri } kind = Hermite;
  S t0 = S(0);
  double h = 0;
  const VecX<S>* y0 = nullptr;
  const VecX<S>* y1 = nullptr;
  const VecX<S>* f0 = nullptr;  // dy/dt at t0 (Hermite)
  const VecX<S>* f1 = nullptr;  // dy/dt at t1 (Hermite)
  const std::vector<VecX<S>>* k = nullptr;  // Dopri stages
  // The step ended on an event: the state at its end (s.t, s.y) may have jumped there (an impact, a mode
  // change and its projection). Else that state is the interpolant's end, up to the step's projection.
  bool endsOnEvent = false;
  void at(const S& t, VecX<S>& out) const {
    const S th = (t - t0) / S(h);
    if (kind == Dopri) {
      // Hairer & Wanner, dopri5 contd5.
      static const double d1 = -12715105075.0 / 11282082432.0, d3 = 87487479700.0 / 32700410799.0,
                          d4 = -10690763975.0 / 1880347072.0, d5 = 701980252875.0 / 199316789632.0,
                          d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;
      const auto& K = *k;
      for (Eigen::Index i = 0; i < out.size(); ++i) {
        const S ydiff = (*y1)[i] - (*y0)[i];
        const S bspl = S(h) * K[0][i] - ydiff;
        const S r4 = ydiff - S(h) * K[6][i] - bspl;
        const S r5 = S(h) * (d1 * K[0][i] + d3 * K[2][i] + d4 * K[3][i] + d5 * K[4][i] + d6 * K[5][i] + d7 * K[6][i]);
        out[i] = (*y0)[i] + th * (ydiff + (S(1) - th) * (bspl + th * (r4 + (S(1) - th) * r5)));
      }
    } else {  // cubic Hermite
      const S h00 = S(2) * th * th * th - S(3) * th * th + S(1), h10 = th * th * th - S(2) * th * th + th,
              h01 = S(-2) * th * th * th + S(3) * th * th, h11 = th * th * th - th * th;
      out = h00 * (*y0) + (h10 * S(h)) * (*f0) + h01 * (*y1) + (h11 * S(h)) * (*f1);
    }
  }
};

}  // namespace lg
