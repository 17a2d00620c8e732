// Point on a plane of the other body (method.md, type 2): 1 row.
//
//   C   = n_j . (p_i - p_j),   n_j = R_j n0_j a body-fixed unit normal of body j
//   J_i = ( n^T,  (a_i x n)^T ),   J_j = (-n^T, -((p_i - r_j) x n)^T )
//   dJ/dt V = 2 (w_j x n).(u_i - u_j) + n.(w_i x (w_i x a_i) - w_j x (w_j x a_j)) + (w_j x (w_j x n)).(p_i - p_j)
// (derivation in row.hpp, writePointOnPlane).
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct PointOnPlane {
  static constexpr int kRows = 1;
  static constexpr bool kUnilateral = false;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i;  // [m] the point, in body i
  Vec3<S> rho_j;  // [m] a point of the plane, in body j
  Vec3<S> n0_j;   // [-] unit normal of the plane, in body j

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows implied = {}) const {
    if (!implied(0)) writePointOnPlane(Ki, rho_i, Kj, rho_j, n0_j, rows[0]);
  }
  template <class T> PointOnPlane<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), castVec<T>(n0_j)};
  }
};

}  // namespace lg
