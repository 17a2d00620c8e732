// Exact Coulomb friction of a force element along a relative rate sdot = G V (method.md: "stick may
// be treated as a constraint"). The element's friction force is P_f (its axial convention: the
// generalised force is -P_f G^T), bounded by F_max >= 0 (for the strut F_max = mu (p_1 - p_atm) F).
// Per lock row k, State::active[k] and State::slip[k] hold its mode:
//
//   slip,  slip[k] = sigma = +-1   P_f = sigma F_max (constant sign over the segment); the element's other
//                                   sign-dependent terms use sigma too, so the right-hand side is smooth
//                                   until the event  sigma sdot = 0  (the rate stops)
//   stick, active[k] = 1           the lock row  sdot = G V = 0  is enforced; its multiplier lambda is the
//                                   friction, P_f = -lambda, while  |lambda| <= F_max; the event
//                                   F_max - |lambda| = 0  lets it slip with sigma = -sgn(lambda)
//   held,  slip[k] = 0, active 0   no friction force: a stop acting between the same two bodies is
//                                   enforced and holds the rate at zero (the lock would repeat its row)
//
// At rest (a rate that stopped, a stop that let go, the start of a run) the mode is decided on the
// acceleration-level problem with the lock enforced: stick if |lambda| <= F_max, else slip with
// sigma = -sgn(lambda) (the direction the unbalanced force drives, friction opposing it at F_max).
//
// The lock row (one row, bodies i and j, lever arms a_i, a_j of the two points, e = (p_i - p_j)/L):
//   C     = 0 (a velocity-level lock: the rate is held at zero, the stuck stroke by its integral)
//   J_i   = -(e, a_i x e),   J_j = (e, a_j x e)                         (sdot = -dL/dt)
//   gamma = -( e.(w_i x (w_i x a_i) - w_j x (w_j x a_j)) + (|d'|^2 - (e.d')^2) / L ),  d' = u_i - u_j
// so that d(sdot)/dt = J dV/dt + gamma.
#pragma once

#include "sim/constraints/row.hpp"

namespace lg {

// What a force element declares about its friction lock (Model::finalize adds the row).
struct FrictionLockInfo {
  bool present = false;
  int bi = kGround, bj = kGround;
};

// Writes the lock row of the rate sdot = -dL/dt, L = |p_i - p_j|, for points with world lever arms
// a_i, a_j of bodies i and j.
template <class S>
inline void writeAxialLock(const BodyKin<S>& Ki, const Vec3<S>& a_i, const BodyKin<S>& Kj, const Vec3<S>& a_j,
                           Row<S>& row) {
  const Vec3<S> d = (Ki.r + a_i) - (Kj.r + a_j);
  const S L = d.norm();
  const Vec3<S> e = d / L;
  const Vec3<S> dd = Ki.pointVelocity(a_i) - Kj.pointVelocity(a_j);
  const S ed = e.dot(dd);
  row.C = S(0);
  row.Ji << -e, -a_i.cross(e);
  row.Jj << e, a_j.cross(e);
  row.gamma = -(e.dot(Ki.w.cross(Ki.w.cross(a_i)) - Kj.w.cross(Kj.w.cross(a_j))) + (dd.dot(dd) - ed * ed) / L);
}

}  // namespace lg
