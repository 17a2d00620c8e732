// Multiplier solvers. They see rows only: the list of rows in the solve, their J blocks, and
// W = M^-1 J^T. Two methods, chosen per run (Settings::solver):
//   direct        J M^-1 J^T lambda = rhs assembled over the row list, exploiting the block sparsity
//                 (an entry is non-zero only where two rows share a body), solved by an in-place
//                 supernodal Cholesky over the envelope of its minimum-degree order; unilateral rows
//                 by an active set (pivoting on the most violated row).
//   Gauss-Seidel  the article's iteration, lambda_k += (rhs_k - A_k lambda)/A_kk, projected onto
//                 lambda_k >= 0 for unilateral rows in a contact solve, warm-started.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <utility>
#ifdef __SSE2__
#include <emmintrin.h>
#endif

#include "sim/model/state.hpp"

namespace lg {

// W_k = M^-1 J_k^T for every row in work.list (M^-1 restricted for a guided, immobile or planar body, see
// BodyKin::invMassTimes; a free body's inline).
template <class S> void computeW(const Model<S>& m, Workspace<S>& w) {
  auto side = [&](int b, const Vec6<S>& J, Vec6<S>& W) {
    const BodyKin<S>& K = w.kin[b];
    if (K.mobility == kFree) {
      W.template head<3>() = K.invMass * J.template head<3>();
      W.template tail<3>() = K.IwInv * J.template tail<3>();
    } else {
      W = K.invMassTimes(J.template head<3>(), J.template tail<3>());
    }
  };
  for (int k : w.list) {
    const RowInfo& ri = m.rowInfo[k];
    const Row<S>& row = w.rows[k];
    if (ri.bi >= 0) side(ri.bi, row.Ji, w.Wi[k]);
    if (ri.bj >= 0) side(ri.bj, row.Jj, w.Wj[k]);
  }
}

// The elimination order and the symbolic factor of A = J M^-1 J^T for the rows in work.list. Two rows
// couple where they share a body; the direct solver eliminates by minimum degree (ties: the lower list
// index), so that the factor follows the constraint graph. Gauss-Seidel keeps the list order (it sweeps
// A as it is). below[belowStart[t] .. belowStart[t+1]) lists, ascending, the positions t' > t where
// L(t', t) may be non-zero: the uneliminated neighbours of the pivot at its elimination.
// The direct factor is stored by rows over their envelope: row t holds L(t, envFirst[t] .. t), packed
// from L[envStart[t]], envFirst[t] being its first structurally non-zero column. On the seed gear the
// minimum-degree order gives 236 stored entries for 221 non-zeros, and the factor runs as contiguous
// dot products (no index per multiply-add).
template <class S> void analyseA(const Model<S>& m, Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  char* adj = w.adjacency.data();  // adj[a n + c]: rows a and c couple (shared body, or fill)
  for (int a = 0; a < n; ++a) {
    const RowInfo& ra = m.rowInfo[w.list[a]];
    for (int c = 0; c < n; ++c) {
      const RowInfo& rc = m.rowInfo[w.list[c]];
      adj[a * n + c] = a != c && ((ra.bi >= 0 && (ra.bi == rc.bi || ra.bi == rc.bj)) ||
                                  (ra.bj >= 0 && (ra.bj == rc.bi || ra.bj == rc.bj)));
    }
  }
  // Minimum degree with the degrees kept current: an elimination lowers its neighbours' by one, and
  // each fill entry raises its row's.
  std::vector<char>& done = w.eliminated;
  std::vector<int>& degree = w.degree;
  for (int a = 0; a < n; ++a) {
    done[a] = 0;
    degree[a] = 0;
    for (int c = 0; c < n; ++c) degree[a] += adj[a * n + c];
  }
  w.order.clear();
  w.below.clear();  // first the cliques in list indices: below[belowStart[t] ..) for the pivot of step t
  w.belowStart.assign(1, 0);
  const bool minDegree = m.settings.solver == MultiplierSolver::Direct;
  for (int t = 0; t < n; ++t) {
    int best = -1;
    for (int a = 0; a < n && (minDegree || best < 0); ++a)
      if (!done[a] && (best < 0 || degree[a] < degree[best])) best = a;
    done[best] = 1;
    w.order.push_back(best);
    const size_t first = w.below.size();
    for (int c = 0; c < n; ++c)
      if (!done[c] && adj[best * n + c]) {
        w.below.push_back(c);
        --degree[c];
      }
    for (size_t qa = first; qa < w.below.size(); ++qa)
      for (size_t qc = first; qc < w.below.size(); ++qc) {
        const int a = w.below[qa], c = w.below[qc];
        if (a != c && !adj[a * n + c]) {
          adj[a * n + c] = 1;
          ++degree[a];
        }
      }
    w.belowStart.push_back(static_cast<int>(w.below.size()));
  }
  w.pos.assign(n, 0);
  for (int t = 0; t < n; ++t) w.pos[w.order[t]] = t;
  w.envFirst.assign(n, 0);
  for (int t = 0; t < n; ++t) w.envFirst[t] = t;
  for (int t = 0; t < n; ++t) {  // the cliques in positions, ascending: the structure below each pivot
    const int first = w.belowStart[t], last = w.belowStart[t + 1];
    for (int q = first; q < last; ++q) w.below[q] = w.pos[w.below[q]];
    std::sort(w.below.begin() + first, w.below.begin() + last);
    for (int q = first; q < last; ++q) w.envFirst[w.below[q]] = std::min(w.envFirst[w.below[q]], t);
  }
  w.envStart.assign(n + 1, 0);
  for (int t = 0; t < n; ++t) w.envStart[t + 1] = w.envStart[t] + (t - w.envFirst[t] + 1);
  // Supernodes: column t + 1 joins t's run when t's structure below is exactly {t + 1} and t + 1's.
  auto at = [&](int r, int c) { return w.envStart[r] + (c - w.envFirst[r]); };  // flat index of L(r, c)
  w.superStart.assign(1, 0);
  for (int t = 0; t + 1 < n; ++t) {
    const int b0 = w.belowStart[t], b1 = w.belowStart[t + 1], b2 = w.belowStart[t + 2];
    const bool same = b1 > b0 && w.below[b0] == t + 1 && (b1 - b0 - 1) == (b2 - b1) &&
                      std::equal(w.below.begin() + b0 + 1, w.below.begin() + b1, w.below.begin() + b1);
    if (!same) w.superStart.push_back(t + 1);
  }
  if (n > 0) w.superStart.push_back(n);
  const int nSuper = static_cast<int>(w.superStart.size()) - 1;
  w.rowAt.assign(n, 0);
  w.superRows.clear();
  w.superRowAt.clear();
  w.superRowStart.assign(1, 0);
  w.updates.clear();
  w.updateStart.assign(1, 0);
  for (int K = 0; K < nSuper; ++K) {
    const int c0 = w.superStart[K], c1 = w.superStart[K + 1];
    for (int i = c0; i < c1; ++i) w.rowAt[i] = at(i, c0);
    const int t = c1 - 1;  // the structure below the run is that of its last column
    for (int q = w.belowStart[t]; q < w.belowStart[t + 1]; ++q) {
      w.superRows.push_back(w.below[q]);
      w.superRowAt.push_back(at(w.below[q], c0));
    }
    w.superRowStart.push_back(static_cast<int>(w.superRows.size()));
    for (int q1 = w.belowStart[t]; q1 < w.belowStart[t + 1]; ++q1)
      for (int q2 = w.belowStart[t]; q2 <= q1; ++q2) {
        const int r1 = w.below[q1], r2 = w.below[q2];
        w.updates.push_back({at(r1, r2), at(r1, c0), at(r2, c0)});
      }
    w.updateStart.push_back(static_cast<int>(w.updates.size()));
  }
}

// Multiply-adds of one factorisation over the current structure (factorA's dot products).
template <class S> long factorMultiplyAdds(const Workspace<S>& w) {
  long madds = 0;
  const int nSuper = static_cast<int>(w.superStart.size()) - 1;
  for (int K = 0; K < nSuper; ++K) {
    const long width = w.superStart[K + 1] - w.superStart[K];
    const long below = w.superRowStart[K + 1] - w.superRowStart[K];
    madds += width * (width - 1) * (width + 1) / 6 + below * width * (width - 1) / 2 +
             (w.updateStart[K + 1] - w.updateStart[K]) * width;
  }
  return madds;
}

// Where entry (row, col), row >= col in elimination order, of A sits in the packed envelope.
template <class S> int flatIndexA(const Workspace<S>& w, int row, int col) {
  return w.envStart[row] + (col - w.envFirst[row]);
}

// Entry (a, c) of the assembled (not yet factored) A, in list indices.
template <class S> S entryA(const Workspace<S>& w, int a, int c) {
  const int pa = std::max(w.pos[a], w.pos[c]), pc = std::min(w.pos[a], w.pos[c]);
  return pc < w.envFirst[pa] ? S(0) : w.L[flatIndexA(w, pa, pc)];
}

// Dot products in a fixed order, the same bits on every machine and for every scalar: two partial
// sums, one over the even and one over the odd indices, added at the end. For double on x86-64 the two
// sums are the two lanes of an SSE2 register (part of the x86-64 baseline), so the vector code computes
// exactly what the scalar code would.
template <class S> inline S dotN(const S* a, const S* b, int len) {
  S s0(0), s1(0);
  int k = 0;
  for (; k + 1 < len; k += 2) {
    s0 += a[k] * b[k];
    s1 += a[k + 1] * b[k + 1];
  }
  if (k < len) s0 += a[k] * b[k];
  return s0 + s1;
}
template <class S> inline S dot6(const S* a, const S* b) { return dotN(a, b, 6); }
// The same sums for a length known at compile time, unrolled (the short products of a sparse factor and
// its solves: most are shorter than 8).
template <int L, class S> inline S dotFixed(const S* a, const S* b) {
  S s0(0), s1(0);
  for (int k = 0; k + 1 < L; k += 2) {
    s0 += a[k] * b[k];
    s1 += a[k + 1] * b[k + 1];
  }
  if constexpr (L % 2 == 1) s0 += a[L - 1] * b[L - 1];
  return s0 + s1;
}
#ifdef __SSE2__
__attribute__((always_inline)) inline double dotN(const double* a, const double* b, int len) {
  switch (len) {  // the short products without the vector set-up
    case 0: return 0.0;
    case 1: return dotFixed<1>(a, b);
    case 2: return dotFixed<2>(a, b);
    case 3: return dotFixed<3>(a, b);
    case 4: return dotFixed<4>(a, b);
    case 5: return dotFixed<5>(a, b);
    case 6: return dotFixed<6>(a, b);
    case 7: return dotFixed<7>(a, b);
    default: break;
  }
  __m128d acc = _mm_setzero_pd();
  int k = 0;
  for (; k + 1 < len; k += 2) acc = _mm_add_pd(acc, _mm_mul_pd(_mm_loadu_pd(a + k), _mm_loadu_pd(b + k)));
  double s[2];
  _mm_storeu_pd(s, acc);
  if (k < len) s[0] += a[k] * b[k];
  return s[0] + s[1];
}
inline double dot6(const double* a, const double* b) {
  __m128d acc = _mm_mul_pd(_mm_loadu_pd(a), _mm_loadu_pd(b));
  acc = _mm_add_pd(acc, _mm_mul_pd(_mm_loadu_pd(a + 2), _mm_loadu_pd(b + 2)));
  acc = _mm_add_pd(acc, _mm_mul_pd(_mm_loadu_pd(a + 4), _mm_loadu_pd(b + 4)));
  double s[2];
  _mm_storeu_pd(s, acc);
  return s[0] + s[1];
}
#endif

// Runs f(std::integral_constant<int, W>) for the width W = 'width' when 1 <= width <= kMaxFixedWidth (code
// compiled for that width: its loops unrolled, no dispatch per dot product), else f with W = 0 (the
// loops of run-time length).
constexpr int kMaxFixedWidth = 16;
template <class F> inline void withWidth(int width, F&& f) {
  [&]<int... W>(std::integer_sequence<int, W...>) {
    const bool fixed = ((width == W + 1 ? (f(std::integral_constant<int, W + 1>{}), true) : false) || ...);
    if (!fixed) f(std::integral_constant<int, 0>{});
  }(std::make_integer_sequence<int, kMaxFixedWidth>{});
}

// One row r of a triangular solve of fixed width W against the rows of L at rowAt[0..W):
// r[j] = (r[j] - r[0..j) . L(rowAt[j])[0..j)) invDiag[j], j = 0..W-1 in turn (the same sums as dotN).
template <int W, class S> inline void triangularRow(S* r, const S* L, const int* rowAt, const S* invDiag) {
  [&]<int... J>(std::integer_sequence<int, J...>) {
    ((r[J] = (r[J] - dotFixed<J>(r, L + rowAt[J])) * invDiag[J]), ...);
  }(std::make_integer_sequence<int, W>{});
}

// The distance in bytes from an array's start to an element of it (the terms of A address the rows and
// W by offsets, so a copied workspace's terms stay valid).
template <class T, class U> int byteOffset(const T* base, const U* at) {
  return static_cast<int>(reinterpret_cast<const char*>(at) - reinterpret_cast<const char*>(base));
}

// The factor's structure for work.list, saved in / restored from the workspace's small cache.
template <class S> void saveStructure(Workspace<S>& w) {
  FactorStructure& c = w.structureCache[w.structureNext];
  w.structureNext = (w.structureNext + 1) % static_cast<int>(w.structureCache.size());
  c.list = w.list;
  c.order = w.order;
  c.pos = w.pos;
  c.below = w.below;
  c.belowStart = w.belowStart;
  c.envFirst = w.envFirst;
  c.envStart = w.envStart;
  c.superStart = w.superStart;
  c.rowAt = w.rowAt;
  c.superRows = w.superRows;
  c.superRowAt = w.superRowAt;
  c.superRowStart = w.superRowStart;
  c.updates = w.updates;
  c.updateStart = w.updateStart;
  c.pairs = w.pairs;
  c.pairGroup = w.pairGroup;
}
template <class S> bool restoreStructure(Workspace<S>& w) {
  for (const FactorStructure& c : w.structureCache) {
    if (c.list.empty() || c.list != w.list) continue;
    w.pairList = w.list;
    w.order = c.order;
    w.pos = c.pos;
    w.below = c.below;
    w.belowStart = c.belowStart;
    w.envFirst = c.envFirst;
    w.envStart = c.envStart;
    w.superStart = c.superStart;
    w.rowAt = c.rowAt;
    w.superRows = c.superRows;
    w.superRowAt = c.superRowAt;
    w.superRowStart = c.superRowStart;
    w.updates = c.updates;
    w.updateStart = c.updateStart;
    w.pairs = c.pairs;
    w.pairGroup = c.pairGroup;
    return true;
  }
  return false;
}

// A = J M^-1 J^T over work.list, lower triangle in elimination order (entry (a, c) of the list at
// position (pos[a], pos[c])), in the packed envelope (flatIndexA). It sums J_k . W_l over the
// bodies the two rows share; pairs with no common body are never visited. The terms depend only on
// which rows are in the solve, so they are built when that list changes (a contact mode switch),
// grouped by which body block of each row they use, each with its target precomputed, and replayed as
// four flat loops otherwise. Gauss-Seidel (list order) also gets the dense matrix work.A.
template <class S> void assembleA(const Model<S>& m, Workspace<S>& w) {
  const int n = static_cast<int>(w.list.size());
  const bool direct = m.settings.solver == MultiplierSolver::Direct;
  if (w.pairList != w.list && !restoreStructure(w)) {  // rebuild the terms and the structure (mode switches only)
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
          const Row<S>& row = w.rows[w.list[a]];
          const Vec6<S>* Wside = sideL ? w.Wj.data() : w.Wi.data();
          w.pairs.push_back({flatIndexA(w, std::max(pa, pc), std::min(pa, pc)),
                             byteOffset(w.rows.data(), (sideK ? row.Jj : row.Ji).data()),
                             byteOffset(Wside, Wside[w.list[c]].data())});
        }
      }
    }
    w.pairGroup[4] = static_cast<int>(w.pairs.size());
    saveStructure(w);
  }
  S* A = w.L.data();
  for (int e = 0; e < w.envStart[n]; ++e) A[e] = S(0);
  const PairTerm* P = w.pairs.data();
  auto terms = [&](int g, const Vec6<S>* Wside) {  // the group's J blocks . W blocks, by their byte offsets
    const char* J = reinterpret_cast<const char*>(w.rows.data());
    const char* Wb = reinterpret_cast<const char*>(Wside);
    for (int p = w.pairGroup[g]; p < w.pairGroup[g + 1]; ++p)
      A[P[p].target] += dot6(reinterpret_cast<const S*>(J + P[p].j), reinterpret_cast<const S*>(Wb + P[p].w));
  };
  terms(0, w.Wi.data());
  terms(1, w.Wj.data());
  terms(2, w.Wi.data());
  terms(3, w.Wj.data());
  if (!direct)  // Gauss-Seidel sweeps the dense matrix (list order = elimination order there)
    for (int c = 0; c < n; ++c)
      for (int a = c; a < n; ++a) w.A(a, c) = w.A(c, a) = entryA(w, a, c);
}

