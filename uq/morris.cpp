// Morris trajectories and elementary effects (morris.hpp).
#include "uq/morris.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "uq/random.hpp"

namespace lg::uq {

MorrisDesign morrisDesign(std::size_t r, std::size_t d, int levels, std::uint64_t seed) {
  if (levels < 2 || levels % 2 != 0) throw std::invalid_argument("Morris design: levels must be even and >= 2");
  if (r == 0 || d == 0) throw std::invalid_argument("Morris design: needs r >= 1 trajectories and d >= 1 variables");
  MorrisDesign m;
  m.r = r;
  m.d = d;
  m.levels = levels;
  const double p1 = static_cast<double>(levels - 1);
  m.delta = static_cast<double>(levels) / (2.0 * p1);
  const int half = levels / 2;  // moves: level k -> k + half (k < half) or k - half
  m.points.resize(m.runs() * d);
  Rng rng(seed);
  std::vector<int> level(d);
  std::vector<std::size_t> order(d);
  for (std::size_t t = 0; t < r; ++t) {
    for (auto& l : level) l = static_cast<int>(rng.below(static_cast<std::size_t>(levels)));
    std::iota(order.begin(), order.end(), std::size_t{0});
    for (std::size_t k = d; k > 1; --k) std::swap(order[k - 1], order[rng.below(k)]);  // Fisher-Yates
    double* row = m.points.data() + t * (d + 1) * d;
    for (std::size_t i = 0; i < d; ++i) row[i] = level[i] / p1;
    for (std::size_t k = 0; k < d; ++k) {
      const std::size_t i = order[k];
      const bool up = level[i] < half;
      level[i] += up ? half : -half;
      double* next = row + (k + 1) * d;
      for (std::size_t q = 0; q < d; ++q) next[q] = level[q] / p1;
      m.moved.push_back(i);
      m.step.push_back(up ? m.delta : -m.delta);
    }
  }
  return m;
}

MorrisIndices morrisIndices(const MorrisDesign& m, const std::vector<double>& y, const BootstrapOptions& o) {
  if (y.size() != m.runs()) throw std::invalid_argument("Morris indices: expected r(d+1) outputs");
  const std::size_t d = m.d;
  std::vector<std::vector<double>> ee(d);
  for (std::size_t t = 0; t < m.r; ++t)
    for (std::size_t k = 0; k < d; ++k) {
      const double y0 = y[t * (d + 1) + k], y1 = y[t * (d + 1) + k + 1];
      if (!std::isfinite(y0) || !std::isfinite(y1)) continue;
      ee[m.moved[t * d + k]].push_back((y1 - y0) / m.step[t * d + k]);
    }
  const double nan = std::numeric_limits<double>::quiet_NaN();
  MorrisIndices r;
  auto stats = [](const std::vector<double>& e, const std::vector<std::size_t>* pick, double* mu, double* muStar,
                  double* sigma) {
    const std::size_t n = pick ? pick->size() : e.size();
    double s = 0, sa = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double v = e[pick ? (*pick)[k] : k];
      s += v;
      sa += std::abs(v);
    }
    *mu = s / static_cast<double>(n);
    *muStar = sa / static_cast<double>(n);
    double q = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double dv = e[pick ? (*pick)[k] : k] - *mu;
      q += dv * dv;
    }
    *sigma = n > 1 ? std::sqrt(q / static_cast<double>(n - 1)) : std::numeric_limits<double>::quiet_NaN();
  };
  for (std::size_t i = 0; i < d; ++i) {
    r.effects.push_back(ee[i].size());
    double mu = nan, ms = nan, sg = nan;
    if (!ee[i].empty()) stats(ee[i], nullptr, &mu, &ms, &sg);
    r.mu.push_back(mu);
    r.muStar.push_back(ms);
    r.sigma.push_back(sg);
    if (o.resamples <= 0) continue;
    std::vector<double> rep;
    if (!ee[i].empty())
      for (const auto& pick : bootstrapSamples(ee[i].size(), o)) {
        double a, b, c;
        stats(ee[i], &pick, &a, &b, &c);
        rep.push_back(b);
      }
    r.muStarCi.push_back(percentileInterval(rep, o.confidence));
  }
  return r;
}

}  // namespace lg::uq
