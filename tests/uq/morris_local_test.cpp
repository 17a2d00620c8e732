// Morris screening (ranks the G-function's variables as their total indices do; the failed-point rule)
// and central-difference elasticities on functions with known elasticities.
#include <cmath>
#include <limits>
#include <vector>

#include "uq/bootstrap.hpp"
#include "uq/local.hpp"
#include "uq/morris.hpp"

#include <catch2/catch.hpp>

using namespace lg::uq;

namespace {
const std::vector<double> kGa{0, 1, 4.5, 9, 99, 99, 99, 99};
double gFunction(const double* u) {
  double p = 1;
  for (std::size_t i = 0; i < kGa.size(); ++i) p *= (std::abs(4 * u[i] - 2) + kGa[i]) / (1 + kGa[i]);
  return p;
}
std::vector<double> run(const MorrisDesign& m) {
  std::vector<double> y(m.runs());
  for (std::size_t k = 0; k < m.runs(); ++k) y[k] = gFunction(m.point(k));
  return y;
}
}  // namespace

TEST_CASE("morris: trajectories move one variable by Delta on the grid per step", "[uq][morris]") {
  const MorrisDesign m = morrisDesign(10, 5, 4, 3);
  CHECK(m.delta == Approx(2.0 / 3.0));
  REQUIRE(m.runs() == 60);
  for (std::size_t t = 0; t < m.r; ++t)
    for (std::size_t k = 0; k < m.d; ++k) {
      const double* a = m.point(t * (m.d + 1) + k);
      const double* b = a + m.d;
      int changed = 0;
      for (std::size_t i = 0; i < m.d; ++i) {
        CHECK(std::abs(b[i] * 3 - std::round(b[i] * 3)) < 1e-12);  // on the grid {0, 1/3, 2/3, 1}
        if (a[i] != b[i]) {
          ++changed;
          CHECK(i == m.moved[t * m.d + k]);
          CHECK(b[i] - a[i] == Approx(m.step[t * m.d + k]));
        }
      }
      CHECK(changed == 1);
    }
  CHECK(morrisDesign(10, 5, 4, 3).points == m.points);  // seeded
  CHECK_THROWS(morrisDesign(10, 5, 3, 3));               // odd levels
}

TEST_CASE("morris: mu* ranks the G-function's variables in the order of their total indices", "[uq][morris]") {
  const MorrisDesign m = morrisDesign(50, 8, 4, 11);
  const MorrisIndices r = morrisIndices(m, run(m), BootstrapOptions{100, 0.95, 2});
  INFO("mu* " << r.muStar[0] << " " << r.muStar[1] << " " << r.muStar[2] << " " << r.muStar[3] << " " << r.muStar[4]);
  CHECK(r.muStar[0] > r.muStar[1]);
  CHECK(r.muStar[1] > r.muStar[2]);
  CHECK(r.muStar[2] > r.muStar[3]);
  for (std::size_t i = 4; i < 8; ++i) CHECK(r.muStar[3] > r.muStar[i]);
  for (std::size_t i = 0; i < 8; ++i) {
    CHECK(r.effects[i] == 50u);
    CHECK(r.muStarCi[i].lo <= r.muStar[i]);
    CHECK(r.muStarCi[i].hi >= r.muStar[i]);
    CHECK(r.sigma[i] >= 0);
  }
}

TEST_CASE("morris: a failed point drops the two effects it ends, the rest stand", "[uq][morris]") {
  const MorrisDesign m = morrisDesign(6, 3, 4, 1);
  std::vector<double> y(m.runs());
  for (std::size_t k = 0; k < m.runs(); ++k) y[k] = 2 * m.point(k)[0] - m.point(k)[1];  // x3 inert
  y[1 * 4 + 2] = std::numeric_limits<double>::quiet_NaN();  // trajectory 1, point 2: the effects into and out of it go
  const MorrisIndices r = morrisIndices(m, y, BootstrapOptions{50, 0.95, 1});
  std::size_t total = 0;
  for (std::size_t i = 0; i < 3; ++i) total += r.effects[i];
  CHECK(total == 6 * 3 - 2);
  CHECK(r.mu[0] == Approx(2));          // linear: every effect is the slope
  CHECK(r.mu[1] == Approx(-1));
  CHECK(r.muStar[1] == Approx(1));
  CHECK(r.sigma[0] == Approx(0).margin(1e-12));
  CHECK(r.muStar[2] == 0.0);
  CHECK(r.muStarCi[2].lo == 0.0);
  CHECK(r.muStarCi[2].hi == 0.0);
}

TEST_CASE("local: central-difference elasticities of power laws", "[uq][local]") {
  const std::vector<double> x0{2.0, 5.0, 3.0};
  const double h = 1e-3;
  const std::vector<double> p = localDesign(x0, h);
  REQUIRE(p.size() == 7 * 3);
  std::vector<double> y(7), zero(7);
  for (std::size_t k = 0; k < 7; ++k) {
    const double* x = &p[k * 3];
    y[k] = x[0] * x[0] / x[1];  // E = (2, -1, 0)
    zero[k] = x[0] - 2.0;       // 0 at the baseline: no elasticity
  }
  const Elasticities e = elasticities(x0, h, y);
  CHECK(e.E[0] == Approx(2).epsilon(1e-12));               // exact for a square
  CHECK(e.E[1] == Approx(-1 / (1 - h * h)).epsilon(1e-9));  // central difference of 1/x
  CHECK(e.E[2] == 0.0);
  CHECK(e.derivative[0] == Approx(2 * 2.0 / 5.0).epsilon(1e-9));
  CHECK(e.why[0].empty());
  const Elasticities z = elasticities(x0, h, zero);
  CHECK(std::isnan(z.E[0]));
  CHECK(z.why[0] == "the metric is 0 at the baseline");
  CHECK(z.derivative[0] == Approx(1).epsilon(1e-9));
  y[3] = std::numeric_limits<double>::quiet_NaN();  // x2's plus point failed
  const Elasticities f = elasticities(x0, h, y);
  CHECK(std::isnan(f.E[1]));
  CHECK_FALSE(f.why[1].empty());
  CHECK(f.E[0] == e.E[0]);
}

TEST_CASE("bootstrap: percentile intervals and seeded resamples", "[uq]") {
  std::vector<double> r;
  for (int k = 0; k <= 100; ++k) r.push_back(100 - k);
  const Interval i = percentileInterval(r, 0.9);
  CHECK(i.lo == Approx(5));
  CHECK(i.hi == Approx(95));
  const auto a = bootstrapSamples(10, BootstrapOptions{5, 0.95, 3});
  CHECK(a.size() == 5);
  CHECK(a == bootstrapSamples(10, BootstrapOptions{5, 0.95, 3}));
  CHECK(a != bootstrapSamples(10, BootstrapOptions{5, 0.95, 4}));
}
