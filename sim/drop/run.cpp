// Drop tests: one case = one engine run from touchdown, observed step by step.
#include "sim/drop/run.hpp"

#include "sim/drop/accuracy.hpp"
#include "sim/drop/observer.hpp"
#include "sim/core/format.hpp"  // shortNumber

#include <omp.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace lg {

CaseMetrics caseMetrics(const CaseFigures<double>& F, const Scene& scene, const DropCase& c) {
  CaseMetrics M;
  M.name = c.name;
  M.sink_speed_mps = touchdownSpeed(c, scene.gravity);  // (at touchdown: a drop from a height's too)
  M.lift_ratio = c.liftRatio;
  M.forward_speed_mps = c.forwardSpeed;
  M.drag_peak_N = F.drag_peak;
  M.t_drag_peak_s = F.t_drag_peak;
  M.springback_peak_N = F.springback_peak;
  M.t_springback_s = F.t_springback;
  M.drag_at_peak_N = F.drag_at_peak;
  M.mass_kg = F.mass;
  M.peak_load_N = F.peak_load;
  M.t_peak_s = F.t_peak;
  if (F.peakCurvature < 0 && F.t_peak > 0 && F.peak_load > 0)
    M.t_peak_condition = F.peak_load / (-F.peakCurvature * F.t_peak * F.t_peak);
  if (const auto [t2, P2] = secondLoadHump(F); std::isfinite(P2) && F.peak_load > 0) {
    M.second_peak_gap = (F.peak_load - P2) / F.peak_load;
    M.t_second_peak_s = t2;
  }
  M.load_factor = F.load_factor;
  M.inertia_load_factor = F.inertia_load_factor;
  M.stroke_max_m = F.stroke_max;
  M.stroke_margin_m = F.stroke_margin;
  M.h_max_m = F.h_max;
  M.tyre_deflection_max_m = F.tyre_deflection_max;
  M.tyre_margin_m = F.tyre_margin;
  M.efficiency = F.efficiency;
  M.strut_efficiency = F.strut_efficiency;
  M.strut_force_max_N = F.strut_force_max;
  M.energy_absorbed_J = F.energy_absorbed;
  M.energy_to_absorb_J = F.energy_to_absorb;
  M.energy_dissipated_J = F.energy_dissipated;
  M.energy_balance_error = F.energy_balance_error;
  M.constraint_violation_max = F.constraint_violation_max;
  M.rebound_velocity_mps = F.rebound_velocity;
  M.compression_ended = F.compression_ended;
  M.bottomed = F.bottomed;
  for (size_t k = 0; k < F.struts.size(); ++k) {
    const auto& St = F.struts[k];
    M.struts.push_back({scene.model.forces[scene.roles.struts[k]].name, St.stroke_max, St.stroke_limit, St.stroke_margin,
                        St.force_max, St.efficiency, St.work});
  }
  for (size_t k = 0; k < F.tyres.size(); ++k) {
    const auto& T = F.tyres[k];
    const auto& t = std::get<Tyre<double>>(scene.model.forces[scene.roles.tyres[k]].type);
    M.tyres.push_back({scene.model.forces[scene.roles.tyres[k]].name, T.deflection_max, T.deflection_limit, T.margin, T.load_max,
                       t.longitudinal, T.drag_max});
    M.longitudinal = M.longitudinal || t.longitudinal;
  }
  return M;
}

