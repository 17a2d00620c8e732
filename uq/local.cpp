// Central-difference elasticities (local.hpp).
#include "uq/local.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace lg::uq {

std::vector<double> localDesign(const std::vector<double>& x0, double h) {
  const std::size_t d = x0.size();
  std::vector<double> p;
  p.reserve((2 * d + 1) * d);
  p.insert(p.end(), x0.begin(), x0.end());
  for (std::size_t i = 0; i < d; ++i)
    for (double s : {1.0, -1.0}) {
      std::vector<double> x = x0;
      x[i] = x0[i] * (1 + s * h);
      p.insert(p.end(), x.begin(), x.end());
    }
  return p;
}

Elasticities elasticities(const std::vector<double>& x0, double h, const std::vector<double>& y) {
  const std::size_t d = x0.size();
  if (y.size() != 2 * d + 1) throw std::invalid_argument("elasticities: expected 2d+1 outputs");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  Elasticities e;
  e.baseline = y[0];
  for (std::size_t i = 0; i < d; ++i) {
    const double yp = y[1 + 2 * i], ym = y[2 + 2 * i];
    std::string why;
    if (!std::isfinite(y[0])) why = "the baseline run failed";
    else if (!std::isfinite(yp) || !std::isfinite(ym)) why = "a run of the central difference failed";
    else if (x0[i] == 0) why = "the parameter is 0 at the baseline";
    const double dfdx = why.empty() ? (yp - ym) / (2 * h * x0[i]) : nan;
    if (why.empty() && y[0] == 0) why = "the metric is 0 at the baseline";
    e.derivative.push_back(dfdx);
    e.E.push_back(why.empty() ? (yp - ym) / (2 * h * y[0]) : nan);
    e.why.push_back(why);
  }
  return e;
}

}  // namespace lg::uq
