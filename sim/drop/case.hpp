// A drop case's vocabulary: what one run measures (CaseMetrics: peaks, efficiencies, energy balance, and
// the limits a loads engineer checks, stroke left to each bottoming stop and each tyre's deflection
// limit), its time histories, and how a case is laid on the scene's model and initial state. The run
// itself is sim/drop/run.hpp; the observer that measures it sim/drop/observer.hpp.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"
#include "sim/drop/hang.hpp"
#include "sim/engine/integrators.hpp"

namespace lg {

// One shock absorber over a drop (its own stroke, force and efficiency: a twin-strut gear is never
// measured on its first strut alone).
struct StrutMetrics {
  std::string name;
  double stroke_max_m = 0;      // max s
  double stroke_limit_m = std::numeric_limits<double>::quiet_NaN();  // S_max at its bottoming stop (NaN: none)
  double stroke_margin_m = std::numeric_limits<double>::quiet_NaN(); // S_max - s_max (NaN: no bottoming stop)
  double force_max_N = 0;       // max P_a
  double efficiency = 0;        // eta_s = integral(P_a ds) / (P_a,max s_max), integral up to s_max
  double work_J = 0;            // integral(P_a ds) up to s_max
};

// One tyre over a drop.
struct TyreMetrics {
  std::string name;
  double deflection_max_m = 0;  // max delta
  double deflection_limit_m = 0;  // delta_max of the tyre
  double margin_m = 0;          // delta_max - max delta (negative: over its limit)
  double load_max_N = 0;        // max P_t
  bool longitudinal = false;    // the tyre declares mu_x (drag_max_N is its)
  double drag_max_N = 0;        // max P_x, the drag load (positive aft)
};

// Per-case figures (definitions in docs/metrics.md). Peaks are refined on the dense
// output; the compression integrals run from touchdown to the maximum they are normalised by.
struct CaseMetrics {
  std::string name;
  bool ok = true;
  std::string message;                 // why a run failed
  double sink_speed_mps = 0;           // V_y0 of the case
  double lift_ratio = 0;               // L of the case
  double forward_speed_mps = 0;        // V_x of the case (the ground under the tyres that declare mu_x)
  bool longitudinal = false;           // a tyre declares mu_x: the drag figures below are its
  double drag_peak_N = 0;              // max P_x, P_x = sum of the tyres' drag loads (spin-up, spring-back)
  double t_drag_peak_s = 0;
  double springback_peak_N = 0;        // max -P_x: the forward load of spring-back (the leg swinging back after spin-up)
  double t_springback_s = 0;
  double drag_at_peak_N = 0;           // P_x at t_peak, when the vertical load is largest (design drag: >= 0.25 P_y,max)
  double mass_kg = 0;                  // W: total mass of the scene in this case
  double peak_load_N = 0;              // max P_y, P_y = sum of the tyre loads
  double t_peak_s = 0;
  // [-] the condition of t_peak, kappa = P_y,max / (|P_y''| t_peak^2): a load error whose slope is a
  // fraction e of P_y,max / t_peak moves t_peak by kappa e of itself (t* moves by P'/|P''|). A peak shaped
  // as a half sine has 4 / pi^2 = 0.41; a flat one more. NaN where the peak is no smooth maximum (a kink).
  double t_peak_condition = std::numeric_limits<double>::quiet_NaN();
  // [-] the next-highest maximum of P_y inside the run (another hump of the load): its height's gap below
  // the peak, (P_y,max - P_2) / P_y,max, and [s] its time; NaN where the load has no other maximum.
  double second_peak_gap = std::numeric_limits<double>::quiet_NaN();
  double t_second_peak_s = std::numeric_limits<double>::quiet_NaN();
  double load_factor = 0;              // n_g = P_y,max / (W g)
  double inertia_load_factor = 0;      // n = n_g + L (Part 23, 23.473)
  double stroke_max_m = 0;             // max over the struts of their max stroke
  double stroke_margin_m = std::numeric_limits<double>::quiet_NaN();  // min over struts of S_max - s_max
  double h_max_m = 0;                  // max airframe displacement
  double tyre_deflection_max_m = 0;    // max over the tyres of their max deflection
  double tyre_margin_m = std::numeric_limits<double>::quiet_NaN();  // min over tyres of delta_max - delta
  double efficiency = 0;               // eta = integral(P_y dh) / (P_y,max h_max), integral up to h_max
  double strut_efficiency = 0;         // min over the struts of eta_s
  double strut_force_max_N = 0;        // max over the struts of P_a,max
  double energy_absorbed_J = 0;        // work of the gear over the compression: integral(P_y dh) up to h_max
  double energy_to_absorb_J = 0;       // E = W V^2 / 2 + (1 - L) W g h_max (certification.md)
  double energy_dissipated_J = 0;      // dissipated by orifices, friction, dampers, tyre slip and impacts over the run
  double energy_balance_error = 0;     // |E(T) - E(0)| / (E_kin(0) + |U_ext(T) - U_ext(0)| + W_g), E = kinetic +
                                       // stored + dissipated - W_g, U_ext the potential of gravity and lift,
                                       // W_g the moving ground's work on the tyres (forward speed; else 0)
  double constraint_violation_max = 0; // [m] largest |C| of an enforced row seen at a step end
  double rebound_velocity_mps = 0;     // largest upward airframe velocity after the compression (>= 0)
  bool compression_ended = false;      // h reached its maximum within the duration
  bool bottomed = false;               // a stop of the "no nearer" form was ever enforced
  std::vector<StrutMetrics> struts;
  std::vector<TyreMetrics> tyres;
  long steps = 0;
  long rhs_evaluations = 0;
  bool stiff_switch = false;            // the run's settings let dopri5 hand over to ros34pw2 (an accuracy setting)
  double stiff_from_s = std::numeric_limits<double>::quiet_NaN();  // [s] where dopri5 found the run stiff and
                                       // went on with ros34pw2 to the end (Settings::stiffSwitchRtol); NaN: it never did
  int stiff_handbacks = 0;             // hand-overs to ros34pw2 that cost more than dopri5 and were handed back
  double accuracy = 0;                 // [-] the accuracy the run's settings were chosen for (0: none; Settings::accuracy)
  double accuracy_rerun = std::numeric_limits<double>::quiet_NaN();  // [-] the tighter accuracy the case was run
                                       // again at last because its peak was flat or had a twin (nextAccuracy,
                                       // sim/drop/accuracy.hpp); NaN: it was not. Steps, evaluations and wall time
                                       // count every run.
  std::string accuracy_rerun_reason;   // why it was run again (nextReason of each run), empty if it was not
  double wall_time_s = 0;

