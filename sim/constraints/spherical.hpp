// Spherical joint (the article's joints "a" and "b"): a point of body i and a point of body j
// coincide. 3 rows, removes the 3 relative translations.
//
//   C   = p_j - p_i,                    p = r + R rho,  a = p - r
//   J_i = (-E3,  [a_i]x),   J_j = (E3, -[a_j]x)
//   dJ/dt V = w_j x (w_j x a_j) - w_i x (w_i x a_i)
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

template <class S> struct Spherical {
  static constexpr int kRows = 3;
  static constexpr bool kUnilateral = false;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;  // [m] the joint point in each body's frame

  void write(const BodyKin<S>& Ki, const BodyKin<S>& Kj, Row<S>* rows, ImpliedRows implied = {}) const {
    writeCoincidentPoints(Ki, rho_i, Kj, rho_j, rows, implied);
  }
  template <class T> Spherical<T> cast() const { return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j)}; }
};

}  // namespace lg
