// A uniformly sampled table y(x), interpolated C1 with ceres::CubicInterpolator (Catmull-Rom).
// A linear table would give jumping gradients; this one gives continuous ones. Outside the sampled
// range the interpolant continues with the end value (the parser checks that a table covers the
// range its element can reach).
#pragma once

#include <ceres/cubic_interpolation.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "sim/core/math.hpp"

namespace lg {

class Table1D {
 public:
  Table1D(std::vector<double> x, std::vector<double> y, std::string source)
      : x_(std::move(x)), y_(std::move(y)), source_(std::move(source)),
        grid_(y_.data(), 0, static_cast<int>(y_.size())), interp_(grid_) {
    x0_ = x_.front();
    dx_ = (x_.back() - x_.front()) / double(x_.size() - 1);
  }
  template <class S> S operator()(const S& x) const {
    S f;
    interp_.Evaluate((x - S(x0_)) / S(dx_), &f);
    return f;
  }
  double x0() const { return x0_; }  // [x] first sample
  double dx() const { return dx_; }  // [x] sample spacing
  double xMin() const { return x_.front(); }
  double xMax() const { return x_.back(); }
  const std::string& source() const { return source_; }
  const std::vector<double>& xs() const { return x_; }
  const std::vector<double>& ys() const { return y_; }

 private:
  std::vector<double> x_, y_;
  std::string source_;
  double x0_ = 0, dx_ = 1;
  ceres::Grid1D<double> grid_;
  ceres::CubicInterpolator<ceres::Grid1D<double>> interp_;
};

// The same C1 interpolant (Catmull-Rom, ends replicated) on the grid of 'grid' with the samples 'y' in
// any scalar, so that the samples themselves can carry derivatives (design parameters of a table).
// For doubles it performs ceres::CubicInterpolator's operations in its order: the same bits.
template <class S> S interpolate(const Table1D& grid, const std::vector<S>& y, const S& x) {
  const S u = (x - S(grid.x0())) / S(grid.dx());
  const int n = static_cast<int>(std::floor(value(u)));
  const int last = static_cast<int>(y.size()) - 1;
  auto at = [&](int i) -> const S& { return y[static_cast<size_t>(std::min(std::max(i, 0), last))]; };
  const S &p0 = at(n - 1), &p1 = at(n), &p2 = at(n + 1), &p3 = at(n + 2);
  const S a = S(0.5) * (-p0 + S(3.0) * p1 - S(3.0) * p2 + p3);
  const S b = S(0.5) * (S(2.0) * p0 - S(5.0) * p1 + S(4.0) * p2 - p3);
  const S c = S(0.5) * (-p0 + p2);
  const S t = u - S(static_cast<double>(n));
  return p1 + t * (c + t * (b + t * a));
}

}  // namespace lg
