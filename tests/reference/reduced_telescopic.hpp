// Reference model of a simple cantilever telescopic gear, Lagrange equations of the second kind
// in q = (y_a, y_u). Independent of sim/.
//
// y_a [m]: height of the sprung mass (airframe + cylinder, rigidly joined), y_a(0) = ya0.
// y_u [m]: height of the wheel centre; the unsprung mass (rod + wheel) translates with it,
//          y_u(0) = R (tyre just touching).
// The strut is vertical: stroke s = (y_u - y_u0) - (y_a - y_a0), compression positive,
// grad s = (-1, 1); extension stop s >= 0 (engaged at t = 0), bottoming stop s <= Smax.
// T = 1/2 (m_a ya'^2 + m_u yu'^2): M = diag(m_a, m_u) constant, no velocity-product terms.
// Generalized forces: gravity (-m_a g, -m_u g), lift (+L G g, 0) with G = total mass, tyre
// (0, +P_t) with delta = R - y_u, strut -P_a grad s = (+P_a, -P_a).
#pragma once

#include "reduced_common.hpp"

namespace ref {

struct TelescopicParams {
  double g = 9.80665;        // [m/s^2] gravity (y up)
  double mAirframe = 1500;   // [kg] airframe share on the leg
  double mCylinder = 15;     // [kg] shock-absorber cylinder (fixed to the airframe)
  double mRod = 10;          // [kg] shock-absorber rod
  double mWheel = 15;        // [kg] wheel
  double ya0 = 1.0;          // [m] initial sprung-mass height (reference only; not in the brief)
  double R = 0.3;            // [m] tyre radius = initial wheel-centre height
  double Smax = 0.25;        // [m] stroke limit (bottoming stop)
  // shock absorber
  double D = 0.08;           // [m] rod diameter
  double D2 = 0.10;          // [m] bore of chamber 3
  double p01 = 2.0e6;        // [Pa] initial gas pressure
  double Omega0 = 1.5e-3;    // [m^3] initial gas volume (> F Smax = 1.26e-3 m^3)
  double n = 1.3;            // [-] polytropic exponent
  double rho = 850;          // [kg/m^3] fluid density
  double f1 = 5e-5;          // [m^2] main orifice area
  double f2 = 4e-5;          // [m^2] rebound orifice area (term used only if > 0)
  double xi1 = 1.6;          // [-] loss coefficient of f1
  double xi2 = 1.6;          // [-] loss coefficient of f2
  double mu = 0.05;          // [-] friction coefficient
  double frictionVelocity = 1e-3;  // [m/s] regularisation of sgn(sdot)
  double pAtm = 0.0;         // [Pa] ambient pressure (off by default)
  // tyre
  double K = 5e5;            // [N/m] tyre stiffness
  double deltaMax = 0.08;    // [m] tyre deflection limit
  double alpha = 0.5;        // [-] tyre non-linearity

  double sprungMass() const { return mAirframe + mCylinder; }  // [kg]
  double unsprungMass() const { return mRod + mWheel; }        // [kg]
  double totalMass() const { return sprungMass() + unsprungMass(); }
};

class TelescopicModel {
 public:
  TelescopicModel(const TelescopicParams& p, double sinkSpeed, double liftRatio)
      : p_(p), V0_(sinkSpeed), PH_(liftRatio * p.totalMass() * p.g) {}

  Vec2 q0() const { return {p_.ya0, p_.R}; }
  Vec2 qd0() const { return {-V0_, -V0_}; }
  double Smax() const { return p_.Smax; }
  StrutLaw strut() const {
    StrutLaw s;
    s.D = p_.D; s.D2 = p_.D2; s.p01 = p_.p01; s.Omega0 = p_.Omega0; s.n = p_.n; s.rho = p_.rho;
    s.f1 = p_.f1; s.f2 = p_.f2; s.xi1 = p_.xi1; s.xi2 = p_.xi2; s.mu = p_.mu;
    s.eps = p_.frictionVelocity; s.pAtm = p_.pAtm;
    return s;
  }
  TyreLaw tyre() const { return {p_.K, p_.deltaMax, p_.alpha}; }

  Kinematics kin(const Vec2& q, const Vec2& /*qd*/) const {
    const double ma = p_.sprungMass(), mu = p_.unsprungMass(), g = p_.g;
    const double dya = q(0) - p_.ya0, dyu = q(1) - p_.R;
    Kinematics K;
    K.M << ma, 0.0, 0.0, mu;
    K.hv.setZero();
    K.Qg = Vec2(-ma * g + PH_, -mu * g);
    K.s = dyu - dya;
    K.gs = Vec2(-1.0, 1.0);
    K.sqq = 0.0;
    K.delta = p_.R - q(1);
    K.gd = Vec2(0.0, -1.0);
    K.V = ma * g * dya + mu * g * dyu - PH_ * dya;
    K.hdisp = -dya;
    K.y5 = q(0);
    K.theta = 0.0;
    return K;
  }

 private:
  TelescopicParams p_;
  double V0_, PH_;
};

inline ReducedResult simulateTelescopic(const TelescopicParams& p, double sinkSpeed, double liftRatio,
                                        double duration, double rtol = 1e-10) {
  const TelescopicModel model(p, sinkSpeed, liftRatio);
  ReducedSolver<TelescopicModel> solver(model, rtol);
  return solver.run(duration);
}

}  // namespace ref
