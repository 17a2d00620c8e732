// Bootstrap resamples and percentile intervals (bootstrap.hpp).
#include "uq/bootstrap.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "uq/random.hpp"

namespace lg::uq {

std::vector<std::vector<std::size_t>> bootstrapSamples(std::size_t n, const BootstrapOptions& o) {
  std::vector<std::vector<std::size_t>> out(static_cast<std::size_t>(std::max(0, o.resamples)));
  if (n == 0) return out;
  Rng rng(o.seed);
  for (auto& s : out) {
    s.resize(n);
    for (auto& i : s) i = rng.below(n);
  }
  return out;
}

Interval percentileInterval(std::vector<double> r, double confidence) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (r.empty()) return {nan, nan};
  std::sort(r.begin(), r.end());
  auto quantile = [&](double p) {
    const double pos = p * static_cast<double>(r.size() - 1);
    const std::size_t k = static_cast<std::size_t>(std::floor(pos));
    if (k + 1 >= r.size()) return r.back();
    const double w = pos - static_cast<double>(k);
    return r[k] == r[k + 1] ? r[k] : r[k] + w * (r[k + 1] - r[k]);
  };
  const double a = 0.5 * (1 - confidence);
  return {quantile(a), quantile(1 - a)};
}

}  // namespace lg::uq
