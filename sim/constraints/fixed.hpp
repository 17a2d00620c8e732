// Fixed joint (weld): body i moves with body j. Removes all 6 degrees of freedom.
//
// A spherical joint at p (3 rows) plus three rows of type 2 that stop the relative rotation:
// p_ix = p + l t_x (l = 1 m) in the planes of body j through p with normals t_y and t_z, and
// p_iy = p + l t_y in the plane with normal t_z ((t_x, t_y, t_z) orthonormal):
//   C = ( p_j - p_i, t_y.(p_ix - p_j), t_z.(p_ix - p_j), t_z.(p_iy - p_j) )
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct Fixed {
  static constexpr int kRows = 6;
  static constexpr bool kUnilateral = false;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;    // [m] the weld point in each body
  Vec3<S> rho_ix, rho_iy;  // [m] p + l t_x and p + l t_y, in body i
  Vec3<S> t_y, t_z;        // [-] plane normals, in body j

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows implied = {}) const {
    writeCoincidentPoints(Ki, rho_i, Kj, rho_j, rows, implied);
    if (!implied.all(3, 5)) {
      const PlanePoint<S> px(Ki, rho_ix, Kj, rho_j);  // (the point's part of both rows, once)
      if (!implied(3)) px.write(Kj, t_y, rows[3]);
      if (!implied(4)) px.write(Kj, t_z, rows[4]);
    }
    if (!implied(5)) writePointOnPlane(Ki, rho_iy, Kj, rho_j, t_z, rows[5]);
  }
  template <class T> Fixed<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), castVec<T>(rho_ix), castVec<T>(rho_iy),
            castVec<T>(t_y), castVec<T>(t_z)};
  }
};

}  // namespace lg
