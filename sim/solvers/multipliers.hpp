// Multiplier solvers. They see rows only: the list of rows in the solve, their J blocks, and
// W = M^-1 J^T. Two methods, chosen per run (Settings::solver):
//   direct        J M^-1 J^T lambda = rhs assembled over the row list, exploiting the block sparsity
//                 (an entry is non-zero only where two rows share a body), solved by an in-place
//                 LDL^T; unilateral rows by an active set (pivoting on the most violated row).
//   Gauss-Seidel  the article's iteration, lambda_k += (rhs_k - A_k lambda)/A_kk, projected onto
//                 lambda_k >= 0 for unilateral rows in a contact solve, warm-started.
#pragma once

#include <algorithm>
#include <cmath>

#include "sim/core/state.hpp"

namespace lg {

// W_k = M^-1 J_k^T for every row in work.list.
template <class S> void computeW(const Model<S>& m, Workspace<S>& w) {
  for (int k : w.list) {
    const RowInfo& ri = m.rowInfo[k];
    const Row<S>& row = w.rows[k];
    if (ri.bi >= 0) {
      const BodyKin<S>& K = w.kin[ri.bi];
      w.Wi[k].template head<3>() = K.invMass * row.Ji.template head<3>();
      w.Wi[k].template tail<3>() = K.IwInv * row.Ji.template tail<3>();
    }
    if (ri.bj >= 0) {
      const BodyKin<S>& K = w.kin[ri.bj];
      w.Wj[k].template head<3>() = K.invMass * row.Jj.template head<3>();
      w.Wj[k].template tail<3>() = K.IwInv * row.Jj.template tail<3>();
    }
  }
}

// A = J M^-1 J^T over work.list (n x n, top-left of work.A). Entry (a, c) sums J_k . W_l over the
// bodies the two rows share; pairs with no common body are never visited. The list of contributing
// (a, c, side) terms depends only on which rows are in the solve, so it is built when that list
// changes (a contact mode switch) and replayed as a flat loop otherwise: the block sparsity of the
// constraint graph without a branch per entry. Writes the lower triangle and mirrors it.
template <class S> void assembleA(const Model<S>& m, Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  if (w.pairList != w.list) {  // rebuild the terms (mode switches only)
    w.pairList = w.list;
    w.pairs.clear();
    for (int a = 0; a < n; ++a) {
      const RowInfo& rk = m.rowInfo[w.list[a]];
      for (int c = a; c < n; ++c) {
        const RowInfo& rl = m.rowInfo[w.list[c]];
        const int k = w.list[a], l = w.list[c];
        if (rk.bi >= 0 && rk.bi == rl.bi) w.pairs.push_back({c, a, k, l, 0, 0});
        if (rk.bi >= 0 && rk.bi == rl.bj) w.pairs.push_back({c, a, k, l, 0, 1});
        if (rk.bj >= 0 && rk.bj == rl.bi) w.pairs.push_back({c, a, k, l, 1, 0});
        if (rk.bj >= 0 && rk.bj == rl.bj) w.pairs.push_back({c, a, k, l, 1, 1});
      }
    }
  }
  for (int c = 0; c < n; ++c)
    for (int a = c; a < n; ++a) w.A(a, c) = S(0);
  for (const PairTerm& t : w.pairs) {
    const Vec6<S>& J = t.sideK ? w.rows[t.k].Jj : w.rows[t.k].Ji;
    const Vec6<S>& W = t.sideL ? w.Wj[t.l] : w.Wi[t.l];
    w.A(t.row, t.col) += J.dot(W);
  }
  for (int c = 0; c < n; ++c)
    for (int a = c + 1; a < n; ++a) w.A(c, a) = w.A(a, c);
}

// In-place Cholesky factor L L^T of the n x n top-left block of M (lower triangle; column-oriented,
// the inner loops contiguous), then x = M^-1 x by the two triangular solves. No allocation. Returns
// false if the block is not positive definite (redundant or inconsistent rows).
template <class S> bool ldltFactor(MatX<S>& M, int n) {
  for (int j = 0; j < n; ++j) {
    S* colj = &M(0, j);
    for (int k = 0; k < j; ++k) {
      const S* colk = &M(0, k);
      const S ljk = colk[j];
      for (int i = j; i < n; ++i) colj[i] -= colk[i] * ljk;
    }
    if (!(value(colj[j]) > 0)) return false;
    const S d = sqrt(colj[j]);
    colj[j] = d;
    const S inv = S(1) / d;
    for (int i = j + 1; i < n; ++i) colj[i] *= inv;
  }
  return true;
}
template <class S> void ldltSolve(const MatX<S>& M, int n, VecX<S>& x) {
  for (int j = 0; j < n; ++j) {  // L y = x (column sweep)
    const S* col = &M(0, j);
    x[j] /= col[j];
    const S xj = x[j];
    for (int i = j + 1; i < n; ++i) x[i] -= col[i] * xj;
  }
  for (int j = n - 1; j >= 0; --j) {  // L^T z = y (dot with column j)
    const S* col = &M(0, j);
    S s = x[j];
    for (int i = j + 1; i < n; ++i) s -= col[i] * x[i];
    x[j] = s / col[j];
  }
}

// Solves A lam = b over work.list with every row as an equality. A is assembled by the caller;
// the direct method overwrites A with its factor.
template <class S> bool solveEquality(const Model<S>& m, Workspace<S>& w, bool projectUnilateral) {
  const int n = static_cast<int>(w.list.size());
  w.report = SolveReport{};
  if (n == 0) return true;
  if (m.settings.solver == MultiplierSolver::Direct && !projectUnilateral) {
    for (int a = 0; a < n; ++a) w.lam[a] = w.b[a];
    if (!ldltFactor(w.A, n)) {
      w.report.ok = false;
      return false;
    }
    ldltSolve(w.A, n, w.lam);
    return true;
  }
  // Gauss-Seidel, warm-started from w.lam (set by the caller).
  double scale = 0;
  for (int a = 0; a < n; ++a) scale = std::max(scale, std::abs(value(w.b[a])));
  scale = std::max(scale, 1e-300);
  const int maxIt = m.settings.gaussSeidelIterations;
  const double tol = m.settings.gaussSeidelTolerance * scale;
  for (int it = 1; it <= maxIt; ++it) {
    double worst = 0;
    for (int a = 0; a < n; ++a) {
      S r = w.b[a];
      for (int c = 0; c < n; ++c) r -= w.A(a, c) * w.lam[c];
      S next = w.lam[a] + r / w.A(a, a);
      if (projectUnilateral && m.rowInfo[w.list[a]].unilateral && value(next) < 0) next = S(0);
      worst = std::max(worst, std::abs(value(next - w.lam[a]) * value(w.A(a, a))));
      w.lam[a] = next;
    }
    w.report.iterations = it;
    w.report.residual = worst;
    if (worst <= tol) return true;
  }
  // Did not reach the tolerance: keep the iterate (the article's method has a fixed budget) and say so.
  w.report.ok = w.report.residual <= 1e3 * tol;
  return w.report.ok;
}

// Mixed LCP over work.list: bilateral rows A lam = b exactly; unilateral rows lam >= 0,
// (A lam - b) >= 0, complementary. A and b are assembled by the caller. On return w.lam holds the
// multipliers and w.list is unchanged. Used at mode switches: which stops stay in contact (b at the
// acceleration level) and plastic impacts (b at the velocity level).
template <class S> bool solveLcp(const Model<S>& m, Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  if (n == 0) return true;
  if (m.settings.solver == MultiplierSolver::GaussSeidel) {
    for (int a = 0; a < n; ++a) w.lam[a] = S(0);
    return solveEquality(m, w, /*projectUnilateral=*/true);
  }
  // Active set with pivoting: start with every row in; drop the most negative unilateral multiplier,
  // add back the most violated dropped row, until both conditions hold.
  MatX<S> A0 = w.A.topLeftCorner(n, n);  // (mode switches only: not in the step's hot path)
  VecX<S> b0 = w.b.head(n);
  std::vector<char> in(n, 1);
  VecX<S> lam = VecX<S>::Zero(n);
  for (int iter = 0; iter < 4 * n + 8; ++iter) {
    std::vector<int> idx;
    for (int a = 0; a < n; ++a)
      if (in[a]) idx.push_back(a);
    const int na = static_cast<int>(idx.size());
    MatX<S> As(na, na);
    VecX<S> x(na);
    for (int a = 0; a < na; ++a) {
      x[a] = b0[idx[a]];
      for (int c = 0; c < na; ++c) As(a, c) = A0(idx[a], idx[c]);
    }
    if (na > 0 && !ldltFactor(As, na)) return false;
    if (na > 0) ldltSolve(As, na, x);
    lam.setZero();
    for (int a = 0; a < na; ++a) lam[idx[a]] = x[a];
    int worst = -1;
    double worstVal = 0;
    for (int a = 0; a < n; ++a)
      if (in[a] && m.rowInfo[w.list[a]].unilateral && value(lam[a]) < worstVal) {
        worst = a;
        worstVal = value(lam[a]);
      }
    if (worst >= 0) {
      in[worst] = 0;
      continue;
    }
    const VecX<S> gap = A0 * lam - b0;  // >= 0 required for the rows left out
    double tol = 1e-12 * (b0.cwiseAbs().maxCoeff() == S(0) ? 1.0 : value(b0.cwiseAbs().maxCoeff()));
    for (int a = 0; a < n; ++a)
      if (!in[a] && value(gap[a]) < -tol && value(gap[a]) < worstVal) {
        worst = a;
        worstVal = value(gap[a]);
      }
    if (worst >= 0) {
      in[worst] = 1;
      continue;
    }
    for (int a = 0; a < n; ++a) w.lam[a] = lam[a];
    w.report = SolveReport{};
    return true;
  }
  return false;
}

}  // namespace lg
