// One Dormand-Prince 5(4) step with error control (PI), FSAL and the 4th-order dense output; events on
// the dense output.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/integration/events.hpp"
#include "sim/integration/tableaus.hpp"

namespace lg {

// One step from c.s over h (shrunk and retried until its error is within the tolerance); hNext is the
// proposed next step. Returns false with the reason in st when the run cannot go on.
template <class S> bool stepDopri(StepContext<S>& c, double h, double& hNext, RunStatus& st) {
  const Settings& cfg = c.m.settings;
  auto& k = c.w.stages;
  const int nErr = c.m.nErr();  // the dissipated-energy states are not error-controlled (but those asked for)
  k[0] = c.w.ydot;
  const bool testStiffness = cfg.stiffSwitchRtol > 0;
  for (int attempt = 0; attempt < 60; ++attempt) {
    c.w.y0 = c.s.y;
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
    // y1 = ytmp after stage 7 (a[6] = b), k[6] = f(y1) (FSAL).
    double err = 0;
    {
      ScopedStage timer(c.w.timer, kIntegrate, cfg.profile);
      c.w.y1 = c.w.ytmp;
      for (int i = 0; i < nErr; ++i) {
        S e(0);
        for (int j = 0; j < 7; ++j)
          if (dopri::e[j] != 0) e += S(dopri::e[j]) * k[j][i];
        const double sc = c.atol + c.rtol * std::max(std::abs(value(c.w.y0[i])), std::abs(value(c.w.y1[i])));
        const double r = h * value(e) / sc;
        err += r * r;
      }
      err = std::sqrt(err / nErr);
    }
    const Trial trial = judge(c, ok, err, 0.2, h, st);
    if (trial == Trial::Fail) return false;
    if (trial == Trial::Retry) continue;
    // Stabilised (PI) step-size control of Hairer's dopri5 (beta = 0.04): fewer rejections where the
    // step is capped by stability rather than accuracy.
    {
      const double e = std::max(err, 1e-10);
      const double fac = std::pow(e, 0.2 - 0.04 * 0.75) / std::pow(c.errOld, 0.04) / 0.9;
      hNext = std::min(cfg.maxStep, h / std::max(0.2, std::min(5.0, fac)));
      c.errOld = std::max(err, 1e-4);
    }
    // Accept: state at the step's end, event functions there.
    if (testStiffness) c.stiffness.observe(h, c.w.y1, c.w.yStiff, k[6], k[5], nErr);
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
    if (slipReversedUnseen(c)) {  // (rows are at y1: the last stage is there)
      if (h > kSlipRetryFloor) {
        c.s.y = c.w.y0;
        c.s.t = c.s.t - S(h);
        h *= 0.25;
        ++st.rejected;
        continue;
      }
      if (!settleUnseenSlips(c, st) || !refresh(c)) return failNonFinite(c, st);
      hNext = std::max(h, 1e-8);
      return true;
    }
    bool ended = false;
    if (!endOnEvent(c, hNext, st, ended)) return false;
    if (ended) return true;
    // Smooth step: first same as last.
    c.w.ydot = k[6];
    c.w.g0 = c.w.g1;
    c.w.gRate0 = c.w.gRate1;
    forceOutputs(c);
    if (!afterStep(c, st)) {
      fail(c, st, "projection failed");
      return false;
    }
    return true;
  }
  fail(c, st, "too many rejected steps");
  return false;
}

}  // namespace lg
