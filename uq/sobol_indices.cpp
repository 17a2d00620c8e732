// Saltelli design and the Saltelli 2010 / Jansen estimators (sobol_indices.hpp).
#include "uq/sobol_indices.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

#include "uq/sobol_sequence.hpp"

namespace lg::uq {

SaltelliDesign saltelliDesign(std::size_t n, std::size_t d, std::uint64_t seed) {
  if (d == 0) throw std::invalid_argument("Saltelli design: no variables");
  SaltelliDesign s;
  s.n = n;
  s.d = d;
  const std::vector<double> q = shiftedSobol(n, 2 * d, seed);
  s.points.resize(s.runs() * d);
  for (std::size_t j = 0; j < n; ++j) {
    const double* a = q.data() + j * 2 * d;
    const double* b = a + d;
    double* out = s.points.data() + j * (d + 2) * d;
    for (std::size_t k = 0; k < d; ++k) {
      out[k] = a[k];        // A
      out[d + k] = b[k];    // B
    }
    for (std::size_t i = 0; i < d; ++i)
      for (std::size_t k = 0; k < d; ++k) out[(2 + i) * d + k] = k == i ? b[k] : a[k];  // AB^i
  }
  return s;
}

namespace {

// Point estimates over the listed complete blocks (positions into the run vector's blocks).
void estimate(const std::vector<double>& y, std::size_t d, const std::vector<std::size_t>& blocks, double* mean,
              double* variance, double* S1, double* ST) {
  const std::size_t w = d + 2;
  const double n = static_cast<double>(blocks.size());
  double m = 0;
  for (std::size_t j : blocks) m += y[j * w] + y[j * w + 1];
  m /= 2 * n;
  double v = 0;
  for (std::size_t j : blocks) {
    const double a = y[j * w] - m, b = y[j * w + 1] - m;
    v += a * a + b * b;
  }
  v /= 2 * n;
  *mean = m;
  *variance = v;
  for (std::size_t i = 0; i < d; ++i) {
    double s1 = 0, st = 0;
    for (std::size_t j : blocks) {
      const double a = y[j * w] - m, b = y[j * w + 1] - m, ab = y[j * w + 2 + i] - m;
      s1 += b * (ab - a);
      st += (a - ab) * (a - ab);
    }
    S1[i] = v > 0 ? s1 / n / v : 0.0;
    ST[i] = v > 0 ? st / (2 * n) / v : 0.0;
  }
}

}  // namespace

SobolIndices sobolIndices(const std::vector<double>& y, std::size_t n, std::size_t d, const BootstrapOptions& o,
                          std::size_t prefix) {
  const std::size_t w = d + 2;
  if (y.size() != n * w) throw std::invalid_argument("Sobol indices: expected N(d+2) outputs");
  SobolIndices r;
  r.blocks = prefix == 0 || prefix > n ? n : prefix;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  r.S1.assign(d, nan);
  r.ST.assign(d, nan);
  std::vector<std::size_t> good;
  for (std::size_t j = 0; j < r.blocks; ++j) {
    bool ok = true;
    for (std::size_t k = 0; k < w; ++k) ok = ok && std::isfinite(y[j * w + k]);
    (ok ? good : r.dropped).push_back(j);
  }
  if (good.size() < 2) {
    r.mean = r.variance = nan;
    return r;
  }
  r.estimated = true;
  estimate(y, d, good, &r.mean, &r.variance, r.S1.data(), r.ST.data());
  r.constant = !(r.variance > 0);
  if (o.resamples <= 0) return r;
  const auto samples = bootstrapSamples(good.size(), o);
  std::vector<std::vector<double>> s1(d), st(d);
  std::vector<std::size_t> blocks(good.size());
  std::vector<double> b1(d), bt(d);
  for (const auto& pick : samples) {
    for (std::size_t k = 0; k < pick.size(); ++k) blocks[k] = good[pick[k]];
    double m, v;
    estimate(y, d, blocks, &m, &v, b1.data(), bt.data());
    for (std::size_t i = 0; i < d; ++i) {
      s1[i].push_back(b1[i]);
      st[i].push_back(bt[i]);
    }
  }
  for (std::size_t i = 0; i < d; ++i) {
    r.S1ci.push_back(percentileInterval(s1[i], o.confidence));
    r.STci.push_back(percentileInterval(st[i], o.confidence));
  }
  return r;
}

}  // namespace lg::uq
