#include "sim/io/results.hpp"

#include "sim/drop/metrics.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <sstream>
#include <stdexcept>

namespace lg {

std::string historyHeader(const CaseResult& r) {
  std::string h = "t[s]";
  for (const Column& c : r.columns) h += "," + c.name + "[" + c.unit + "]";
  return h;
}

std::string historyCsv(const CaseResult& r) {
  // Round-off-sized values (|v| below 1e-12 of the column's largest) are written as 0.
  std::vector<double> scale(r.columns.size(), 0.0);
  for (const Sample& s : r.samples)
    for (size_t i = 0; i < s.values.size() && i < scale.size(); ++i) scale[i] = std::max(scale[i], std::abs(s.values[i]));
  std::string out = historyHeader(r) + "\n";
  char buf[48];
  for (const Sample& s : r.samples) {
    std::snprintf(buf, sizeof buf, "%.10g", s.t);
    out += buf;
    for (size_t i = 0; i < s.values.size(); ++i) {
      const double v = std::abs(s.values[i]) <= 1e-12 * scale[i] ? 0.0 : s.values[i];
      std::snprintf(buf, sizeof buf, ",%.10g", v);
      out += buf;
    }
    out += "\n";
  }
  return out;
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
  num("t_peak_condition", m.t_peak_condition);  // (null: the peak is no smooth maximum)
  num("second_peak_gap", m.second_peak_gap);    // (null: P_y has no other maximum)
  num("t_second_peak_s", m.t_second_peak_s);
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
  if (m.longitudinal) {  // a tyre declares mu_x
    num("forward_speed_mps", m.forward_speed_mps);
    num("drag_peak_N", m.drag_peak_N);
    num("t_drag_peak_s", m.t_drag_peak_s);
    num("springback_peak_N", m.springback_peak_N);
    num("t_springback_s", m.t_springback_s);
    num("drag_at_peak_N", m.drag_at_peak_N);
    num("drag_ratio", m.peak_load_N > 0 ? m.drag_at_peak_N / m.peak_load_N : NAN);
  }
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
      << ", \"load_max_N\": " << jsonNumber(t.load_max_N);
    if (t.longitudinal) o << ", \"drag_max_N\": " << jsonNumber(t.drag_max_N);
    o << "}";
  }
  o << "],\n";
  o << in << "  \"steps\": " << m.steps << ",\n";
  o << in << "  \"rhs_evaluations\": " << m.rhs_evaluations << ",\n";
  if (m.stiff_switch) {
    num("stiff_from_s", m.stiff_from_s);  // (null: dopri5 to the end)
    o << in << "  \"stiff_handbacks\": " << m.stiff_handbacks << ",\n";
  }
  if (m.accuracy > 0) {
    num("accuracy", m.accuracy);
    num("accuracy_rerun", m.accuracy_rerun);  // (null: one run was enough)
    if (!m.accuracy_rerun_reason.empty())
      o << in << "  \"accuracy_rerun_reason\": " << jsonString(m.accuracy_rerun_reason) << ",\n";
  }
  num("wall_time_s", m.wall_time_s, true);
  o << in << "}";
  return o.str();
}

std::string summaryJson(const Scene& scene, const std::vector<CaseResult>& results,
                        const std::vector<CaseGradient>* gradients, const std::vector<std::string>* units) {
  std::ostringstream out;
  out << "{\n  \"scene\": " << jsonString(scene.file) << ",\n  \"cases\": {\n";
  for (size_t i = 0; i < results.size(); ++i) {
    out << "    " << jsonString(results[i].metrics.name) << ": " << metricsJson(results[i].metrics, "    ")
        << (i + 1 < results.size() ? ",\n" : "\n");
  }
  out << "  }";
  if (gradients && units) out << ",\n  \"gradients\": " << gradientJson(*gradients, *units, "  ");
  out << "\n}\n";
  return out.str();
}

std::string gradientJson(const std::vector<CaseGradient>& g, const std::vector<std::string>& units,
                         const std::string& in) {
  std::ostringstream o;
  o << "{\n" << in << "  \"parameters\": [";
  const std::vector<std::string> none;
  const auto& params = g.empty() ? none : g.front().parameters;
  for (size_t j = 0; j < params.size(); ++j)
    o << (j ? ", " : "") << "{\"path\": " << jsonString(params[j]) << ", \"unit\": " << jsonString(units[j]) << "}";
  o << "],\n" << in << "  \"method\": \"forward mode (ceres::Jet) through the run; one-sided where \\\"smooth\\\" is false\",\n";
  o << in << "  \"cases\": {\n";
  for (size_t c = 0; c < g.size(); ++c) {
    o << in << "    " << jsonString(g[c].caseName) << ": {";
    if (!g[c].ok) o << "\"ok\": false, \"message\": " << jsonString(g[c].message);
    for (size_t i = 0; g[c].ok && i < g[c].metrics.size(); ++i) {
      const auto& m = g[c].metrics[i];
      o << (i ? "," : "") << "\n" << in << "      " << jsonString(m.metric) << ": {\"value\": " << jsonNumber(m.value)
        << ", \"unit\": " << jsonString(findMetric(m.metric)->unit) << ", \"d\": {";
      for (size_t j = 0; j < m.d.size(); ++j) o << (j ? ", " : "") << jsonString(params[j]) << ": " << jsonNumber(m.d[j]);
      o << "}, \"smooth\": " << jsonBool(m.smooth) << ", \"note\": " << jsonString(m.note) << "}";
    }
    o << (g[c].ok ? "\n" + in + "    }" : "}") << (c + 1 < g.size() ? ",\n" : "\n");
  }
  o << in << "  }\n" << in << "}";
  return o.str();
}

