// The event functions of a mode: free stops, enforced stops, friction locks and the force elements'
// own switching functions, the free stops' rates, and when a function has triggered.
#pragma once

#include "sim/engine/engine.hpp"

namespace lg {

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
  return (g0 < 0 && g1 >= 0) || (g0 > 0 && g1 <= 0);  // (a step that ends on g = 0 holds the event)
}

}  // namespace lg
