// Reference model of the seed trailing-link gear (spec: shared/spec/seed-gear.md) written as
// Lagrange equations of the SECOND kind in q = (y5, theta). Independent of sim/.
//
// Derivation (planar: every motion is in the x-y plane, every rotation about z)
// ---------------------------------------------------------------------------
// y5 [m]: height of the airframe CoM (vertical guide), y5(0) = 1.50; dy = y5 - y5(0).
// theta [rad]: lever rotation about the hinge D (fixed in the airframe), counter-clockwise about
//   +z, theta(0) = 0. R(a) = planar rotation by a, perp(v) = z x v = (-v_y, v_x).
// Points fixed in the airframe: D = D0 + dy e_y, C = C0 + dy e_y.
// Points fixed in the lever (A, B, lever CoM G2): P = D + R(theta) (P0 - D0), so with
//   w = R(theta)(P0 - D0):  dP/dy5 = e_y,  dP/dtheta = perp(w),  d2P/dtheta2 = -w.
// Strut: d = B - C = (D0 - C0) + R(theta)(B0 - D0) depends on theta only;
//   l = |d|, l' = d.d'/l, l'' = (d'.d' + d.d'' - l'^2)/l,  d' = perp(R b0), d'' = -R b0;
//   stroke s = L0 - l, grad s = (0, -l'), qdot^T Hess(s) qdot = -l'' thetadot^2;
//   strut direction phi = atan2(d_y, d_x): with c = d x d' (z component), c' = d x d'',
//   phi' = c/l^2, phi'' = c'/l^2 - 2 c l'/l^3.
// Rod 3 (pivot B) and cylinder 4 (pivot C) rotate with phi; their CoMs are fixed in them:
//   G3 = B + R(phi - phi0)(G30 - B0),  G4 = C + R(phi - phi0)(G40 - C0); with u = R(phi-phi0) r0:
//   dG/dtheta = dPivot/dtheta + phi' perp(u),  d2G/dtheta2 = d2Pivot/dtheta2 + phi'' perp(u) - phi'^2 u.
// Wheel 1: its hinge is frictionless, and gravity and the tyre force act at its centre A, so no
//   moment acts on it: its absolute angular velocity stays 0 and it only translates with A.
// Airframe 5: translation along y only.
// Every CoM r_i(q) = r_i(theta) + dy e_y, so the Jacobian is J_i = [e_y, r_i'(theta)] and the
//   acceleration is J_i qdd + r_i''(theta) thetadot^2 (exact; second derivatives analytic).
// Kinetic energy T = 1/2 qdot^T M qdot with
//   M = sum_i m_i J_i^T J_i + Izz2 e2 e2^T + (Izz3 + Izz4) [0 phi']^T [0 phi'],
// and the velocity-product terms (d/dt dT/dqdot - dT/dq - M qdd) are
//   hv = sum_i m_i J_i^T r_i'' thetadot^2 + (Izz3 + Izz4) [0 phi']^T phi'' thetadot^2
// (the rotation terms of rod and cylinder reduce to this because omega = phidot is integrable).
// Generalized forces: gravity sum_i J_i^T (0, -m_i g); lift (P_H, 0) with P_H = L G g;
// tyre force P_t e_y at A: -P_t grad delta with delta = R_w - y_A, grad delta = (-1, -A_y');
// strut force P_a (compression positive) pushes B and C apart: virtual work P_a dl = -P_a ds.
#pragma once

#include "reduced_common.hpp"

