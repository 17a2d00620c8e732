// Sliding joint (the article's "v": a rod in a cylinder). Removes 4 degrees of freedom and keeps
// the slide along the axis and the spin about it free.
//
// Four rows of type 2 (point on a plane, see point_on_plane.hpp): two points p_i1, p_i2 on the axis
// of body i (the rod), each held in two planes of body j (the cylinder) that contain the axis, with
// body-fixed normals n_a, n_b perpendicular to the axis and to each other:
//   C = ( n_a.(p_i1 - p_j), n_b.(p_i1 - p_j), n_a.(p_i2 - p_j), n_b.(p_i2 - p_j) )
// J and dJ/dt V of each row as in writePointOnPlane.
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct Sliding {
  static constexpr int kRows = 4;
  static constexpr bool kUnilateral = false;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i1, rho_i2;  // [m] two points of the axis, in body i
  Vec3<S> rho_j;           // [m] a point of the axis, in body j
  Vec3<S> n_a, n_b;        // [-] normals of the two planes through the axis, in body j

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows implied = {}) const {
    writeAxisPoints(Ki, rho_i1, rho_i2, Kj, rho_j, n_a, n_b, rows, implied);
  }
  template <class T> Sliding<T> cast() const {
    return {bi, bj, castVec<T>(rho_i1), castVec<T>(rho_i2), castVec<T>(rho_j), castVec<T>(n_a), castVec<T>(n_b)};
  }
};

}  // namespace lg
