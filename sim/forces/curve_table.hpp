// A force curve y(x) sampled on a uniform grid x_0 < x_1 < ... < x_{N-1} (N >= 4), interpolated C1 by
// cubic Hermite segments whose slopes are finite differences exact for cubics: five points inside,
//   m_i = (y_{i-2} - 8 y_{i-1} + 8 y_{i+1} - y_{i+2}) / (12 dx)                  (2 <= i <= N-3)
// and four one-sided points at the two ends and next to them,
//   m_0 = (-11 y_0 + 18 y_1 - 9 y_2 + 2 y_3) / (6 dx),   m_1 = (-2 y_0 - 3 y_1 + 6 y_2 - y_3) / (6 dx),
//   m_{N-2}, m_{N-1}: the same mirrored,
// so that a cubic (the polynomial tyre law of method.md) is reproduced to round-off, the end intervals
// included, and a smooth curve to fourth order in dx. Beyond the ends the curve continues linearly with
// its end slope. Its antiderivative
//   Y(x) = integral from x_0 to x of y
// is exact (each segment's quartic, summed), so an element storing the energy of a force y(x) closes
// its energy balance to round-off. Values, slopes and integrals take a double or a ceres::Jet x: x's
// derivatives flow through (the samples are data, not design parameters).
#pragma once

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "sim/core/math.hpp"

namespace lg {

class CurveTable {
 public:
  CurveTable(std::vector<double> x, std::vector<double> y, std::string source)
      : x_(std::move(x)), y_(std::move(y)), source_(std::move(source)) {
    const size_t N = y_.size();
    dx_ = (x_.back() - x_.front()) / double(N - 1);
    m_.assign(N, 0.0);
    for (size_t i = 2; i + 2 < N; ++i) m_[i] = (y_[i - 2] - 8 * y_[i - 1] + 8 * y_[i + 1] - y_[i + 2]) / (12 * dx_);
    m_[0] = (-11 * y_[0] + 18 * y_[1] - 9 * y_[2] + 2 * y_[3]) / (6 * dx_);
    m_[1] = (-2 * y_[0] - 3 * y_[1] + 6 * y_[2] - y_[3]) / (6 * dx_);
    m_[N - 2] = (2 * y_[N - 1] + 3 * y_[N - 2] - 6 * y_[N - 3] + y_[N - 4]) / (6 * dx_);
    m_[N - 1] = (11 * y_[N - 1] - 18 * y_[N - 2] + 9 * y_[N - 3] - 2 * y_[N - 4]) / (6 * dx_);
    Y_.assign(N, 0.0);
    for (size_t i = 0; i + 1 < N; ++i)  // the segment's integral: dx ((p0 + p1)/2 + (d0 - d1)/12), d = m dx
      Y_[i + 1] = Y_[i] + dx_ * ((y_[i] + y_[i + 1]) / 2 + (m_[i] - m_[i + 1]) * dx_ / 12);
  }

  // y(x), dy/dx and Y(x), with x's derivatives (Jet) carried: f(x) = f(x.a) + f'(x.a) (x - x.a).
  template <class S> S operator()(const S& x) const {
    double f, df, d2f, F;
    eval(value(x), f, df, d2f, F);
    return S(f) + S(df) * (x - S(value(x)));
  }
  template <class S> S slope(const S& x) const {
    double f, df, d2f, F;
    eval(value(x), f, df, d2f, F);
    return S(df) + S(d2f) * (x - S(value(x)));
  }
  template <class S> S integral(const S& x) const {
    double f, df, d2f, F;
    eval(value(x), f, df, d2f, F);
    return S(F) + S(f) * (x - S(value(x)));
  }

  double xMin() const { return x_.front(); }
  double xMax() const { return x_.back(); }
  const std::string& source() const { return source_; }
  const std::vector<double>& xs() const { return x_; }
  const std::vector<double>& ys() const { return y_; }

 private:
  void eval(double x, double& f, double& df, double& d2f, double& F) const {
    const size_t N = y_.size();
    const double u = (x - x_.front()) / dx_;
    if (!(u > 0)) {  // before the first sample (and NaN): linear
      const double e = x - x_.front();
      f = y_[0] + m_[0] * e;
      df = m_[0];
      d2f = 0;
      F = y_[0] * e + m_[0] * e * e / 2;
      return;
    }
    if (u >= double(N - 1)) {  // beyond the last sample: linear
      const double e = x - x_.back();
      f = y_[N - 1] + m_[N - 1] * e;
      df = m_[N - 1];
      d2f = 0;
      F = Y_[N - 1] + y_[N - 1] * e + m_[N - 1] * e * e / 2;
      return;
    }
    const size_t n = std::min(static_cast<size_t>(u), N - 2);
    const double t = u - double(n), t2 = t * t, t3 = t2 * t, t4 = t3 * t;
    const double p0 = y_[n], p1 = y_[n + 1], d0 = m_[n] * dx_, d1 = m_[n + 1] * dx_;
    f = (2 * t3 - 3 * t2 + 1) * p0 + (t3 - 2 * t2 + t) * d0 + (-2 * t3 + 3 * t2) * p1 + (t3 - t2) * d1;
    df = ((6 * t2 - 6 * t) * p0 + (3 * t2 - 4 * t + 1) * d0 + (-6 * t2 + 6 * t) * p1 + (3 * t2 - 2 * t) * d1) / dx_;
    d2f = ((12 * t - 6) * p0 + (6 * t - 4) * d0 + (-12 * t + 6) * p1 + (6 * t - 2) * d1) / (dx_ * dx_);
    F = Y_[n] + dx_ * ((t - t3 + t4 / 2) * p0 + (t2 / 2 - 2 * t3 / 3 + t4 / 4) * d0 + (t3 - t4 / 2) * p1 +
                       (-t3 / 3 + t4 / 4) * d1);
  }

  std::vector<double> x_, y_, m_, Y_;
  std::string source_;
  double dx_ = 1;
};

}  // namespace lg
