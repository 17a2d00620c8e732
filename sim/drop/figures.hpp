// A drop's figures in any scalar: what the observer (sim/drop/observer.hpp) reduces a run to, before
// caseMetrics (sim/drop/run.cpp) takes their values and the gradients (sim/drop/gradient.cpp) their
// derivatives.
#pragma once

#include <cmath>
#include <limits>
#include <utility>
#include <vector>

#include "sim/core/math.hpp"  // value()
#include "sim/drop/case.hpp"   // CaseMetrics, Scene, DropCase

namespace lg {

// The larger / smaller of two scalars by value (the whole scalar, derivatives included, is kept).
template <class S> const S& maxByValue(const S& a, const S& b) { return value(a) < value(b) ? b : a; }
template <class S> const S& minByValue(const S& a, const S& b) { return value(b) < value(a) ? b : a; }

template <class S> struct StrutFigures {
  S stroke_max = S(0), stroke_limit = S(0), stroke_margin = S(0), force_max = S(0), efficiency = S(0), work = S(0);
};
template <class S> struct TyreFigures {
  S deflection_max = S(0), deflection_limit = S(0), margin = S(0), load_max = S(0), drag_max = S(0);
};

// A drop's figures in the scalar S (CaseMetrics holds their values).
template <class S> struct CaseFigures {
  S peak_load = S(0), t_peak = S(0), load_factor = S(0), inertia_load_factor = S(0), stroke_max = S(0),
    stroke_margin = S(0), h_max = S(0), tyre_deflection_max = S(0), tyre_margin = S(0), efficiency = S(0),
    strut_efficiency = S(0), strut_force_max = S(0), energy_absorbed = S(0), energy_to_absorb = S(0),
    rebound_velocity = S(0), mass = S(0), drag_peak = S(0), t_drag_peak = S(0),
    springback_peak = S(0), t_springback = S(0),  // the largest forward load -P_x (spring-back), its time
    drag_at_peak = S(0);                          // P_x at t_peak, the time of the largest vertical load
  std::vector<StrutFigures<S>> struts;
  std::vector<TyreFigures<S>> tyres;
  double energy_dissipated = 0, energy_balance_error = 0, constraint_violation_max = 0;
  bool compression_ended = false, bottomed = false;
  // For the kink report (values only).
  std::vector<std::pair<double, double>> loadHumps;     // (t, P_y) of each local maximum of P_y: interior
                                                         // (P_y' from + to -) or at an event (a kink)
  std::vector<std::pair<double, double>> stickIntervals;  // [t0, t1] where a strut with regularised friction
                                                           // stuck after moving (exact Coulomb: not a kink)
  double tStrokeMax = 0, tHMax = 0, tStrutForceMax = 0;  // [s] when s_max, h_max and P_a,max were reached
  double peakCurvature = 0;  // [N/s^2] P_y'' at t_peak where the peak is a smooth maximum inside a step (< 0);
                             // 0 where it is not (a kink, a step's end): the t_peak condition (caseMetrics)
};

// The highest maximum of P_y other than the peak's own hump (told apart by its time): (t, P_2), or
// (NaN, -inf) where the load has no other maximum. caseMetrics' second peak and the gradients' kinks.
template <class S> std::pair<double, double> secondLoadHump(const CaseFigures<S>& F) {
  const double tPeak = value(F.t_peak);
  std::pair<double, double> best{std::numeric_limits<double>::quiet_NaN(), -std::numeric_limits<double>::infinity()};
  for (const auto& [t, v] : F.loadHumps)
    if (std::abs(t - tPeak) > 1e-9 * std::max(1.0, tPeak) && v > best.second) best = {t, v};
  return best;
}

// The metrics (values) of a run's figures, for case c of the scene (defined in sim/drop/run.cpp).
CaseMetrics caseMetrics(const CaseFigures<double>& F, const Scene& scene, const DropCase& c);

// The value parts of a run's figures.
template <class S> CaseFigures<double> valuesOf(const CaseFigures<S>& F) {
  CaseFigures<double> v;
  for (auto [dst, src] : {std::pair<double*, const S*>{&v.peak_load, &F.peak_load}, {&v.t_peak, &F.t_peak},
                          {&v.load_factor, &F.load_factor}, {&v.inertia_load_factor, &F.inertia_load_factor},
                          {&v.stroke_max, &F.stroke_max}, {&v.stroke_margin, &F.stroke_margin}, {&v.h_max, &F.h_max},
                          {&v.tyre_deflection_max, &F.tyre_deflection_max}, {&v.tyre_margin, &F.tyre_margin},
                          {&v.efficiency, &F.efficiency}, {&v.strut_efficiency, &F.strut_efficiency},
                          {&v.strut_force_max, &F.strut_force_max}, {&v.energy_absorbed, &F.energy_absorbed},
                          {&v.energy_to_absorb, &F.energy_to_absorb}, {&v.rebound_velocity, &F.rebound_velocity},
                          {&v.mass, &F.mass}, {&v.drag_peak, &F.drag_peak}, {&v.t_drag_peak, &F.t_drag_peak},
                          {&v.springback_peak, &F.springback_peak}, {&v.t_springback, &F.t_springback},
                          {&v.drag_at_peak, &F.drag_at_peak}})
    *dst = value(*src);
  for (const auto& st : F.struts)
    v.struts.push_back({value(st.stroke_max), value(st.stroke_limit), value(st.stroke_margin), value(st.force_max),
                        value(st.efficiency), value(st.work)});
  for (const auto& t : F.tyres)
    v.tyres.push_back({value(t.deflection_max), value(t.deflection_limit), value(t.margin), value(t.load_max), value(t.drag_max)});
  v.energy_dissipated = F.energy_dissipated;
  v.energy_balance_error = F.energy_balance_error;
  v.constraint_violation_max = F.constraint_violation_max;
  v.compression_ended = F.compression_ended;
  v.bottomed = F.bottomed;
  v.peakCurvature = F.peakCurvature;
  v.loadHumps = F.loadHumps;  // (values already: the second peak's gap, caseMetrics)
  return v;
}

}  // namespace lg
