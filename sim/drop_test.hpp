// Drop tests of a gear scene: one case is one run of the engine from touchdown, with the outputs
// seed-gear.md asks for (time histories, peaks, efficiencies, energy balance).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "sim/io/scene.hpp"
#include "sim/integrators.hpp"

namespace lg {

// Per-case figures (definitions in seed-gear.md). Peaks are refined on the dense output.
struct CaseMetrics {
  std::string name;
  bool ok = true;
  std::string message;                 // why a run failed
  double peak_load_N = 0;              // max P_y (sum of the tyre loads)
  double t_peak_s = 0;
  double load_factor = 0;              // P_y,max / (G g)
  double stroke_max_m = 0;             // max s (first strut)
  double h_max_m = 0;                  // max airframe displacement
  double tyre_deflection_max_m = 0;    // max delta
  double efficiency = 0;               // integral(P_y dh) / (P_y,max h_max) over the compression
  double strut_efficiency = 0;         // integral(P_a ds) / (P_a,max s_max) over the compression
  double energy_absorbed_J = 0;        // dissipated by orifices, friction and impacts
  double energy_balance_error = 0;     // |E(t_end) - E(0)| / E_kin(0)
  double constraint_violation_max = 0; // [m] largest |C| of an enforced row seen at a step end
  double strut_force_max_N = 0;        // max P_a
  double rebound_h_min_m = 0;          // min h after the compression (rebound height; negative = above touchdown)
  bool bottomed = false;               // a stop of the "no nearer" form was ever enforced
  long steps = 0;
  long rhs_evaluations = 0;
  double wall_time_s = 0;
};

// One time-history sample.
struct Sample {
  double t, P_y, s, h, delta, P_a;
  std::vector<double> stopLambda;  // per stop
  double violation;
};

struct CaseOptions {
  bool record = false;       // keep every step's sample
  std::function<bool()> stop;  // polled each step (Ctrl-C); null = never
};

struct CaseResult {
  CaseMetrics metrics;
  std::vector<Sample> samples;
  std::vector<std::string> stopNames;
  std::vector<double> initialEnergy;  // unused placeholder for future reporting
};

// The model of a case: the scene's model with the case's masses and lift applied.
Model<double> caseModel(const Scene& scene, const DropCase& c);
// Initial state of a case: scene positions, every body moving at sinkSpeed against gravity.
State<double> caseState(const Scene& scene, const Model<double>& m, const DropCase& c);

CaseResult runCase(const Scene& scene, const DropCase& c, const CaseOptions& opt = {});

// Runs several cases (OpenMP, one case per thread); results identical to a serial run.
std::vector<CaseResult> runCases(const Scene& scene, const std::vector<DropCase>& cases, int threads,
                                 const CaseOptions& opt = {});

// Static stroke: the strut stroke after settling under 1 g without lift from rest (seconds of
// simulated time, friction included), for the first strut. Returns NaN and sets 'message' on failure.
double staticStroke(const Scene& scene, std::string* message = nullptr, double duration = 3.0);

}  // namespace lg
