// Independent reference models of landing gears (Lagrange equations of the second kind).
//
// Shared part: result types, the shock-absorber and tyre laws of method.md, an explicit
// Dormand-Prince 5(4) integrator with event location and peak refinement, and the driver
// that handles the strut stops (unilateral, plastic impact, release on reaction sign).
//
// Depends on the C++20 standard library and Eigen 3.4 only (nothing in sim/).
//
// A reduced model has two generalized coordinates q = (q1, q2), q1 = airframe height [m].
// It supplies, at (q, qdot):
//   M(q)              2x2 mass matrix                                  [kg, kg m, kg m^2]
//   hv(q, qdot)       velocity-product (Coriolis/centrifugal) terms,   M qdd + hv = Q
//   Qg(q)             generalized gravity + lift force                 [N or N m]
//   s(q), grad s      strut stroke (positive in compression)           [m]
//   qdot^T Hess(s) qdot                                                [m/s^2]
//   delta(q), grad delta   tyre deflection                              [m]
//   V(q)              potential of gravity + lift, relative to t = 0   [J]
// The driver adds the strut force P_a (generalized force -P_a grad s: the strut pushes so as to
// decrease s) and the tyre force P_t (generalized force -P_t grad delta).
//
// Stops: g_ext = s >= 0 (extension stop), g_bot = S_max - s >= 0 (bottoming stop).
// While a stop is engaged the model has one DOF; the constrained equations
//     M qdd + hv = Q + G^T lambda,   G qdd + Gdot qdot = 0,   G = grad g
// give lambda [N] (the stop force, >= 0 while it pushes). The stop releases when lambda
// crosses zero (it would pull). Engagement is a plastic impact: the impulse G^T Lambda makes
// G qdot+ = 0, i.e. qdot+ = qdot- - M^-1 G^T (G M^-1 G^T)^-1 G qdot-; the kinetic energy lost
// is booked as dissipated.
#pragma once

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <vector>

namespace ref {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;
using State = Eigen::Matrix<double, 5, 1>;  // (q1, q2, q1dot, q2dot, E_dissipated [J])

struct ReducedSample {
  double t;      // [s]
  double y5;     // [m] airframe height (CoM)
  double theta;  // [rad] lever angle (0 for the telescopic gear)
  double Py;     // [N] vertical ground load on the wheel (tyre force)
  double s;      // [m] strut stroke, positive in compression
  double h;      // [m] airframe displacement y5(0) - y5(t)
  double delta;  // [m] tyre deflection
  double Pa;     // [N] strut axial force, positive in compression
  double hdot;   // [m/s] rate of h (airframe moving down)
};

struct ReducedResult {
  double peakLoad = 0;   // [N] max tyre force (= P_t(deltaMax): P_t is monotone in delta)
  double tPeak = 0;      // [s] its time
  double strokeMax = 0;  // [m]
  double hMax = 0;       // [m]
  double deltaMax = 0;   // [m]
  double energyInitial = 0;  // [J] total energy at t = 0 (= initial kinetic energy; potentials are relative to t = 0)
  double energyError = 0;    // [J] max over accepted steps of |E(t) - E(0)|, E = T + V + stored + dissipated
  std::vector<ReducedSample> samples;  // every accepted step (plus post-impact states)
  // extra diagnostics
  double energyDissipated = 0;  // [J] at the end (orifices + friction + impacts)
  double energyImpacts = 0;     // [J] lost in plastic stop impacts
  int acceptedSteps = 0, rejectedSteps = 0, events = 0;
  struct Event {
    double t;          // [s]
    const char* what;  // "tyre contact", "tyre lift-off", "engage extension stop", ...
  };
  std::vector<Event> eventLog;
};

// ---------------------------------------------------------------------------------------------
// Force laws (method.md)
struct StrutLaw {
  double D = 0;        // [m] rod (plunger) diameter
  double D2 = 0;       // [m] cylinder bore of chamber 3
  double p01 = 0;      // [Pa] initial gas pressure
  double Omega0 = 0;   // [m^3] initial gas volume
  double n = 1.3;      // [-] polytropic exponent
  double rho = 0;      // [kg/m^3] fluid density
  double f1 = 0;       // [m^2] main orifice area (chambers 1-2)
  double f2 = 0;       // [m^2] rebound orifice area (chambers 2-3); term used only if f2 > 0
  double xi1 = 0;      // [-] loss coefficient of f1
  double xi2 = 0;      // [-] loss coefficient of f2
  double mu = 0;       // [-] friction coefficient
  double eps = 1e-3;   // [m/s] friction regularisation velocity: sgn(v) ~ v / sqrt(v^2 + eps^2)
  double pAtm = 0;     // [Pa] ambient pressure on the rod outside (0: method.md as written)

