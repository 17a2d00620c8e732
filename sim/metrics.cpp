// Metric catalogue (metrics.hpp).
#include "sim/metrics.hpp"

#include <limits>

namespace lg {

const std::vector<MetricInfo>& metricCatalogue() {
  static const std::vector<MetricInfo> c{
      {"peak_load", "N", "largest vertical ground load P_y,max (sum of the tyres)", 1e3},
      {"t_peak", "s", "time of the largest vertical ground load", 1e-3},
      {"load_factor", "-", "ground-reaction load factor n_g = P_y,max / (W g)", 0.1},
      {"inertia_load_factor", "-", "inertia load factor n = n_g + L", 0.1},
      {"stroke", "m", "largest stroke of any strut", 0.01},
      {"stroke_margin", "m", "stroke left to the bottoming stop, min over the struts of S_max - s_max", 0.01, -MetricInfo::kInf},
      {"h_max", "m", "largest airframe travel after touchdown", 0.01},
      {"tyre_deflection", "m", "largest deflection of any tyre", 0.01},
      {"tyre_margin", "m", "deflection left to the tyre limit, min over the tyres of delta_max - delta", 0.01, -MetricInfo::kInf},
      {"efficiency", "-", "gear efficiency eta = integral(P_y dh) / (P_y,max h_max) over the compression", 0.01, 0, 1},
      {"strut_efficiency", "-", "shock-absorber efficiency eta_s, min over the struts", 0.01, 0, 1},
      {"strut_force", "N", "largest strut force P_a,max of any strut", 1e3},
      {"energy_absorbed", "J", "work of the gear over the compression, integral(P_y dh) to h_max", 100},
      {"rebound_velocity", "m/s", "largest upward airframe velocity after the compression", 0.01},
      {"drag_peak", "N", "largest drag load P_x (wheel spin-up, positive aft; the tyres that declare mu_x)", 1e3},
      {"springback_peak", "N", "largest forward load -P_x (spring-back after spin-up; the tyres that declare mu_x)", 1e3},
      {"drag_at_peak", "N", "drag load P_x when the vertical load is largest (t_peak; the tyres that declare mu_x)", 1e3,
       -MetricInfo::kInf},
      {"drag_ratio", "-", "P_x / P_y at the largest vertical load (the rules' design drag: at least 0.25)", 0.01, -MetricInfo::kInf},
  };
  return c;
}

const MetricInfo* findMetric(const std::string& name) {
  for (const auto& m : metricCatalogue())
    if (name == m.name) return &m;
  return nullptr;
}

std::string metricNames() {
  std::string s;
  for (const auto& m : metricCatalogue()) s += (s.empty() ? "" : ", ") + std::string(m.name);
  return s;
}

double metricValue(const CaseMetrics& m, const std::string& name) {
  if (name == "peak_load") return m.peak_load_N;
  if (name == "t_peak") return m.t_peak_s;
  if (name == "load_factor") return m.load_factor;
  if (name == "inertia_load_factor") return m.inertia_load_factor;
  if (name == "stroke") return m.stroke_max_m;
  if (name == "stroke_margin") return m.stroke_margin_m;
  if (name == "h_max") return m.h_max_m;
  if (name == "tyre_deflection") return m.tyre_deflection_max_m;
  if (name == "tyre_margin") return m.tyre_margin_m;
  if (name == "efficiency") return m.efficiency;
  if (name == "strut_efficiency") return m.strut_efficiency;
  if (name == "strut_force") return m.strut_force_max_N;
  if (name == "energy_absorbed") return m.energy_absorbed_J;
  if (name == "rebound_velocity") return m.rebound_velocity_mps;
  if (name == "drag_peak") return m.longitudinal ? m.drag_peak_N : std::numeric_limits<double>::quiet_NaN();
  if (name == "springback_peak") return m.longitudinal ? m.springback_peak_N : std::numeric_limits<double>::quiet_NaN();
  if (name == "drag_at_peak") return m.longitudinal ? m.drag_at_peak_N : std::numeric_limits<double>::quiet_NaN();
  if (name == "drag_ratio")
    return m.longitudinal && m.peak_load_N > 0 ? m.drag_at_peak_N / m.peak_load_N : std::numeric_limits<double>::quiet_NaN();
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace lg
