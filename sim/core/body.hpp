// Bodies and their kinematics.
//
// A body i has mass m_i, principal inertia I0_i = diag(Ixi, Ieta, Izeta) in a frame at its centre of
// mass, and a pose (r_i, q_i): centre-of-mass position in the world and unit quaternion. Velocities
// are (v_i, omega_i), both in world coordinates. World inertia I_i = R_i I0_i R_i^T (method.md).
// Body index -1 is the fixed ground: r = 0, R = E3, v = omega = 0, infinite mass.
#pragma once

#include <string>

#include "sim/core/math.hpp"

namespace lg {

constexpr int kGround = -1;

template <class S> struct Body {
  std::string name;
  S mass;            // [kg]
  Vec3<S> inertia;   // [kg m^2] principal moments (Ixi, Ieta, Izeta) in the body frame

  template <class T> Body<T> cast() const { return {name, T(mass), castVec<T>(inertia)}; }
};

// How a body may move (Model::finalize): freely (6 DOF), only along a fixed world axis (a prismatic joint to
// the ground eliminated), not at all (a fixed joint to the ground eliminated), or in the plane of a planar
// model (translations perpendicular to its unit normal n, rotation about n: 3 DOF).
enum Mobility : signed char { kFree = 0, kTranslation = 1, kImmobile = 2, kPlanar = 3 };

// The part of a body-side 6-vector (lin, ang) in the body's motions (Mobility, axis a): the orthogonal
// projection onto them. Velocities (projectMobility) and a row's plane part (impliedPlanarRows) use it.
template <class T> void restrictToMobility(signed char mobility, const Vec3<T>& a, Vec3<T>& lin, Vec3<T>& ang) {
  if (mobility == kFree) return;
  if (mobility == kPlanar) {
    lin = lin - a * a.dot(lin);
    ang = a * a.dot(ang);
    return;
  }
  if (mobility == kTranslation) lin = a * a.dot(lin);
  else lin.setZero();
  ang.setZero();
}

// What the stages after "kinematics" read about one body at one instant.
template <class S> struct BodyKin {
  Vec3<S> r;        // [m] centre of mass, world
  Mat3<S> R;        // body-to-world rotation
  Vec3<S> v;        // [m/s] centre-of-mass velocity, world
  Vec3<S> w;        // [rad/s] angular velocity, world
  Vec3<S> I0;       // [kg m^2] principal inertia (body frame); the world inertia is R I0 R^T
  Mat3<S> IwInv;    // [1/(kg m^2)] (R I0 R^T)^-1; of a planar body the restricted n n^T / I_n (invMassTimes)
  S mass;           // [kg]
  S invMass;        // [1/kg]
  signed char mobility = kFree;  // see Mobility; set once by the workspace from the model
  Vec3<S> axis = Vec3<S>::Zero();  // [-] the world axis of a kTranslation body, the plane normal n of a kPlanar one
  signed char planeAxis = -1;      // of a kPlanar body whose n is a coordinate axis (+-e_k): k, else -1

  // The body's (restricted) inverse mass applied to a wrench (f, tau): for a free body
  // (f / m, I^-1 tau); for one guided along the unit axis a, the inverse mass restricted to its
  // motions S = (a, 0), S (S^T M S)^-1 S^T (f, tau) = (a (a.f) / m, 0) -- the exact elimination of the
  // guide's five rows; for an immobile body 0; for a planar one with plane normal n (a principal axis of
  // its inertia, checked where the scene is read), S = [(E3 - n n^T, 0), (0, n)]:
  //   ((f - n (n.f)) / m, n (n.tau) / I_n),   I_n = n^T R I0 R^T n = I0 . (R^T n)^2 (componentwise),
  // the rotation's part held in IwInv = n n^T / I_n (kinematics), so that it is one product as for a free body.
  [[gnu::always_inline]] Vec6<S> invMassTimes(const Vec3<S>& f, const Vec3<S>& tau) const {  // (inline: W, aFree)
    Vec6<S> out;
    if (mobility == kFree) {
      out.template head<3>() = invMass * f;
      out.template tail<3>() = IwInv * tau;
    } else if (mobility == kTranslation) {
      out.template head<3>() = axis * (axis.dot(f) * invMass);
      out.template tail<3>().setZero();
    } else if (planeAxis >= 0) {  // n = +-e_a: the products below without their terms of exact zeros
      out.template head<3>() = f * invMass;
      out[planeAxis] = S(0);
      out.template tail<3>().setZero();
      out[3 + planeAxis] = IwInv(planeAxis, planeAxis) * tau[planeAxis];
    } else if (mobility == kPlanar) {
      out.template head<3>() = inPlane(f) * invMass;
      out.template tail<3>() = IwInv * tau;
    } else {
      out.setZero();
    }
    return out;
  }

  // The coordinate axis k of a unit vector that is +-e_k exactly, else -1.
  static signed char coordinateAxis(const Vec3<S>& n) {
    for (int k = 0; k < 3; ++k)
      if (std::abs(value(n[k])) == 1.0 && value(n[(k + 1) % 3]) == 0.0 && value(n[(k + 2) % 3]) == 0.0)
        return static_cast<signed char>(k);
    return -1;
  }

  // A planar body's vector without its part along the plane normal.
  Vec3<S> inPlane(const Vec3<S>& f) const { return f - axis * axis.dot(f); }

  // Angular momentum about the centre of mass, I_w w = R (I0 (R^T w)) (world).
  Vec3<S> angularMomentum() const { return R * I0.cwiseProduct(R.transpose() * w); }

  // World position of a body-fixed point rho (body coordinates), its lever arm and velocity.
  Vec3<S> point(const Vec3<S>& rho) const { return r + R * rho; }
  Vec3<S> pointVelocity(const Vec3<S>& arm) const { return v + w.cross(arm); }

  static BodyKin ground() {
    BodyKin k;
    k.r.setZero();
    k.R.setIdentity();
    k.v.setZero();
    k.w.setZero();
    k.I0.setZero();
    k.IwInv.setZero();
    k.mass = S(0);
    k.invMass = S(0);
    return k;
  }
};

// Kinematics of all bodies, with index -1 (kGround) mapping to the ground, and the modes of the
// friction-lock rows (sim/forces/friction_lock.hpp) that the force elements with exact friction read.
template <class S> struct Kins {
  const BodyKin<S>* k;  // n bodies followed by the ground
  int n;
  const signed char* slip = nullptr;  // per row: the slip direction of a friction lock (+1, -1, 0: none)
  const S* lambda = nullptr;          // per row: the multiplier of the last solve (0 where not enforced)
  const BodyKin<S>& operator[](int b) const { return b < 0 ? k[n] : k[b]; }
  int slipOf(int row) const { return (slip && row >= 0) ? slip[row] : 0; }
  S lambdaOf(int row) const { return (lambda && row >= 0) ? lambda[row] : S(0); }
};

// Resultant force and moment on each body (world), accumulated by the force elements.
template <class S> struct Wrenches {
  Vec6<S>* w;  // (f, tau) per body
  // Adds a force f applied at the world lever arm 'arm' from the centre of mass of body b.
  void addAt(int b, const Vec3<S>& arm, const Vec3<S>& f) const {
    if (b < 0) return;
    w[b].template head<3>() += f;
    w[b].template tail<3>() += arm.cross(f);
  }
  void addForce(int b, const Vec3<S>& f) const {
    if (b >= 0) w[b].template head<3>() += f;
  }
};

// A force element's stiffness as a rank-1 term: its force law P(s, sdot) acts through the generalised
// force Q = -P G^T, with sdot = G V = Gi.(v_i, w_i) + Gj.(v_j, w_j) a relative rate and s the coordinate
// whose rate it is, so dQ/dV = -c G^T G with c = dP/dsdot >= 0 (the velocity stiffness) and, through s,
// dQ/dx = -k G^T ds/dx with k = dP/ds (the position stiffness). The linearly implicit integrators
// (ros2, ros34pw2) take both into their W: the orifice damping and the regularised friction that make a
// drop stiff, and the gas spring's and the tyre's stiffness, without which ros34pw2 loses most of its
// accuracy where the strut starts to stroke (a W-method keeps its order with any W; its error constant
// is what the terms set).
template <class S> struct DampingTerm {
  int bi = kGround, bj = kGround;
  Vec6<S> Gi = Vec6<S>::Zero(), Gj = Vec6<S>::Zero();
  S c = S(0);  // [N s/m] dP/dsdot
  S k = S(0);  // [N/m] dP/ds

  // For an element acting along the unit axis e between points with lever arms a_i, a_j of bodies
  // bi, bj (its rate the elongation rate, e from i to j): G_i = -(e, a_i x e), G_j = (e, a_j x e).
  void setAxial(int i, int j, const Vec3<S>& e, const Vec3<S>& a_i, const Vec3<S>& a_j, const S& c_,
                const S& k_ = S(0)) {
    bi = i;
    bj = j;
    Gi << -e, -a_i.cross(e);
    Gj << e, a_j.cross(e);
    c = c_;
    k = k_;
  }
};

}  // namespace lg
