// Cylindrical hinge / revolute joint (the article's "g" and "d"). Removes 5 degrees of freedom and
// keeps the rotation about the hinge axis free.
//
// One spherical joint at the hinge point p (3 rows, see spherical.hpp) plus two rows of type 2 for a
// second point of the axis, p_i2 = p + l e (l = 1 m, e the axis, fixed in body i), held in two planes
// of body j through the axis with normals n_a, n_b perpendicular to e:
//   C = ( p_j - p_i,  n_a.(p_i2 - p_j),  n_b.(p_i2 - p_j) )
// J and dJ/dt V as in writeCoincidentPoints and writePointOnPlane.
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct Revolute {
  static constexpr int kRows = 5;
  static constexpr bool kUnilateral = false;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;  // [m] the hinge point in each body
  Vec3<S> rho_i2;        // [m] a second point of the axis, in body i
  Vec3<S> n_a, n_b;      // [-] normals of two planes through the axis, in body j

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows implied = {}) const {
    writeCoincidentPoints(Ki, rho_i, Kj, rho_j, rows, implied);
    if (implied.all(3, 5)) return;  // (a planar model: the axis is the plane's normal)
    const PlanePoint<S> p2(Ki, rho_i2, Kj, rho_j);  // (the axis point's part of both rows, once)
    if (!implied(3)) p2.write(Kj, n_a, rows[3]);
    if (!implied(4)) p2.write(Kj, n_b, rows[4]);
  }
  template <class T> Revolute<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), castVec<T>(rho_i2), castVec<T>(n_a), castVec<T>(n_b)};
  }
};

}  // namespace lg
