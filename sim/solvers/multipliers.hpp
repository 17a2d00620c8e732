// Multiplier solvers. They see rows only: the list of rows in the solve, their J blocks, and
// W = M^-1 J^T. Two methods, chosen per run (Settings::solver):
//   direct        J M^-1 J^T lambda = rhs assembled over the row list, exploiting the block sparsity
//                 (an entry is non-zero only where two rows share a body), solved by an in-place
//                 sparse Cholesky in minimum-degree order; unilateral rows by an active set
//                 (pivoting on the most violated row).
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

// The elimination order and the symbolic factor of A = J M^-1 J^T for the rows in work.list. Two rows
// couple where they share a body; the direct solver eliminates by minimum degree (ties: the lower list
// index), so that the factor follows the constraint graph: on the seed gear 965 multiply-adds instead
// of the 2925 of a dense 26 x 26 Cholesky. Gauss-Seidel keeps the list order (it sweeps A as it is).
// below[belowStart[t] .. belowStart[t+1]) lists, ascending, the positions t' > t where L(t', t) may be
// non-zero: the uneliminated neighbours of the pivot at its elimination.
template <class S> void analyseA(const Model<S>& m, Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  std::vector<std::vector<char>> adj(n, std::vector<char>(n, 0));  // mode switches only
  for (int a = 0; a < n; ++a) {
    const RowInfo& ra = m.rowInfo[w.list[a]];
    for (int c = 0; c < n; ++c) {
      const RowInfo& rc = m.rowInfo[w.list[c]];
      adj[a][c] = a != c && ((ra.bi >= 0 && (ra.bi == rc.bi || ra.bi == rc.bj)) ||
                             (ra.bj >= 0 && (ra.bj == rc.bi || ra.bj == rc.bj)));
    }
  }
  w.order.clear();
  std::vector<char> done(n, 0);
  const bool minDegree = m.settings.solver == MultiplierSolver::Direct;
  std::vector<std::vector<int>> cliques(n);
  for (int t = 0; t < n; ++t) {
    int best = -1, bestDeg = 0;
    for (int a = 0; a < n && (minDegree || best < 0); ++a) {
      if (done[a]) continue;
      int deg = 0;
      for (int c = 0; c < n; ++c) deg += (!done[c] && adj[a][c]) ? 1 : 0;
      if (best < 0 || deg < bestDeg) {
        best = a;
        bestDeg = deg;
      }
    }
    done[best] = 1;
    w.order.push_back(best);
    for (int c = 0; c < n; ++c)
      if (!done[c] && adj[best][c]) cliques[t].push_back(c);
    for (int a : cliques[t])
      for (int c : cliques[t])
        if (a != c) adj[a][c] = 1;
  }
  w.pos.assign(n, 0);
  for (int t = 0; t < n; ++t) w.pos[w.order[t]] = t;
  w.below.clear();
  w.belowStart.assign(1, 0);
  for (int t = 0; t < n; ++t) {
    const size_t first = w.below.size();
    for (int c : cliques[t]) w.below.push_back(w.pos[c]);
    std::sort(w.below.begin() + static_cast<long>(first), w.below.end());
    w.belowStart.push_back(static_cast<int>(w.below.size()));
  }
}

