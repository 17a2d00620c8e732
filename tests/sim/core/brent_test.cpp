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

TEST_CASE("brentMinimise from three known points: the same minimum, the first step their parabola's vertex", "[core][brent]") {
  // A peak inside one step, as the drop observer searches it (the minimum of -P): P = 1 - u^2 + 0.3 u^3,
  // u = (t - 0.0537) / 0.02, on the step [0.05, 0.06] whose start, middle and end are known.
  int calls = 0;
  auto f = [&](double t) {
    ++calls;
    const double u = (t - 0.0537) / 0.02;
    return -(1 - u * u + 0.3 * u * u * u);
  };
  const double a = 0.05, b = 0.06, rel = std::sqrt(2.2e-16), abs = 1e-13;
  const lg::BrentStart start{3, {a, 0.5 * (a + b), b}, {f(a), f(0.5 * (a + b)), f(b)}};
  double fx = 0, fs = 0;
  calls = 0;
  const double plain = lg::brentMinimise(f, a, b, rel, abs, fx, [](double) { return false; });
  const int plainCalls = calls;
  calls = 0;
  const double seeded = lg::brentMinimise(f, a, b, rel, abs, fs, [](double) { return false; }, 100, start);
  const int seededCalls = calls;
  // Both to the tolerance, 3 sqrt(eps) |t| = 2.4e-9 (achieved 2.5e-10 and 2.2e-10).
  CHECK(std::abs(plain - 0.0537) < 3 * rel * 0.0537);
  CHECK(std::abs(seeded - 0.0537) < 3 * rel * 0.0537);
  CHECK(fs == f(seeded));
  CHECK(plainCalls == 9);
  CHECK(seededCalls == 7);  // no first evaluation, and no golden section: the vertex is near the peak
  // A start whose best point lies outside [a, b] is not used: the plain search, point for point.
  const lg::BrentStart outside{3, {0.0537, 0.07, 0.08}, {f(0.0537), f(0.07), f(0.08)}};
  const double fallback = lg::brentMinimise(f, 0.055, 0.065, rel, abs, fx, [](double) { return false; }, 100, outside);
  CHECK(fallback == lg::brentMinimise(f, 0.055, 0.065, rel, abs, fs, [](double) { return false; }));
}
