// Metric catalogue (metrics.hpp).
#include "sim/drop/metrics.hpp"

#include <limits>

namespace lg {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = MetricInfo::kInf;
}  // namespace

const std::vector<MetricInfo>& metricCatalogue() {
  using M = const CaseMetrics&;
  static const std::vector<MetricInfo> c{
      {.name = "peak_load", .field = "peak_load_N", .unit = "N",
       .description = "largest vertical ground load P_y,max (sum of the tyres)", .scale = 1e3,
       .value = [](M m) { return m.peak_load_N; }},
      {.name = "t_peak", .field = "t_peak_s", .unit = "s", .description = "time of the largest vertical ground load",
       .scale = 1e-3, .value = [](M m) { return m.t_peak_s; }},
      {.name = "load_factor", .field = "load_factor", .unit = "-",
       .description = "ground-reaction load factor n_g = P_y,max / (W g)", .scale = 0.1,
       .value = [](M m) { return m.load_factor; }},
      {.name = "inertia_load_factor", .field = "inertia_load_factor", .unit = "-",
       .description = "inertia load factor n = n_g + L", .scale = 0.1, .value = [](M m) { return m.inertia_load_factor; }},
      {.name = "stroke", .field = "stroke_max_m", .unit = "m", .description = "largest stroke of any strut", .scale = 0.01,
       .value = [](M m) { return m.stroke_max_m; }},
      {.name = "stroke_margin", .field = "stroke_margin_m", .unit = "m",
       .description = "stroke left to the bottoming stop, min over the struts of S_max - s_max", .scale = 0.01,
       .least = -kInf, .value = [](M m) { return m.stroke_margin_m; }},
      {.name = "h_max", .field = "h_max_m", .unit = "m", .description = "largest airframe travel after touchdown",
       .scale = 0.01, .value = [](M m) { return m.h_max_m; }},
      {.name = "tyre_deflection", .field = "tyre_deflection_max_m", .unit = "m",
       .description = "largest deflection of any tyre", .scale = 0.01, .value = [](M m) { return m.tyre_deflection_max_m; }},
      {.name = "tyre_margin", .field = "tyre_margin_m", .unit = "m",
       .description = "deflection left to the tyre limit, min over the tyres of delta_max - delta", .scale = 0.01,
       .least = -kInf, .value = [](M m) { return m.tyre_margin_m; }},
      {.name = "efficiency", .field = "efficiency", .unit = "-",
       .description = "gear efficiency eta = integral(P_y dh) / (P_y,max h_max) over the compression", .scale = 0.01,
       .least = 0, .most = 1, .value = [](M m) { return m.efficiency; }},
      {.name = "strut_efficiency", .field = "strut_efficiency", .unit = "-",
       .description = "shock-absorber efficiency eta_s, min over the struts", .scale = 0.01, .least = 0, .most = 1,
       .value = [](M m) { return m.strut_efficiency; }},
      {.name = "strut_force", .field = "strut_force_max_N", .unit = "N",
       .description = "largest strut force P_a,max of any strut", .scale = 1e3, .value = [](M m) { return m.strut_force_max_N; }},
      {.name = "energy_absorbed", .field = "energy_absorbed_J", .unit = "J",
       .description = "work of the gear over the compression, integral(P_y dh) to h_max", .scale = 100,
       .value = [](M m) { return m.energy_absorbed_J; }},
      {.name = "rebound_velocity", .field = "rebound_velocity_mps", .unit = "m/s",
       .description = "largest upward airframe velocity after the compression", .scale = 0.01,
       .value = [](M m) { return m.rebound_velocity_mps; }},
      {.name = "drag_peak", .field = "drag_peak_N", .unit = "N",
       .description = "largest drag load P_x (wheel spin-up, positive aft; the tyres that declare mu_x)", .scale = 1e3,
       .value = [](M m) { return m.longitudinal ? m.drag_peak_N : kNaN; }},
      {.name = "springback_peak", .field = "springback_peak_N", .unit = "N",
       .description = "largest forward load -P_x (spring-back after spin-up; the tyres that declare mu_x)", .scale = 1e3,
       .value = [](M m) { return m.longitudinal ? m.springback_peak_N : kNaN; }},
      {.name = "drag_at_peak", .field = "drag_at_peak_N", .unit = "N",
       .description = "drag load P_x when the vertical load is largest (t_peak; the tyres that declare mu_x)", .scale = 1e3,
       .least = -kInf, .value = [](M m) { return m.longitudinal ? m.drag_at_peak_N : kNaN; }},
      {.name = "drag_ratio", .field = "drag_ratio", .unit = "-",
       .description = "P_x / P_y at the largest vertical load (the rules' design drag: at least 0.25)", .scale = 0.01,
       .least = -kInf,
       .value = [](M m) { return m.longitudinal && m.peak_load_N > 0 ? m.drag_at_peak_N / m.peak_load_N : kNaN; }},
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
  const MetricInfo* info = findMetric(name);
  return info ? info->value(m) : kNaN;
}

}  // namespace lg
