// First-order and total Sobol indices by the Saltelli sampling scheme, for any model: the design (the
// points to run) and the estimators (from the outputs) are separate, so an analytic function and a
// drop-test study go through the same code (tests/uq/sobol_indices_test.cpp: Ishigami, G-function).
//
// Design. A shifted Sobol sequence of dimension 2d (sobol_sequence.hpp): A = its first d columns,
// B = its last d, AB^i = A with column i taken from B. Runs in block order: block j (j = 0 .. N-1) is
// [A_j, B_j, AB_j^1, ..., AB_j^d], N(d+2) runs in all.
//
// Estimators (Saltelli et al. 2010, Table 2 (b) and (f)), with V the variance of the 2n outputs of A
// and B and the outputs centred on their mean (it leaves the expectation unchanged and keeps large
// means from cancelling):
//   S1_i = (1/n) sum_j f(B)_j (f(AB^i)_j - f(A)_j) / V                 (Saltelli 2010)
//   ST_i = (1/2n) sum_j (f(A)_j - f(AB^i)_j)^2 / V                     (Jansen 1999)
// An output that does not depend on x_i has f(AB^i) = f(A) bit for bit, hence S1_i = ST_i = 0
// exactly, and so are all its bootstrap replicates. A constant output (V = 0) gets every index 0 and
// 'constant' set.
//
// Failed runs. A non-finite output (a failed simulation) removes its whole block j from the estimate
// of that output, never a single term: the estimators stay the same functions of complete blocks. The
// blocks dropped are listed; fewer than 2 complete blocks leave the indices NaN ('estimated' false).
//
// Intervals: percentile bootstrap over the complete blocks (bootstrap.hpp), the same resamples of block
// positions for every output.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "uq/bootstrap.hpp"

namespace lg::uq {

struct SaltelliDesign {
  std::size_t n = 0;  // base sample N
  std::size_t d = 0;  // variables
  std::vector<double> points;  // N(d+2) points of dimension d in [0, 1), row-major, block order
  std::size_t runs() const { return n * (d + 2); }
  const double* point(std::size_t run) const { return points.data() + run * d; }
};

// The points of the scheme on a shifted Sobol sequence of dimension 2d with 'seed'.
SaltelliDesign saltelliDesign(std::size_t n, std::size_t d, std::uint64_t seed);

// What a run of block j is: 0 = A, 1 = B, 2 + i = AB^i.
inline std::size_t saltelliBlock(std::size_t run, std::size_t d) { return run / (d + 2); }
inline std::size_t saltelliMatrix(std::size_t run, std::size_t d) { return run % (d + 2); }

struct SobolIndices {
  std::size_t blocks = 0;          // blocks offered (the prefix used)
  std::vector<std::size_t> dropped;  // blocks with a non-finite output (removed whole)
  bool estimated = false;          // at least 2 complete blocks
  bool constant = false;           // V = 0: no variance to apportion
  double mean = 0, variance = 0;   // of the outputs of A and B [output unit, its square]
  std::vector<double> S1, ST;      // per variable
  std::vector<Interval> S1ci, STci;  // bootstrap intervals (empty when resamples = 0)
};

// Indices of one output from its N(d+2) values in run order, using the first 'prefix' blocks
// (0: all N); intervals when o.resamples > 0.
SobolIndices sobolIndices(const std::vector<double>& y, std::size_t n, std::size_t d, const BootstrapOptions& o,
                          std::size_t prefix = 0);

}  // namespace lg::uq
