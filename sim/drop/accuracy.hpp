// Accuracy on demand: which integrator and tolerances give the reported metrics of a drop to a requested
// relative accuracy (the work-precision data behind the calibration: sim/drop/work_precision.hpp).
//
// The mapping (settingForAccuracy) is the one place that turns an accuracy into solver settings; the
// command line (--accuracy), the scene and study parsers ([solver] accuracy) call it. It was calibrated on
// every shipped scene and case (tests/sim/drop/accuracy_test.cpp checks it at 1e-2, 1e-3, 1e-4 against runs at
// rtol 1e-10): the largest relative error of the metrics below stays under the accuracy asked for.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/drop/case.hpp"

namespace lg {

// The metrics an accuracy promise covers and their relative errors against a reference run: peak load,
// its time, max stroke, max airframe travel h, max tyre deflection, efficiency, the struts' peak force
// P_a,max, and the peak drag load P_x,max of spin-up (a tyre with mu_x, in a drop with a forward speed).
// A metric whose reference is zero (a scene without tyre or strut) counts as exact. Without a forward
// speed the drag is not covered: it is then the contact point's scrub held by the regularised static
// friction (the main gear: 295 N, 0.24 % of P_y, with f1 x 0.6 at 2.5 m/s), a stiff mode's transient
// that the loose settings do not resolve (2.2 kN at 1e-2; 2.3 % off at 1e-4), where with spin-up it is
// within 0.42 A (bench/accuracy_sweep).
struct MetricErrors {
  double peakLoad = 0, tPeak = 0, stroke = 0, travel = 0, tyreDeflection = 0, efficiency = 0, strutForce = 0,
         dragPeak = 0;
  double max() const;
};
MetricErrors metricErrors(const CaseMetrics& m, const CaseMetrics& reference);

// Solver settings for a relative accuracy of the metrics.
struct AccuracySetting {
  IntegratorKind integrator = IntegratorKind::DormandPrince;
  double rtol = 1e-6, atol = 1e-8;  // [-], [m, m/s, rad/s]
  double maxStep = 1e-2;            // [s]
  double stiffSwitchRtol = 0;       // [-] dopri5 goes on with ros34pw2 at this rtol once it finds the run stiff
};
constexpr double kAccuracyMin = 1e-5;  // the range of accuracies the mapping covers (below 1e-5 the time
                                       // of a flat peak is not defined that well: two maxima within 1e-6 s)
constexpr double kAccuracyMax = 1e-1;
constexpr double kAccuracyTightEnd = 1e-4;  // below it ros34pw2 at accuracy / 8 (settingForAccuracy)
// ros34pw2 is never run looser than rtol kRosRtolMax for an accuracy: above it its error no longer
// follows its tolerance (bench/accuracy_sweep: up to 9 .. 12 times rtol at 3e-3 .. 1e-2, against 3.6
// at 1.7e-3). Accuracies looser than kAccuracyLooseEnd (= 6 kRosRtolMax) therefore all run the setting
// of kAccuracyLooseEnd, and deliver it (accuracyDelivered).
constexpr double kRosRtolMax = 2e-3;
constexpr double kAccuracyLooseEnd = 6 * kRosRtolMax;
AccuracySetting settingForAccuracy(double accuracy);
// The accuracy settingForAccuracy(accuracy) is calibrated to deliver: min(accuracy, kAccuracyLooseEnd).
// The second-run rules below test the first run's metrics against it.
double accuracyDelivered(double accuracy);
// The time of a flat peak. The calibration's cases have t_peak conditions (CaseMetrics::t_peak_condition,
// kappa) up to 1.22; at kappa up to kFlatPeakCondition their t_peak errors stay below 0.66 of the
// accuracy. A flatter peak moves its time further for the same error in the load's slope: the nose gear
// at 1 m/s with full lift (kappa 3.37) missed it by 1.44 times the accuracy at 1e-4 (0.99 at 1e-3) while
// its other metrics stayed within 0.13 of it. Its case is then run again at the accuracy
//   A' = A / f,  f = kappa / kFlatPeakCondition rounded up to a power of 2^(1/4)   (A' >= kFlatPeakAccuracyMin),
// which holds the slope error f times tighter (the grid: a double and a Jet run of the case, whose kappa
// agree to round-off, take the same A'). Returns A', or 0 where no second run is needed: kappa
// accuracyDelivered(A) / kFlatPeakCondition <= A (kappa NaN, or no accuracy asked for, too). Looser
// than kAccuracyLooseEnd the first run is more accurate than asked, and a flat peak may need nothing more.
constexpr double kFlatPeakCondition = 1.25;
constexpr double kFlatPeakAccuracyMin = 1e-6;
double flatPeakAccuracy(double accuracy, double tPeakCondition);
// Two peaks of nearly one height. Where P_y has another maximum whose height is within 2 a of the peak's
// (a = accuracyDelivered(A') for the run at A'; CaseMetrics::second_peak_gap < kClosePeaksFactor a:
// each height within a, their order is not decided at that accuracy) and whose time is more than
// A t_peak away from it (A the accuracy asked for), the peak's time may jump from one to the other: the
// nose gear with f1 at 0.6 of its own, at 1.5 m/s without lift, has humps at 0.085 s and 0.235 s
// 0.135 % apart, and its run at 1e-2 saw them within 4e-5 and reported the first (a t_peak error of 64
// times the accuracy; every other metric within 0.6 of it). Its case is then run again at
//   A'' = a / f,  f = kClosePeaksFactor a / gap rounded up to a power of 2^(1/4), at most kClosePeaksStep
//   (A'' >= kFlatPeakAccuracyMin),
// and again from that run while its own gap does not order the two (nextAccuracy): a measured gap
// within the error of its heights says little of the true one (4e-5 measured, 1.35e-3 true), so one
// step to the accuracy it seems to ask for can overpay (1e-2 / 512 there, 6.3 times one run's cost; in
// a step of at most 32, 1e-2 / 32 orders them, for 4.0 times). Over the sweep (bench/accuracy_sweep), against
// one step to what the first gap asks for: steps of at most 16 cost 2.0 % more evaluations at 0.1 (a third
// run where 1/16 fell just short) and 0.6 % less at 1e-2; 32, 0.4 % more and 0.5 % less; unlimited
// steps (each run checked), 0.4 % more at both; 3e-3 and 1e-3 the same. Returns A'', or 0 where no
// further run is needed or the floor was run. 'asked' (0: 'ran') is the accuracy asked for, 'ran' the run's.
constexpr double kClosePeaksFactor = 2;
constexpr double kClosePeaksStep = 32;
double closePeaksAccuracy(double ran, double tPeak, double secondPeakGap, double tSecondPeak, double asked = 0);
// The accuracy a case is run again at after its first run (the tighter of flatPeakAccuracy and
// closePeaksAccuracy for its metrics), or 0 for none.
double rerunAccuracy(double accuracy, const CaseMetrics& first);
// The accuracy a case is run at next after a run at 'ran' for the accuracy 'asked': after the first
// (ran == asked) rerunAccuracy, after a later one the close-peaks rule alone (the flat-peak rule's one
// run was enough), 0 for none. runCase, caseGradient and caseHistoryGradient all follow it.
double nextAccuracy(double asked, double ran, const CaseMetrics& run);
// Why (for people): "flat peak (t_peak condition 3.37 > 1.25)", "two peaks within 0.0051 % (t = 0.08535 s
// and 0.2345 s)", or both, for the first run; "at 0.000625 still within 0.096 %" for a later one
// (ran < asked). Empty where nextAccuracy is 0.
std::string rerunReason(double accuracy, const CaseMetrics& first);
std::string nextReason(double asked, double ran, const CaseMetrics& run);
// "; closer than any accuracy decides: t_peak may be either" where the last run, at 'ran', still does
// not order two peaks (the floor kFlatPeakAccuracyMin was run); empty otherwise.
std::string undecidedPeaks(double asked, double ran, const CaseMetrics& last);
// Marks 'again' (the run at 'rerun', after 'before' at 'ran' for the accuracy 'asked') as a later run:
// the accuracy asked for, A', the reasons so far, and the cost of every run.
void markRerun(CaseMetrics& again, const CaseMetrics& before, double asked, double ran, double rerun);
void applyAccuracy(Settings& s, double accuracy);

// Solver settings given over a scene's [solver], by a study's or a calibration's [solver] table or on
// simulate's command line (--integrator, --rtol, --atol, --step, --accuracy): one rule for the three, the
// one a scene's own [solver] follows, so that a written scene (best.toml) that says them runs the same.
//  - accuracy chooses integrator, rtol, atol and max_step (applyAccuracy): none of the first three with it;
//  - an integrator, rtol or atol over a scene's accuracy replaces it: what the accuracy chose goes back
//    to the defaults (as if the scene's [solver] had not said it), then the given values apply;
//  - rtol (< 1) sets atol = rtol / 100 unless atol is given; step sets the fixed (first trial) step.
struct SolverOverrides {
  std::optional<IntegratorKind> integrator{};
  std::optional<double> rtol{}, atol{}, step{}, accuracy{};  // [-], [m, m/s, rad/s], [s], [-] (each > 0: the readers check)
  bool empty() const { return !integrator && !rtol && !atol && !step && !accuracy; }
};
// The first override that breaks a rule: its key (as 'prefix' + the [solver] key: "rtol", "--rtol") and
// the rule; nothing where they all hold.
std::optional<std::pair<std::string, std::string>> solverOverridesProblem(const SolverOverrides& o,
                                                                         const std::string& prefix = "");
void applySolverOverrides(Settings& s, const SolverOverrides& o);
// The relative accuracy of the metrics that solver settings give, by the same calibration read backwards:
// 'accuracy' if the settings came from one, dopri5 at rtol r about r, ros34pw2 at rtol r <= kRosRtolMax
// about 6 r; NaN for the integrators the calibration does not cover (ros2, rk4, euler) or tolerances
// beyond it (ros34pw2 looser than kRosRtolMax among them).
double impliedAccuracy(const Settings& s);
// Why an accuracy value is not accepted ("" if it is): the rule for messages of the parsers and the CLI.
std::string accuracyRule(double accuracy);

// The scene with its solver set for one point: an adaptive integrator at rtol = tolerance (atol = rtol /
// 100), a fixed-step one at step = tolerance. It replaces an accuracy setting of the scene (no hand-over,
// no second run of a flat peak: the point is the setting it names).
Scene withSolver(const Scene& scene, IntegratorKind kind, double tolerance);
// The scene with its solver set for 'accuracy' (applyAccuracy): a flat peak's second run.
Scene withAccuracy(const Scene& scene, double accuracy);
// The scene-file name of an integrator ("dopri5", "ros34pw2", ...).
std::string integratorName(IntegratorKind kind);

}  // namespace lg
