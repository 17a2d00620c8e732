// The dense output of an accepted step, y(t) on [t0, t0 + h]: Dormand-Prince's own continuous
// extension (4th order); a Rosenbrock method's, the positions by the cubic Hermite between the step's
// ends and the velocities by the method's own extension (3rd order, RosenbrockTableau::hasDense); or a
// cubic Hermite of every component; and derivativePart, what an
// event-time Newton correction moves.
#pragma once

#include <vector>

#include "sim/core/math.hpp"

namespace lg {

// The derivative part of a scalar (zero for double): what an event-time Newton correction moves.
template <class S> inline S derivativePart(const S& x) { return x - S(value(x)); }

// Dense output over the last accepted step, y(t) for t in [t0, t0 + h].
template <class S> struct DenseOutput {
  enum Kind { Hermite, Dopri, Rosenbrock } kind = Hermite;
  S t0 = S(0);
  double h = 0;
  const VecX<S>* y0 = nullptr;
  const VecX<S>* y1 = nullptr;
  const VecX<S>* f0 = nullptr;  // dy/dt at t0 (Hermite)
  const VecX<S>* f1 = nullptr;  // dy/dt at t1 (Hermite)
  const std::vector<VecX<S>>* k = nullptr;  // Dopri stages; Rosenbrock: k[1..4] = U_1..U_4
  const double (*weights)[3] = nullptr;      // Rosenbrock: RosenbrockTableau::d
  int nx = 0;  // Rosenbrock: the positions y[0, nx) (the rest: velocities and the dissipated energies)
  // The step ended on an event: the state at its end (s.t, s.y) may have jumped there (an impact, a mode
  // change and its projection). Else that state is the interpolant's end, up to the step's projection.
  bool endsOnEvent = false;
  // The step's closing evaluation (kinematics, rows, multipliers and outputs in the workspace) is at the
  // state it ends on itself (the Rosenbrock steps, which evaluate after the projection); else a round-off
  // away (dopri5's last stage is before the quaternions' renormalisation, the fixed steps' likewise).
  bool closesAtState = false;
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
    } else {
      // Cubic Hermite: of every component, or with a Rosenbrock step of the positions alone. Their rates
      // at the ends are the step's velocities; those of the velocities, the accelerations f(y_n+1), carry
      // the stiff eigenvalue times whatever the step left off the slow manifold, so the velocities take
      // the method's continuous extension (RosenbrockTableau::hasDense), which never evaluates f.
      const S h00 = S(2) * th * th * th - S(3) * th * th + S(1), h10 = th * th * th - S(2) * th * th + th,
              h01 = S(-2) * th * th * th + S(3) * th * th, h11 = th * th * th - th * th;
      const Eigen::Index n = kind == Rosenbrock ? nx : out.size();
      out.head(n) = h00 * y0->head(n) + (h10 * S(h)) * f0->head(n) + h01 * y1->head(n) + (h11 * S(h)) * f1->head(n);
      if (kind == Rosenbrock) {
        const auto& K = *k;
        const double(*d)[3] = weights;
        S w[4];
        for (int j = 0; j < 4; ++j) w[j] = th * (S(d[j][0]) + th * (S(d[j][1]) + th * S(d[j][2])));
        const Eigen::Index nv = out.size() - n;
        out.tail(nv) = y0->tail(nv) + w[0] * K[1].tail(nv) + w[1] * K[2].tail(nv) + w[2] * K[3].tail(nv) +
                       w[3] * K[4].tail(nv);
      }
    }
  }
};

}  // namespace lg
