// Time integration of the index-1 equations with contact modes, events and stabilisation.
//
//   semi-implicit Euler   V += h dV/dt(x, V);  x += h dx/dt(x, V_new)              (fixed step)
//   RK4                   classical 4th order                                       (fixed step)
//   Dormand-Prince 5(4)   embedded pair, error control, FSAL, 4th-order dense output (adaptive)
//   ROS2, ROS34PW2        linearly implicit Rosenbrock-W methods of order 2 and 3 with embedded
//                         error estimates (adaptive): the strut's velocity stiffness is implicit
//
// Between events the mode (which stops are enforced) is fixed and the right-hand side is smooth. An
// event is: a free stop reaching contact (C crosses 0), an enforced stop whose multiplier would pull
// (lambda crosses 0), a force element's switching function (the tyre's deflection crosses 0). The
// adaptive pair locates the earliest event on its dense output (Illinois regula falsi, to
// eventTolerance) and ends the step on it; the fixed-step methods handle events at the step's end.
// Contact mode changes and plastic impacts are done by resolveContacts (engine.hpp).
// Stabilisation: projection (engine.hpp, project) whenever the violation exceeds projectionTolerance,
// or Baumgarte terms inside the multiplier right-hand side, or none.
#pragma once

#include <cmath>
#include <string>
#include <type_traits>

#include "sim/core/brent.hpp"
#include "sim/engine.hpp"

namespace lg {

struct RunStatus {
  bool ok = true;
  std::string message;
  long steps = 0, rejected = 0, events = 0, projections = 0;
  double maxPositionViolation = 0;  // [m] largest |C| seen at the end of a step (before projection)
  double maxVelocityViolation = 0;  // [m/s]
};

// The derivative part of a scalar (zero for double): what an event-time Newton correction moves.
template <class S> inline S derivativePart(const S& x) { return x - S(value(x)); }

// Dense output over the last accepted step, y(t) for t in [t0, t0 + h].
template <class S> struct DenseOutput {
  enum Kind { Hermite, Dopri } kind = Hermite;
  S t0 = S(0);
  double h = 0;
  const VecX<S>* y0 = nullptr;
  const VecX<S>* y1 = nullptr;
  const VecX<S>* f0 = nullptr;  // dy/dt at t0 (Hermite)
  const VecX<S>* f1 = nullptr;  // dy/dt at t1 (Hermite)
  const std::vector<VecX<S>>* k = nullptr;  // Dopri stages
  void at(const S& t, VecX<S>& out) const {
    const S th = (t - t0) / S(h);
    if (kind == Dopri) {
      // Hairer & Wanner, dopri5 contd5.
      static const double d1 = -12715105075.0 / 11282082432.0, d3 = 87487479700.0 / 32700410799.0,
                          d4 = -10690763975.0 / 1880347072.0, d5 = 701980252875.0 / 199316789632.0,
                          d6 = -1453857185.0 / 822651844.0, d7 = 69997945.0 / 29380423.0;
      const auto& K = *k;
      for (Eigen::Index i = 0; i < out.size(); ++i) {
        const S ydiff = (*y1)[i] - (*y0)[i];
        const S bspl = S(h) * K[0][i] - ydiff;
        const S r4 = ydiff - S(h) * K[6][i] - bspl;
        const S r5 = S(h) * (d1 * K[0][i] + d3 * K[2][i] + d4 * K[3][i] + d5 * K[4][i] + d6 * K[5][i] + d7 * K[6][i]);
        out[i] = (*y0)[i] + th * (ydiff + (S(1) - th) * (bspl + th * (r4 + (S(1) - th) * r5)));
      }
    } else {  // cubic Hermite
      const S h00 = S(2) * th * th * th - S(3) * th * th + S(1), h10 = th * th * th - S(2) * th * th + th,
              h01 = S(-2) * th * th * th + S(3) * th * th, h11 = th * th * th - th * th;
      out = h00 * (*y0) + (h10 * S(h)) * (*f0) + h01 * (*y1) + (h11 * S(h)) * (*f1);
    }
  }
};

// Event functions at the current workspace (rows, multipliers and force events must be current):
// free stop: C + contactTolerance |dC/dp| (it triggers on reaching the contact band, so a stop that was
// let go at C = 0 is still watched); enforced stop: lambda; friction lock: F_max - |lambda| while stuck,
// sigma sdot while slipping, 0 while held; bilateral row: 0 (never triggers); then the force events.
template <class S>
void eventFunctions(const Model<S>& m, const State<S>& s, const VecX<S>& lambda, const Workspace<S>& w, VecX<S>& g) {
  const S shift(m.settings.contactTolerance);
  for (int k = 0; k < m.nRows; ++k) {
    const RowInfo& ri = m.rowInfo[k];
    if (ri.friction()) {
      if (s.active[k]) g[k] = frictionBound(m, w, k) - (value(lambda[k]) < 0 ? -lambda[k] : lambda[k]);
      else g[k] = S(s.slip[k]) * rowVelocity(m, w, k);
    } else if (!ri.unilateral) {
      g[k] = S(0);
    } else if (s.active[k]) {
      g[k] = lambda[k];
    } else {
      g[k] = w.rows[k].C + shift * w.rows[k].Ji.template head<3>().norm();
    }
  }
  for (int e = 0; e < m.nForceEvents; ++e) g[m.nRows + e] = w.forceEvents[e];
}

// The rates dC/dt = J V of the free stops (0 for every other row): where a stop's rate turns from
// approaching to receding inside a step, its function may dip below zero and back between two
// positive ends (a loose step through a stop); handleEvents looks there.
template <class S> void freeStopRates(const Model<S>& m, const State<S>& s, const Workspace<S>& w, VecX<S>& r) {
  for (int k = 0; k < m.nRows; ++k) {
    const RowInfo& ri = m.rowInfo[k];
    r[k] = (ri.unilateral && !ri.friction() && !s.active[k]) ? rowVelocity(m, w, k) : S(0);
  }
}

// Does event function i trigger between g0 and g1, and is g on its "after" side? Stops and friction
// locks alike: an enforced row whenever its function ends negative, a free one on crossing zero.
template <class S> bool eventTriggered(const Model<S>& m, const State<S>& s, int i, double g0, double g1) {
  if (i < m.nRows) {
    if (!m.rowInfo[i].unilateral && !m.rowInfo[i].friction()) return false;
    return s.active[i] ? (g1 < 0) : (g0 > 0 && g1 <= 0);
  }
  return g0 * g1 < 0;
}

// One Dormand-Prince 5(4) step with error control. On return accepted says whether y1 = stages
// result was accepted; hNext is the proposed next step.
namespace dopri {
static constexpr double c[7] = {0, 1.0 / 5, 3.0 / 10, 4.0 / 5, 8.0 / 9, 1, 1};
static constexpr double a[7][6] = {
    {0, 0, 0, 0, 0, 0},
    {1.0 / 5, 0, 0, 0, 0, 0},
    {3.0 / 40, 9.0 / 40, 0, 0, 0, 0},
    {44.0 / 45, -56.0 / 15, 32.0 / 9, 0, 0, 0},
    {19372.0 / 6561, -25360.0 / 2187, 64448.0 / 6561, -212.0 / 729, 0, 0},
    {9017.0 / 3168, -355.0 / 33, 46732.0 / 5247, 49.0 / 176, -5103.0 / 18656, 0},
    {35.0 / 384, 0, 500.0 / 1113, 125.0 / 192, -2187.0 / 6784, 11.0 / 84}};
static constexpr double e[7] = {71.0 / 57600, 0, -71.0 / 16695, 71.0 / 1920, -17253.0 / 339200, 22.0 / 525,
                                -1.0 / 40};
}  // namespace dopri

// A Rosenbrock-W method given as (alpha, Gamma, b, b_hat) with Gamma_ii = gamma, stored in the
// transformed form used by the step (Hairer & Wanner IV.7.25): A = alpha Gamma^-1,
// C = diag(1/gamma) - Gamma^-1, m = b Gamma^-1, e = (b - b_hat) Gamma^-1.
struct RosenbrockTableau {
  int stages = 0, embeddedOrder = 0;
  double gamma = 0;
  double A[4][4] = {}, C[4][4] = {}, m[4] = {}, e[4] = {};