// Cholesky L L^T of the assembled A, in place over its envelope, by supernodes (analyseA): for each
// run K of columns [c0, c1) that share their structure below, (1) the dense diagonal block, (2) the
// rows R_K below it (each a short triangular solve of width c1 - c0), (3) the update of every entry
// (r1, r2) of R_K x R_K by one dot product of width c1 - c0. The dot products of (3) are independent of
// each other (no chain through the row, unlike a row-by-row factor), and every operand is a contiguous
// piece of an envelope row. No allocation. Returns false if A is not positive definite (redundant or
// inconsistent rows).
template <class S> bool factorA(Workspace<S>& w) {
  S* L = w.L.data();
  const int nSuper = static_cast<int>(w.superStart.size()) - 1;
  for (int K = 0; K < nSuper; ++K) {
    const int c0 = w.superStart[K], c1 = w.superStart[K + 1], width = c1 - c0;
    const int* rowAt = w.rowAt.data() + c0;
    const S* invDiag = w.invDiag.data() + c0;
    for (int i = c0; i < c1; ++i) {  // (1) the diagonal block
      S* Li = L + w.rowAt[i];        // Li[k] = L(i, c0 + k)
      withWidth(i - c0, [&](auto fixed) {
        if constexpr (fixed > 0) triangularRow<fixed>(Li, L, rowAt, invDiag);
        else for (int j = c0; j < i; ++j) Li[j - c0] = (Li[j - c0] - dotN(Li, L + w.rowAt[j], j - c0)) * w.invDiag[j];
      });
      const S d = Li[i - c0] - dotN(Li, Li, i - c0);
      if (!(value(d) > 0)) return false;
      Li[i - c0] = sqrt(d);
      w.invDiag[i] = S(1) / Li[i - c0];
    }
    withWidth(width, [&](auto fixed) {
      for (int q = w.superRowStart[K]; q < w.superRowStart[K + 1]; ++q) {  // (2) the rows below
        S* Lr = L + w.superRowAt[q];
        if constexpr (fixed > 0) triangularRow<fixed>(Lr, L, rowAt, invDiag);
        else for (int j = c0; j < c1; ++j) Lr[j - c0] = (Lr[j - c0] - dotN(Lr, L + w.rowAt[j], j - c0)) * w.invDiag[j];
      }
      for (int u = w.updateStart[K]; u < w.updateStart[K + 1]; ++u) {  // (3) the update below
        const FactorUpdate& up = w.updates[u];
        if constexpr (fixed > 0) L[up.dst] -= dotFixed<fixed>(L + up.a, L + up.b);
        else L[up.dst] -= dotN(L + up.a, L + up.b, width);
      }
    });
  }
  return true;
}

