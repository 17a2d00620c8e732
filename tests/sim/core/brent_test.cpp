// Brent's minimisation (sim/core/brent.hpp) against closed-form minima.
#include <cmath>

#include "sim/core/brent.hpp"

#include <catch2/catch.hpp>

TEST_CASE("brentMinimise: closed-form minima to its tolerance, few evaluations, an early stop", "[core][brent]") {
  int calls = 0;
  double fx = 0;
  // cos on [2, 4]: minimum -1 at pi; values decide the location to about sqrt(eps) |x|.
  auto cosine = [&](double t) {
    ++calls;
    return std::cos(t);
  };
  const double x = lg::brentMinimise(cosine, 2.0, 4.0, std::sqrt(2.2e-16), 1e-13, fx, [](double) { return false; });
  CHECK(std::abs(x - M_PI) < 3 * std::sqrt(2.2e-16) * M_PI);  // the promise; achieved 4.3e-13
  CHECK(fx == std::cos(x));
  CHECK(fx + 1 < 1e-15);
  CHECK(calls <= 10);  // parabolic steps: 9 evaluations (golden sections alone would take about 40)
  // A quartic whose minimum lies off-centre, at a fixed absolute tolerance of 1e-9 / 3 * 3.
  calls = 0;
  auto quartic = [&](double t) {
    ++calls;
    return std::pow(t - 0.3, 4) + 0.5 * (t - 0.3) * (t - 0.3);
  };
  const double q = lg::brentMinimise(quartic, -1.0, 2.0, 0.0, 3e-9, fx, [](double) { return false; });
  CHECK(std::abs(q - 0.3) < 2e-9);  // the tolerance; achieved 3.1e-13 in 11 evaluations
  CHECK(calls <= 12);
  // The search stops at the first value the caller accepts: a dip below zero of a function positive
  // at both ends, (t - 0.5)^2 - 1e-4 on [0, 1], found without locating its minimum.
  calls = 0;
  auto dip = [&](double t) {
    ++calls;
    return (t - 0.5) * (t - 0.5) - 1e-4;
  };
  const double d = lg::brentMinimise(dip, 0.0, 1.0, 0.0, 3e-9, fx, [](double g) { return g <= 0; });
  CHECK(fx <= 0);
  CHECK(std::abs(d - 0.5) <= 1e-2);
  CHECK(calls <= 4);  // achieved 4: the parabola's vertex is the minimum
}