  static RosenbrockTableau make(int s, int embeddedOrder, double gamma, const double (&alpha)[4][4],
                                const double (&Gam)[4][4], const double (&b)[4], const double (&bhat)[4]) {
    RosenbrockTableau t;
    t.stages = s;
    t.embeddedOrder = embeddedOrder;
    t.gamma = gamma;
    double G[4][4] = {}, Gi[4][4] = {};  // Gamma (lower triangular, gamma on the diagonal) and its inverse
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < i; ++j) G[i][j] = Gam[i][j];
    for (int i = 0; i < s; ++i) G[i][i] = gamma;
    for (int i = 0; i < s; ++i) {  // forward substitution, column by column
      Gi[i][i] = 1.0 / gamma;
      for (int r = i + 1; r < s; ++r) {
        double acc = 0;
        for (int c = i; c < r; ++c) acc += G[r][c] * Gi[c][i];
        Gi[r][i] = -acc / gamma;
      }
    }
    for (int i = 0; i < s; ++i)
      for (int j = 0; j < s; ++j) {
        double a = 0;
        for (int c = 0; c < s; ++c) a += alpha[i][c] * Gi[c][j];
        t.A[i][j] = a;
        t.C[i][j] = (i == j ? 1.0 / gamma : 0.0) - Gi[i][j];
        if (j >= i) t.A[i][j] = t.C[i][j] = 0;  // strictly lower (the diagonal of C cancels exactly)
      }
    for (int j = 0; j < s; ++j) {
      double mm = 0, ee = 0;
      for (int c = 0; c < s; ++c) {
        mm += b[c] * Gi[c][j];
        ee += (b[c] - bhat[c]) * Gi[c][j];
      }
      t.m[j] = mm;
      t.e[j] = ee;
    }
    return t;
  }
  // ROS2 (Verwer, Spee, Blom & Hundsdorfer 1999): order 2, L-stable, gamma = 1 + 1/sqrt(2); the
  // embedded method is first order.
  static const RosenbrockTableau& ros2() {
    static const RosenbrockTableau t = [] {
      const double g = 1.0 + 1.0 / std::sqrt(2.0);
      const double alpha[4][4] = {{0}, {1.0}};
      const double Gam[4][4] = {{0}, {-2.0 * g}};
      const double b[4] = {0.5, 0.5}, bhat[4] = {1.0, 0.0};
      return make(2, 1, g, alpha, Gam, b, bhat);
    }();
    return t;
  }
  // ROS34PW2 (Rang & Angermann 2005): a W-method of order 3 with an embedded order-2 method, 4 stages,
  // L-stable and stiffly accurate.
  static const RosenbrockTableau& ros34pw2() {
    static const RosenbrockTableau t = [] {
      const double g = 4.3586652150845900e-01;
      const double alpha[4][4] = {{0},
                                  {8.7173304301691801e-01},
                                  {8.4457060015369423e-01, -1.1299064236484185e-01},
                                  {0.0, 0.0, 1.0}};
      const double Gam[4][4] = {{0},
                                {-8.7173304301691801e-01},
                                {-9.0338057013044082e-01, 5.4180672388095326e-02},
                                {2.4212380706095346e-01, -1.2232505839045147e+00, 5.4526025533510214e-01}};
      const double b[4] = {2.4212380706095346e-01, -1.2232505839045147e+00, 1.5452602553351020e+00,
                           4.3586652150845900e-01};
      const double bhat[4] = {3.7810903145819369e-01, -9.6042292212423178e-02, 5.0000000000000000e-01,
                              2.1793326075422950e-01};
      return make(4, 2, g, alpha, Gam, b, bhat);
    }();
    return t;
  }
};

