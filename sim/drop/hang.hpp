// The gear hanging on its elastic extension stops (sim/forces/stop_pad.hpp) at a drop's release.
//
// Before touchdown the gear falls as one body, every point at the same velocity, accelerated by
// g (1 - L): the strut's gas preload presses it onto its extension stops. A rigid stop takes that load
// as its multiplier with no overtravel; a pad of stiffness k takes it as an overtravel x = F/k. The
// hanging configuration is found as a fixed point: each pad replaced by a rigid stop at L + x (a
// temporary unilateral row, enforced), the positions projected onto it (the mass-weighted smallest
// correction, every joint kept: engine.hpp, project), the load the pad must carry read off the
// multipliers at zero relative velocity, F = k x + lambda |d| (the pad itself stays in the model and
// pushes k x; the row adds the rest), x <- max(F, 0)/k. Each pass contracts by about the strut's
// gas stiffness over k (the load changes only with the gas volume); it stops at round-off.
// The gear hangs 1 m above the ground (its tyres in the air, as before touchdown); it is then moved
// along the drop direction (the ground's normal) so that its lowest tyre touches the ground as in the
// scene: a contact drop touches down at t = 0, a drop from a height is raised from there.
// Templated on the scalar: a design parameter's derivatives (k, p01, the masses) pass through the
// fixed point and the projection.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/engine/engine.hpp"
#include "sim/scene/scene.hpp"

namespace lg {

// Moves y (positions at the scene's touchdown pose, velocities ignored) to the hanging configuration
// of model m's pads. Returns false when the fixed point does not settle (the message says why).
template <class S> bool hangOnPads(const Scene& scene, const Model<S>& m, VecX<S>& y, std::string* message = nullptr) {
  const auto& pads = scene.roles.pads;
  if (pads.empty()) return true;
  // The temporary rigid rows, one per pad.
  Model<S> mh = m;
  for (int f : pads) {
    const auto& p = std::get<StopPad<S>>(m.forces[f].type);
    Constraint<S> c;
    c.name = m.forces[f].name;
    c.type = DistanceStop<S>{p.bi, p.bj, p.rho_i, p.rho_j, p.L, true};
    mh.constraints.push_back(c);
  }
  mh.settings.projectionTolerance = 1e-13;  // (the overtravel to round-off, not to a step's drift)
  mh.finalize();
  const int first = static_cast<int>(m.constraints.size());
  State<S> s(mh);
  s.y = y;
  const int N = m.nBodies();
  // In the air: 1 m above the scene's pose (the tyres clear of the ground), moved back below.
  for (int b = 0; b < N; ++b) s.y.template segment<3>(7 * b) += scene.up.template cast<S>();
  s.y.segment(7 * N, 6 * N).setZero();  // (every body at the same velocity: only relative ones matter)
  for (size_t k = 0; k < pads.size(); ++k) s.active[mh.rowOffset[first + k]] = 1;
  Workspace<S> w(mh);
  impliedPlanarRows(mh, s, w);  // (a planar model: the rows out of its mode, as at a run's start)
  VecX<S> ydot = VecX<S>::Zero(mh.ny());
  std::vector<S> x(pads.size(), S(0));
  for (int it = 0; it < 60; ++it) {
    for (size_t k = 0; k < pads.size(); ++k)
      std::get<DistanceStop<S>>(mh.constraints[first + k].type).L = std::get<StopPad<S>>(m.forces[pads[k]].type).L + x[k];
    if (!project(mh, s, w)) {
      if (message) *message = "the hanging configuration on the elastic stops: projection failed";
      return false;
    }
    s.y.segment(7 * N, 6 * N).setZero();
    evaluate(mh, s.y, s.active, s.lambda, w, ydot, RowsFor::Solve);
    double change = 0, size = 0;
    for (size_t k = 0; k < pads.size(); ++k) {
      const int row = mh.rowOffset[first + k];
      // The load the pad must carry: its own k x (it stays in the model) and what the row adds.
      const auto& pad = std::get<StopPad<S>>(m.forces[pads[k]].type);
      const S F = pad.k * x[k] + s.lambda[row] * w.rows[row].Ji.template head<3>().norm();  // [N] (J_i = (d, ...))
      const S next = positivePart(F) / pad.k;
      change = std::max(change, std::abs(value(next) - value(x[k])));
      size = std::max(size, std::abs(value(next)));
      x[k] = next;
    }
    if (!std::isfinite(change)) break;
    if (change <= 1e-15 + 1e-13 * size) {
      // The lowest tyre back onto the ground as in the scene.
      Workspace<S> w0(m), w1(m);
      kinematics(m, y, w0);
      kinematics(m, s.y, w1);
      S before = S(-1e300), after = S(-1e300);
      for (int t : scene.roles.tyres) {
        const auto& tyre = std::get<Tyre<S>>(m.forces[t].type);
        const S d0 = tyre.deflection(w0.kins()), d1 = tyre.deflection(w1.kins());
        if (value(d0) > value(before)) before = d0;
        if (value(d1) > value(after)) after = d1;
      }
      const S lift = scene.roles.tyres.empty() ? S(0) : S(after - before);
      for (int b = 0; b < N; ++b) y.template segment<3>(7 * b) = s.y.template segment<3>(7 * b) + lift * scene.up.template cast<S>();
      for (int b = 0; b < N; ++b) y.template segment<4>(7 * b + 3) = s.y.template segment<4>(7 * b + 3);
      return true;
    }
  }
  if (message) *message = "the hanging configuration on the elastic stops did not settle (60 passes)";
  return false;
}

}  // namespace lg
