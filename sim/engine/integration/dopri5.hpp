// One Dormand-Prince 5(4) step with error control (PI), FSAL and the 4th-order dense output; events on
// the dense output.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/engine/integration/events.hpp"
#include "sim/engine/integration/tableaus.hpp"

namespace lg {

// The six new stages of one trial step from y_n = w.y0 (k[0] = f(y_n) holds): k[i] = f(y_n + h sum_j
// a_ij k_j); the last one's argument is y_n+1 (a[6] = b), left in w.ytmp, and k[6] = f(y_n+1) (FSAL).
// With the stiffness test on, the 6th stage's argument (c6 = 1) is kept as y*. Returns false where an
// evaluation failed.
template <class S> bool dopriStages(StepContext<S>& c, double h, bool testStiffness) {
  const Settings& cfg = c.m.settings;
  auto& k = c.w.stages;
  bool ok = true;
  for (int i = 1; i < 7; ++i) {
    {
      ScopedStage timer(c.w.timer, kIntegrate, cfg.profile);
      if (i == 6 && testStiffness) c.w.yStiff = c.w.ytmp;  // y*, the 6th stage's argument (c6 = 1)
      c.w.ytmp = c.w.y0;
      for (int j = 0; j < i; ++j)
        if (dopri::a[i][j] != 0) c.w.ytmp += S(h * dopri::a[i][j]) * k[j];
    }
    ok = evaluate(c.m, c.w.ytmp, c.s.active, c.s.lambda, c.w, k[i], i < 6 ? RowsFor::Solve : RowsFor::Events) && ok;
  }
  return ok;
}

// The trial's end y_n+1 into w.y1 and its error norm (1 = the tolerance): the RMS over the
// error-controlled states (the dissipated-energy states are not, but those asked for) of h sum_j e_j k_j
// scaled by atol + rtol max(|y_n|, |y_n+1|).
template <class S> double dopriEnd(StepContext<S>& c, double h) {
  ScopedStage timer(c.w.timer, kIntegrate, c.m.settings.profile);
  const auto& k = c.w.stages;
  const int nErr = c.m.nErr();
  c.w.y1 = c.w.ytmp;
  double err = 0;
  for (int i = 0; i < nErr; ++i) {
    S e(0);
    for (int j = 0; j < 7; ++j)
      if (dopri::e[j] != 0) e += S(dopri::e[j]) * k[j][i];
    const double sc = c.atol + c.rtol * std::max(std::abs(value(c.w.y0[i])), std::abs(value(c.w.y1[i])));
    const double r = h * value(e) / sc;
    err += r * r;
  }
  return std::sqrt(err / nErr);
}

// Stabilised (PI) step-size control of Hairer's dopri5 (beta = 0.04): fewer rejections where the step is
// capped by stability rather than accuracy. The next step after an accepted one of size h and error err.
template <class S> double dopriNextStep(StepContext<S>& c, double h, double err) {
  const double e = std::max(err, 1e-10);
  const double fac = std::pow(e, 0.2 - 0.04 * 0.75) / std::pow(c.errOld, 0.04) / 0.9;
  c.errOld = std::max(err, 1e-4);
  return std::min(c.m.settings.maxStep, h / std::max(0.2, std::min(5.0, fac)));
}

// An accepted trial of size h becomes the step: the dense output set, the state moved to its end, the
// event functions there; a slip that reversed unseen retried at a quarter of h (Retry) or, down to the
// retry floor, settled; the events inside the step; else FSAL and the stabilisation of the end.
template <class S> Accepted acceptDopri(StepContext<S>& c, double& h, double& hNext, RunStatus& st) {
  auto& k = c.w.stages;
  c.dense.kind = DenseOutput<S>::Dopri;
  c.dense.closesAtState = false;
  c.dense.t0 = c.s.t;
  c.dense.h = h;
  c.dense.y0 = &c.w.y0;
  c.dense.y1 = &c.w.y1;
  c.dense.k = &c.w.stages;
  c.s.y = c.w.y1;
  c.s.t = c.s.t + S(h);
  eventFunctions(c.m, c.s, c.s.lambda, c.w, c.w.g1);
  freeStopRates(c.m, c.s, c.w, c.w.gRate1);
  if (slipReversedUnseen(c))  // (rows are at y1: the last stage is there)
    return h > kSlipRetryFloor ? retryUnseenSlip(c, h, st) : settleAtRetryFloor(c, h, hNext, st);
  bool ended = false;
  if (!endOnEvent(c, hNext, st, ended)) return Accepted::Failed;
  if (ended) return Accepted::Done;
  // Smooth step: first same as last.
  c.w.ydot = k[6];
  c.w.g0 = c.w.g1;
  c.w.gRate0 = c.w.gRate1;
  forceOutputs(c);
  if (!afterStep(c, st)) {
    fail(c, st, "projection failed");
    return Accepted::Failed;
  }
  return Accepted::Done;
}

// One step from c.s over h (shrunk and retried until its error is within the tolerance); hNext is the
// proposed next step. Returns false with the reason in st when the run cannot go on.
template <class S> bool stepDopri(StepContext<S>& c, double h, double& hNext, RunStatus& st) {
  auto& k = c.w.stages;
  k[0] = c.w.ydot;
  const bool testStiffness = c.m.settings.stiffSwitchRtol > 0;
  for (int attempt = 0; attempt < 60; ++attempt) {
    c.w.y0 = c.s.y;
    const bool ok = dopriStages(c, h, testStiffness);
    const double err = dopriEnd(c, h);
    const Trial trial = judge(c, ok, err, 0.2, h, st);
    if (trial == Trial::Fail) return false;
    if (trial == Trial::Retry) continue;
    hNext = dopriNextStep(c, h, err);
    if (testStiffness) c.stiffness.observe(h, c.w.y1, c.w.yStiff, k[6], k[5], c.m.nErr());
    switch (acceptDopri(c, h, hNext, st)) {
      case Accepted::Done: return true;
      case Accepted::Failed: return false;
      case Accepted::Retry: continue;
    }
  }
  fail(c, st, "too many rejected steps");
  return false;
}

}  // namespace lg
