#include "sim/io/results.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lg {

std::vector<std::string> historyColumns(const Scene& scene) {
  std::vector<std::string> c{"t"};
  if (!scene.roles.tyres.empty()) c.push_back("P_y");
  if (!scene.roles.struts.empty()) c.push_back("s");
  if (!scene.roles.airframe.empty()) c.push_back("h");
  if (!scene.roles.tyres.empty()) c.push_back("delta");
  if (!scene.roles.struts.empty()) c.push_back("P_a");
  for (int ci : scene.roles.stops) c.push_back("F_" + scene.model.constraints[ci].name);
  c.push_back("violation");
  return c;
}

void writeHistoryCsv(const Scene& scene, const CaseResult& r, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  const auto cols = historyColumns(scene);
  for (size_t i = 0; i < cols.size(); ++i) out << (i ? "," : "") << cols[i];
  out << "\n";
  const bool tyre = !scene.roles.tyres.empty(), strut = !scene.roles.struts.empty(), af = !scene.roles.airframe.empty();
  char buf[64];
  auto put = [&](double v) {
    std::snprintf(buf, sizeof buf, ",%.10g", v);
    out << buf;
  };
  for (const Sample& s : r.samples) {
    std::snprintf(buf, sizeof buf, "%.10g", s.t);
    out << buf;
    if (tyre) put(s.P_y);
    if (strut) put(s.s);
    if (af) put(s.h);
    if (tyre) put(s.delta);
    if (strut) put(s.P_a);
    for (double l : s.stopLambda) put(l);
    put(s.violation);
    out << "\n";
  }
}

std::string metricsJson(const CaseMetrics& m, const std::string& in) {
  std::ostringstream o;
  o << "{\n";
  o << in << "  \"ok\": " << (m.ok ? "true" : "false") << ",\n";
  if (!m.ok) o << in << "  \"message\": " << jsonString(m.message) << ",\n";
  auto num = [&](const char* k, double v, bool last = false) {
    o << in << "  \"" << k << "\": " << jsonNumber(v) << (last ? "\n" : ",\n");
  };
  num("sink_speed_mps", m.sink_speed_mps);
  num("lift_ratio", m.lift_ratio);
  num("mass_kg", m.mass_kg);
  num("peak_load_N", m.peak_load_N);
  num("t_peak_s", m.t_peak_s);
  num("load_factor", m.load_factor);
  num("inertia_load_factor", m.inertia_load_factor);
  num("stroke_max_m", m.stroke_max_m);
  num("stroke_margin_m", m.stroke_margin_m);
  num("h_max_m", m.h_max_m);
  num("tyre_deflection_max_m", m.tyre_deflection_max_m);
  num("tyre_margin_m", m.tyre_margin_m);
  num("efficiency", m.efficiency);
  num("strut_efficiency", m.strut_efficiency);
  num("strut_force_max_N", m.strut_force_max_N);
  num("energy_absorbed_J", m.energy_absorbed_J);
  num("energy_to_absorb_J", m.energy_to_absorb_J);
  num("energy_dissipated_J", m.energy_dissipated_J);
  num("energy_balance_error", m.energy_balance_error);
  num("constraint_violation_max", m.constraint_violation_max);
  num("rebound_velocity_mps", m.rebound_velocity_mps);
  o << in << "  \"compression_ended\": " << (m.compression_ended ? "true" : "false") << ",\n";
  o << in << "  \"bottomed\": " << (m.bottomed ? "true" : "false") << ",\n";
  o << in << "  \"limits\": {\"within\": " << (m.withinLimits() ? "true" : "false")
    << ", \"violations\": " << jsonString(m.limitViolations()) << "},\n";
  o << in << "  \"struts\": [";
  for (size_t k = 0; k < m.struts.size(); ++k) {
    const auto& s = m.struts[k];
    o << (k ? ", " : "") << "{\"name\": " << jsonString(s.name) << ", \"stroke_max_m\": " << jsonNumber(s.stroke_max_m)
      << ", \"stroke_limit_m\": " << jsonNumber(s.stroke_limit_m) << ", \"stroke_margin_m\": " << jsonNumber(s.stroke_margin_m)
      << ", \"force_max_N\": " << jsonNumber(s.force_max_N) << ", \"efficiency\": " << jsonNumber(s.efficiency)
      << ", \"work_J\": " << jsonNumber(s.work_J) << "}";
  }
  o << "],\n";
  o << in << "  \"tyres\": [";
  for (size_t k = 0; k < m.tyres.size(); ++k) {
    const auto& t = m.tyres[k];
    o << (k ? ", " : "") << "{\"name\": " << jsonString(t.name) << ", \"deflection_max_m\": " << jsonNumber(t.deflection_max_m)
      << ", \"deflection_limit_m\": " << jsonNumber(t.deflection_limit_m) << ", \"margin_m\": " << jsonNumber(t.margin_m)
      << ", \"load_max_N\": " << jsonNumber(t.load_max_N) << "}";
  }
  o << "],\n";
  o << in << "  \"steps\": " << m.steps << ",\n";
  o << in << "  \"rhs_evaluations\": " << m.rhs_evaluations << ",\n";
  num("wall_time_s", m.wall_time_s, true);
  o << in << "}";
  return o.str();
}

void writeSummaryJson(const Scene& scene, const std::vector<CaseResult>& results, const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error(path + ": cannot write");
  out << "{\n  \"scene\": " << jsonString(scene.file) << ",\n  \"cases\": {\n";
  for (size_t i = 0; i < results.size(); ++i) {
    out << "    " << jsonString(results[i].metrics.name) << ": " << metricsJson(results[i].metrics, "    ")
        << (i + 1 < results.size() ? ",\n" : "\n");
  }
  out << "  }\n}\n";
}

}  // namespace lg