namespace {

// One run of a case at the scene's settings.
CaseResult runOnce(const Scene& scene, const DropCase& c, const CaseOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult res;
  const Model<double> m = caseModel(scene, c);
  std::string hang;
  State<double> s = caseState(scene, m, c, &hang);
  if (!hang.empty()) {  // (no run: the gear has no hanging configuration to start from)
    res.metrics.name = c.name;
    res.metrics.sink_speed_mps = touchdownSpeed(c, scene.gravity);
    res.metrics.lift_ratio = c.liftRatio;
    res.metrics.ok = false;
    res.metrics.message = hang;
    return res;
  }
  Workspace<double> w(m);
  DropObserver<double> obs(scene, m, c, c.sinkSpeed, c.liftRatio, opt, &res);
  const RunStatus st = simulate(m, s, w, c.duration, obs);
  res.metrics = caseMetrics(obs.finish(s, w), scene, c);
  res.metrics.ok = st.ok;
  res.metrics.message = st.message;
  res.metrics.steps = st.steps;
  res.metrics.rhs_evaluations = w.rhsEvaluations;
  res.metrics.stiff_switch = m.settings.stiffSwitchRtol > 0;
  res.metrics.stiff_from_s = st.stiffFrom;
  res.metrics.stiff_handbacks = st.handBacks;
  res.metrics.accuracy = m.settings.accuracy;
  res.metrics.constraint_violation_max = std::max(res.metrics.constraint_violation_max, st.maxPositionViolation);
  auto& M = res.metrics;
  for (double v : {M.peak_load_N, M.stroke_max_m, M.h_max_m, M.tyre_deflection_max_m, M.efficiency, M.strut_efficiency,
                   M.energy_absorbed_J, M.energy_dissipated_J, M.energy_balance_error, M.rebound_velocity_mps})
    if (!std::isfinite(v) && M.ok) {
      M.ok = false;
      M.message = "non-finite result";
    }
  res.metrics.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

}  // namespace

CaseResult runCase(const Scene& scene, const DropCase& c, const CaseOptions& opt) {
  for (size_t k = 0; k < opt.outputTimes.size(); ++k) {
    const double t = opt.outputTimes[k];
    if (!(t >= 0 && t <= c.duration) || (k > 0 && !(t > opt.outputTimes[k - 1])))
      throw std::invalid_argument("output time " + shortNumber(t, 4) + " s (row " + std::to_string(k) +
                                  "): the times must increase strictly within [0, duration = " + shortNumber(c.duration, 4) + " s]");
  }
  // A flat peak, or two of nearly one height: its time needs a tighter accuracy than the other metrics,
  // and two close peaks may need more than one step to order them (nextAccuracy, sim/drop/accuracy.hpp).
  const double asked = scene.model.settings.accuracy;
  CaseResult res = runOnce(scene, c, opt);
  for (double ran = asked, next; res.metrics.ok && !(opt.stop && opt.stop()) &&
                                 (next = nextAccuracy(asked, ran, res.metrics)) > 0;
       ran = next) {
    CaseResult again = runOnce(withAccuracy(scene, next), c, opt);
    markRerun(again.metrics, res.metrics, asked, ran, next);
    res = std::move(again);
  }
  if (std::isfinite(res.metrics.accuracy_rerun))
    res.metrics.accuracy_rerun_reason += undecidedPeaks(asked, res.metrics.accuracy_rerun, res.metrics);
  return res;
}

std::vector<CaseResult> runCases(const Scene& scene, const std::vector<DropCase>& cases, int threads,
                                 const CaseOptions& opt) {
  // Cases that differ only by name (same sink speed, lift ratio, duration and effective masses: a
  // scene's "limit" and the matrix's limit case, say) run once; their results are copied, renamed.
  auto key = [&](const DropCase& c) {
    std::vector<double> k{c.sinkSpeed, c.liftRatio, c.duration, c.forwardSpeed};
    const EnvelopePoint<double>& p = casePoint(scene, c);
    k.insert(k.end(), {p.temperature, p.charge, p.gasVolume, p.oilLevel, p.orifice, p.tyreStiffness});
    for (const auto& b : scene.model.bodies) {
      const auto it = c.masses.find(b.name);
      k.push_back(it == c.masses.end() ? b.mass : it->second);
    }
    return k;
  };
  std::vector<int> first(cases.size());
  std::vector<int> unique;
  for (size_t i = 0; i < cases.size(); ++i) {
    first[i] = static_cast<int>(i);
    for (int u : unique)
      if (key(cases[u]) == key(cases[i])) first[i] = u;
    if (first[i] == static_cast<int>(i)) unique.push_back(static_cast<int>(i));
  }
  std::vector<CaseResult> out(cases.size());
  const int n = static_cast<int>(unique.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads))
  for (int i = 0; i < n; ++i) out[unique[i]] = runCase(scene, cases[unique[i]], opt);
  for (size_t i = 0; i < cases.size(); ++i)
    if (first[i] != static_cast<int>(i)) {
      out[i] = out[first[i]];
      out[i].metrics.name = cases[i].name;
    }
  return out;
}

double staticStroke(const Scene& scene, std::string* message, double duration) {
  if (scene.roles.struts.empty()) {
    if (message) *message = "the scene has no shock absorber";
    return std::numeric_limits<double>::quiet_NaN();
  }
  DropCase c;
  c.name = "static";
  c.sinkSpeed = 0;
  c.liftRatio = 0;
  c.duration = duration;
  CaseOptions opt;
  opt.record = true;
  CaseResult r = runCase(scene, c, opt);
  if (!r.metrics.ok || r.samples.empty()) {
    if (message) *message = r.metrics.message;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const int col = r.column(r.column("s") >= 0 ? "s" : "s_" + scene.model.forces[scene.roles.struts[0]].name);
  return r.samples.back().values[col];
}

}  // namespace lg
