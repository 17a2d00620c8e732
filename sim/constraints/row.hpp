// One scalar constraint row, as the multiplier solvers see it.
//
// For a row k between bodies i and j (j may be the ground):
//   C_k            the constraint value (= 0 for a bilateral row, >= 0 for a unilateral one)
//   J_i, J_j       1x6 blocks over (v, omega) of each body, with dC/dt = J_i V_i + J_j V_j
//   gamma          dJ/dt V, the velocity-product part of d2C/dt2 = J dV/dt + gamma
// The solvers see rows only; each constraint type writes its own rows.
#pragma once

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct Row {
  S C;
  S gamma;
  Vec6<S> Ji;
  Vec6<S> Jj;
};

// The static part of a row: which bodies it couples and whether it may only push.
struct RowInfo {
  int bi = kGround;
  int bj = kGround;
  bool unilateral = false;
  int constraint = -1;  // index of the constraint that owns the row (-1 for a force element's row)
  int force = -1;       // index of the force element that owns the row: a Coulomb friction lock (stick)
  bool friction() const { return force >= 0; }
};

// The rows of one constraint that its write may leave as they are: those the bodies' mobility
// satisfies by itself (a planar model's out-of-plane rows, impliedPlanarRows), which no solve,
// projection or event reads. Empty: every row is written.
struct ImpliedRows {
  const char* implied = nullptr;  // per row of the constraint: 1 = implied (not written)
  bool operator()(int k) const { return implied && implied[k]; }
  bool all(int first, int last) const {  // rows [first, last) all implied
    for (int k = first; k < last; ++k)
      if (!(*this)(k)) return false;
    return true;
  }
};

// Writes one row of the type "point p_i of body i lies in the plane of body j through p_j with the
// body-fixed unit normal n0_j" (method.md, type 2):
//   C    = n . (p_i - p_j),                     n = R_j n0_j, d = p_i - p_j, a_i = p_i - r_i, a_j = p_j - r_j
//   dC/dt = n.(u_i - u_j) + (w_j x n).d,        u = v + w x a (material point velocity)
//   J_i  = ( n^T,  (a_i x n)^T )
//   J_j  = (-n^T, -((p_i - r_j) x n)^T )
//   gamma = 2 (w_j x n).(u_i - u_j) + n.(w_i x (w_i x a_i) - w_j x (w_j x a_j)) + (w_j x (w_j x n)).d
// The part of it that depends on the point only (not on the plane's normal), shared by the rows of
// one point in several planes of body j (a revolute joint's axis point, a sliding joint's).
template <class S> struct PlanePoint {
  Vec3<S> a_i, d, lever, u, acc;  // a_i, p_i - p_j, p_i - r_j, u_i - u_j, w_i x (w_i x a_i) - w_j x (w_j x a_j)
  PlanePoint(const BodyKin<S>& Ki, const Vec3<S>& rho_i, const BodyKin<S>& Kj, const Vec3<S>& rho_j) {
    a_i = Ki.R * rho_i;
    const Vec3<S> a_j = Kj.R * rho_j;
    const Vec3<S> p_i = Ki.r + a_i;
    const Vec3<S> p_j = Kj.r + a_j;
    d = p_i - p_j;
    lever = p_i - Kj.r;
    u = Ki.pointVelocity(a_i) - Kj.pointVelocity(a_j);
    acc = Ki.w.cross(Ki.w.cross(a_i)) - Kj.w.cross(Kj.w.cross(a_j));
  }
  void write(const BodyKin<S>& Kj, const Vec3<S>& n0_j, Row<S>& row) const {
    const Vec3<S> n = Kj.R * n0_j;
    const Vec3<S> wn = Kj.w.cross(n);
    row.C = n.dot(d);
    row.Ji << n, a_i.cross(n);
    row.Jj << -n, -lever.cross(n);
    row.gamma = S(2) * wn.dot(u) + n.dot(acc) + Kj.w.cross(wn).dot(d);
  }
};

template <class S>
inline void writePointOnPlane(const BodyKin<S>& Ki, const Vec3<S>& rho_i, const BodyKin<S>& Kj,
                              const Vec3<S>& rho_j, const Vec3<S>& n0_j, Row<S>& row) {
  PlanePoint<S>(Ki, rho_i, Kj, rho_j).write(Kj, n0_j, row);
}

// Writes the four rows of "two points of body i, rho_i1 and rho_i2, lie on the axis of body j through p_j"
// (a sliding or prismatic joint): each point in the two planes through the axis with normals n_a, n_b
// (rows 2 p and 2 p + 1 for point p), each point's part once (PlanePoint); a point whose both rows are
// implied is skipped.
template <class S>
inline void writeAxisPoints(const BodyKin<S>& Ki, const Vec3<S>& rho_i1, const Vec3<S>& rho_i2, const BodyKin<S>& Kj,
                            const Vec3<S>& rho_j, const Vec3<S>& n_a, const Vec3<S>& n_b, Row<S>* rows,
                            ImpliedRows implied = {}) {
  const Vec3<S>* rho[2] = {&rho_i1, &rho_i2};
  for (int p = 0; p < 2; ++p) {
    if (implied.all(2 * p, 2 * p + 2)) continue;
    const PlanePoint<S> point(Ki, *rho[p], Kj, rho_j);
    if (!implied(2 * p)) point.write(Kj, n_a, rows[2 * p]);
    if (!implied(2 * p + 1)) point.write(Kj, n_b, rows[2 * p + 1]);
  }
}

// Writes the three rows of "p_j - p_i = 0" (method.md, type 1):
//   J_i = (-E3, [a_i]x),  J_j = (E3, -[a_j]x),  gamma = w_j x (w_j x a_j) - w_i x (w_i x a_i)
template <class S>
inline void writeCoincidentPoints(const BodyKin<S>& Ki, const Vec3<S>& rho_i, const BodyKin<S>& Kj,
                                  const Vec3<S>& rho_j, Row<S>* rows, ImpliedRows implied = {}) {
  const Vec3<S> a_i = Ki.R * rho_i;
  const Vec3<S> a_j = Kj.R * rho_j;
  const Vec3<S> C = (Kj.r + a_j) - (Ki.r + a_i);
  const Vec3<S> g = Kj.w.cross(Kj.w.cross(a_j)) - Ki.w.cross(Ki.w.cross(a_i));
  const Mat3<S> Ai = skew(a_i);
  const Mat3<S> Aj = skew(a_j);
  for (int k = 0; k < 3; ++k) {
    if (implied(k)) continue;
    rows[k].C = C[k];
    rows[k].gamma = g[k];
    rows[k].Ji.setZero();
    rows[k].Jj.setZero();
    rows[k].Ji[k] = S(-1);
    rows[k].Jj[k] = S(1);
    rows[k].Ji.template tail<3>() = Ai.row(k).transpose();
    rows[k].Jj.template tail<3>() = -Aj.row(k).transpose();
  }
}

}  // namespace lg