  double F() const { return std::numbers::pi * D * D / 4.0; }                  // [m^2]
  double F2() const { return std::numbers::pi * (D2 * D2 - D * D) / 4.0; }     // [m^2]
  double p1(double s) const {                                                   // [Pa]
    const double x = 1.0 - s * F() / Omega0;
    if (!(x > 0.0)) throw std::runtime_error("ref::StrutLaw: gas volume exhausted");
    return p01 / std::pow(x, n);
  }
  double sgn(double v) const { return v / std::sqrt(v * v + eps * eps); }
  struct Out {
    double Pa;     // [N] total axial force (compression positive)
    double Pgas;   // [N] conservative part (p1 - pAtm) F
    double Pdiss;  // [N] dissipative part (friction + orifices); power Pdiss * sdot >= 0
  };
  Out force(double s, double sdot) const {
    const double A = F();
    const double pg = (p1(s) - pAtm) * A;
    const double fr = mu * pg * sgn(sdot);
    double orf = xi1 * rho * A * A * A * sdot * std::abs(sdot) / (2.0 * f1 * f1);
    if (f2 > 0.0) {
      const double A2 = F2();
      orf += xi2 * rho * A2 * A2 * A2 * sdot * std::abs(sdot) / (2.0 * f2 * f2);
    }
    return {pg + fr + orf, pg, fr + orf};
  }
  // [J] integral_0^s (p1 - pAtm) F ds
  double energy(double s) const {
    const double x = 1.0 - s * F() / Omega0;
    const double gas = (n == 1.0) ? -p01 * Omega0 * std::log(x)
                                  : p01 * Omega0 * (std::pow(x, 1.0 - n) - 1.0) / (n - 1.0);
    return gas - pAtm * F() * s;
  }
};

struct TyreLaw {
  double K = 0;         // [N/m] tyre stiffness
  double deltaMax = 0;  // [m] tyre deflection limit
  double alpha = 0;     // [-] non-linearity
  double force(double d) const {  // [N], never pulls
    if (d <= 0.0) return 0.0;
    const double r = d / deltaMax;
    return K * d * (1.0 + alpha * r * r);
  }
  double energy(double d) const {  // [J]
    if (d <= 0.0) return 0.0;
    return K * (0.5 * d * d + 0.25 * alpha * d * d * d * d / (deltaMax * deltaMax));
  }
};

// What a reduced model returns at (q, qdot).
struct Kinematics {
  Mat2 M;        // mass matrix
  Vec2 hv;       // velocity-product terms
  Vec2 Qg;       // gravity + lift generalized force
  double s;      // [m] stroke
  Vec2 gs;       // grad s
  double sqq;    // qdot^T Hess(s) qdot
  double delta;  // [m] tyre deflection
  Vec2 gd;       // grad delta
  double V;      // [J] gravity + lift potential relative to t = 0
  double hdisp;  // [m] airframe displacement y(0) - y
  double y5;     // [m] airframe height (for samples)
  double theta;  // [rad] lever angle (for samples)
};

// ---------------------------------------------------------------------------------------------
// Dormand-Prince 5(4) step. f: State -> State (autonomous). Returns the 5th-order solution;
// if err != nullptr, the embedded error estimate.
template <class F>
State dp5Step(F&& f, const State& x, double h, State* err = nullptr) {
  static constexpr double a21 = 1.0 / 5.0;
  static constexpr double a31 = 3.0 / 40.0, a32 = 9.0 / 40.0;
  static constexpr double a41 = 44.0 / 45.0, a42 = -56.0 / 15.0, a43 = 32.0 / 9.0;
  static constexpr double a51 = 19372.0 / 6561.0, a52 = -25360.0 / 2187.0, a53 = 64448.0 / 6561.0,
                          a54 = -212.0 / 729.0;
  static constexpr double a61 = 9017.0 / 3168.0, a62 = -355.0 / 33.0, a63 = 46732.0 / 5247.0,
                          a64 = 49.0 / 176.0, a65 = -5103.0 / 18656.0;
  static constexpr double b1 = 35.0 / 384.0, b3 = 500.0 / 1113.0, b4 = 125.0 / 192.0,
                          b5 = -2187.0 / 6784.0, b6 = 11.0 / 84.0;
  static constexpr double e1 = 71.0 / 57600.0, e3 = -71.0 / 16695.0, e4 = 71.0 / 1920.0,
                          e5 = -17253.0 / 339200.0, e6 = 22.0 / 525.0, e7 = -1.0 / 40.0;
  const State k1 = f(x);
  const State k2 = f(x + h * (a21 * k1));
  const State k3 = f(x + h * (a31 * k1 + a32 * k2));
  const State k4 = f(x + h * (a41 * k1 + a42 * k2 + a43 * k3));
  const State k5 = f(x + h * (a51 * k1 + a52 * k2 + a53 * k3 + a54 * k4));
  const State k6 = f(x + h * (a61 * k1 + a62 * k2 + a63 * k3 + a64 * k4 + a65 * k5));
  const State y = x + h * (b1 * k1 + b3 * k3 + b4 * k4 + b5 * k5 + b6 * k6);
  if (err) {
    const State k7 = f(y);
    *err = h * (e1 * k1 + e3 * k3 + e4 * k4 + e5 * k5 + e6 * k6 + e7 * k7);
  }
  return y;
}

// Illinois (modified regula falsi) on a bracket [0, b] with g(0) = g0, g(b) = gb of opposite
// signs (or gb == 0). Returns {lo, hi}: hi is on the far side of the root (sign of gb or 0).
template <class G>
std::pair<double, double> bracketRoot(G&& g, double b, double g0, double gb, double tol) {
  double a = 0.0, fa = g0, fb = gb;
  int side = 0;
  for (int it = 0; it < 300 && b - a > tol; ++it) {
    if (fb == 0.0) {  // b is an exact root; shrink from the left by bisection
      const double c = 0.5 * (a + b);
      const double fc = g(c);
      if (fc == 0.0 || (fc > 0) != (fa > 0)) { b = c; fb = fc; } else { a = c; fa = fc; }
      continue;
    }
    double c = (fa * b - fb * a) / (fa - fb);
    if (!(c > a && c < b)) c = 0.5 * (a + b);
    const double fc = g(c);
    if (fc != 0.0 && (fc > 0) == (fa > 0)) {
      a = c; fa = fc;
      if (side == -1) fb *= 0.5;
      side = -1;
    } else {
      b = c; fb = fc;
      if (side == +1) fa *= 0.5;
      side = +1;
    }
  }
  return {a, b};
}

// ---------------------------------------------------------------------------------------------
// Driver for a reduced model with a two-sided stroke range [0, Smax].
//
// Model requirements:
//   Kinematics kin(const Vec2& q, const Vec2& qd) const;
//   Vec2 q0() const, qd0() const;  StrutLaw strut() const;  TyreLaw tyre() const;  double Smax() const;
template <class Model>
class ReducedSolver {
 public:
  enum Mode { Free = 0, LockExt = 1, LockBot = 2 };

