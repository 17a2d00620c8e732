// A drop case's vocabulary: its limits, history columns, mass, model and initial state.
#include "sim/drop/case.hpp"

#include "sim/core/format.hpp"  // shortNumber

namespace lg {

bool CaseMetrics::withinLimits() const { return limitViolations().empty(); }

std::string CaseMetrics::limitViolations() const {
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  if (bottomed) add("bottomed");
  if (ok && !compression_ended) add("compression not ended (the run ended before h reached its maximum: a longer duration)");
  for (const auto& s : struts)
    if (s.stroke_margin_m < 0 && !bottomed)
      add("strut '" + s.name + "' stroke " + shortNumber(s.stroke_max_m, 4) + " m > S_max " + shortNumber(s.stroke_limit_m, 4) + " m");
  for (const auto& t : tyres)
    if (t.margin_m < 0)
      add("tyre '" + t.name + "' " + shortNumber(t.deflection_max_m, 4) + " m > delta_max " + shortNumber(t.deflection_limit_m, 4) +
          " m");
  return out;
}

std::vector<Column> historyColumns(const Scene& scene) {
  const Model<double>& m = scene.model;
  std::vector<Column> c;
  if (!scene.roles.tyres.empty()) c.push_back({"P_y", "N"});
  if (!scene.roles.airframe.empty()) c.push_back({"h", "m"});
  const bool manyTyres = scene.roles.tyres.size() > 1, manyStruts = scene.roles.struts.size() > 1;
  for (int f : scene.roles.tyres) {
    const std::string sfx = manyTyres ? "_" + m.forces[f].name : "";
    c.push_back({"delta" + sfx, "m"});
    if (manyTyres) c.push_back({"P_t" + sfx, "N"});
    if (std::get<Tyre<double>>(m.forces[f].type).longitudinal) c.push_back({"P_x" + sfx, "N"});
  }
  for (int f : scene.roles.struts) {
    const std::string sfx = manyStruts ? "_" + m.forces[f].name : "";
    for (const std::string& n : m.forces[f].outputNames())
      c.push_back({n + sfx, n == "s" ? "m" : n == "s_dot" ? "m/s" : n == "p_1" || n == "p_2" ? "Pa" : "N"});
  }
  for (int ci : scene.roles.stops) c.push_back({"F_" + m.constraints[ci].name, "N"});
  // Bushings and bearing friction, when declared: their outputs, suffixed by the element's name.
  for (const auto& f : m.forces)
    std::visit(
        [&](const auto& e) {
          if constexpr (requires { e.outputUnit(std::string()); })
            for (const std::string& n : e.outputNames()) c.push_back({n + "_" + f.name, e.outputUnit(n)});
        },
        f.type);
  c.push_back({"violation", "m"});
  return c;
}

int CaseResult::column(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i)
    if (columns[i].name == name) return static_cast<int>(i);
  return -1;
}

double caseMass(const Scene& scene, const DropCase& c) {
  double G = 0;
  for (const auto& b : scene.model.bodies) {
    const auto it = c.masses.find(b.name);
    G += it == c.masses.end() ? b.mass : it->second;
  }
  return G;
}

Model<double> caseModel(const Scene& scene, const DropCase& c) {
  Model<double> m = scene.model;
  applyCase(scene, m, c, c.liftRatio);
  return m;
}

State<double> caseState(const Scene& scene, const Model<double>& m, const DropCase& c, std::string* problem) {
  return caseState(scene, m, c.sinkSpeed, c.dropHeight, problem);
}

}  // namespace lg
