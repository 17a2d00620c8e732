// Accuracy on demand (sim/drop/accuracy.hpp).
#include "sim/drop/accuracy.hpp"

#include "sim/core/format.hpp"  // shortNumber

#include <limits>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>

namespace lg {

namespace {

double relErr(double x, double ref) {
  if (ref == 0) return x == 0 ? 0.0 : std::abs(x);
  return std::abs(x - ref) / std::abs(ref);
}

}  // namespace

double MetricErrors::max() const {
  return std::max({peakLoad, tPeak, stroke, travel, tyreDeflection, efficiency, strutForce, dragPeak});
}

MetricErrors metricErrors(const CaseMetrics& m, const CaseMetrics& r) {
  MetricErrors e;
  e.peakLoad = relErr(m.peak_load_N, r.peak_load_N);
  e.tPeak = relErr(m.t_peak_s, r.t_peak_s);
  e.stroke = relErr(m.stroke_max_m, r.stroke_max_m);
  e.travel = relErr(m.h_max_m, r.h_max_m);
  e.tyreDeflection = relErr(m.tyre_deflection_max_m, r.tyre_deflection_max_m);
  e.efficiency = relErr(m.efficiency, r.efficiency);
  e.strutForce = relErr(m.strut_force_max_N, r.strut_force_max_N);
  e.dragPeak = r.forward_speed_mps > 0 ? relErr(m.drag_peak_N, r.drag_peak_N) : 0.0;  // (spin-up only)
  return e;
}

// The mapping. Calibrated on every case of the shipped scenes against dopri5 at rtol 1e-10 (the largest
// relative error over the seven metrics, max step 0.05 s; measured again when the struts' peak force
// joined them, with ros34pw2's velocities on its continuous extension):
//   ros34pw2  rtol 1e-2: 4.1e-2   5e-3: 2.0e-2   3e-3: 6.1e-3   2e-3: 4.2e-3   1e-3: 1.7e-3   3e-4: 5.6e-4
//             (about 1.7 .. 4 rtol; the telescopic gear's stroke and P_a,max and the nose gear's time of a
//             flat peak are the worst metrics; with the damping alone in W it was 2.9e-2 at 1e-2, 3.1e-3 at
//             1e-3, a fifth more evaluations)
//   dopri5    rtol 1e-2: 8.4e-3   5e-3: 4.6e-3   1e-3: 8.9e-4   5e-4: 3.2e-4   1e-4: 6.5e-5   5e-5: 2.2e-5
//             (about rtol / 2 .. rtol; the seed gear's P_a,max is the worst metric at 1e-3 and looser, 100
//             times its other metrics' error there, the time of the peak below)
// Looser than 1e-3 the linearly implicit ros34pw2 is the cheaper (at 1e-2 half dopri5's evaluations,
// whose steps the orifice damping caps), at 1e-3 and tighter dopri5 (as cheap at 1e-3, cheaper below).
// Each is given a tolerance with a margin of 1.6 or more on that worst error: rtol = accuracy / 6 for
// ros34pw2 (at most kRosRtolMax = 2e-3: off the shipped cases, at 2e-2 .. 5e-2, rtol = accuracy / 6
// missed by up to 1.57 times the accuracy, its steps of up to 30 ms spanning a peak; an error of 9 .. 12
// rtol at rtol 3e-3 .. 1e-2, where at 2e-3 and tighter the sweep's worst is 2.6 rtol), rtol = accuracy / 2 for dopri5 (at rtol = accuracy P_a,max left a margin of
// 1.1 at 1e-3; half of it costs 2 % more evaluations); atol = rtol / 100; steps up to 0.05 s (flights
// and rest phases, where nothing happens, need no more).
// Below 1e-4 (kAccuracyTightEnd) ros34pw2 again, at rtol = accuracy / 8. Off the shipped cases
// (bench/accuracy_sweep: four gears, ten variants, six drops) dopri5 at accuracy / 2 missed the time of the
// peak by up to 7.4 times the accuracy at 1e-5 and 5.5 at 3e-5: on a stiff run (the main gear dropped
// without forward speed, its tyre's spin-up friction regularised) that kept dopri5 at its stability
// bound, the fast mode's ripple moved the flat top by 3 us, and on the nose gear (not stiff) its error
// control left a peak-time error of 4.2 times the accuracy at 3e-5. ros34pw2 damps the ripple: at
// accuracy / 8 the sweep's worst metric is 0.80 of the accuracy at 5e-5, 3e-5 and 1e-5 (1.02 at
// accuracy / 6, the telescopic gear's stroke), for 36 % fewer evaluations than dopri5 at 1e-5 and 2 %
// more at 3e-5.
AccuracySetting settingForAccuracy(double accuracy) {
  AccuracySetting a;
  if (accuracy > 1e-3) {
    a.integrator = IntegratorKind::Ros34pw2;
    a.rtol = std::min(accuracy / 6, kRosRtolMax);
  } else if (accuracy < kAccuracyTightEnd) {
    a.integrator = IntegratorKind::Ros34pw2;
    a.rtol = accuracy / 8;
  } else {
    a.integrator = IntegratorKind::DormandPrince;
    a.rtol = accuracy / 2;
    a.stiffSwitchRtol = accuracy / 6;  // ros34pw2's own rule, should the run turn out stiff
  }
  a.atol = a.rtol * 1e-2;
  a.maxStep = 0.05;
  return a;
}

double accuracyDelivered(double accuracy) { return std::min(accuracy, kAccuracyLooseEnd); }

double flatPeakAccuracy(double accuracy, double kappa) {
  if (!(accuracy > 0) || !(kappa > kFlatPeakCondition * (accuracy / accuracyDelivered(accuracy))))
    return 0;  // (NaN: no smooth peak, nothing to tighten)
  // The factor kappa / kFlatPeakCondition rounded up onto the grid 2^(k/4): the double and the Jet run of a
  // case (whose kappa agree to round-off) take the same setting.
  const double factor = std::exp2(std::ceil(4 * std::log2(kappa / kFlatPeakCondition)) / 4);
  return std::max(accuracy / factor, kFlatPeakAccuracyMin);
}

double closePeaksAccuracy(double ran, double tPeak, double gap, double tSecond, double asked) {
  if (!(asked > 0)) asked = ran;
  const double a = accuracyDelivered(ran);
  if (!(ran > 0) || !(gap >= 0) || !(gap < kClosePeaksFactor * a)) return 0;  // (NaN: one maximum)
  if (!(std::abs(tSecond - tPeak) > asked * tPeak)) return 0;  // (either time is within the promise)
  if (!(ran > kFlatPeakAccuracyMin)) return 0;                 // (the floor was run: nothing tighter)
  // The factor rounded up onto the grid 2^(k/4), as flatPeakAccuracy's, at most kClosePeaksStep; a gap
  // of zero takes the step.
  const double ratio = kClosePeaksFactor * a / std::max(gap, 1e-300);
  const double factor = std::min(std::exp2(std::ceil(4 * std::log2(ratio)) / 4), kClosePeaksStep);
  return std::max(a / factor, kFlatPeakAccuracyMin);
}

double rerunAccuracy(double accuracy, const CaseMetrics& m) {
  const double flat = flatPeakAccuracy(accuracy, m.t_peak_condition);
  const double close = closePeaksAccuracy(accuracy, m.t_peak_s, m.second_peak_gap, m.t_second_peak_s);
  if (flat > 0 && close > 0) return std::min(flat, close);
  return std::max(flat, close);
}

double nextAccuracy(double asked, double ran, const CaseMetrics& m) {
  if (ran == asked) return rerunAccuracy(asked, m);
  return closePeaksAccuracy(ran, m.t_peak_s, m.second_peak_gap, m.t_second_peak_s, asked);
}

namespace {

std::string closeWords(const CaseMetrics& m) {
  char buf[128];
  std::snprintf(buf, sizeof buf, "two peaks within %.3g %% (t = %.5g s and %.5g s)", 100 * m.second_peak_gap, m.t_peak_s,
                m.t_second_peak_s);
  return buf;
}

}  // namespace

std::string rerunReason(double accuracy, const CaseMetrics& m) {
  if (!(rerunAccuracy(accuracy, m) > 0)) return "";
  std::string out;
  if (flatPeakAccuracy(accuracy, m.t_peak_condition) > 0) {
    char flat[96];
    std::snprintf(flat, sizeof flat, "flat peak (t_peak condition %.3g > %.3g)", m.t_peak_condition,
                  kFlatPeakCondition * accuracy / accuracyDelivered(accuracy));
    out = flat;
  }
  if (closePeaksAccuracy(accuracy, m.t_peak_s, m.second_peak_gap, m.t_second_peak_s) > 0)
    out += (out.empty() ? "" : ", ") + closeWords(m);
  return out;
}

std::string nextReason(double asked, double ran, const CaseMetrics& m) {
  if (ran == asked) return rerunReason(asked, m);
  if (!(nextAccuracy(asked, ran, m) > 0)) return "";
  char buf[96];
  std::snprintf(buf, sizeof buf, "at %.3g still within %.3g %%", ran, 100 * m.second_peak_gap);
  return buf;
}

std::string undecidedPeaks(double asked, double ran, const CaseMetrics& m) {
  const bool undecided = m.second_peak_gap >= 0 && m.second_peak_gap < kClosePeaksFactor * accuracyDelivered(ran) &&
                         std::abs(m.t_second_peak_s - m.t_peak_s) > asked * m.t_peak_s;
  return undecided && !(ran > kFlatPeakAccuracyMin) ? "; closer than any accuracy decides: t_peak may be either" : "";
}

void markRerun(CaseMetrics& again, const CaseMetrics& before, double asked, double ran, double rerun) {
  again.accuracy = asked;
  again.accuracy_rerun = rerun;
  const std::string why = nextReason(asked, ran, before);
  again.accuracy_rerun_reason = before.accuracy_rerun_reason.empty() ? why : before.accuracy_rerun_reason + "; " + why;
  again.steps += before.steps;  // (what the case cost: every run)
  again.rhs_evaluations += before.rhs_evaluations;
  again.wall_time_s += before.wall_time_s;
}

void applyAccuracy(Settings& s, double accuracy) {
  const AccuracySetting a = settingForAccuracy(accuracy);
  s.integrator = a.integrator;
  s.rtol = a.rtol;
  s.atol = a.atol;
  s.maxStep = a.maxStep;
  s.stiffSwitchRtol = a.stiffSwitchRtol;
  s.accuracy = accuracy;
}

std::optional<std::pair<std::string, std::string>> solverOverridesProblem(const SolverOverrides& o,
                                                                         const std::string& prefix) {
  if (o.accuracy) {
    if (const std::string rule = accuracyRule(*o.accuracy); !rule.empty())
      return std::make_pair(prefix + "accuracy", "value " + shortNumber(*o.accuracy, 10) + " " + rule);
    const std::pair<bool, const char*> chosen[] = {{o.integrator.has_value(), "integrator"}, {o.rtol.has_value(), "rtol"},
                                                   {o.atol.has_value(), "atol"}};
    for (const auto& [given, k] : chosen)
      if (given)
        return std::make_pair(prefix + k, prefix + "accuracy chooses integrator, rtol and atol: give either " + prefix +
                                              "accuracy or " + prefix + k);
  }
  if (o.rtol && !(*o.rtol < 1))
    return std::make_pair(prefix + "rtol", "value " + shortNumber(*o.rtol, 10) + " must be < 1 (a relative tolerance)");
  return std::nullopt;
}

void applySolverOverrides(Settings& s, const SolverOverrides& o) {
  if (o.accuracy) {
    applyAccuracy(s, *o.accuracy);
  } else if (o.integrator || o.rtol || o.atol) {
    if (s.accuracy > 0) {  // what the scene's accuracy chose goes back to the defaults
      const Settings d{};
      s.integrator = d.integrator;
      s.rtol = d.rtol;
      s.atol = d.atol;
      s.maxStep = d.maxStep;
    }
    s.accuracy = 0;
    s.stiffSwitchRtol = 0;
  }
  if (o.integrator) s.integrator = *o.integrator;
  if (o.rtol) {
    s.rtol = *o.rtol;
    if (!o.atol) s.atol = *o.rtol * 1e-2;
  }
  if (o.atol) s.atol = *o.atol;
  if (o.step) s.step = *o.step;
}

double impliedAccuracy(const Settings& s) {
  if (s.accuracy > 0) return s.accuracy;
  double a = std::numeric_limits<double>::quiet_NaN();
  if (s.integrator == IntegratorKind::DormandPrince) a = 2 * s.rtol;
  if (s.integrator == IntegratorKind::Ros34pw2 && s.rtol <= kRosRtolMax) a = 6 * s.rtol;
  return a <= kAccuracyMax ? std::max(a, kAccuracyMin) : std::numeric_limits<double>::quiet_NaN();
}

std::string accuracyRule(double accuracy) {
  if (std::isfinite(accuracy) && accuracy >= kAccuracyMin && accuracy <= kAccuracyMax) return "";
  char buf[160];
  std::snprintf(buf, sizeof buf, "must be a relative accuracy between %g and %g", kAccuracyMin, kAccuracyMax);
  return buf;
}

Scene withSolver(const Scene& scene, IntegratorKind kind, double tolerance) {
  Scene sc = scene;
  Settings& s = sc.model.settings;
  s.integrator = kind;
  s.stiffSwitchRtol = 0;  // (each integrator on its own)
  s.accuracy = 0;         // (explicit settings: no accuracy's second run of a flat peak either)
  if (kind == IntegratorKind::DormandPrince || isRosenbrock(kind)) {
    s.rtol = tolerance;
    s.atol = tolerance * 1e-2;
  } else {
    s.step = tolerance;
  }
  return sc;
}

Scene withAccuracy(const Scene& scene, double accuracy) {
  Scene sc = scene;
  applyAccuracy(sc.model.settings, accuracy);
  return sc;
}

std::string integratorName(IntegratorKind k) {
  switch (k) {
    case IntegratorKind::DormandPrince: return "dopri5";
    case IntegratorKind::Ros34pw2: return "ros34pw2";
    case IntegratorKind::Ros2: return "ros2";
    case IntegratorKind::RK4: return "rk4";
    case IntegratorKind::SemiImplicitEuler: return "euler";
  }
  return "?";
}

}  // namespace lg
