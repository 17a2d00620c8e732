// Morris screening (elementary effects), for any model: design and estimators apart, as for Sobol.
//
// Design. A grid of p levels {0, 1/(p-1), ..., 1} per variable (p even), step Delta = p / (2(p-1)),
// r trajectories of d+1 points each: a random start on the grid, then one variable at a time in a
// random order moves by +Delta from a level below 1/2 or by -Delta from a level at or above it (the
// only move that stays on the grid for even p), so each level is used equally often (Morris 1991,
// with the random orientation of Campolongo et al. 2007). Runs in trajectory order, r(d+1) in all.
//
// Estimators. EE_i = (f(x + e_i Delta_signed) - f(x)) / Delta_signed in scaled units (per unit of the
// variable's range), one per trajectory and variable; mu = mean EE, mu* = mean |EE|, sigma = standard
// deviation of EE (divisor n-1). An elementary effect with a non-finite end point (a failed run) is
// dropped, the others of its trajectory kept; mu, mu*, sigma use the effects that remain (counted).
// The interval on mu* is a percentile bootstrap over the variable's effects (bootstrap.hpp).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "uq/bootstrap.hpp"

namespace lg::uq {

struct MorrisDesign {
  std::size_t r = 0, d = 0;
  int levels = 4;
  double delta = 0;                  // [-] Delta = p / (2(p-1))
  std::vector<double> points;        // r(d+1) points in [0, 1], row-major, trajectory order
  std::vector<std::size_t> moved;    // per trajectory and step k = 1..d: the variable moved (r*d)
  std::vector<double> step;          // the signed step of that move (+-Delta)
  std::size_t runs() const { return r * (d + 1); }
  const double* point(std::size_t run) const { return points.data() + run * d; }
};

// Throws std::invalid_argument unless levels >= 2 is even, r >= 1, d >= 1.
MorrisDesign morrisDesign(std::size_t r, std::size_t d, int levels, std::uint64_t seed);

struct MorrisIndices {
  std::vector<double> mu, muStar, sigma;  // per variable [output unit per unit of scaled variable]
  std::vector<Interval> muStarCi;         // bootstrap (empty when resamples = 0)
  std::vector<std::size_t> effects;       // effects used per variable (r minus the dropped ones)
};

// Indices of one output from its r(d+1) values in run order.
MorrisIndices morrisIndices(const MorrisDesign& m, const std::vector<double>& y, const BootstrapOptions& o);

}  // namespace lg::uq