// A null observer: every hook does nothing.
struct NoObserver {
  template <class S> void onStart(const Model<S>&, const State<S>&, Workspace<S>&) {}
  template <class S> void onStep(const Model<S>&, const State<S>&, Workspace<S>&, const DenseOutput<S>&) {}
  bool stopRequested() const { return false; }
};

template <class S> class Integrator {
 public:
  Integrator(const Model<S>& m, State<S>& s, Workspace<S>& w) : m_(m), s_(s), w_(w) {}

  // Integrates from s.t to tEnd. The observer's onStep runs after every accepted step with the state
  // at the step's end (kinematics, rows, multipliers and outputs current in the workspace).
  template <class Observer> RunStatus run(double tEnd, Observer& obs) {
    RunStatus st;
    const Settings& cfg = m_.settings;
    w_.needDampingResponse = isRosenbrock(cfg.integrator);
    w_.slip = s_.slip;
    projectMobility(m_, s_.y);  // a guided or immobile body's velocity into its subspace
    // Initial contact modes (and impacts if a stop starts approaching), then a consistent state.
    if (resolveContacts(m_, s_, w_) < 0) return fail(st, "contact solve failed at the start");
    if (cfg.stabilization != Stabilization::None && !project(m_, s_, w_))
      return fail(st, "projection failed at the start (redundant or inconsistent constraints)");
    if (!refresh()) return fail(st, "multiplier solve failed at the start");
    obs.onStart(m_, s_, w_);
    double h = cfg.step;
    while (value(s_.t) < tEnd - 1e-14 * std::max(1.0, tEnd)) {
      if (obs.stopRequested()) return fail(st, "stopped on request");
      if (st.steps >= cfg.maxSteps) return fail(st, "step limit reached (" + std::to_string(cfg.maxSteps) + " steps)");
      const double remaining = tEnd - value(s_.t);
      bool ok;
      if (cfg.integrator == IntegratorKind::DormandPrince) ok = stepDopri(std::min(h, remaining), h, st);
      else if (cfg.integrator == IntegratorKind::Ros2) ok = stepRosenbrock(RosenbrockTableau::ros2(), std::min(h, remaining), h, st);
      else if (cfg.integrator == IntegratorKind::Ros34pw2)
        ok = stepRosenbrock(RosenbrockTableau::ros34pw2(), std::min(h, remaining), h, st);
      else ok = stepFixed(std::min(cfg.step, remaining), st);
      if (!ok) return st;
      ++st.steps;
      obs.onStep(m_, s_, w_, dense_);
    }
    // An event whose time depends on the parameters (a stop reached, a strut breaking away) moves every
    // later step by that much: the run ends at tEnd in value but at tEnd + dt_event/dp in derivative.
    // The state at tEnd itself: y(tEnd) = y - dy/dt (t - tEnd), to first order in the derivative part.
    if constexpr (!std::is_same_v<S, double>) {
      const S dt = derivativePart(s_.t);
      s_.y -= w_.ydot * dt;
      s_.t -= dt;
    }
    return st;
  }

 private:
  RunStatus& fail(RunStatus& st, const std::string& why) {
    st.ok = false;
    st.message = why + " at t = " + std::to_string(value(s_.t)) + " s";
    return st;
  }

  // f at the current state into w.ydot (always the derivative at s.y), event functions into g0.
  bool refresh() {
    const bool ok = evaluate(m_, s_.y, s_.active, s_.lambda, w_, w_.ydot);
    eventFunctions(m_, s_, s_.lambda, w_, w_.g0);
    freeStopRates(m_, s_, w_, w_.gRate0);
    forceOutputs();
    return ok && allFinite(w_.ydot);
  }
  void forceOutputs() {
    const Kins<S> K = w_.kins();
    for (size_t f = 0; f < m_.forces.size(); ++f)
      std::visit([&](const auto& e) { e.outputs(K, w_.outputs.data() + m_.outputOffset[f]); }, m_.forces[f].type);
  }
  static bool allFinite(const VecX<S>& v) {
    for (Eigen::Index i = 0; i < v.size(); ++i)
      if (!isFinite(v[i])) return false;
    return true;
  }

  // The stabilisation of an accepted state (the rows in the workspace must be current at s.y): records
  // the violation, then projects onto the constraint manifold if it exceeds the tolerance, or else only
  // renormalises the quaternions. Returns false if the projection fails; 'projected' says if it ran.
  bool stabilise(RunStatus& st, bool& projected) {
    const Settings& cfg = m_.settings;
    double pos, vel;
    violation(m_, s_.active, w_, pos, vel);
    st.maxPositionViolation = std::max(st.maxPositionViolation, pos);
    st.maxVelocityViolation = std::max(st.maxVelocityViolation, vel);
    projected = cfg.stabilization == Stabilization::Projection &&
                (pos > cfg.projectionTolerance || vel > cfg.projectionTolerance);
    if (!projected) {
      normalizeQuaternions(m_, s_.y);
      return true;
    }
    ++st.projections;
    return project(m_, s_, w_, /*factorNearby=*/true);  // the step's last evaluation factored A nearby
  }

  // After an accepted step or event whose end was evaluated: stabilise if needed, then refresh f and g.
  bool afterStep(RunStatus& st) {
    bool projected = false;
    if (!stabilise(st, projected)) return false;
    return projected ? refresh() : true;
  }

  // Handles the events between the step's start (g0) and its end (g1 = w.g1); if one triggers, moves
  // the state back onto the earliest one. Returns false on failure.
  bool handleEvents(const DenseOutput<S>& dense, RunStatus& st, bool& hadEvent) {
    hadEvent = false;
    const int nG = m_.nRows + m_.nForceEvents;
    int first = -1;
    double tFirst = 0;
    for (int i = 0; i < nG; ++i) {
      double tb = value(dense.t0) + dense.h, gb = value(w_.g1[i]);
      if (!eventTriggered(m_, s_, i, value(w_.g0[i]), gb) && !dipsThrough(dense, i, tb, gb)) continue;
      const double te = locate(dense, i, tb, gb);
      if (first < 0 || te < tFirst) {
        first = i;
        tFirst = te;
      }
    }
    if (first < 0) return true;
    hadEvent = true;
    ++st.events;
    ScopedStage timer(w_.timer, kEvents, m_.settings.profile);
    // The event time carries the derivatives of g (one Newton correction in S); its value is tFirst.
    // (For double there are no derivatives: only a stuck friction lock needs its reaction's sign there.)
    S te = S(tFirst);
    if constexpr (!std::is_same_v<S, double>) {
      const double dt = 1e-7 * std::max(dense.h, 1e-9);
      dense.at(S(tFirst - dt), w_.ytmp);
      w_.lamTmp = s_.lambda;
      evaluate(m_, w_.ytmp, s_.active, w_.lamTmp, w_, w_.fTmp);
      eventFunctions(m_, s_, w_.lamTmp, w_, w_.g2);
      dense.at(te, w_.ytmp);
      w_.lamTmp = s_.lambda;
      evaluate(m_, w_.ytmp, s_.active, w_.lamTmp, w_, w_.fTmp);  // f at the event, the mode before it
      eventFunctions(m_, s_, w_.lamTmp, w_, w_.gtmp);
      const double ga = value(w_.gtmp[first]);
      const double slope = (ga - value(w_.g2[first])) / dt;
      if (std::abs(slope) > 0) te -= derivativePart(w_.gtmp[first]) / S(slope);
      // The state at the moved event time: the dense output at its value, moved along f at the event
      // (the right-hand side there, not the interpolant's slope, which a step across a kink of f averages
      // over both sides of it).
      dense.at(S(tFirst), s_.y);
      s_.y += w_.fTmp * (te - S(tFirst));
    } else {
      if (first < m_.nRows && m_.rowInfo[first].friction() && s_.active[first]) {
        dense.at(te, w_.ytmp);
        w_.lamTmp = s_.lambda;
        evaluate(m_, w_.ytmp, s_.active, w_.lamTmp, w_, w_.fTmp);
      }
      dense.at(te, s_.y);
    }
    s_.t = te;
    // Act on it: a stop whose multiplier would pull is let go; a stuck friction lock whose reaction
    // reached its bound slips (against the reaction); a slipping one that stopped is at rest. Then the
    // contact modes are resolved (impacts for a stop arriving) for every stop at once, and the friction
    // locks at rest are decided.
    if (first < m_.nRows && m_.rowInfo[first].friction()) {
      if (s_.active[first]) {
        s_.active[first] = 0;
        setSlip(s_, w_, first, value(w_.lamTmp[first]) > 0 ? -1 : 1);
      } else {
        setSlip(s_, w_, first, 0);
      }
    } else if (first < m_.nRows && s_.active[first] && value(w_.g1[first]) < 0) {
      s_.active[first] = 0;
    }
    if (resolveContacts(m_, s_, w_) < 0) return false;
    if (m_.settings.stabilization != Stabilization::None && !project(m_, s_, w_)) return false;
    return true;
  }

  // Does event function i need the multipliers (an enforced stop or a stuck friction lock), or only
  // the positions and velocities (a free stop's C, a slip's rate, a force element's event)?
  bool eventNeedsSolve(int i) const { return i < m_.nRows && s_.active[i]; }

  // Event function i on the dense output at time t. Those of positions and velocities need the poses
  // and one row or one element only; the others a full evaluation.
  double eventValueAt(const DenseOutput<S>& dense, int i, double t) {
    dense.at(S(t), w_.ytmp);
    if (eventNeedsSolve(i)) {
      evaluate(m_, w_.ytmp, s_.active, w_.lamTmp, w_, w_.fTmp);
      eventFunctions(m_, s_, w_.lamTmp, w_, w_.gtmp);
      return value(w_.gtmp[i]);
    }
    poses(m_, w_.ytmp, w_);
    const Kins<S> K = w_.kins();
    if (i >= m_.nRows) {
      const int e = i - m_.nRows;
      for (size_t f = 0; f < m_.forces.size(); ++f) {
        const int first = m_.eventOffset[f], count = (f + 1 < m_.forces.size() ? m_.eventOffset[f + 1] : m_.nForceEvents) - first;
        if (e < first || e >= first + count) continue;
        std::visit([&](const auto& el) { el.events(K, w_.forceEvents.data() + first); }, m_.forces[f].type);
        return value(w_.forceEvents[e]);
      }
      return 0.0;
    }
    constraintRows(m_, w_);  // (all rows: one constraint's would do, the lock rows come last)
    if (m_.rowInfo[i].friction()) return value(S(s_.slip[i]) * rowVelocity(m_, w_, i));
    return value(w_.rows[i].C + S(m_.settings.contactTolerance) * w_.rows[i].Ji.template head<3>().norm());
  }

  // A free stop whose function is positive at both ends of the step but turns from approaching to
  // receding inside it: its minimum on the dense output (Brent's search, stopped at the first value on
  // the "after" side) may lie below zero, a contact the ends do not show. If so, returns true with
  // (tb, gb) a point after the crossing, the right end of the bracket for locate.
  bool dipsThrough(const DenseOutput<S>& dense, int i, double& tb, double& gb) {
    if (i >= m_.nRows || !m_.rowInfo[i].unilateral || m_.rowInfo[i].friction() || s_.active[i]) return false;
    if (!(value(w_.g0[i]) > 0 && value(w_.g1[i]) > 0 && value(w_.gRate0[i]) < 0 && value(w_.gRate1[i]) > 0)) return false;
    ScopedStage timer(w_.timer, kEvents, m_.settings.profile);
    const double t0 = value(dense.t0);
    double fx = 0;
    const double x = brentMinimise([&](double t) { return eventValueAt(dense, i, t); }, t0, t0 + dense.h, 0.0,
                                   3e-6 * dense.h, fx, [](double g) { return g <= 0; }, 60);
    if (fx > 0) {  // no contact: the workspace's poses and rows back at the step's end
      poses(m_, s_.y, w_);
      constraintRows(m_, w_);
      return false;
    }
    tb = x;
    gb = fx;
    return true;
  }

  // Earliest root of event function i on the dense output (Illinois) in [t0, tb] (g(tb) = gb on the
  // "after" side), returned on its "after" side.
  double locate(const DenseOutput<S>& dense, int i, double tbIn, double gbIn) {
    ScopedStage timer(w_.timer, kEvents, m_.settings.profile);
    double ta = value(dense.t0), tb = tbIn;
    double ga = value(w_.g0[i]), gb = gbIn;
    const bool unilateralActive = i < m_.nRows && s_.active[i];
    auto after = [&](double g) {
      if (i < m_.nRows) return unilateralActive ? g < 0 : g <= 0;
      return (g > 0) == (value(w_.g1[i]) > 0);
    };
    w_.lamTmp = s_.lambda;
    int side = 0;
    for (int it = 0; it < 200 && tb - ta > m_.settings.eventTolerance; ++it) {
      double tc = (ga == gb) ? 0.5 * (ta + tb) : tb - gb * (tb - ta) / (gb - ga);
      if (!(tc > ta && tc < tb)) tc = 0.5 * (ta + tb);
      const double gc = eventValueAt(dense, i, tc);
      if (after(gc)) {
        tb = tc;
        gb = gc;
        if (side == 1) ga *= 0.5;
        side = 1;
      } else {
        ta = tc;
        ga = gc;
        if (side == -1) gb *= 0.5;
        side = -1;
      }
    }
    return tb;
  }

  // The verdict on a trial step of an adaptive method with error norm err (1 = the tolerance): a
  // non-finite trial is retried at a quarter of the step, one over the tolerance at the size its error
  // suggests (0.9 err^-expo, at least a fifth); a step that underflows fails the run.
  enum class Trial { Accept, Retry, Fail };
  Trial judge(bool ok, double err, double expo, double& h, RunStatus& st) {
    if (!ok || !allFinite(w_.y1) || !std::isfinite(err)) {
      if (h < 1e-12) {
        failNonFinite(st);
        return Trial::Fail;
      }
      h *= 0.25;
      ++st.rejected;
      return Trial::Retry;
    }
    if (err <= 1.0) return Trial::Accept;
    h *= std::max(0.2, 0.9 * std::pow(err, -expo));
    ++st.rejected;
    if (h < 1e-14) {
      fail(st, "step size underflow");
      return Trial::Fail;
    }
    return Trial::Retry;
  }

  // A friction lock that started slipping at rest (its rate zero at the step's start) and ends the step
  // moving against its slip direction: the slip was shorter than the step, which must not cross it
  // unseen (the segment's law would then drive the motion). Rows must be current at the step's end.
  bool slipReversedUnseen() const {
    for (int k = 0; k < m_.nRows; ++k) {
      if (!m_.rowInfo[k].friction() || s_.active[k] || s_.slip[k] == 0) continue;
      if (value(w_.g0[k]) <= 0 && s_.slip[k] * value(rowVelocity(m_, w_, k)) < 0) return true;
    }
    return false;
  }
  // Such a step is retried at a quarter of its size; when it is down to the event tolerance, the slip is
  // over: the lock is at rest at the step's end, and its mode is decided there (resolveFriction).
  static constexpr double kSlipRetryFloor = 1e-9;  // [s]
  bool settleUnseenSlips(RunStatus& st) {
    for (int k = 0; k < m_.nRows; ++k)
      if (m_.rowInfo[k].friction() && !s_.active[k] && s_.slip[k] != 0 && value(w_.g0[k]) <= 0 &&
          s_.slip[k] * value(rowVelocity(m_, w_, k)) < 0)
        setSlip(s_, w_, k, 0);
    ++st.events;
    if (resolveContacts(m_, s_, w_) < 0) return false;
    return m_.settings.stabilization == Stabilization::None || project(m_, s_, w_);
  }

  // The events of an accepted adaptive step: if one triggered, the step ends on it ('ended'); the dense
  // output (valid on [t0, t0 + h]) still describes [t0, t_event] for the observer, the state may have
  // jumped (impact, projection), so f and g are refreshed and the next step starts small. Returns false
  // on failure.
  bool endOnEvent(double h, double& hNext, RunStatus& st, bool& ended) {
    if (!handleEvents(dense_, st, ended)) {
      fail(st, "contact or projection solve failed after an event");
      return false;
    }
    if (!ended) return true;
    if (!refresh()) return failNonFinite(st);
    hNext = std::max(h * 0.1, 1e-8);
    return true;
  }

  bool stepDopri(double h, double& hNext, RunStatus& st) {
    const Settings& cfg = m_.settings;
    auto& k = w_.stages;
    const int nErr = m_.nErr();  // the dissipated-energy states are not error-controlled (but those asked for)
    k[0] = w_.ydot;
    for (int attempt = 0; attempt < 60; ++attempt) {
      w_.y0 = s_.y;
      bool ok = true;
      for (int i = 1; i < 7; ++i) {
        {
          ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
          w_.ytmp = w_.y0;
          for (int j = 0; j < i; ++j)
            if (dopri::a[i][j] != 0) w_.ytmp += S(h * dopri::a[i][j]) * k[j];
        }
        ok = evaluate(m_, w_.ytmp, s_.active, s_.lambda, w_, k[i]) && ok;
      }
      // y1 = ytmp after stage 7 (a[6] = b), k[6] = f(y1) (FSAL).
      double err = 0;
      {
        ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
        w_.y1 = w_.ytmp;
        for (int i = 0; i < nErr; ++i) {
          S e(0);
          for (int j = 0; j < 7; ++j)
            if (dopri::e[j] != 0) e += S(dopri::e[j]) * k[j][i];
          const double sc = cfg.atol + cfg.rtol * std::max(std::abs(value(w_.y0[i])), std::abs(value(w_.y1[i])));
          const double r = h * value(e) / sc;
          err += r * r;
        }
        err = std::sqrt(err / nErr);
      }
      const Trial trial = judge(ok, err, 0.2, h, st);
      if (trial == Trial::Fail) return false;
      if (trial == Trial::Retry) continue;
      // Stabilised (PI) step-size control of Hairer's dopri5 (beta = 0.04): fewer rejections where the
      // step is capped by stability rather than accuracy.
      {
        const double e = std::max(err, 1e-10);
        const double fac = std::pow(e, 0.2 - 0.04 * 0.75) / std::pow(errOld_, 0.04) / 0.9;
        hNext = std::min(cfg.maxStep, h / std::max(0.2, std::min(5.0, fac)));
        errOld_ = std::max(err, 1e-4);
      }
      // Accept: state at the step's end, event functions there.
      dense_.kind = DenseOutput<S>::Dopri;
      dense_.t0 = s_.t;
      dense_.h = h;
      dense_.y0 = &w_.y0;
      dense_.y1 = &w_.y1;
      dense_.k = &w_.stages;
      s_.y = w_.y1;
      s_.t = s_.t + S(h);
      eventFunctions(m_, s_, s_.lambda, w_, w_.g1);
      freeStopRates(m_, s_, w_, w_.gRate1);
      if (slipReversedUnseen()) {  // (rows are at y1: the last stage is there)
        if (h > kSlipRetryFloor) {
          s_.y = w_.y0;
          s_.t = s_.t - S(h);
          h *= 0.25;
          ++st.rejected;
          continue;
        }
        if (!settleUnseenSlips(st) || !refresh()) return failNonFinite(st);
        hNext = std::max(h, 1e-8);
        return true;
      }
      bool ended = false;
      if (!endOnEvent(h, hNext, st, ended)) return false;
      if (ended) return true;
      // Smooth step: first same as last.
      w_.ydot = k[6];
      w_.g0 = w_.g1;
      w_.gRate0 = w_.gRate1;
      forceOutputs();
      if (!afterStep(st)) {
        fail(st, "projection failed");
        return false;
      }
      return true;
    }
    fail(st, "too many rejected steps");
    return false;
  }

  // r <- W^-1 r with W = I - gamma h J_W, J_W = [[0, K], [0, J_vv]] over (positions, velocities):
  // J_vv = -sum_e c_e u_e G_e the force elements' damping (the terms saved at the step's start) and K
  // the kinematic map V -> (r', q') at y_n. W is block upper triangular: the velocities first, by
  // Woodbury, (I + U C G)^-1 r = r - U C (I + G U C)^-1 G r with C = gamma h diag(c); then the
  // positions, x += gamma h K v. (Without K the W-method keeps its order but loses accuracy where a
  // stiff damper couples to the positions: an overdamped oscillator at h |lambda| = 100 erred by 2 %.)
  void solveW(double gh, VecX<S>& r) {
    solveVelocityW(gh, r);
    const int N = m_.nBodies(), nx = m_.nx();
    for (int b = 0; b < N; ++b) {
      r.template segment<3>(7 * b) += S(gh) * r.template segment<3>(nx + 6 * b);
      const Vec4<S> q = w_.y0.template segment<4>(7 * b + 3);
      r.template segment<4>(7 * b + 3) += S(gh) * quaternionRate<S>(q, r.template segment<3>(nx + 6 * b + 3));
    }
  }
  void solveVelocityW(double gh, VecX<S>& r) {
    const int k = m_.nDamping, nx = m_.nx();
    if (k == 0) return;
    auto Gdot = [&](const DampingTerm<S>& d, const VecX<S>& v) {  // G . (velocity part of v)
      S s(0);
      if (d.bi >= 0) s += d.Gi.dot(v.template segment<6>(nx + 6 * d.bi));
      if (d.bj >= 0) s += d.Gj.dot(v.template segment<6>(nx + 6 * d.bj));
      return s;
    };
    auto GdotU = [&](const DampingTerm<S>& d, int f) {
      S s(0);
      if (d.bi >= 0) s += d.Gi.dot(w_.U0.col(f).template segment<6>(6 * d.bi));
      if (d.bj >= 0) s += d.Gj.dot(w_.U0.col(f).template segment<6>(6 * d.bj));
      return s;
    };
    for (int e = 0; e < k; ++e) {
      w_.smallT[e] = Gdot(w_.damping0[e], r);
      for (int f = 0; f < k; ++f)
        w_.smallM(e, f) = (e == f ? S(1) : S(0)) + GdotU(w_.damping0[e], f) * S(gh) * w_.damping0[f].c;
    }
    // small dense solve (k is the number of dampers), Gaussian elimination with partial pivoting
    for (int j = 0; j < k; ++j) {
      int p = j;
      for (int i = j + 1; i < k; ++i)
        if (std::abs(value(w_.smallM(i, j))) > std::abs(value(w_.smallM(p, j)))) p = i;
      if (p != j) {
        w_.smallM.row(p).swap(w_.smallM.row(j));
        std::swap(w_.smallT[p], w_.smallT[j]);
      }
      for (int i = j + 1; i < k; ++i) {
        const S f = w_.smallM(i, j) / w_.smallM(j, j);
        for (int c = j; c < k; ++c) w_.smallM(i, c) -= f * w_.smallM(j, c);
        w_.smallT[i] -= f * w_.smallT[j];
      }
    }
    for (int j = k - 1; j >= 0; --j) {
      S s = w_.smallT[j];
      for (int c = j + 1; c < k; ++c) s -= w_.smallM(j, c) * w_.smallT[c];
      w_.smallT[j] = s / w_.smallM(j, j);
    }
    for (int f = 0; f < k; ++f) r.segment(nx, m_.nv()) -= (S(gh) * w_.damping0[f].c * w_.smallT[f]) * w_.U0.col(f);
  }

  // One step of a linearly implicit Rosenbrock-W method (RosenbrockTableau: ROS2 or ROS34PW2) in the
  // transformed form of Hairer & Wanner (IV.7.25), which needs no Jacobian-vector products:
  //   (I/(gamma h) - J_W) U_i = f(y_n + sum_j A_ij U_j) + sum_j C_ij/h U_j,   i = 1..s
  //   y_n+1 = y_n + sum_i m_i U_i,   error estimate sum_i e_i U_i (against the embedded method),
  // with J_W the force elements' velocity stiffness (rank 1 per damper, see DampingTerm) taken at y_n:
  // the orifice damping and the regularised friction no longer cap the step. Any J_W keeps the order
  // (W-method). Dense output: cubic Hermite between f(y_n) and f(y_n+1).
  bool stepRosenbrock(const RosenbrockTableau& tab, double h, double& hNext, RunStatus& st) {
    const Settings& cfg = m_.settings;
    auto& k = w_.stages;  // k[0] = f(y_n), k[1..s] = U_1..U_s, k[6] = f(y_n+1)
    const int nErr = m_.nErr();
    k[0] = w_.ydot;
    w_.U0 = w_.U;  // the damping terms at y_n (the last evaluation was at s.y)
    w_.damping0 = w_.damping;
    const double expo = 1.0 / (tab.embeddedOrder + 1);
    w_.needDampingResponse = false;  // the stages need f only; U is taken at the accepted state below
    for (int attempt = 0; attempt < 60; ++attempt) {
      w_.y0 = s_.y;
      bool ok = true;
      const double gh = tab.gamma * h;
      for (int i = 0; i < tab.stages; ++i) {
        VecX<S>& U = k[1 + i];
        if (i == 0) {
          U = k[0];
        } else {
          {
            ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
            w_.ytmp = w_.y0;
            for (int j = 0; j < i; ++j)
              if (tab.A[i][j] != 0) w_.ytmp += S(tab.A[i][j]) * k[1 + j];
          }
          ok = evaluate(m_, w_.ytmp, s_.active, s_.lambda, w_, U) && ok;
        }
        ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
        for (int j = 0; j < i; ++j)
          if (tab.C[i][j] != 0) U += S(tab.C[i][j] / h) * k[1 + j];
        solveW(gh, U);
        U *= S(gh);
      }
      double err = 0;
      {
        ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
        w_.y1 = w_.y0;
        for (int j = 0; j < tab.stages; ++j) w_.y1 += S(tab.m[j]) * k[1 + j];
        for (int i = 0; i < nErr; ++i) {
          double e = 0;
          for (int j = 0; j < tab.stages; ++j) e += tab.e[j] * value(k[1 + j][i]);
          const double sc = cfg.atol + cfg.rtol * std::max(std::abs(value(w_.y0[i])), std::abs(value(w_.y1[i])));
          err += (e / sc) * (e / sc);
        }
        err = std::sqrt(err / nErr);
      }
      const Trial trial = judge(ok, err, expo, h, st);
      if (trial == Trial::Fail) return false;
      if (trial == Trial::Retry) continue;
      hNext = std::min(cfg.maxStep, h * std::min(4.0, std::max(0.2, 0.9 * std::pow(std::max(err, 1e-10), -expo))));
      // Accept: stabilise the step's end first (kinematics and rows only), so that the closing evaluation
      // (f, multipliers, damping terms, event functions) is the only one even when it projects.
      s_.y = w_.y1;
      s_.t = s_.t + S(h);
      kinematics(m_, s_.y, w_);
      constraintRows(m_, w_);
      if (slipReversedUnseen() && h > kSlipRetryFloor) {
        s_.y = w_.y0;
        s_.t = s_.t - S(h);
        h *= 0.25;
        ++st.rejected;
        continue;
      }
      bool projected = false;
      if (!stabilise(st, projected)) {
        fail(st, "projection failed");
        return false;
      }
      w_.needDampingResponse = true;  // and after an event, refresh() takes it again
      if (!evaluate(m_, s_.y, s_.active, s_.lambda, w_, w_.ydot) || !allFinite(w_.ydot)) return failNonFinite(st);
      if (slipReversedUnseen()) {  // (down to the retry floor)
        if (!settleUnseenSlips(st) || !refresh()) return failNonFinite(st);
        k[6] = w_.ydot;
        hNext = std::max(h, 1e-8);
        return true;
      }
      eventFunctions(m_, s_, s_.lambda, w_, w_.g1);
      freeStopRates(m_, s_, w_, w_.gRate1);
      k[6] = w_.ydot;
      dense_.kind = DenseOutput<S>::Hermite;
      dense_.t0 = s_.t - S(h);
      dense_.h = h;
      dense_.y0 = &w_.y0;
      dense_.y1 = &w_.y1;
      dense_.f0 = &k[0];
      dense_.f1 = &k[6];
      bool ended = false;
      if (!endOnEvent(h, hNext, st, ended)) return false;
      if (ended) return true;
      w_.g0 = w_.g1;
      w_.gRate0 = w_.gRate1;
      forceOutputs();  // (stabilised above)
      return true;
    }
    fail(st, "too many rejected steps");
    return false;
  }

  bool failNonFinite(RunStatus& st) {
    fail(st, "non-finite state (a force or multiplier overflowed)");
    return false;
  }

  bool stepFixed(double h, RunStatus& st) {
    const Settings& cfg = m_.settings;
    auto& k = w_.stages;
    w_.y0 = s_.y;
    k[0] = w_.ydot;
    w_.yerr = k[0];  // f(t0), kept for the Hermite dense output
    bool ok = true;
    if (cfg.integrator == IntegratorKind::SemiImplicitEuler) {
      const int nx = m_.nx(), nv = m_.nv(), N = m_.nBodies();
      ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
      w_.y1 = w_.y0;
      w_.y1.segment(nx, nv) += S(h) * k[0].segment(nx, nv);
      w_.y1.tail(m_.nDissipation) += S(h) * k[0].tail(m_.nDissipation);
      for (int b = 0; b < N; ++b) {
        w_.y1.template segment<3>(7 * b) += S(h) * w_.y1.template segment<3>(nx + 6 * b);
        const Vec3<S> om = w_.y1.template segment<3>(nx + 6 * b + 3);
        w_.y1.template segment<4>(7 * b + 3) = rotateQuaternion<S>(w_.y1.template segment<4>(7 * b + 3), S(h) * om);
      }
    } else {  // RK4
      auto stage = [&](int i, double c) {
        {
          ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
          w_.ytmp = w_.y0 + S(c * h) * k[i - 1];
        }
        ok = evaluate(m_, w_.ytmp, s_.active, s_.lambda, w_, k[i]) && ok;
      };
      stage(1, 0.5);
      stage(2, 0.5);
      stage(3, 1.0);
      ScopedStage timer(w_.timer, kIntegrate, cfg.profile);
      w_.y1 = w_.y0 + S(h / 6) * (k[0] + S(2) * k[1] + S(2) * k[2] + k[3]);
    }
    if (!ok || !allFinite(w_.y1)) return failNonFinite(st);
    s_.y = w_.y1;
    s_.t = s_.t + S(h);
    normalizeQuaternions(m_, s_.y);
    if (!refresh()) return failNonFinite(st);
    w_.g1 = w_.g0;
    // Events at the step's end: a stop that arrived or would pull, a friction lock past its bound or a
    // slip that reversed; then stabilise.
    bool any = false;
    for (int i = 0; i < m_.nRows; ++i) {
      if (m_.rowInfo[i].friction()) {
        if (value(w_.g1[i]) < 0) any = true;
        continue;
      }
      if (!m_.rowInfo[i].unilateral) continue;
      if (s_.active[i] ? value(s_.lambda[i]) < 0 : value(w_.rows[i].C) <= 0) any = true;
    }
    if (any) {
      ++st.events;
      for (int i = 0; i < m_.nRows; ++i) {
        if (m_.rowInfo[i].friction() && value(w_.g1[i]) < 0) {
          if (s_.active[i]) {
            s_.active[i] = 0;
            setSlip(s_, w_, i, value(s_.lambda[i]) > 0 ? -1 : 1);
          } else {
            setSlip(s_, w_, i, 0);
          }
        }
        if (m_.rowInfo[i].unilateral && s_.active[i] && value(s_.lambda[i]) < 0) s_.active[i] = 0;
      }
      if (resolveContacts(m_, s_, w_) < 0) {
        fail(st, "contact solve failed");
        return false;
      }
      if (cfg.stabilization == Stabilization::Projection && !project(m_, s_, w_)) {
        fail(st, "projection failed");
        return false;
      }
      if (!refresh()) return failNonFinite(st);
    } else if (!afterStep(st)) {
      fail(st, "projection failed");
      return false;
    }
    dense_.kind = DenseOutput<S>::Hermite;
    dense_.t0 = s_.t - S(h);
    dense_.h = h;
    dense_.y0 = &w_.y0;
    dense_.y1 = &s_.y;
    dense_.f0 = &w_.yerr;
    dense_.f1 = &w_.ydot;
    return true;
  }

  const Model<S>& m_;
  State<S>& s_;
  Workspace<S>& w_;
  DenseOutput<S> dense_;
  double errOld_ = 1e-4;  // error of the last accepted step (PI control)
};

// Runs a model from state s to tEnd (free-function form, like mj_step).
template <class S, class Observer> RunStatus simulate(const Model<S>& m, State<S>& s, Workspace<S>& w, double tEnd,
                                                      Observer& obs) {
  Integrator<S> integ(m, s, w);
  return integ.run(tEnd, obs);
}
template <class S> RunStatus simulate(const Model<S>& m, State<S>& s, Workspace<S>& w, double tEnd) {
  NoObserver obs;
  return simulate(m, s, w, tEnd, obs);
}

}  // namespace lg
