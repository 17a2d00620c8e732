// One fixed step of semi-implicit Euler or classical RK4; events handled at the step's end.
#pragma once

#include "sim/engine/integration/step_context.hpp"

namespace lg {

// Semi-implicit (symplectic) Euler from y_n = w.y0 with k[0] = f(y_n): the velocities (and the
// dissipation channels) first, then the positions with the new velocities, each quaternion rotated by
// h omega; into w.y1.
template <class S> void eulerEnd(StepContext<S>& c, double h) {
  const auto& k = c.w.stages;
  const int nx = c.m.nx(), nv = c.m.nv(), N = c.m.nBodies();
  ScopedStage timer(c.w.timer, kIntegrate, c.m.settings.profile);
  c.w.y1 = c.w.y0;
  c.w.y1.segment(nx, nv) += S(h) * k[0].segment(nx, nv);
  c.w.y1.tail(c.m.nDissipation) += S(h) * k[0].tail(c.m.nDissipation);
  for (int b = 0; b < N; ++b) {
    c.w.y1.template segment<3>(7 * b) += S(h) * c.w.y1.template segment<3>(nx + 6 * b);
    const Vec3<S> om = c.w.y1.template segment<3>(nx + 6 * b + 3);
    c.w.y1.template segment<4>(7 * b + 3) = rotateQuaternion<S>(c.w.y1.template segment<4>(7 * b + 3), S(h) * om);
  }
}

// Classical RK4 from y_n = w.y0 with k[0] = f(y_n): three more evaluations, then w.y1. Returns false
// where one failed.
template <class S> bool rk4End(StepContext<S>& c, double h) {
  const Settings& cfg = c.m.settings;
  auto& k = c.w.stages;
  bool ok = true;
  auto stage = [&](int i, double ci) {
    {
      ScopedStage timer(c.w.timer, kIntegrate, cfg.profile);
      c.w.ytmp = c.w.y0 + S(ci * h) * k[i - 1];
    }
    ok = evaluate(c.m, c.w.ytmp, c.s.active, c.s.lambda, c.w, k[i], RowsFor::Solve) && ok;
  };
  stage(1, 0.5);
  stage(2, 0.5);
  stage(3, 1.0);
  ScopedStage timer(c.w.timer, kIntegrate, cfg.profile);
  c.w.y1 = c.w.y0 + S(h / 6) * (k[0] + S(2) * k[1] + S(2) * k[2] + k[3]);
  return ok;
}

// Events at a fixed step's end (f and g refreshed there): a stop that arrived or would pull, a friction
// lock past its bound or a slip that reversed. If any ('any'), the modes change and the contacts are
// resolved there, the state projected and refreshed; else the end is stabilised. Returns false on failure.
template <class S> bool fixedStepEvents(StepContext<S>& c, RunStatus& st, bool& any) {
  any = false;
  for (int i = 0; i < c.m.nRows; ++i) {
    if (c.m.rowInfo[i].friction()) {
      if (value(c.w.g1[i]) < 0) any = true;
      continue;
    }
    if (!c.m.rowInfo[i].unilateral) continue;
    if (c.s.active[i] ? value(c.s.lambda[i]) < 0 : value(c.w.rows[i].C) <= 0) any = true;
  }
  if (!any) {
    if (!afterStep(c, st)) {
      fail(c, st, "projection failed");
      return false;
    }
    return true;
  }
  ++st.events;
  for (int i = 0; i < c.m.nRows; ++i) {
    if (c.m.rowInfo[i].friction() && value(c.w.g1[i]) < 0) {
      if (c.s.active[i]) {
        c.s.active[i] = 0;
        setSlip(c.s, c.w, i, value(c.s.lambda[i]) > 0 ? -1 : 1);
      } else {
        setSlip(c.s, c.w, i, 0);
      }
    }
    if (c.m.rowInfo[i].unilateral && c.s.active[i] && value(c.s.lambda[i]) < 0) c.s.active[i] = 0;
  }
  if (resolveContacts(c.m, c.s, c.w) < 0) {
    fail(c, st, "contact solve failed");
    return false;
  }
  if (c.m.settings.stabilization == Stabilization::Projection && !project(c.m, c.s, c.w)) {
    fail(c, st, "projection failed");
    return false;
  }
  if (!refresh(c)) return failNonFinite(c, st);
  return true;
}

// One step of size h: the method's end, the state moved there and refreshed, its events, and the
// Hermite dense output over the step.
template <class S> bool stepFixed(StepContext<S>& c, double h, RunStatus& st) {
  auto& k = c.w.stages;
  c.w.y0 = c.s.y;
  k[0] = c.w.ydot;
  c.w.yerr = k[0];  // f(t0), kept for the Hermite dense output
  bool ok = true;
  if (c.m.settings.integrator == IntegratorKind::SemiImplicitEuler)
    eulerEnd(c, h);
  else
    ok = rk4End(c, h);
  if (!ok || !allFinite(c.w.y1)) return failNonFinite(c, st);
  c.s.y = c.w.y1;
  c.s.t = c.s.t + S(h);
  normalizeQuaternions(c.m, c.s.y);
  if (!refresh(c)) return failNonFinite(c, st);
  c.w.g1 = c.w.g0;
  bool any = false;
  if (!fixedStepEvents(c, st, any)) return false;
  c.dense.kind = DenseOutput<S>::Hermite;
  c.dense.closesAtState = false;
  c.dense.t0 = c.s.t - S(h);
  c.dense.h = h;
  c.dense.y0 = &c.w.y0;
  c.dense.y1 = &c.s.y;
  c.dense.f0 = &c.w.yerr;
  c.dense.f1 = &c.w.ydot;
  c.dense.endsOnEvent = any;
  return true;
}

}  // namespace lg
