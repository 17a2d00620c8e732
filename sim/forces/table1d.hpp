// A uniformly sampled table y(x), interpolated C1 with ceres::CubicInterpolator (Catmull-Rom).
// A linear table would give jumping gradients; this one gives continuous ones. Outside the sampled
// range the interpolant continues with the end value (the parser checks that a table covers the
// range its element can reach).
#pragma once

#include <ceres/cubic_interpolation.h>

#include <memory>
#include <string>
#include <vector>

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

}  // namespace lg
