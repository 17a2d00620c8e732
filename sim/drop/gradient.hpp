// Exact derivatives of a drop test's metrics with respect to design parameters: forward mode with
// ceres::Jet through the whole run (integrator, event location, plastic impacts and mode switches,
// refined extrema; see sim/drop/observer.hpp for the rules), several parameters per pass (kJetWidth)
// and as many passes as needed. The derivatives differentiate the adaptive run as it steps (its step
// sizes, chosen on values, are constants to it): at a tight tolerance they approach the exact
// sensitivities of the model.
//
// Honesty at kinks: where the design sits on a kink of a metric the derivative is one-sided, and the
// result says so per metric, with the side it belongs to:
//  - two maxima of P_y(t) within 0.1 %: the peak load (and what is divided by it) can jump between them;
//  - the strut reaches its bottoming stop with an approach speed below 1e-3 of the sink speed, or stays
//    clear of it by less than 1e-3 of S_max: bottoming begins at this design;
//  - the rebound velocity with lift equal to the weight: after lift-off no net force acts, and with L > 1
//    the largest upward velocity moves to the end of the run (one-sided in the lift ratio);
//  - a strut with regularised friction sticks (|s'| within ten times the friction velocity, longer than a
//    passage) before the metric is reached: the derivative is the regularised friction's, not the
//    Coulomb limit's (listed last in the note). With exact Coulomb friction (friction = "coulomb") stick
//    and slip are events whose times are differentiated: no note.
#pragma once

#include <string>
#include <vector>

#include "sim/drop/run.hpp"
#include "sim/core/input_error.hpp"
#include "sim/drop/metrics.hpp"
#include "sim/scene/parameters.hpp"

namespace lg {

constexpr int kJetWidth = 4;  // parameters per forward-mode pass

struct MetricDerivative {
  std::string metric;       // a name of gradientMetrics()
  double value = 0;         // the metric [its unit]
  std::vector<double> d;    // d metric / d parameter_j [metric unit / parameter unit]
  bool smooth = true;       // false: a kink at this design, 'd' is one-sided
  std::string note;         // why not smooth, and the side 'd' belongs to
};

struct CaseGradient {
  std::string caseName;
  bool ok = true;
  std::string message;                    // why the run failed
  CaseMetrics values;                     // the run's metrics (the Jet run's values: the double run's to round-off)
  std::vector<std::string> parameters;    // paths, in the order of 'd'
  std::vector<MetricDerivative> metrics;  // gradientMetrics() order
  const MetricDerivative* find(const std::string& metric) const;
};

// The metrics with derivatives: peak_load, t_peak, load_factor, inertia_load_factor, stroke,
// stroke_margin, h_max, tyre_deflection, tyre_margin, efficiency, strut_efficiency, strut_force,
// energy_absorbed, rebound_velocity (units from the catalogue).
const std::vector<MetricInfo>& gradientMetrics();

// The SI unit of a parameter ("m^2" for an orifice area, "Pa" for a pressure, "-" for a ratio).
std::string parameterUnit(const Scene& scene, const Parameter& p);

// The derivatives of a case's metrics with respect to 'params' at the scene's values. A case
// parameter (sink_speed, lift_ratio) acts on its own case only; 'duration' has no derivative (an
// InputError where resolved for gradients: see checkGradientParameter). 'width' parameters per pass
// (1 .. kJetWidth); the derivatives do not depend on it.
// Under an accuracy setting a case whose peak is flat or has a twin is differentiated at the tighter
// accuracy runCase runs it at last (nextAccuracy; CaseMetrics::accuracy_rerun in 'values').
CaseGradient caseGradient(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params,
                          int width = kJetWidth);

// The time histories of a case at given times with their derivatives (the exact Jacobian of a
// calibration): value[r][c] of column c (historyColumns(scene)) at times[r], d[r][c][j] its derivative
// with respect to params[j] at that fixed time, and with 'rates' rate[r][c], its derivative in time
// along the integrator's dense output (0 in a row at t = 0, which precedes the first step). The rows
// are those of CaseOptions::outputTimes (strictly increasing in [0, duration]); a row at an event's
// time is its left limit, and its derivatives are the left side's (the state jumps there). Passes of
// up to kJetWidth components as in caseGradient, the rates taking one component. Under an accuracy
// setting a case whose peak is flat or has a twin gives the histories of runCase's last run (nextAccuracy).
struct HistoryGradient {
  bool ok = true;
  std::string message;                          // why the run failed
  std::vector<double> times;                    // [s]
  std::vector<std::vector<double>> value;       // [row][column]
  std::vector<std::vector<std::vector<double>>> d;  // [row][column][parameter]
  std::vector<std::vector<double>> rate;        // [row][column] [unit/s] (with rates)
};
HistoryGradient caseHistoryGradient(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params,
                                    const std::vector<double>& times, bool rates, int width = kJetWidth);

// Throws InputError(where, 0, path, rule) for a parameter that has no derivative (a case duration).
void checkGradientParameter(const Parameter& p, const std::string& where);

}  // namespace lg