std::string gradientCsv(const std::vector<CaseGradient>& g, const std::vector<std::string>& units) {
  std::string out = "case,metric,unit,value";
  const std::vector<std::string> none;
  const auto& params = g.empty() ? none : g.front().parameters;
  for (size_t j = 0; j < params.size(); ++j) out += ",d/d" + params[j] + "[unit per " + units[j] + "]";
  out += ",smooth,note\n";
  char b[40];
  for (const auto& cg : g) {
    if (!cg.ok) continue;
    for (const auto& m : cg.metrics) {
      std::snprintf(b, sizeof b, "%.10g", m.value);
      out += cg.caseName + "," + m.metric + "," + findMetric(m.metric)->unit + "," + (std::isfinite(m.value) ? b : "");
      for (double d : m.d) {
        std::snprintf(b, sizeof b, "%.10g", d);
        out += "," + (std::isfinite(d) ? std::string(b) : std::string());
      }
      std::string note = m.note;
      for (char& ch : note)
        if (ch == '"') ch = '\'';
      out += std::string(",") + (m.smooth ? "1" : "0") + ",\"" + note + "\"\n";
    }
  }
  return out;
}

std::string summaryCsv(const std::vector<CaseResult>& results) {
  std::string out = "case,ok,sink_speed[m/s],lift_ratio[-],mass[kg],peak_load[N],t_peak[s],load_factor[-],"
                    "inertia_load_factor[-],stroke_max[m],stroke_margin[m],h_max[m],tyre_deflection_max[m],"
                    "tyre_margin[m],efficiency[-],strut_efficiency[-],strut_force_max[N],energy_absorbed[J],"
                    "energy_to_absorb[J],energy_dissipated[J],energy_balance_error[-],rebound_velocity[m/s],";
  // The drag figures where a tyre declares mu_x.
  bool drag = false;
  for (const CaseResult& r : results) drag = drag || r.metrics.longitudinal;
  if (drag) out += "forward_speed[m/s],drag_peak[N],t_drag_peak[s],springback_peak[N],t_springback[s],drag_at_peak[N],drag_ratio[-],";
  out += "bottomed,within_limits,violations,";
  // Where dopri5 may hand over to ros34pw2 (an accuracy setting): the time it did for good, empty if never,
  // and the trials it handed back.
  bool stiff = false;
  for (const CaseResult& r : results) stiff = stiff || r.metrics.stiff_switch;
  if (stiff) out += "stiff_from[s],stiff_handbacks[-],";
  // Where a case ran under an accuracy setting: the condition of its peak's time and the tighter accuracy
  // it was run again at, empty if none (flatPeakAccuracy).
  bool accuracy = false;
  for (const CaseResult& r : results) accuracy = accuracy || r.metrics.accuracy > 0;
  if (accuracy) out += "accuracy[-],t_peak_condition[-],accuracy_rerun[-],";
  out += "steps,rhs_evaluations,wall_time[s]\n";
  auto num = [](double v) {
    if (!std::isfinite(v)) return std::string();
    char b[40];
    std::snprintf(b, sizeof b, "%.10g", v);
    return std::string(b);
  };
  for (const CaseResult& r : results) {
    const CaseMetrics& m = r.metrics;
    std::string viol = m.limitViolations();
    for (char& c : viol)
      if (c == '"') c = '\'';
    out += m.name + "," + (m.ok ? "1" : "0");
    for (double v : {m.sink_speed_mps, m.lift_ratio, m.mass_kg, m.peak_load_N, m.t_peak_s, m.load_factor,
                     m.inertia_load_factor, m.stroke_max_m, m.stroke_margin_m, m.h_max_m, m.tyre_deflection_max_m,
                     m.tyre_margin_m, m.efficiency, m.strut_efficiency, m.strut_force_max_N, m.energy_absorbed_J,
                     m.energy_to_absorb_J, m.energy_dissipated_J, m.energy_balance_error, m.rebound_velocity_mps})
      out += "," + num(v);
    if (drag)
      for (double v : {m.forward_speed_mps, m.drag_peak_N, m.t_drag_peak_s, m.springback_peak_N, m.t_springback_s,
                       m.drag_at_peak_N, m.peak_load_N > 0 ? m.drag_at_peak_N / m.peak_load_N : NAN})
        out += "," + num(v);
    out += std::string(",") + (m.bottomed ? "1" : "0") + "," + (m.withinLimits() ? "1" : "0") + ",\"" + viol + "\",";
    if (stiff) out += num(m.stiff_from_s) + "," + std::to_string(m.stiff_handbacks) + ",";
    if (accuracy) out += num(m.accuracy) + "," + num(m.t_peak_condition) + "," + num(m.accuracy_rerun) + ",";
    out += std::to_string(m.steps) + "," + std::to_string(m.rhs_evaluations) + "," + num(m.wall_time_s) + "\n";
  }
  return out;
}

}  // namespace lg
