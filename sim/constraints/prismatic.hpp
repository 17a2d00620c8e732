// Prismatic joint (the drop rig's vertical guide): translation along one axis only. Removes 5.
//
// The four rows of a sliding joint (see sliding.hpp: two axis points of body i in two planes of body j
// through the axis) plus one row that stops the spin: an off-axis point p_i3 = p + l t_a of body i
// (l = 1 m, t_a perpendicular to the axis) held in the plane of body j through the axis with normal
// n_b = e x t_a:
//   C = ( n_a.(p_i1 - p_j), n_b.(p_i1 - p_j), n_a.(p_i2 - p_j), n_b.(p_i2 - p_j), n_b.(p_i3 - p_j) )
// J and dJ/dt V of each row as in writePointOnPlane.
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct Prismatic {
  static constexpr int kRows = 5;
  static constexpr bool kUnilateral = false;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i1, rho_i2, rho_i3;  // [m] two axis points and one off-axis point, in body i
  Vec3<S> rho_j;                   // [m] a point of the axis, in body j
  Vec3<S> n_a, n_b;                // [-] normals of two planes through the axis, in body j

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows implied = {}) const {
    writeAxisPoints(Ki, rho_i1, rho_i2, Kj, rho_j, n_a, n_b, rows, implied);
    if (!implied(4)) writePointOnPlane(Ki, rho_i3, Kj, rho_j, n_b, rows[4]);
  }
  template <class T> Prismatic<T> cast() const {
    return {bi, bj, castVec<T>(rho_i1), castVec<T>(rho_i2), castVec<T>(rho_i3), castVec<T>(rho_j),
            castVec<T>(n_a), castVec<T>(n_b)};
  }
};

}  // namespace lg
