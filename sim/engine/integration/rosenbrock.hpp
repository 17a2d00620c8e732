// One step of a linearly implicit Rosenbrock-W method (ROS2, ROS34PW2) with the force elements'
// velocity stiffness in W; cubic Hermite dense output; events on it.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/engine/integration/events.hpp"
#include "sim/engine/integration/tableaus.hpp"

namespace lg {

// r <- W^-1 r with W = I - gamma h J_W, J_W = [[0, K], [J_vx, J_vv]] over (positions, velocities): K the
// kinematic map V -> (r', q') at y_n, and the force elements' stiffness terms (DampingTerm, saved at the
// step's start): J_vv = -sum_e c_e U_e G_e, J_vx = -sum_e k_e U_e H_e with H_e = ds_e/dx (H_e K = G_e)
// and U_e = M_c^-1 G_e^T the constrained response. Positions x = r_x + gamma h K v give for the
// velocities
//   (I + U C G) v = r_v - gamma h sum_e k_e U_e (H_e r_x),   C = gamma h diag(c_e + gamma h k_e),
// solved by Woodbury, (I + U C G)^-1 b = b - U C (I + G U C)^-1 G b. (Without K the W-method keeps its
// order but loses accuracy where a stiff damper couples to the positions: an overdamped oscillator at
// h |lambda| = 100 erred by 2 %; on the seed gear's limit drop at rtol 3e-3, max step 0.05 s, ros34pw2
// takes 104 steps to a peak-load error of 0.095 % without the k_e, 78 to 0.037 % with them.)
template <class S> void solveW(StepContext<S>& c, double gh, bool withStiffness, VecX<S>& r) {
  solveVelocityW(c, withStiffness, r);
  const int N = c.m.nBodies(), nx = c.m.nx();
  for (int b = 0; b < N; ++b) {
    r.template segment<3>(7 * b) += S(gh) * r.template segment<3>(nx + 6 * b);
    const Vec4<S> q = c.w.y0.template segment<4>(7 * b + 3);
    r.template segment<4>(7 * b + 3) += S(gh) * quaternionRate<S>(q, r.template segment<3>(nx + 6 * b + 3));
  }
}

// H_e r_x: the change of term d's coordinate s under the position change r_x (per body (dr, dq), the
// rotation dtheta = 2 vec(dq q*) at y_n's unit quaternion q, the inverse of q' = (0, w) q / 2).
template <class S> S positionRate(const StepContext<S>& c, const DampingTerm<S>& d, const VecX<S>& r) {
  auto body = [&](int b, const Vec6<S>& G) {
    if (b < 0) return S(0);
    const Vec4<S> q = c.w.y0.template segment<4>(7 * b + 3), dq = r.template segment<4>(7 * b + 3);
    const Vec3<S> qv = q.template tail<3>(), dqv = dq.template tail<3>();
    const Vec3<S> dtheta = S(2) * (q[0] * dqv - dq[0] * qv - dqv.cross(qv));
    return G.template head<3>().dot(r.template segment<3>(7 * b)) + G.template tail<3>().dot(dtheta);
  };
  return body(d.bi, d.Gi) + body(d.bj, d.Gj);
}

// The part of W's velocity solve that a trial step's stages share (gh, and the terms saved at its start):
// the terms that change W, their coefficients gamma h (c_e + gamma h k_e) and the elimination of the
// small matrix (I + G U C) with partial pivoting (its multipliers below the diagonal, the pivots in
// smallPivot). solveVelocityW applies them to each stage's right-hand side.
template <class S> void prepareVelocityW(StepContext<S>& c, double gh, bool withStiffness) {
  const int k = c.m.nDamping;
  c.w.termsInWCount = 0;
  if (k == 0) return;
  auto GdotU = [&](const DampingTerm<S>& d, int f) {
    S s(0);
    if (d.bi >= 0) s += d.Gi.dot(c.w.U0.col(f).template segment<6>(6 * d.bi));
    if (d.bj >= 0) s += d.Gj.dot(c.w.U0.col(f).template segment<6>(6 * d.bj));
    return s;
  };
  const auto stiffness = [&](int f) { return withStiffness ? c.w.damping0[f].k : S(0); };
  const auto rate = [&](int f) { return c.w.damping0[f].c + S(gh) * stiffness(f); };  // C = gamma h diag(rate)
  int n = 0;  // the terms that change W (an undamped tyre's in ros2, a tyre in the air: none)
  for (int f = 0; f < k; ++f) {
    c.w.stiffInW[f] = S(gh) * stiffness(f);
    const S coefficient = S(gh) * rate(f);
    if (!exactZero(coefficient)) {
      c.w.coefInW[n] = coefficient;
      c.w.termsInW[n++] = f;
    }
  }
  c.w.termsInWCount = n;
  const int* T = c.w.termsInW.data();
  for (int e = 0; e < n; ++e)
    for (int f = 0; f < n; ++f)
      c.w.smallM(e, f) = (e == f ? S(1) : S(0)) + GdotU(c.w.damping0[T[e]], T[f]) * S(gh) * rate(T[f]);
  for (int j = 0; j < n; ++j) {  // Gaussian elimination with partial pivoting
    int p = j;
    for (int i = j + 1; i < n; ++i)
      if (std::abs(value(c.w.smallM(i, j))) > std::abs(value(c.w.smallM(p, j)))) p = i;
    c.w.smallPivot[j] = p;
    if (p != j)  // (the active columns only: the multipliers of earlier columns stay where they were applied)
      for (int col = j; col < n; ++col) std::swap(c.w.smallM(p, col), c.w.smallM(j, col));
    for (int i = j + 1; i < n; ++i) {
      const S f = c.w.smallM(i, j) / c.w.smallM(j, j);
      for (int col = j + 1; col < n; ++col) c.w.smallM(i, col) -= f * c.w.smallM(j, col);
      c.w.smallM(i, j) = f;  // (the multiplier, for the right-hand sides)
    }
  }
}

template <class S> void solveVelocityW(StepContext<S>& c, bool withStiffness, VecX<S>& r) {
  const int k = c.m.nDamping, nx = c.m.nx();
  if (k == 0) return;
  auto Gdot = [&](const DampingTerm<S>& d, const VecX<S>& v) {  // G . (velocity part of v)
    S s(0);
    if (d.bi >= 0) s += d.Gi.dot(v.template segment<6>(nx + 6 * d.bi));
    if (d.bj >= 0) s += d.Gj.dot(v.template segment<6>(nx + 6 * d.bj));
    return s;
  };
  if (withStiffness)
    for (int f = 0; f < k; ++f)  // the positions' share of the right-hand side
      if (!exactZero(c.w.damping0[f].k))
        r.segment(nx, c.m.nv()) -= (c.w.stiffInW[f] * positionRate(c, c.w.damping0[f], r)) * c.w.U0.col(f);
  const int n = c.w.termsInWCount;
  const int* T = c.w.termsInW.data();
  S* t = c.w.smallT.data();
  for (int e = 0; e < n; ++e) t[e] = Gdot(c.w.damping0[T[e]], r);
  for (int j = 0; j < n; ++j) {  // the elimination of prepareVelocityW on the right-hand side
    if (c.w.smallPivot[j] != j) std::swap(t[c.w.smallPivot[j]], t[j]);
    for (int i = j + 1; i < n; ++i) t[i] -= c.w.smallM(i, j) * t[j];
  }
  for (int j = n - 1; j >= 0; --j) {
    S s = t[j];
    for (int col = j + 1; col < n; ++col) s -= c.w.smallM(j, col) * t[col];
    t[j] = s / c.w.smallM(j, j);
  }
  for (int f = 0; f < n; ++f) r.segment(nx, c.m.nv()) -= (c.w.coefInW[f] * t[f]) * c.w.U0.col(T[f]);
}

// out = base + sum_q c[q] v[q] over n entries in one pass, the terms added in order: the same sums as
// out = base, then out += c[q] v[q] for each q (out may be base).
template <class S> void combine(S* out, const S* base, const double* c, const S* const* v, int terms, int n) {
  using Map = Eigen::Map<VecX<S>>;
  using CMap = Eigen::Map<const VecX<S>>;
  Map o(out, n);
  const CMap b(base, n);
  switch (terms) {  // (coefficient-wise expressions: one pass, evaluated left to right)
    case 0: if (out != base) o = b; return;
    case 1: o = b + S(c[0]) * CMap(v[0], n); return;
    case 2: o = b + S(c[0]) * CMap(v[0], n) + S(c[1]) * CMap(v[1], n); return;
    case 3: o = b + S(c[0]) * CMap(v[0], n) + S(c[1]) * CMap(v[1], n) + S(c[2]) * CMap(v[2], n); return;
    default:
      o = b + S(c[0]) * CMap(v[0], n) + S(c[1]) * CMap(v[1], n) + S(c[2]) * CMap(v[2], n) + S(c[3]) * CMap(v[3], n);
  }
}

// The stages of one trial step of a Rosenbrock-W method (below), from y_n = w.y0 with W prepared for
// gamma h: k[1 + i] = U_i. Returns false where an evaluation failed.
template <class S> bool rosenbrockStages(StepContext<S>& c, const RosenbrockTableau& tab, double h) {
  const Settings& cfg = c.m.settings;
  auto& k = c.w.stages;
  const int ny = c.m.ny();
  const double gh = tab.gamma * h;
  double coef[4];
  const S* vecs[4];
  bool ok = true;
  for (int i = 0; i < tab.stages; ++i) {
    VecX<S>& U = k[1 + i];
    if (i == 0) {
      U = k[0];
    } else {
      {
        ScopedStage timer(c.w.timer, kIntegrate, cfg.profile);
        int terms = 0;
        for (int j = 0; j < i; ++j)
          if (tab.A[i][j] != 0) {
            coef[terms] = tab.A[i][j];
            vecs[terms++] = k[1 + j].data();
          }
        combine(c.w.ytmp.data(), c.w.y0.data(), coef, vecs, terms, ny);
      }
      ok = evaluate(c.m, c.w.ytmp, c.s.active, c.s.lambda, c.w, U, RowsFor::Solve) && ok;
    }
    ScopedStage timer(c.w.timer, kIntegrate, cfg.profile);
    int terms = 0;
    for (int j = 0; j < i; ++j)
      if (tab.C[i][j] != 0) {
        coef[terms] = tab.C[i][j] / h;
        vecs[terms++] = k[1 + j].data();
      }
    combine(U.data(), U.data(), coef, vecs, terms, ny);
    solveW(c, gh, tab.stiffnessInW, U);
    U *= S(gh);
  }
  return ok;
}

// The trial's end y_n+1 = y_n + sum_i m_i U_i into w.y1, and its error norm (1 = the tolerance): the RMS
// over the positions and velocities of sum_i e_i U_i scaled by atol + rtol max(|y_n|, |y_n+1|).
template <class S> double rosenbrockEnd(StepContext<S>& c, const RosenbrockTableau& tab) {
  ScopedStage timer(c.w.timer, kIntegrate, c.m.settings.profile);
  auto& k = c.w.stages;
  const int nErr = c.m.nErr(), ny = c.m.ny();
  const S* vecs[4];
  for (int j = 0; j < tab.stages; ++j) vecs[j] = k[1 + j].data();
  combine(c.w.y1.data(), c.w.y0.data(), tab.m, vecs, tab.stages, ny);
  // The scaled error of each component in one pass (vectorisable), then their squares summed in order.
  double* q = c.w.errTerm.data();
  const auto scaled = [&](int i, double e) {
    return e / (c.atol + c.rtol * std::max(std::abs(value(c.w.y0[i])), std::abs(value(c.w.y1[i]))));
  };
  if (tab.stages == 4) {
    const S *k1 = vecs[0], *k2 = vecs[1], *k3 = vecs[2], *k4 = vecs[3];
    const double e1 = tab.e[0], e2 = tab.e[1], e3 = tab.e[2], e4 = tab.e[3];
    for (int i = 0; i < nErr; ++i)
      q[i] = scaled(i, (((0.0 + e1 * value(k1[i])) + e2 * value(k2[i])) + e3 * value(k3[i])) + e4 * value(k4[i]));
  } else {
    for (int i = 0; i < nErr; ++i) {
      double e = 0;
      for (int j = 0; j < tab.stages; ++j) e += tab.e[j] * value(vecs[j][i]);
      q[i] = scaled(i, e);
    }
  }
  double err = 0;
  for (int i = 0; i < nErr; ++i) err += q[i] * q[i];
  return std::sqrt(err / nErr);
}

// An accepted trial of size h becomes the step: its end stabilised first (kinematics and rows only), so
// that the closing evaluation (f, multipliers, damping terms, event functions) is the only one even when
// it projects; the dense output set; a slip that reversed unseen retried at a quarter of h (Retry) or,
// down to the retry floor, settled; then the events inside the step.
template <class S> Accepted acceptRosenbrock(StepContext<S>& c, const RosenbrockTableau& tab, double& h, double& hNext,
                                             RunStatus& st) {
  auto& k = c.w.stages;
  c.s.y = c.w.y1;
  c.s.t = c.s.t + S(h);
  normalizeQuaternions(c.m, c.s.y);  // (first: the rows below are then those the projection starts from)
  kinematics(c.m, c.s.y, c.w);
  constraintRows(c.m, c.w);
  if (slipReversedUnseen(c) && h > kSlipRetryFloor) return retryUnseenSlip(c, h, st);
  bool projected = false;
  if (!stabilise(c, st, projected, /*normalised=*/true)) {
    fail(c, st, "projection failed");
    return Accepted::Failed;
  }
  c.w.needDampingResponse = true;  // and after an event, refresh(c) takes it again
  if (!evaluate(c.m, c.s.y, c.s.active, c.s.lambda, c.w, c.w.ydot) || !allFinite(c.w.ydot)) {
    failNonFinite(c, st);
    return Accepted::Failed;
  }
  c.dense.t0 = c.s.t - S(h);
  c.dense.h = h;
  c.dense.y0 = &c.w.y0;
  c.dense.y1 = &c.w.y1;
  k[6] = c.w.ydot;
  c.dense.f0 = &k[0];
  c.dense.f1 = &k[6];
  c.dense.kind = tab.hasDense ? DenseOutput<S>::Rosenbrock : DenseOutput<S>::Hermite;
  c.dense.closesAtState = true;
  c.dense.k = &k;
  c.dense.weights = tab.d;
  c.dense.nx = c.m.nx();
  if (slipReversedUnseen(c)) return settleAtRetryFloor(c, h, hNext, st);  // (down to the retry floor)
  eventFunctions(c.m, c.s, c.s.lambda, c.w, c.w.g1);
  freeStopRates(c.m, c.s, c.w, c.w.gRate1);
  bool ended = false;
  if (!endOnEvent(c, hNext, st, ended)) return Accepted::Failed;
  if (ended) return Accepted::Done;
  c.w.g0 = c.w.g1;
  c.w.gRate0 = c.w.gRate1;
  forceOutputs(c);  // (stabilised above)
  return Accepted::Done;
}

// One step of a linearly implicit Rosenbrock-W method (RosenbrockTableau: ROS2 or ROS34PW2) in the
// transformed form of Hairer & Wanner (IV.7.25), which needs no Jacobian-vector products:
//   (I/(gamma h) - J_W) U_i = f(y_n + sum_j A_ij U_j) + sum_j C_ij/h U_j,   i = 1..s
//   y_n+1 = y_n + sum_i m_i U_i,   error estimate sum_i e_i U_i (against the embedded method),
// with J_W the force elements' velocity stiffness (rank 1 per damper, see DampingTerm) taken at y_n:
// the orifice damping and the regularised friction no longer cap the step. Any J_W keeps the order
// (W-method). Dense output: the positions by the cubic Hermite between f(y_n) and f(y_n+1), the
// velocities by the method's continuous extension where the tableau has one (ROS34PW2; ROS2: Hermite).
// The trial steps: W prepared, the stages, the end and its error, the verdict; then the accepted step.
template <class S> bool stepRosenbrock(StepContext<S>& c, const RosenbrockTableau& tab, double h, double& hNext, RunStatus& st) {
  auto& k = c.w.stages;  // k[0] = f(y_n), k[1..s] = U_1..U_s, k[6] = f(y_n+1)
  k[0] = c.w.ydot;
  c.w.U0 = c.w.U;  // the damping terms at y_n (the last evaluation was at s.y)
  c.w.damping0 = c.w.damping;
  const double expo = 1.0 / (tab.embeddedOrder + 1);
  c.w.needDampingResponse = false;  // the stages need f only; U is taken at the accepted state
  for (int attempt = 0; attempt < 60; ++attempt) {
    c.w.y0 = c.s.y;
    prepareVelocityW(c, tab.gamma * h, tab.stiffnessInW);
    const bool ok = rosenbrockStages(c, tab, h);
    const double err = rosenbrockEnd(c, tab);
    const Trial trial = judge(c, ok, err, expo, h, st);
    if (trial == Trial::Fail) return false;
    if (trial == Trial::Retry) continue;
    hNext = std::min(c.m.settings.maxStep,
                     h * std::min(4.0, std::max(0.2, 0.9 * std::pow(std::max(err, 1e-10), -expo))));
    switch (acceptRosenbrock(c, tab, h, hNext, st)) {
      case Accepted::Done: return true;
      case Accepted::Failed: return false;
      case Accepted::Retry: continue;
    }
  }
  fail(c, st, "too many rejected steps");
  return false;
}

}  // namespace lg