// x <- A^-1 x with the factor of factorA; x in list order. By supernodes like the factor: forward, the
// diagonal block then one dot product per row below; backward, one update of the block per row below,
// then the block.
template <class S> void solveA(Workspace<S>& w, VecX<S>& x) {
  const int n = static_cast<int>(w.list.size());
  S* y = w.permTmp.data();
  const S* L = w.L.data();
  for (int t = 0; t < n; ++t) y[t] = x[w.order[t]];
  const int nSuper = static_cast<int>(w.superStart.size()) - 1;
  for (int K = 0; K < nSuper; ++K) {  // L z = y
    const int c0 = w.superStart[K], c1 = w.superStart[K + 1];
    withWidth(c1 - c0, [&](auto fixed) {
      if constexpr (fixed > 0) {
        const int* rowAt = w.rowAt.data() + c0;
        const S* invDiag = w.invDiag.data() + c0;
        [&]<int... I>(std::integer_sequence<int, I...>) {
          ((y[c0 + I] = (y[c0 + I] - dotFixed<I>(L + rowAt[I], y + c0)) * invDiag[I]), ...);
        }(std::make_integer_sequence<int, fixed>{});
      } else {
        for (int i = c0; i < c1; ++i) y[i] = (y[i] - dotN(L + w.rowAt[i], y + c0, i - c0)) * w.invDiag[i];
      }
      for (int q = w.superRowStart[K]; q < w.superRowStart[K + 1]; ++q) {
        if constexpr (fixed > 0) y[w.superRows[q]] -= dotFixed<fixed>(L + w.superRowAt[q], y + c0);
        else y[w.superRows[q]] -= dotN(L + w.superRowAt[q], y + c0, c1 - c0);
      }
    });
  }
  for (int K = nSuper - 1; K >= 0; --K) {  // L^T u = z
    const int c0 = w.superStart[K], c1 = w.superStart[K + 1];
    withWidth(c1 - c0, [&](auto fixed) {
      constexpr int W = fixed;
      const int width = W > 0 ? W : c1 - c0;
      for (int q = w.superRowStart[K]; q < w.superRowStart[K + 1]; ++q) {
        const S* Lr = L + w.superRowAt[q];
        const S yr = y[w.superRows[q]];
        for (int j = 0; j < width; ++j) y[c0 + j] -= Lr[j] * yr;
      }
      for (int i = width - 1; i >= 0; --i) {
        const S* Li = L + w.rowAt[c0 + i];
        const S yi = y[c0 + i] * w.invDiag[c0 + i];
        y[c0 + i] = yi;
        for (int k = 0; k < i; ++k) y[c0 + k] -= Li[k] * yi;
      }
    });
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
  // add back the most violated dropped row, until both conditions hold. (In the workspace's buffers: the
  // top-left n x n block of A0, the na x na block of As.)
  MatX<S>& A0 = w.lcpA;
  for (int a = 0; a < n; ++a)
    for (int c = 0; c < n; ++c) A0(a, c) = entryA(w, a, c);
  auto b0 = w.lcpB.head(n);
  b0 = w.b.head(n);
  std::vector<char>& in = w.lcpIn;
  for (int a = 0; a < n; ++a) in[a] = 1;
  auto lam = w.lcpLam.head(n);
  lam.setZero();
  for (int iter = 0; iter < 4 * n + 8; ++iter) {
    std::vector<int>& idx = w.lcpIdx;
    idx.clear();
    for (int a = 0; a < n; ++a)
      if (in[a]) idx.push_back(a);
    const int na = static_cast<int>(idx.size());
    MatX<S>& As = w.lcpAs;
    VecX<S>& x = w.lcpX;
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
    auto gap = w.lcpGap.head(n);  // >= 0 required for the rows left out
    gap.noalias() = A0.topLeftCorner(n, n) * lam;
    gap -= b0;
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