namespace ref {

struct SeedGearParams {
  double g = 9.80665;  // [m/s^2] gravity (y up)
  // configuration at touchdown (t = 0), x forward, y up
  double xD = 0.00, yD = 0.60;   // [m] lever pivot D (hinge "d", lever 2 to airframe 5)
  double xA = -0.40, yA = 0.30;  // [m] wheel axle A (hinge "g", wheel 1 to lever 2)
  double xB = -0.20, yB = 0.45;  // [m] lower strut end B (joint "a", rod 3 to lever 2)
  double xC = -0.56, yC = 0.93;  // [m] upper strut end C (joint "b", cylinder 4 to airframe 5)
  double L0 = 0.60;              // [m] extended strut length |C - B|
  double Smax = 0.16;            // [m] stroke limit (bottoming stop)
  // bodies: mass, CoM at t = 0, principal inertias (local z = global z)
  double m1 = 20.0;   // [kg] wheel
  double x1 = -0.40, y1 = 0.30;                    // [m] wheel CoM (= A)
  double I1xx = 0.45, I1yy = 0.45, I1zz = 0.80;    // [kg m^2] (wheel does not rotate: unused)
  double m2 = 16.0;   // [kg] lever
  double x2 = -0.20, y2 = 0.45;                    // [m]
  double I2xx = 0.02, I2yy = 0.35, I2zz = 0.35;    // [kg m^2]
  double m3 = 12.0;   // [kg] shock-absorber rod
  double x3 = -0.32, y3 = 0.61;                    // [m]
  double I3xx = 0.015, I3yy = 0.17, I3zz = 0.17;   // [kg m^2]
  double m4 = 22.0;   // [kg] shock-absorber cylinder
  double x4 = -0.44, y4 = 0.77;                    // [m]
  double I4xx = 0.04, I4yy = 0.31, I4zz = 0.31;    // [kg m^2]
  double m5 = 3980.0; // [kg] airframe share on the leg
  double x5 = -0.30, y5 = 1.50;                    // [m]
  double I5xx = 2000, I5yy = 2000, I5zz = 2000;    // [kg m^2] (airframe does not rotate: unused)
  // tyre
  double Rw = 0.30;         // [m] wheel radius, delta = Rw - y_A
  double K = 8.0e5;         // [N/m] tyre stiffness
  double deltaMax = 0.10;   // [m] tyre deflection limit
  double alpha = 0.5;       // [-] tyre non-linearity
  // shock absorber
  double D = 0.100;         // [m] rod diameter, F = pi D^2/4
  double D2 = 0.120;        // [m] cylinder bore of chamber 3, F2 = pi (D2^2 - D^2)/4
  double p01 = 3.0e6;       // [Pa] initial gas pressure
  double Omega0 = 1.30e-3;  // [m^3] initial gas volume
  double n = 1.3;           // [-] polytropic exponent
  double rho = 850.0;       // [kg/m^3] fluid density
  double f1 = 7.0e-5;       // [m^2] main orifice area (chambers 1-2)
  double f2 = 5.0e-5;       // [m^2] rebound orifice area (chambers 2-3), term used only if > 0
  double xi1 = 1.6;         // [-] loss coefficient of f1
  double xi2 = 1.6;         // [-] loss coefficient of f2
  double mu = 0.05;         // [-] friction coefficient
  double frictionVelocity = 1e-3;  // [m/s] regularisation of sgn(sdot)
  double pAtm = 0.0;        // [Pa] ambient pressure (off by default)

  double totalMass() const { return m1 + m2 + m3 + m4 + m5; }  // [kg] G = 4050
};

class SeedGearModel {
 public:
  SeedGearModel(const SeedGearParams& p, double sinkSpeed, double liftRatio)
      : p_(p), V0_(sinkSpeed), PH_(liftRatio * p.totalMass() * p.g) {
    D0_ = {p.xD, p.yD};
    C0_ = {p.xC, p.yC};
    a0_ = Vec2(p.xA, p.yA) - D0_;
    b0_ = Vec2(p.xB, p.yB) - D0_;
    g10_ = Vec2(p.x1, p.y1) - Vec2(p.xA, p.yA);  // wheel CoM offset from A (translates with A)
    g20_ = Vec2(p.x2, p.y2) - D0_;
    g30_ = Vec2(p.x3, p.y3) - Vec2(p.xB, p.yB);
    g40_ = Vec2(p.x4, p.y4) - C0_;
    e_ = D0_ - C0_;
    const Vec2 d0 = e_ + b0_;
    phi0_ = std::atan2(d0.y(), d0.x());
    // CoM heights at t = 0 for the potential
    yc0_[0] = p.y1; yc0_[1] = p.y2; yc0_[2] = p.y3; yc0_[3] = p.y4; yc0_[4] = p.y5;
    m_[0] = p.m1; m_[1] = p.m2; m_[2] = p.m3; m_[3] = p.m4; m_[4] = p.m5;
  }

  Vec2 q0() const { return {p_.y5, 0.0}; }
  Vec2 qd0() const { return {-V0_, 0.0}; }
  double Smax() const { return p_.Smax; }
  StrutLaw strut() const {
    StrutLaw s;
    s.D = p_.D; s.D2 = p_.D2; s.p01 = p_.p01; s.Omega0 = p_.Omega0; s.n = p_.n; s.rho = p_.rho;
    s.f1 = p_.f1; s.f2 = p_.f2; s.xi1 = p_.xi1; s.xi2 = p_.xi2; s.mu = p_.mu;
    s.eps = p_.frictionVelocity; s.pAtm = p_.pAtm;
    return s;
  }
  TyreLaw tyre() const { return {p_.K, p_.deltaMax, p_.alpha}; }

  static Vec2 rot(double a, const Vec2& v) {
    const double c = std::cos(a), s = std::sin(a);
    return {c * v.x() - s * v.y(), s * v.x() + c * v.y()};
  }
  static Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }
  static double cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

