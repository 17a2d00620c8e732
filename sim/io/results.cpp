#include "sim/io/results.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace lg {

std::string jsonString(const std::string& s) {
  std::string o = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\', o += c;
    else if (c == '\n') o += "\\n";
    else if (static_cast<unsigned char>(c) < 0x20) o += ' ';
    else o += c;
  }
  return o + "\"";
}

std::string jsonNumber(double v) {
  if (!std::isfinite(v)) return "null";
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

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
  num("peak_load_N", m.peak_load_N);
  num("t_peak_s", m.t_peak_s);
  num("load_factor", m.load_factor);
  num("stroke_max_m", m.stroke_max_m);
  num("h_max_m", m.h_max_m);
  num("tyre_deflection_max_m", m.tyre_deflection_max_m);
  num("efficiency", m.efficiency);
  num("strut_efficiency", m.strut_efficiency);
  num("strut_force_max_N", m.strut_force_max_N);
  num("energy_absorbed_J", m.energy_absorbed_J);
  num("energy_balance_error", m.energy_balance_error);
  num("constraint_violation_max", m.constraint_violation_max);
  num("rebound_h_min_m", m.rebound_h_min_m);
  o << in << "  \"bottomed\": " << (m.bottomed ? "true" : "false") << ",\n";
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

bool writePlots(const Scene& scene, const CaseResult& r, const std::string& csvPath, const std::string& outDir,
                std::string* why) {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    if (why) *why = "gnuplot is not installed (scripts/setup.sh installs gnuplot-nox)";
    return false;
  }
  const auto cols = historyColumns(scene);
  auto col = [&](const std::string& n) {
    for (size_t i = 0; i < cols.size(); ++i)
      if (cols[i] == n) return static_cast<int>(i) + 1;
    return 0;
  };
  const std::string name = r.metrics.name;
  const std::string script = outDir + "/" + name + ".gp";
  std::ofstream gp(script);
  gp << "set datafile separator ','\nset terminal pngcairo size 1200,900 noenhanced\n";
  gp << "set output '" << outDir << "/" << name << ".png'\n";
  gp << "set multiplot layout 2,2 title 'drop test: " << name << "'\nset grid\n";
  auto plot = [&](const std::string& x, const std::string& y, const std::string& title, const std::string& xl,
                  const std::string& yl, double scale) {
    if (!col(x) || !col(y)) {
      gp << "set multiplot next\n";
      return;
    }
    gp << "set title '" << title << "'\nset xlabel '" << xl << "'\nset ylabel '" << yl << "'\n";
    gp << "plot '" << csvPath << "' every ::1 using " << col(x) << ":($" << col(y) << "*" << scale
       << ") with lines lw 2 notitle\n";
  };
  plot("t", "P_y", "vertical ground load P_y(t)", "t [s]", "P_y [kN]", 1e-3);
  plot("t", "s", "shock-absorber stroke s(t)", "t [s]", "s [m]", 1.0);
  plot("t", "h", "airframe displacement h(t)", "t [s]", "h [m]", 1.0);
  if (col("h") && col("P_y")) {
    gp << "set title 'work diagram P_y(h)'\nset xlabel 'h [m]'\nset ylabel 'P_y [kN]'\n";
    gp << "plot '" << csvPath << "' every ::1 using " << col("h") << ":($" << col("P_y") << "*1e-3) with lines lw 2 notitle\n";
  }
  gp << "unset multiplot\n";
  gp.close();
  const int rc = std::system(("gnuplot '" + script + "' 2>/dev/null").c_str());
  if (rc != 0) {
    if (why) *why = "gnuplot failed on " + script;
    return false;
  }
  return true;
}

}  // namespace lg