  // Within every declared limit: no bottoming, every stroke margin >= 0, every tyre within delta_max, and
  // the compression ended within the run (a run cut short measured no peak).
  bool withinLimits() const;
  // The limits it breaks, for people ("bottomed", "tyre 0.1096 m > delta_max 0.1 m"); empty if none.
  std::string limitViolations() const;
};

// A column of the time histories: name and SI unit ("P_y", "N"). Only what the scene declares has a
// column: no tyre, no P_y and delta; no strut, no s, s_dot, p_1, P_a, P_gas, P_friction, P_orifice*.
struct Column {
  std::string name, unit;
};
// The columns of a scene's time histories after t [s]: P_y, h, each tyre's delta (and P_t with several
// tyres, P_x with a longitudinal force), each strut's internals (s, s_dot, p_1, P_a, P_gas, P_friction, P_orifice1, P_orifice2 and
// p_2 when declared; suffixed "_<strut>" with several struts), each stop's force F_<stop>, and violation.
std::vector<Column> historyColumns(const Scene& scene);

// One row of the time histories: t [s] and the values of the columns.
struct Sample {
  double t = 0;
  std::vector<double> values;
};

struct CaseOptions {
  bool record = false;         // keep time histories
  double outputInterval = 0;   // [s] > 0: rows at t = 0, DT, 2 DT, ... from the dense output; 0: one per step
  // [s] rows at exactly these times from the dense output (a measurement's samples), strictly increasing
  // in [0, duration] (runCase throws std::invalid_argument otherwise); t = 0 only when listed. Replaces
  // outputInterval when not empty. The run itself is unchanged.
  std::vector<double> outputTimes;
  std::function<bool()> stop;  // polled each step (Ctrl-C); null = never
};

struct CaseResult {
  CaseMetrics metrics;
  std::vector<Column> columns;  // historyColumns(scene) when recorded
  std::vector<Sample> samples;
  // The index of a column by name (-1 if the scene has none such).
  int column(const std::string& name) const;
};

// The total mass [kg] of a case: the scene's bodies with the case's mass overrides.
double caseMass(const Scene& scene, const DropCase& c);
// Applies a case to a model of the scene (any scalar): the case's masses, the lift L G g on the lift
// elements with G the total mass (L and the masses may carry derivatives), and the forward speed V_x
// under the tyres with a longitudinal force.
// The envelope's point (sim/scene/envelope.hpp) is the case's corner, or the scene's point; 'at' (optional)
// replaces it with one that may carry derivatives (an envelope quantity as a parameter).
template <class S>
void applyCase(const Scene& scene, Model<S>& m, const DropCase& c, const S& liftRatio, const EnvelopePoint<S>* at = nullptr) {
  if (scene.envelope.declared) applyEnvelope(scene.envelope, m, at ? *at : casePoint(scene, c).template cast<S>());
  for (const auto& [name, mass] : c.masses) m.bodies[m.bodyIndex(name)].mass = S(mass);
  for (int ti : scene.roles.tyres) {
    auto& t = std::get<Tyre<S>>(m.forces[ti].type);
    if (t.longitudinal) t.groundSpeed = S(c.forwardSpeed);
  }
  S G = S(0);  // [kg] total mass
  for (const auto& b : m.bodies) G += b.mass;
  for (int li : scene.roles.lifts) {
    auto& f = m.forces[li];
    auto& cf = std::get<ConstantForce<S>>(f.type);
    const Vec3<double> dir = std::get<ConstantForce<double>>(scene.model.forces[li].type).force;  // unit
    f.liftRatio = liftRatio;
    cf.force = dir.template cast<S>() * (liftRatio * G * S(scene.gravity));
  }
}
// Initial state of a case: scene positions (the gear hanging on its elastic extension stops, sim/drop/hang.hpp;
// raised by dropHeight [m] for a drop from a height), every body moving at the sink speed against
// gravity. Where the hang does not settle, 'problem' says why and the positions are NaN.
template <class S> State<S> caseState(const Scene& scene, const Model<S>& m, const S& sinkSpeed, double dropHeight = 0,
                                      std::string* problem = nullptr) {
  State<S> s(m);
  s.y = scene.initial.y.template cast<S>();
  s.lambda = scene.initial.lambda.template cast<S>();
  s.active = scene.initial.active;
  const int N = m.nBodies();
  std::string why;
  if (!hangOnPads(scene, m, s.y, &why)) {
    s.y.head(7 * N).setConstant(S(std::numeric_limits<double>::quiet_NaN()));
    if (problem) *problem = why;
  }
  for (int b = 0; b < N; ++b) {
    s.y.template segment<3>(7 * b) += (dropHeight * scene.up).template cast<S>();
    s.y.template segment<3>(7 * N + 6 * b) = -sinkSpeed * scene.up.template cast<S>();
    s.y.template segment<3>(7 * N + 6 * b + 3).setZero();
  }
  s.t = S(0);
  return s;
}
// The model of a case: the scene's model with the case's masses and lift applied.
Model<double> caseModel(const Scene& scene, const DropCase& c);
// Initial state of a case: scene positions, every body moving at sinkSpeed against gravity.
State<double> caseState(const Scene& scene, const Model<double>& m, const DropCase& c, std::string* problem = nullptr);

}  // namespace lg