  // Positions of the 5 CoMs and of A, with first and second theta-derivatives.
  struct Geo {
    Vec2 r[5], r1[5], r2[5];  // CoM positions, d/dtheta, d2/dtheta2
    Vec2 A, A1, A2;
    double l, l1, l2;         // strut length and derivatives
    double phi, phi1, phi2;   // strut angle and derivatives
  };
  Geo geo(double y5, double th) const {
    Geo G;
    const Vec2 dy(0.0, y5 - p_.y5);
    const Vec2 D = D0_ + dy, C = C0_ + dy;
    // lever points
    const Vec2 wa = rot(th, a0_), wb = rot(th, b0_), w2 = rot(th, g20_);
    G.A = D + wa; G.A1 = perp(wa); G.A2 = -wa;
    const Vec2 B = D + wb, B1 = perp(wb), B2 = -wb;
    // strut
    const Vec2 d = e_ + wb, d1 = B1, d2 = B2;
    G.l = d.norm();
    G.l1 = d.dot(d1) / G.l;
    G.l2 = (d1.dot(d1) + d.dot(d2) - G.l1 * G.l1) / G.l;
    const double c = cross(d, d1), c1 = cross(d, d2);
    const double l2 = G.l * G.l;
    G.phi = std::atan2(d.y(), d.x());
    G.phi1 = c / l2;
    G.phi2 = c1 / l2 - 2.0 * c * G.l1 / (l2 * G.l);
    // body 1: wheel (translates with A)
    G.r[0] = G.A + g10_; G.r1[0] = G.A1; G.r2[0] = G.A2;
    // body 2: lever
    G.r[1] = D + w2; G.r1[1] = perp(w2); G.r2[1] = -w2;
    // body 3: rod (pivot B, turns with phi)
    const Vec2 u3 = rot(G.phi - phi0_, g30_), u4 = rot(G.phi - phi0_, g40_);
    G.r[2] = B + u3;
    G.r1[2] = B1 + G.phi1 * perp(u3);
    G.r2[2] = B2 + G.phi2 * perp(u3) - G.phi1 * G.phi1 * u3;
    // body 4: cylinder (pivot C fixed in the airframe)
    G.r[3] = C + u4;
    G.r1[3] = G.phi1 * perp(u4);
    G.r2[3] = G.phi2 * perp(u4) - G.phi1 * G.phi1 * u4;
    // body 5: airframe
    G.r[4] = Vec2(p_.x5, y5); G.r1[4] = Vec2::Zero(); G.r2[4] = Vec2::Zero();
    return G;
  }

  Kinematics kin(const Vec2& q, const Vec2& qd) const {
    const Geo G = geo(q(0), q(1));
    const double thd = qd(1);
    Kinematics K;
    K.M.setZero();
    K.hv.setZero();
    K.Qg.setZero();
    K.V = 0.0;
    for (int i = 0; i < 5; ++i) {
      Eigen::Matrix2d J;
      J.col(0) = Vec2(0.0, 1.0);
      J.col(1) = G.r1[i];
      K.M += m_[i] * J.transpose() * J;
      K.hv += m_[i] * J.transpose() * (G.r2[i] * thd * thd);
      K.Qg += J.transpose() * Vec2(0.0, -m_[i] * p_.g);
      K.V += m_[i] * p_.g * (G.r[i].y() - yc0_[i]);
    }
    const double Irod = p_.I3zz + p_.I4zz;
    K.M(1, 1) += p_.I2zz + Irod * G.phi1 * G.phi1;
    K.hv(1) += Irod * G.phi1 * G.phi2 * thd * thd;
    K.Qg(0) += PH_;
    K.V -= PH_ * (q(0) - p_.y5);
    K.s = p_.L0 - G.l;
    K.gs = Vec2(0.0, -G.l1);
    K.sqq = -G.l2 * thd * thd;
    K.delta = p_.Rw - G.A.y();
    K.gd = Vec2(-1.0, -G.A1.y());
    K.hdisp = p_.y5 - q(0);
    K.y5 = q(0);
    K.theta = q(1);
    return K;
  }

 private:
  SeedGearParams p_;
  double V0_, PH_;
  Vec2 D0_, C0_, a0_, b0_, g10_, g20_, g30_, g40_, e_;
  double phi0_;
  double yc0_[5], m_[5];
};

// Drop test of the seed gear: every body at (0, -sinkSpeed, 0), strut on its extension stop,
// tyre deflection 0 at t = 0; lift P_H = liftRatio * G * g.
inline ReducedResult simulateSeedGear(const SeedGearParams& p, double sinkSpeed, double liftRatio,
                                      double duration, double rtol = 1e-10) {
  const SeedGearModel model(p, sinkSpeed, liftRatio);
  ReducedSolver<SeedGearModel> solver(model, rtol);
  return solver.run(duration);
}

}  // namespace ref
