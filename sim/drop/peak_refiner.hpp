// The one peak refiner of the drop observer (sim/drop/observer.hpp): the running maximum of a channel
// over the steps of a run, located on each step's dense output where the step may hold it. With a rate
// channel (refine) a maximum is bracketed by the rate turning from + to - and found by Brent's search on
// values; without one (refineWithoutRate) the step's start, middle and end samples decide where to
// search. Every figure that is a maximum over time (the peak load, each tyre's deflection and load, each
// strut's stroke and force, the drag and spring-back peaks, h_max, the rebound) is refined here, in any
// scalar: with ceres::Jet the maximum carries its derivatives (the channel's at the time found).
#pragma once

#include <algorithm>
#include <cmath>
#include <functional>
#include <type_traits>

#include "sim/core/brent.hpp"
#include "sim/drop/channels.hpp"
#include "sim/engine/integration/dense_output.hpp"

namespace lg {

template <class S> class PeakRefiner {
 public:
  using Channels = DropChannels<S>;
  // Reads the channels at a time of the step in progress, on its dense output (the observer's own
  // workspace, the step's contact mode).
  using Probe = std::function<void(const S& t, const DenseOutput<S>& d, Channels& c)>;

  PeakRefiner(Probe probe, size_t struts, size_t tyres) : probe_(std::move(probe)), scratch_(struts, tyres) {}

  // The step in progress: its channels at the start, the middle and the end (the observer's, read before
  // the searches).
  void setStep(const Channels& start, const Channels& middle, const Channels& end) {
    prev_ = &start;
    mid_ = &middle;
    end_ = &end;
  }

  // The last search's maximum (refine): its time [s] and value; the observer reads them for the load's
  // humps and the peak's polished time, and sets lastTime to the polished one.
  double lastTime = 0, lastValue = 0;

  // Updates the running maximum 'best' of a channel. If its rate goes from + to - inside the step, the
  // maximum is located on the dense output (Brent's search on values). Returns true if the maximum
  // moved; 'tFound' (optional) receives the time of an interior maximum (-1 if the end holds it).
  // 'everyPeak': search every peak, also one below 'best' (P_y's humps, lastRefined*).
  template <class F>
  bool refine(const S& rate0, const S& rate1, const S& t0, const S& t1, const DenseOutput<S>& d, F f, S& best, S* tBest,
              const S& endValue, const S& tEnd, double* tFound = nullptr, bool everyPeak = false) {
    S v = endValue, tv = tEnd;
    double interior = -1;
    // Rates of round-off size (a stuck strut's s', ~1e-17 m/s, changes sign at random): a maximum inside
    // could exceed the ends by at most |rate| h / 2, below the value's round-off: no search.
    const double reach = std::max(std::abs(value(rate0)), std::abs(value(rate1))) * (value(t1) - value(t0));
    // Inside the step, its start, middle and end are known: a search that cannot reach the running
    // maximum (see refineWithoutRate) is not made (a stroke at rest, its rate round-off).
    const bool inStep = value(t0) >= value(prev_->t) && value(t1) <= value(end_->t);
    double f0 = 0, fm = 0, f1 = 0;
    auto reachable = [&] {  // (read only where the rates bracket a peak)
      if (!inStep) return true;
      f0 = value(f(*prev_)), fm = value(f(*mid_)), f1 = value(f(*end_));
      return everyPeak || canReach(f0, fm, f1, best);
    };
    if (value(rate0) > 0 && value(rate1) < 0 && reach > 1e-14 * std::abs(value(endValue)) && reachable()) {
      auto at = [&](double t) {
        probe_(S(t), d, scratch_);
        return value(f(scratch_));
      };
      // Brent's minimisation of -f (golden sections and parabolic steps, Forsythe, Malcolm & Moler's
      // fmin; tolerance sqrt(eps) |t| + 1e-13, where the values are equal to round-off). Inside the step
      // it starts from the parabola through the step's start, middle and end (known: no evaluation).
      double fx = 0;
      BrentStart start;
      if (inStep) start = {3, {value(prev_->t), value(mid_->t), value(end_->t)}, {-f0, -fm, -f1}};
      const double tm = brentMinimise([&](double t) { return -at(t); }, value(t0), value(t1), kSearchRel, searchAbs(t1),
                                      fx, [](double) { return false; }, 100, start);
      S vm;
      if constexpr (kDouble) {
        vm = -fx;  // (the value at tm, from the same evaluation)
      } else {
        probe_(S(tm), d, scratch_);  // (its derivatives)
        vm = f(scratch_);
      }
      lastTime = tm;
      lastValue = value(vm);
      if (value(vm) > value(v)) {
        v = vm;
        tv = S(tm);
        interior = tm;
      }
    }
    if (value(v) > value(best)) {
      best = v;
      if (tBest) *tBest = tv;
      if (tFound) *tFound = interior;
      return true;
    }
    return false;
  }

  // A running maximum of a channel without a rate: from its values at the step's start, middle and
  // end, the step is searched (Brent's search on values) where its largest sample is inside, or at the
  // start if the channel rises there (a maximum just after the start, or the one carried over from the
  // previous step, lies in [t0, t_mid]; one that falls at the start has its maximum there); a largest
  // value at the end is taken there, and the next step looks further.
  // 'endOnly' (a step entered part-way): only the middle and end samples count.
  // Returns true if the maximum moved.
  template <class F>
  bool refineWithoutRate(const S& v0, const S& vm, const S& v1, const S& t0, const S& t1, const DenseOutput<S>& d, F f,
                         S& best, bool endOnly = false, S* tBest = nullptr) {
    const double a = value(v0), m = value(vm), b = value(v1);
    // A smooth channel sampled at three points rises above its largest sample by less than its variation
    // over the step: a step that cannot reach the running maximum is not searched (a falling P_a after
    // its peak, every step).
    if (!canReach(a, m, b, best)) return false;
    // Samples equal to round-off (a stuck strut's constant P_a): a search would only sort round-off, in
    // some forty evaluations (each a full one for P_a). The largest sample holds the maximum.
    const double hi = std::max({a, m, b}), lo = std::min({a, m, b});
    if (hi - lo <= 1e-14 * std::max(std::abs(hi), std::abs(lo))) {
      if (!(hi > value(best))) return false;
      const int at = b == hi ? 2 : (m == hi ? 1 : 0);  // (the latest of the largest)
      best = at == 2 ? v1 : (at == 1 ? vm : v0);
      if (tBest) *tBest = at == 2 ? t1 : (at == 1 ? S(0.5) * (t0 + t1) : t0);
      return true;
    }
    const bool atStart = !endOnly && a >= m && a >= b, atMiddle = m > b && (endOnly || m > a);
    if (atStart) {
      // The largest sample at the start: the maximum is inside [t0, t_mid] only if the channel rises at t0
      // (a forward difference on the dense output), else the start holds it. (A search that converges
      // onto the step's start takes some thirty evaluations of the channel: a stuck strut's P_a.)
      const double dt = 1e-3 * (value(t1) - value(t0));
      probe_(S(value(t0) + dt), d, scratch_);
      if (!(value(f(scratch_)) > a)) {
        if (!(a > value(best))) return false;
        best = v0;
        if (tBest) *tBest = t0;
        return true;
      }
    }
    if (atStart || atMiddle) {
      const S tb = atStart ? S(0.5) * (t0 + t1) : t1;
      return refine(S(1.0), S(-1.0), t0, tb, d, f, best, tBest, atStart ? v0 : vm, atStart ? t0 : S(0.5) * (t0 + t1));
    }
    if (b > value(best)) {
      // The largest sample at the end: the maximum is inside [t_mid, t1] if the channel already falls at
      // t1 (a backward difference on the dense output), else at t1 or beyond.
      const double dt = 1e-3 * (value(t1) - value(t0));
      probe_(S(value(t1) - dt), d, scratch_);
      if (value(f(scratch_)) > b) return refine(S(1.0), S(-1.0), S(0.5) * (t0 + t1), t1, d, f, best, tBest, v1, t1);
      best = v1;
      if (tBest) *tBest = t1;
      return true;
    }
    return false;
  }

 private:
  static constexpr bool kDouble = std::is_same_v<S, double>;
  // The extrema searches' tolerance on t (brentMinimise): sqrt(eps) |t| + 1e-13 max(1, t1), where values
  // are equal to round-off.
  static inline const double kSearchRel = std::sqrt(2.2e-16);
  static double searchAbs(const S& t1) { return 1e-13 * std::max(1.0, value(t1)); }
  // Whether a smooth channel sampled at three points of a step (a, m, b) may reach 'best' inside it: it
  // rises above its largest sample by less than its variation over the step.
  static bool canReach(double a, double m, double b, const S& best) {
    return !(std::max({a, m, b}) + std::abs(a - m) + std::abs(m - b) < value(best));
  }

  Probe probe_;
  const Channels *prev_ = nullptr, *mid_ = nullptr, *end_ = nullptr;
  Channels scratch_;  // the searches' own reads
};

}  // namespace lg