  struct Eval {
    State xdot;
    double lambda = 0;  // [N] stop force (locked modes)
    Kinematics K;
    double sdot = 0, deltadot = 0, hdot = 0;
    double Pt = 0;  // [N] tyre force
    StrutLaw::Out strut;
  };

  ReducedSolver(const Model& m, double rtol) : m_(m), strut_(m.strut()), tyre_(m.tyre()), rtol_(rtol) {}

  Eval eval(Mode mode, const State& x) const {
    Eval e;
    const Vec2 q = x.head<2>(), qd = x.segment<2>(2);
    e.K = m_.kin(q, qd);
    const Kinematics& K = e.K;
    e.sdot = K.gs.dot(qd);
    e.deltadot = K.gd.dot(qd);
    e.hdot = -qd(0);
    e.strut = strut_.force(K.s, e.sdot);
    e.Pt = tyre_.force(K.delta);
    const Vec2 Fv = K.Qg - e.strut.Pa * K.gs - e.Pt * K.gd - K.hv;
    const Eigen::LDLT<Mat2> ldlt(K.M);
    Vec2 qdd = ldlt.solve(Fv);
    if (mode != Free) {
      const double sig = (mode == LockExt) ? 1.0 : -1.0;
      const Vec2 G = sig * K.gs;
      const double gamma = sig * K.sqq;  // Gdot qdot
      const Vec2 MiG = ldlt.solve(G);
      e.lambda = -(gamma + G.dot(qdd)) / G.dot(MiG);
      qdd += MiG * e.lambda;
    }
    e.xdot << qd, qdd, e.strut.Pdiss * e.sdot;
    return e;
  }

