// Joint friction from joint reactions: Coulomb friction along a sliding (or prismatic) joint, proportional
// to the lateral reactions at its two bearings, beside the strut's pressure-proportional seal friction.
//
// The joint (a rod, its body 1 = body i, in a cylinder, its body 2 = body j) holds two axis points p_1, p_2
// of the rod in two planes of the cylinder through the axis, normals n_a, n_b (a prismatic joint adds an
// off-axis point p_3 of the rod in the plane n_b, at the axial position of p_1). Its multipliers give the
// lateral forces the cylinder exerts on the rod there:
//   F_1 = lambda_0 n_a + lambda_1 n_b (+ lambda_4 n_b),   F_2 = lambda_2 n_a + lambda_3 n_b          [N]
// The bearings: one fixed to the cylinder at p_u (its gland), one on the rod at p_l (both on the axis;
// their separation changes with the stroke). With the axial coordinate z = e.(p - p_u) (e the cylinder's
// axis) the lever rule puts the same force and moment on the two bearings:
//   N_l = (z_1 F_1 + z_2 F_2) / z_l,   N_u = F_1 + F_2 - N_l                                          [N]
// and the friction force along the joint, F_f = mu (|N_u| + |N_l|) times the direction of sliding,
// acts as -F_f e on the rod at p_l and +F_f e on the cylinder at p_u (both on the axis: no moment pair).
//   dissipation rate F_f sdot >= 0,  sdot = e.(u_l - u_u);  stored energy none.
//
// Two laws, chosen by the slide (Model::finalize):
//   with the strut's exact friction  the slide carries a Coulomb strut (friction = "coulomb") between the
//     (joined)                       same rod and cylinder, its points on the joint's axis: both frictions
//                                    share the strut's friction lock (friction_lock.hpp), one set of modes
//                                    for the slide. Slipping in the lock's direction sigma:
//                                      F_f = mu (|N_u| + |N_l|) sigma c,   c = sgn(d sdot / d sdot_lock) = +-1
//                                    (exact, no regularisation); stuck: F_f = 0 here, the lock's reaction
//                                    carries it, bounded by the sum of both elements' bounds
//                                      |lambda_lock| <= mu_s (p_1 - p_atm) F + mu (|N_u| + |N_l|);
//                                    held by a stop: 0.
//   alone (regularised)              F_f = mu (|N_u| + |N_l|) sgn_eps(sdot), sgn_eps(v) = v / sqrt(v^2 + eps^2)
//
// The reactions depend on the friction: the engine's stage bearingFriction (sim/engine/engine.hpp) iterates
// F -> lambda -> F on the factor of the multipliers' solve, which contracts when mu times the lever ratio
// of the joint is below 1; it stops at |dF| <= 1e-12 (1 + |F|), or at its round-off floor (|dF| <= 1e-9
// (1 + |F|), no longer halving), and fails the evaluation (a failed run status, never an exception)
// after 60 iterations. Without sliding (joined and stuck or held, or zero
// reactions) the stage does nothing. apply() therefore adds nothing: the stage applies the friction and
// writes the dissipation rate. The joint keeps its rows (a prismatic joint to the ground is not
// eliminated into its body's mobility when it has bearing friction). A plastic impact takes no friction
// impulse; the contact decisions (resolveContacts) are taken without a sliding bearing friction.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct BearingFriction {
  static constexpr int kDissipation = 1;
  static constexpr int kDamping = 1;
  static constexpr int kEvents = 0;
  int joint = -1;                  // the constraint index of the sliding or prismatic joint
  int jointRow = -1;               // its first row (set by Model::finalize)
  int rows = 4;                    // 4 (sliding) or 5 (prismatic)
  int bi = kGround, bj = kGround;  // rod and cylinder (the joint's bodies 1 and 2)
  Vec3<S> rho_1, rho_2;            // [m] the joint's axis points in the rod
  Vec3<S> n_a, n_b;                // [-] the joint's plane normals in the cylinder
  Vec3<S> rho_u;                   // [m] upper bearing, in the cylinder
  Vec3<S> rho_l;                   // [m] lower bearing, in the rod
  S mu = S(0);                     // [-] friction coefficient of the bearings
  double frictionVelocity = 1e-3;  // [m/s] eps of sgn_eps (alone)
  int strut = -1;                  // the Coulomb strut on the same slide (force index, scene reader), or -1
  int slideSign = 1;               // c = sgn(d sdot / d sdot_lock) of that strut's lock rate (scene reader)
  int lockRow = -1;                // that strut's friction-lock row (Model::finalize), or -1: alone

  bool joined() const { return lockRow >= 0; }

  struct Eval {
    Vec3<S> e, armU, armL, Nu, Nl;  // axis; lever arms of p_u (cylinder) and p_l (rod); bearing reactions
    S sdot, Nsum, force;            // [m/s], [N], [N] F_f
  };
  // The bearing reactions from the joint's multipliers lam[0 .. rows), the rate and the friction.
  Eval eval(const Kins<S>& K, const S* lam) const {
    const BodyKin<S>& R = K[bi];
    const BodyKin<S>& C = K[bj];
    Eval r;
    const Vec3<S> na = C.R * n_a, nb = C.R * n_b;
    r.e = na.cross(nb);
    r.armU = C.R * rho_u;
    r.armL = R.R * rho_l;
    const Vec3<S> pu = C.r + r.armU;
    const S z1 = r.e.dot(R.r + R.R * rho_1 - pu), z2 = r.e.dot(R.r + R.R * rho_2 - pu);
    const S zl = r.e.dot(R.r + r.armL - pu);
    Vec3<S> F1 = lam[0] * na + lam[1] * nb;
    const Vec3<S> F2 = lam[2] * na + lam[3] * nb;
    if (rows == 5) F1 += lam[4] * nb;
    r.Nl = (z1 * F1 + z2 * F2) / zl;
    r.Nu = F1 + F2 - r.Nl;
    r.sdot = r.e.dot(R.pointVelocity(r.armL) - C.pointVelocity(r.armU));
    r.Nsum = norm(r.Nu) + norm(r.Nl);
    r.force = joined() ? S(K.slipOf(lockRow) * slideSign) * mu * r.Nsum : mu * r.Nsum * smoothSign(r.sdot, frictionVelocity);
    return r;
  }
  // Does the element push now (alone: always; joined: while its lock slips)?
  bool sliding(const Kins<S>& K) const { return !joined() || K.slipOf(lockRow) != 0; }
  // Its share of the shared lock's bound while stuck, mu (|N_u| + |N_l|) from the last solve's multipliers.
  S lockBound(const Kins<S>& K) const { return mu * eval(K, K.lambda ? K.lambda + jointRow : zeros()).Nsum; }
  // |v| with the derivative 0 at v = 0 (a Jet's sqrt would give NaN there).
  static S norm(const Vec3<S>& v) {
    using std::sqrt;
    const S s2 = v.squaredNorm();
    return value(s2) > 0 ? S(sqrt(s2)) : S(0);
  }
  // The friction on the two bodies (the stage's generalised forces).
  void wrench(const Eval& r, const S& force, Vec6<S>& onRod, Vec6<S>& onCylinder) const {
    const Vec3<S> f = -force * r.e;
    onRod << f, r.armL.cross(f);
    onCylinder << -f, r.armU.cross(Vec3<S>(-f));
  }

  void apply(const Kins<S>&, const Wrenches<S>&, S* dissipation) const { dissipation[0] = S(0); }  // the stage's
  S stored(const Kins<S>&) const { return S(0); }
  void events(const Kins<S>&, S*) const {}
  // dF_f/dsdot = mu (|N_u| + |N_l|) eps^2 / (sdot^2 + eps^2)^(3/2) along sdot = G V (the reactions of the
  // last solve held fixed: their dependence on V is left to the W-method's approximate Jacobian); joined,
  // 0 (constant over a slip segment).
  void damping(const Kins<S>& K, DampingTerm<S>* d) const {
    using std::sqrt;
    const Eval r = eval(K, K.lambda ? K.lambda + jointRow : zeros());
    const S v2 = r.sdot * r.sdot, e2 = S(frictionVelocity * frictionVelocity);
    const S q = sqrt(v2 + e2);
    d->setAxial(bj, bi, r.e, r.armU, r.armL, joined() ? S(0) : mu * r.Nsum * e2 / (q * q * q));
  }
  static std::vector<std::string> outputNames() { return {"N_upper", "N_lower", "F_friction", "s_dot"}; }
  static const char* outputUnit(const std::string& n) { return n == "s_dot" ? "m/s" : "N"; }
  // From the multipliers of the last solve (current after an evaluation of the equations of motion).
  void outputs(const Kins<S>& K, S* out) const {
    const Eval r = eval(K, K.lambda ? K.lambda + jointRow : zeros());
    out[0] = norm(r.Nu);
    out[1] = norm(r.Nl);
    out[2] = r.force;
    out[3] = r.sdot;
  }
  S* parameter(const std::string& key) { return key == "mu" ? &mu : nullptr; }
  template <class T> BearingFriction<T> cast() const {
    return {joint, jointRow, rows, bi, bj, castVec<T>(rho_1), castVec<T>(rho_2), castVec<T>(n_a), castVec<T>(n_b),
            castVec<T>(rho_u), castVec<T>(rho_l), T(mu), frictionVelocity, strut, slideSign, lockRow};
  }
  static const S* zeros() {  // the multipliers before any solve
    static const S z[5] = {S(0), S(0), S(0), S(0), S(0)};
    return z;
  }
};

}  // namespace lg
