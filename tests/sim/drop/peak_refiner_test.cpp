// The one peak refiner (sim/drop/peak_refiner.hpp) on channels given in closed form: a maximum bracketed
// by its rate is found by the search to its tolerance; without a rate the step's samples decide, a
// maximum at a step's end is carried to the next step and found there; a step that cannot reach the
// running maximum leaves it alone.
#include "sim/drop/peak_refiner.hpp"

#include <cmath>

#include <catch2/catch.hpp>

namespace {

using Channels = lg::DropChannels<double>;
const double kPi = std::acos(-1.0);

// P(t) = 1 - 50 (t - 0.3)^2 (its top 1 at t = 0.3), and Q(t) = sin(pi t) (its top 1 at t = 0.5) in Px.
void closedForm(double t, Channels& c) {
  c.t = t;
  c.Py = 1 - 50 * (t - 0.3) * (t - 0.3);
  c.PyDot = -100 * (t - 0.3);
  c.Px = std::sin(kPi * t);
}

struct Run {
  int reads = 0;
  lg::PeakRefiner<double> refiner{[this](const double& t, const lg::DenseOutput<double>&, Channels& c) {
                                    ++reads;
                                    closedForm(t, c);
                                  },
                                  0, 0};
  Channels prev, mid, end;
  lg::DenseOutput<double> d;  // (the probe reads the closed form, not a dense output)
  Run() { refiner.setStep(prev, mid, end); }
  void step(double t0, double t1) {
    closedForm(t0, prev);
    closedForm(0.5 * (t0 + t1), mid);
    closedForm(t1, end);
  }
};

}  // namespace

TEST_CASE("peak refiner: a maximum inside a step, bracketed by its rate, is found to the search's tolerance",
          "[peak_refiner]") {
  Run r;
  r.step(0.25, 0.41);
  double best = 0, tBest = -1, tFound = -1;
  const auto Py = [](const Channels& c) { return c.Py; };
  CHECK(r.refiner.refine(r.prev.PyDot, r.end.PyDot, 0.25, 0.41, r.d, Py, best, &tBest, r.end.Py, 0.41, &tFound));
  CHECK(best == Approx(1.0).epsilon(1e-15));
  CHECK(std::abs(tBest - 0.3) < 2e-8);  // values flat to round-off within sqrt(eps / 50) of the top
  CHECK(tFound == tBest);
  CHECK(r.refiner.lastTime == tBest);
  CHECK(r.refiner.lastValue == best);
  // the search starts from the parabola through the step's three samples, here P itself: a few reads
  CHECK(r.reads > 0);
  CHECK(r.reads <= 4);
  // the next step falls from a lower value: it cannot reach the maximum, and is not searched
  r.step(0.41, 0.5);
  const int reads = r.reads;
  CHECK_FALSE(r.refiner.refine(r.prev.PyDot, r.end.PyDot, 0.41, 0.5, r.d, Py, best, &tBest, r.end.Py, 0.5));
  CHECK(r.reads == reads);
  CHECK(best == Approx(1.0).epsilon(1e-15));
}

TEST_CASE("peak refiner: without a rate, a maximum at a step's end is taken there and found in the next step",
          "[peak_refiner]") {
  Run r;
  const auto Px = [](const Channels& c) { return c.Px; };
  double best = 0, tBest = -1;
  r.step(0.0, 0.4);  // rising throughout: the end holds the step's maximum
  CHECK(r.refiner.refineWithoutRate(r.prev.Px, r.mid.Px, r.end.Px, 0.0, 0.4, r.d, Px, best, false, &tBest));
  CHECK(best == std::sin(0.4 * kPi));
  CHECK(tBest == 0.4);
  r.step(0.4, 0.8);  // the top at 0.5, inside
  CHECK(r.refiner.refineWithoutRate(r.prev.Px, r.mid.Px, r.end.Px, 0.4, 0.8, r.d, Px, best, false, &tBest));
  CHECK(best == Approx(1.0).epsilon(1e-15));
  CHECK(std::abs(tBest - 0.5) < 2e-8);
  r.step(0.8, 1.0);  // falling below it: nothing moves
  CHECK_FALSE(r.refiner.refineWithoutRate(r.prev.Px, r.mid.Px, r.end.Px, 0.8, 1.0, r.d, Px, best, false, &tBest));
  CHECK(std::abs(tBest - 0.5) < 2e-8);
}