  double energy(const State& x) const {
    const Vec2 q = x.head<2>(), qd = x.segment<2>(2);
    const Kinematics K = m_.kin(q, qd);
    return 0.5 * qd.dot(K.M * qd) + K.V + strut_.energy(K.s) + tyre_.energy(K.delta) + x(4);
  }

  ReducedResult run(double duration) {
    ReducedResult res;
    State x;
    x << m_.q0(), m_.qd0(), 0.0;
    const double E0 = energy(x);
    res.energyInitial = E0;
    atol_ << 1.0, 1.0, 1.0, 1.0, std::max(1.0, std::abs(E0));
    atol_ *= rtol_;

    Mode mode = LockExt;  // at t = 0 the strut rests on the extension stop
    if (eval(mode, x).lambda < 0.0) mode = Free;

    double t = 0.0;
    struct Peak { double v, t; };
    Peak pk[3];  // 0 delta, 1 s, 2 h
    {
      const Eval e = eval(mode, x);
      pk[0] = {e.K.delta, 0.0}; pk[1] = {e.K.s, 0.0}; pk[2] = {e.K.hdisp, 0.0};
    }
    record(res, t, x, mode);

    const double hmax = std::min(1e-3, duration / 100.0);
    double h = 1e-6;
    const double tTol = 1e-13;  // [s] event / extremum location tolerance

    while (t < duration * (1.0 - 1e-15)) {
      h = std::min({h, hmax, duration - t});
      auto f = [&](const State& y) { return eval(mode, y).xdot; };
      State err;
      State x1 = dp5Step(f, x, h, &err);
      double en = 0.0;
      for (int i = 0; i < 5; ++i) {
        const double sc = atol_(i) + rtol_ * std::max(std::abs(x(i)), std::abs(x1(i)));
        en = std::max(en, std::abs(err(i)) / sc);
      }
      if (!(en <= 1.0)) {
        h *= std::max(0.1, 0.9 * std::pow(std::isfinite(en) ? en : 1e10, -0.2));
        ++res.rejectedSteps;
        if (h < 1e-14) throw std::runtime_error("ref::ReducedSolver: step size underflow");
        continue;
      }
      ++res.acceptedSteps;
      const double hAcc = h;

      // ---- events in (t, t+h]
      const Eval e0 = eval(mode, x);
      const Eval e1 = eval(mode, x1);
      enum Ev { None, Tyre, EngExt, EngBot, Release };
      Ev ev = None;
      double tauEv = h;
      auto stepTo = [&](double tau) { return tau <= 0.0 ? x : dp5Step(f, x, tau); };
      auto locate = [&](auto&& gfun, double g0, double g1, Ev kind) {
        auto [lo, hi] = bracketRoot([&](double tau) { return gfun(stepTo(tau)); }, h, g0, g1, tTol);
        (void)lo;
        if (hi < tauEv || ev == None) { tauEv = hi; ev = kind; }
      };
      {
        const double g0 = e0.K.delta, g1 = e1.K.delta;
        if ((g0 > 0 && g1 <= 0) || (g0 < 0 && g1 >= 0))
          locate([&](const State& y) { return eval(mode, y).K.delta; }, g0, g1, Tyre);
      }
      if (mode == Free) {
        if (e0.K.s > 0 && e1.K.s <= 0)
          locate([&](const State& y) { return eval(mode, y).K.s; }, e0.K.s, e1.K.s, EngExt);
        const double Sm = m_.Smax();
        if (Sm - e0.K.s > 0 && Sm - e1.K.s <= 0)
          locate([&](const State& y) { return Sm - eval(mode, y).K.s; }, Sm - e0.K.s, Sm - e1.K.s, EngBot);
      } else {
        if (e0.lambda > 0 && e1.lambda <= 0)
          locate([&](const State& y) { return eval(mode, y).lambda; }, e0.lambda, e1.lambda, Release);
      }
      double tau1 = h;
      if (ev != None) {
        tau1 = tauEv;
        x1 = stepTo(tau1);
        ++res.events;
      }

      // ---- extrema inside (t, t+tau1]: root of the rate, then re-integration to it
      {
        const Eval eb = (ev != None) ? eval(mode, x1) : e1;
        const double r0[3] = {e0.deltadot, e0.sdot, e0.hdot};
        const double r1[3] = {eb.deltadot, eb.sdot, eb.hdot};
        const double v1[3] = {eb.K.delta, eb.K.s, eb.K.hdisp};
        for (int k = 0; k < 3; ++k) {
          if (v1[k] > pk[k].v) pk[k] = {v1[k], t + tau1};
          if (k == 1 && mode != Free) continue;  // stroke frozen by the stop
          if (r0[k] > 0 && r1[k] < 0) {
            auto rate = [&](const State& y) {
              const Eval ey = eval(mode, y);
              return k == 0 ? ey.deltadot : (k == 1 ? ey.sdot : ey.hdot);
            };
            auto [lo, hi] = bracketRoot([&](double tau) { return rate(stepTo(tau)); }, tau1, r0[k], r1[k], tTol);
            const double tm = 0.5 * (lo + hi);
            const Eval em = eval(mode, stepTo(tm));
            const double vm = k == 0 ? em.K.delta : (k == 1 ? em.K.s : em.K.hdisp);
            if (vm > pk[k].v) pk[k] = {vm, t + tm};
          }
        }
      }

      t += tau1;
      x = x1;
      res.energyError = std::max(res.energyError, std::abs(energy(x) - E0));
      record(res, t, x, mode);

      // ---- event handling
      if (ev == Tyre) res.eventLog.push_back({t, eval(mode, x).deltadot > 0 ? "tyre contact" : "tyre lift-off"});
      if (ev == Release) res.eventLog.push_back({t, mode == LockExt ? "release extension stop" : "release bottoming stop"});
      if (ev == EngExt || ev == EngBot) {
        const Mode lock = (ev == EngExt) ? LockExt : LockBot;
        const Vec2 q = x.head<2>(), qd = x.segment<2>(2);
        const Kinematics K = m_.kin(q, qd);
        const Vec2 G = ((lock == LockExt) ? 1.0 : -1.0) * K.gs;
        const Eigen::LDLT<Mat2> ldlt(K.M);
        const Vec2 MiG = ldlt.solve(G);
        const Vec2 qdp = qd - MiG * (G.dot(qd) / G.dot(MiG));
        const double dT = 0.5 * qd.dot(K.M * qd) - 0.5 * qdp.dot(K.M * qdp);
        x.segment<2>(2) = qdp;
        x(4) += dT;
        res.energyImpacts += dT;
        mode = (eval(lock, x).lambda >= 0.0) ? lock : Free;
        res.eventLog.push_back({t, lock == LockExt ? (mode == Free ? "hit extension stop, no lock" : "engage extension stop")
                                                   : (mode == Free ? "hit bottoming stop, no lock" : "engage bottoming stop")});
        res.energyError = std::max(res.energyError, std::abs(energy(x) - E0));
        record(res, t, x, mode);
      } else if (ev == Release) {
        mode = Free;
      }
      // ---- next step size (from the accepted trial step)
      const double fac = (en > 0.0) ? std::min(5.0, std::max(0.2, 0.9 * std::pow(en, -0.2))) : 5.0;
      h = hAcc * fac;
    }

    res.deltaMax = pk[0].v;
    res.tPeak = pk[0].t;
    res.peakLoad = tyre_.force(pk[0].v);
    res.strokeMax = pk[1].v;
    res.hMax = pk[2].v;
    res.energyDissipated = x(4);
    return res;
  }

 private:
  void record(ReducedResult& res, double t, const State& x, Mode mode) const {
    const Eval e = eval(mode, x);
    res.samples.push_back({t, e.K.y5, e.K.theta, e.Pt, e.K.s, e.K.hdisp, e.K.delta, e.strut.Pa, -x(2)});
  }

  const Model& m_;
  StrutLaw strut_;
  TyreLaw tyre_;
  double rtol_;
  State atol_;
};

}  // namespace ref
