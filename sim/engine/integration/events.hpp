// Events inside an accepted adaptive step: which event functions trigger (a sign change at the step's
// ends, or a free stop dipping through zero inside it), their earliest root on the dense output, the
// state moved onto it (with the event time's derivatives in Jet runs), and the mode changes there
// (resolveContacts); a friction slip that reversed unseen inside a step.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>

#include "sim/core/brent.hpp"
#include "sim/engine/integration/step_context.hpp"

namespace lg {

// Does event function i need the multipliers (an enforced stop or a stuck friction lock), or only
// the positions and velocities (a free stop's C, a slip's rate, a force element's event)?
template <class S> bool eventNeedsSolve(StepContext<S>& c, int i) { return i < c.m.nRows && c.s.active[i]; }

// Event function i on the dense output at time t. Those of positions and velocities need the poses
// and one row or one element only; the others a full evaluation.
template <class S> double eventValueAt(StepContext<S>& c, const DenseOutput<S>& dense, int i, double t) {
  dense.at(S(t), c.w.ytmp);
  if (eventNeedsSolve(c, i)) {
    evaluate(c.m, c.w.ytmp, c.s.active, c.w.lamTmp, c.w, c.w.fTmp);
    eventFunctions(c.m, c.s, c.w.lamTmp, c.w, c.w.gtmp);
    return value(c.w.gtmp[i]);
  }
  poses(c.m, c.w.ytmp, c.w);
  const Kins<S> K = c.w.kins();
  if (i >= c.m.nRows) {
    const int e = i - c.m.nRows;
    for (size_t f = 0; f < c.m.forces.size(); ++f) {
      const int first = c.m.eventOffset[f], count = (f + 1 < c.m.forces.size() ? c.m.eventOffset[f + 1] : c.m.nForceEvents) - first;
      if (e < first || e >= first + count) continue;
      std::visit([&](const auto& el) { el.events(K, c.w.forceEvents.data() + first); }, c.m.forces[f].type);
      return value(c.w.forceEvents[e]);
    }
    return 0.0;
  }
  ownerRows(c.m, c.w, i);  // (row i's constraint or lock only: the workspace's other rows are stale until
                           // the next constraintRows, which dipsThrough and every event's handling run)
  if (c.m.rowInfo[i].friction()) return value(S(c.s.slip[i]) * rowVelocity(c.m, c.w, i));
  return value(c.w.rows[i].C + S(c.m.settings.contactTolerance) * c.w.rows[i].Ji.template head<3>().norm());
}

// A free stop whose function is positive at both ends of the step but turns from approaching to
// receding inside it: its minimum on the dense output (Brent's search, stopped at the first value on
// the "after" side) may lie below zero, a contact the ends do not show. If so, returns true with
// (tb, gb) a point after the crossing, the right end of the bracket for locate.
//
// No search where the dip cannot reach zero: under a constant acceleration over the step, the rate
// going from r0 < 0 to r1 > 0, the function falls below g0 by r0^2 h / (2 (r1 - r0)) <= |r0| h / 2 at
// most (and below g1 by at most r1 h / 2). The search runs only where min(g0, g1) is within
// kDipMargin h max(|r0|, r1), twenty times that bound. (The stops that call it most are clear by
// centimetres, their rates round-off that changed sign: the seed gear's limit drop searched four such
// dips, 21 values each, for nothing.)
constexpr double kDipMargin = 10;
template <class S> bool dipsThrough(StepContext<S>& c, const DenseOutput<S>& dense, int i, double& tb, double& gb) {
  if (i >= c.m.nRows || !c.m.rowInfo[i].unilateral || c.m.rowInfo[i].friction() || c.s.active[i]) return false;
  const double g0 = value(c.w.g0[i]), g1 = value(c.w.g1[i]), r0 = value(c.w.gRate0[i]), r1 = value(c.w.gRate1[i]);
  if (!(g0 > 0 && g1 > 0 && r0 < 0 && r1 > 0)) return false;
  if (std::min(g0, g1) > kDipMargin * value(dense.h) * std::max(-r0, r1)) return false;
  ScopedStage timer(c.w.timer, kEvents, c.m.settings.profile);
  const double t0 = value(dense.t0);
  double fx = 0;
  const double x = brentMinimise([&](double t) { return eventValueAt(c, dense, i, t); }, t0, t0 + dense.h, 0.0,
                                 3e-6 * dense.h, fx, [](double g) { return g <= 0; }, 60);
  if (fx > 0) {  // no contact: the workspace's poses and rows back at the step's end
    poses(c.m, c.s.y, c.w);
    constraintRows(c.m, c.w);
    return false;
  }
  tb = x;
  gb = fx;
  return true;
}

// Earliest root of event function i on the dense output (Illinois) in [t0, tb] (g(tb) = gb on the
// "after" side), returned on its "after" side.
template <class S> double locate(StepContext<S>& c, const DenseOutput<S>& dense, int i, double tbIn, double gbIn) {
  ScopedStage timer(c.w.timer, kEvents, c.m.settings.profile);
  double ta = value(dense.t0), tb = tbIn;
  double ga = value(c.w.g0[i]), gb = gbIn;
  const bool unilateralActive = i < c.m.nRows && c.s.active[i];
  auto after = [&](double g) {
    if (i < c.m.nRows) return unilateralActive ? g < 0 : g <= 0;
    return (g > 0) == (value(c.w.g1[i]) > 0);
  };
  c.w.lamTmp = c.s.lambda;
  int side = 0;
  for (int it = 0; it < 200 && tb - ta > c.m.settings.eventTolerance; ++it) {
    double tc = (ga == gb) ? 0.5 * (ta + tb) : tb - gb * (tb - ta) / (gb - ga);
    // The secant through the last point (on the "after" side, its value unscaled) rounds onto it: the
    // root is at tb to the resolution of t (else the search bisected down to the tolerance, a strut's
    // slip ending took 22 values instead of 7).
    if (side == 1 && tc == tb) break;
    if (!(tc > ta && tc < tb)) tc = 0.5 * (ta + tb);
    const double gc = eventValueAt(c, dense, i, tc);
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

// Is force event e (an index into the force elements' event functions) a tyre's contact, whose crossing
// from negative is a touchdown?
template <class S> bool startsContact(const Model<S>& m, int e) {
  for (size_t f = 0; f < m.forces.size(); ++f) {
    const int end = f + 1 < m.forces.size() ? m.eventOffset[f + 1] : m.nForceEvents;  // (its events: [offset, end))
    if (m.eventOffset[f] == e && end > e) return std::holds_alternative<Tyre<S>>(m.forces[f].type);
  }
  return false;
}

// Handles the events between the step's start (g0) and its end (g1 = w.g1); if one triggers, moves
// the state back onto the earliest one. Returns false on failure.
template <class S> bool handleEvents(StepContext<S>& c, const DenseOutput<S>& dense, RunStatus& st, bool& hadEvent) {
  hadEvent = false;
  // The evaluations below (an event function that needs the multipliers, on the dense output) need f
  // only: a located event is always followed by refresh(c), which takes the damping terms' responses
  // at the state the next step starts from.
  const ScopedFlag noResponse(c.w.needDampingResponse, false);
  const int nG = c.m.nRows + c.m.nForceEvents;
  int first = -1;
  double tFirst = 0;
  for (int i = 0; i < nG; ++i) {
    double tb = value(dense.t0) + dense.h, gb = value(c.w.g1[i]);
    if (!eventTriggered(c.m, c.s, i, value(c.w.g0[i]), gb) && !dipsThrough(c, dense, i, tb, gb)) continue;
    const double te = locate(c, dense, i, tb, gb);
    if (first < 0 || te < tFirst) {
      first = i;
      tFirst = te;
    }
  }
  if (first < 0) return true;
  hadEvent = true;
  ++st.events;
  if (first >= c.m.nRows && value(c.w.g0[first]) < 0 && startsContact(c.m, first - c.m.nRows)) c.touchdown = true;
  ScopedStage timer(c.w.timer, kEvents, c.m.settings.profile);
  // The event time carries the derivatives of g (one Newton correction in S); its value is tFirst.
  // (For double there are no derivatives: only a stuck friction lock needs its reaction's sign there.)
  S te = S(tFirst);
  if constexpr (!std::is_same_v<S, double>) {
    const double dt = 1e-7 * std::max(dense.h, 1e-3);  // (>= 1e-10 s: g's slope above its round-off)
    dense.at(S(tFirst - dt), c.w.ytmp);
    c.w.lamTmp = c.s.lambda;
    evaluate(c.m, c.w.ytmp, c.s.active, c.w.lamTmp, c.w, c.w.fTmp);
    eventFunctions(c.m, c.s, c.w.lamTmp, c.w, c.w.g2);
    dense.at(te, c.w.ytmp);
    c.w.lamTmp = c.s.lambda;
    evaluate(c.m, c.w.ytmp, c.s.active, c.w.lamTmp, c.w, c.w.fTmp);  // f at the event, the mode before it
    eventFunctions(c.m, c.s, c.w.lamTmp, c.w, c.w.gtmp);
    const double ga = value(c.w.gtmp[first]);
    const double slope = (ga - value(c.w.g2[first])) / dt;
    if (std::abs(slope) > 0) te -= derivativePart(c.w.gtmp[first]) / S(slope);
    // The state at the moved event time: the dense output at its value, moved along f at the event
    // (the right-hand side there, not the interpolant's slope, which a step across a kink of f averages
    // over both sides of it).
    dense.at(S(tFirst), c.s.y);
    c.s.y += c.w.fTmp * (te - S(tFirst));
  } else {
    if (first < c.m.nRows && c.m.rowInfo[first].friction() && c.s.active[first]) {
      dense.at(te, c.w.ytmp);
      c.w.lamTmp = c.s.lambda;
      evaluate(c.m, c.w.ytmp, c.s.active, c.w.lamTmp, c.w, c.w.fTmp);
    }
    dense.at(te, c.s.y);
  }
  c.s.t = te;
  // Act on it: a stop whose multiplier would pull is let go; a stuck friction lock whose reaction
  // reached its bound slips (against the reaction); a slipping one that stopped is at rest. Then the
  // contact modes are resolved (impacts for a stop arriving) for every stop at once, and the friction
  // locks at rest are decided.
  if (first < c.m.nRows && c.m.rowInfo[first].friction()) {
    if (c.s.active[first]) {
      c.s.active[first] = 0;
      setSlip(c.s, c.w, first, value(c.w.lamTmp[first]) > 0 ? -1 : 1);
    } else {
      setSlip(c.s, c.w, first, 0);
    }
  } else if (first < c.m.nRows && c.s.active[first] && value(c.w.g1[first]) < 0) {
    c.s.active[first] = 0;
  }
  if (resolveContacts(c.m, c.s, c.w) < 0) return false;
  if (c.m.settings.stabilization != Stabilization::None && !project(c.m, c.s, c.w)) return false;
  return true;
}

// A friction lock that started slipping at rest (its rate zero at the step's start) and ends the step
// moving against its slip direction: the slip was shorter than the step, which must not cross it
// unseen (the segment's law would then drive the motion). Rows must be current at the step's end.
template <class S> bool slipReversedUnseen(StepContext<S>& c) {
  for (int k = 0; k < c.m.nRows; ++k) {
    if (!c.m.rowInfo[k].friction() || c.s.active[k] || c.s.slip[k] == 0) continue;
    if (value(c.w.g0[k]) <= 0 && c.s.slip[k] * value(rowVelocity(c.m, c.w, k)) < 0) return true;
  }
  return false;
}

// Such a step is retried at a quarter of its size; when it is down to the event tolerance, the slip is
// over: the lock is at rest at the step's end, and its mode is decided there (resolveFriction).
constexpr double kSlipRetryFloor = 1e-9;  // [s]

template <class S> bool settleUnseenSlips(StepContext<S>& c, RunStatus& st) {
  for (int k = 0; k < c.m.nRows; ++k)
    if (c.m.rowInfo[k].friction() && !c.s.active[k] && c.s.slip[k] != 0 && value(c.w.g0[k]) <= 0 &&
        c.s.slip[k] * value(rowVelocity(c.m, c.w, k)) < 0)
      setSlip(c.s, c.w, k, 0);
  ++st.events;
  c.dense.endsOnEvent = true;
  if (resolveContacts(c.m, c.s, c.w) < 0) return false;
  return c.m.settings.stabilization == Stabilization::None || project(c.m, c.s, c.w);
}

// The accepted step's end (size h) where a slip reversed unseen inside it: undone, to be tried again at
// a quarter of its size (above the retry floor).
template <class S> Accepted retryUnseenSlip(StepContext<S>& c, double& h, RunStatus& st) {
  c.s.y = c.w.y0;
  c.s.t = c.s.t - S(h);
  h *= 0.25;
  ++st.rejected;
  return Accepted::Retry;
}

// Down to the retry floor: the slip is over; the locks are settled at the step's end and f and g
// refreshed there; the next step is at least h.
template <class S> Accepted settleAtRetryFloor(StepContext<S>& c, double h, double& hNext, RunStatus& st) {
  if (!settleUnseenSlips(c, st) || !refresh(c)) {
    failNonFinite(c, st);
    return Accepted::Failed;
  }
  hNext = std::max(h, 1e-8);
  return Accepted::Done;
}

// The events of an accepted adaptive step: if one triggered, the step ends on it ('ended'); the dense
// output (valid on [t0, t0 + h]) still describes [t0, t_event] for the observer, the state may have
// jumped (impact, projection), so f and g are refreshed. 'hNext' holds the error controller's proposal
// after the step; the next step takes half of it (kEventRestart): the mode changed, and a rejected step
// costs a whole step's evaluations. (Restarted at a tenth of the step that held the event, as before,
// the seed gear's limit drop, six events, took 63 steps to a peak-load error of 0.108 % with ros34pw2 at
// rtol 1e-2, the step regrowing at most four-fold a step after each; at half the proposal it takes 47
// to 0.085 %, and the evaluations over every case of every shipped scene fall by 2 .. 3 %, the worst
// errors within --accuracy's promise.) Returns false on failure.
// A touchdown (a tyre's contact starting, after a fall or a bounce) restarts as a run does, at the first
// trial step (Settings::step) at most: the steps of the flight before it, grown on a motion the error
// estimate follows exactly, say nothing of the impact's, and the first step after it would otherwise carry
// the orifices' dissipation (a quadrature the estimate does not control) over milliseconds.
constexpr double kEventRestart = 0.5;
template <class S> bool endOnEvent(StepContext<S>& c, double& hNext, RunStatus& st, bool& ended) {
  if (!handleEvents(c, c.dense, st, ended)) {
    fail(c, st, "contact or projection solve failed after an event");
    return false;
  }
  c.dense.endsOnEvent = ended;
  if (!ended) return true;
  if (!refresh(c)) return failNonFinite(c, st);
  hNext = std::max(kEventRestart * hNext, 1e-8);
  if (c.touchdown) hNext = std::min(hNext, c.m.settings.step);
  c.touchdown = false;
  return true;
}

}  // namespace lg
