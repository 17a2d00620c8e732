// Distance stop (the article's "zh"; unilateral, 1 row): keeps a point of body i and a point of
// body j no farther apart than L ("max" form) or no nearer than L ("min" form).
//
// With d = p_j - p_i and a = p - r:
//   "max":  C = (L^2 - d.d)/2 >= 0,   J_i = ( d^T, (a_i x d)^T ),   J_j = (-d^T, -(a_j x d)^T )
//           dJ/dt V = -(u_j - u_i).(u_j - u_i) - d.(w_j x (w_j x a_j) - w_i x (w_i x a_i))
//   "min":  C = (d.d - L^2)/2 >= 0, every sign reversed.
// (dC/dt = -d.(u_j - u_i); d.(w x a) = w.(a x d).)  The multiplier may only push: lambda >= 0.
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct DistanceStop {
  static constexpr int kRows = 1;
  static constexpr bool kUnilateral = true;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;  // [m] the two points, in their bodies
  S L;                   // [m] the limiting distance
  bool noFarther = true; // true: |d| <= L; false: |d| >= L

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows = {}) const {  // (never implied)
    const Vec3<S> a_i = Ki.R * rho_i;
    const Vec3<S> a_j = Kj.R * rho_j;
    const Vec3<S> d = (Kj.r + a_j) - (Ki.r + a_i);
    const Vec3<S> dd = Kj.pointVelocity(a_j) - Ki.pointVelocity(a_i);
    const S sign = noFarther ? S(1) : S(-1);
    Row<S>& row = rows[0];
    row.C = sign * (L * L - d.dot(d)) / S(2);
    row.Ji << sign * d, sign * a_i.cross(d);
    row.Jj << -sign * d, -sign * a_j.cross(d);
    row.gamma = -sign * (dd.dot(dd) + d.dot(Kj.w.cross(Kj.w.cross(a_j)) - Ki.w.cross(Ki.w.cross(a_i))));
  }
  template <class T> DistanceStop<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), T(L), noFarther};
  }
};

}  // namespace lg