// A = J M^-1 J^T over work.list (n x n, top-left of work.A), stored in elimination order: entry (a, c)
// of the list at A(pos[a], pos[c]), lower triangle. It sums J_k . W_l over the bodies the two rows
// share; pairs with no common body are never visited. The terms depend only on which rows are in the
// solve, so they are built when that list changes (a contact mode switch), grouped by which body block
// of each row they use, and replayed as four flat loops otherwise. Gauss-Seidel (list order) also gets
// the upper triangle.
template <class S> void assembleA(const Model<S>& m, Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  if (w.pairList != w.list) {  // rebuild the terms and the factor's structure (mode switches only)
    w.pairList = w.list;
    analyseA(m, w);
    w.pairs.clear();
    for (int g = 0; g < 4; ++g) {
      w.pairGroup[g] = static_cast<int>(w.pairs.size());
      const int sideK = g / 2, sideL = g % 2;
      for (int a = 0; a < n; ++a) {
        const RowInfo& rk = m.rowInfo[w.list[a]];
        const int bk = sideK ? rk.bj : rk.bi;
        if (bk < 0) continue;
        for (int c = a; c < n; ++c) {
          const RowInfo& rl = m.rowInfo[w.list[c]];
          if (bk != (sideL ? rl.bj : rl.bi)) continue;
          const int pa = w.pos[a], pc = w.pos[c];
          w.pairs.push_back({std::max(pa, pc), std::min(pa, pc), w.list[a], w.list[c]});
        }
      }
    }
    w.pairGroup[4] = static_cast<int>(w.pairs.size());
  }
  for (int c = 0; c < n; ++c)
    for (int a = c; a < n; ++a) w.A(a, c) = S(0);
  auto accumulate = [&](int g, auto J, auto W) {
    for (int p = w.pairGroup[g]; p < w.pairGroup[g + 1]; ++p) {
      const PairTerm& t = w.pairs[p];
      w.A(t.row, t.col) += J(t.k).dot(W(t.l));
    }
  };
  auto Ji = [&](int k) -> const Vec6<S>& { return w.rows[k].Ji; };
  auto Jj = [&](int k) -> const Vec6<S>& { return w.rows[k].Jj; };
  auto Wi = [&](int l) -> const Vec6<S>& { return w.Wi[l]; };
  auto Wj = [&](int l) -> const Vec6<S>& { return w.Wj[l]; };
  accumulate(0, Ji, Wi);
  accumulate(1, Ji, Wj);
  accumulate(2, Jj, Wi);
  accumulate(3, Jj, Wj);
  if (m.settings.solver == MultiplierSolver::GaussSeidel)
    for (int c = 0; c < n; ++c)
      for (int a = c + 1; a < n; ++a) w.A(c, a) = w.A(a, c);
}

// Entry (a, c) of the assembled (not yet factored) A, in list indices.
template <class S> const S& entryA(const Workspace<S>& w, int a, int c) {
  const int pa = w.pos[a], pc = w.pos[c];
  return pa >= pc ? w.A(pa, pc) : w.A(pc, pa);
}

// Sparse Cholesky L L^T of the assembled A, in place, over the symbolic structure of analyseA
// (right-looking: each pivot column updates only the clique of its neighbours). No allocation.
// Returns false if A is not positive definite (redundant or inconsistent rows).
template <class S> bool factorA(Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  for (int t = 0; t < n; ++t) {
    S* colt = &w.A(0, t);
    if (!(value(colt[t]) > 0)) return false;
    const S d = sqrt(colt[t]);
    colt[t] = d;
    const S inv = S(1) / d;
    const int* nb = w.below.data() + w.belowStart[t];
    const int cnt = w.belowStart[t + 1] - w.belowStart[t];
    for (int q = 0; q < cnt; ++q) colt[nb[q]] *= inv;
    // Rank-1 update of the pivot's clique: column j -= L(., t) L(j, t) over the structure's rows >= j.
    for (int q = 0; q < cnt; ++q) {
      const int j = nb[q];
      const S ljt = colt[j];
      S* colj = &w.A(0, j);
      for (int r = q; r < cnt; ++r) colj[nb[r]] -= colt[nb[r]] * ljt;
    }
  }
  return true;
}

// x <- A^-1 x with the factor of factorA; x in list order.
template <class S> void solveA(Workspace<S>& w, VecX<S>& x) {
  const int n = static_cast<int>(w.list.size());
  VecX<S>& y = w.permTmp;
  for (int t = 0; t < n; ++t) y[t] = x[w.order[t]];
  for (int t = 0; t < n; ++t) {  // L z = y
    const S* col = &w.A(0, t);
    y[t] /= col[t];
    const S yt = y[t];
    for (int q = w.belowStart[t]; q < w.belowStart[t + 1]; ++q) y[w.below[q]] -= col[w.below[q]] * yt;
  }
  for (int t = n - 1; t >= 0; --t) {  // L^T u = z
    const S* col = &w.A(0, t);
    S s = y[t];
    for (int q = w.belowStart[t]; q < w.belowStart[t + 1]; ++q) s -= col[w.below[q]] * y[w.below[q]];
    y[t] = s / col[t];
  }
  for (int t = 0; t < n; ++t) x[w.order[t]] = y[t];
}

// In-place dense Cholesky factor L L^T of the n x n top-left block of M (lower triangle; column-oriented,
// the inner loops contiguous), then x = M^-1 x by the two triangular solves. For the small systems of
// the contact LCP. Returns false if the block is not positive definite.
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
    if (!factorA(w)) {
      w.report.ok = false;
      return false;
    }
    solveA(w, w.lam);
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
  MatX<S> A0(n, n);  // (mode switches only: not in the step's hot path)
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < n; ++c) A0(a, c) = entryA(w, a, c);
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
