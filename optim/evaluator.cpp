// Design evaluation on the simulator (evaluator.hpp).
#include "optim/evaluator.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <variant>

namespace lg::optim {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

bool finiteMetrics(const CaseMetrics& m) {
  for (double v : {m.peak_load_N, m.stroke_max_m, m.h_max_m, m.tyre_deflection_max_m, m.efficiency, m.rebound_h_min_m})
    if (!std::isfinite(v)) return false;
  return true;
}
}  // namespace

double sceneTyreDeltaMax(const Scene& scene) {
  for (int i : scene.roles.tyres)
    if (i >= 0 && i < static_cast<int>(scene.model.forces.size()))
      if (const auto* t = std::get_if<Tyre<double>>(&scene.model.forces[i].type)) return t->deltaMax;
  for (const auto& f : scene.model.forces)
    if (const auto* t = std::get_if<Tyre<double>>(&f.type)) return t->deltaMax;
  return kNaN;
}

toml::table designDocument(const Study& s, const std::vector<double>& x) {
  toml::table doc = s.scene.doc;
  for (size_t i = 0; i < s.variables.size(); ++i) setParameter(doc, s.variables[i].path, x[i], s.file);
  return doc;
}

std::vector<DropCase> designCases(const Study& s, const Scene& designScene) {
  std::vector<DropCase> out;
  for (const auto& c : s.cases) {
    DropCase d = c.dropCase;
    if (c.fromScene)
      for (const auto& sc : designScene.cases)
        if (sc.name == d.name) d = sc;  // design variables may edit scene cases ("case.limit.sink_speed")
    out.push_back(d);
  }
  return out;
}

std::vector<std::string> constraintNames(const Study& s) {
  std::vector<std::string> n;
  const Constraints& c = s.constraints;
  if (c.strokeMax) n.push_back("stroke");
  if (c.tyreDeflectionFromScene || c.tyreDeflectionMax) n.push_back("tyre_deflection");
  if (c.staticStrokeLower) {
    n.push_back("static_stroke_low");
    n.push_back("static_stroke_high");
  }
  if (c.noBottoming) n.push_back("bottoming");
  if (c.reboundMax) n.push_back("rebound");
  return n;
}

std::vector<double> constraintScales(const Study& s) {
  std::vector<double> k;
  const Constraints& c = s.constraints;
  if (c.strokeMax) k.push_back(*c.strokeMax);                                        // [m]
  if (c.tyreDeflectionFromScene) k.push_back(sceneTyreDeltaMax(s.scene));            // [m]
  else if (c.tyreDeflectionMax) k.push_back(*c.tyreDeflectionMax);                   // [m]
  if (c.staticStrokeLower) {
    k.push_back(*c.staticStrokeUpper);                                               // [m]
    k.push_back(*c.staticStrokeUpper);
  }
  if (c.noBottoming) k.push_back(1.0);                                               // [0/1]
  if (c.reboundMax) k.push_back(std::max(0.01, std::abs(*c.reboundMax)));            // [m]
  return k;
}

Evaluation reduceMetrics(const Study& s, std::vector<CaseMetrics> cases, double tyreDeltaMax, double staticStroke) {
  Evaluation e;
  e.staticStroke = staticStroke;
  e.cases = std::move(cases);
  for (const auto& m : e.cases) {
    if (!m.ok) {
      e.ok = false;
      e.message = "case '" + m.name + "': " + (m.message.empty() ? "simulation failed" : m.message);
      return e;
    }
    if (!finiteMetrics(m)) {
      e.ok = false;
      e.message = "case '" + m.name + "': non-finite metrics";
      return e;
    }
  }
  // Objective: fixed case order, no parallel reduction.
  const bool peak = s.objective.kind == ObjectiveKind::MinPeakLoad;
  double f = 0;
  for (size_t i = 0; i < e.cases.size(); ++i) {
    const double fi = peak ? e.cases[i].peak_load_N : e.cases[i].efficiency;
    if (s.objective.aggregate == Aggregate::WeightedSum) f += s.cases[i].weight * fi;
    else if (i == 0) f = fi;
    else f = peak ? std::max(f, fi) : std::min(f, fi);  // the worst case
  }
  e.objective = f;
  // Constraints g <= 0 on the worst case.
  const Constraints& c = s.constraints;
  auto worst = [&](auto get) {
    double w = -std::numeric_limits<double>::infinity();
    for (const auto& m : e.cases) w = std::max(w, get(m));
    return w;
  };
  if (c.strokeMax) e.constraints.push_back(worst([](const CaseMetrics& m) { return m.stroke_max_m; }) - (*c.strokeMax - c.strokeMargin));
  if (c.tyreDeflectionFromScene || c.tyreDeflectionMax) {
    const double lim = c.tyreDeflectionFromScene ? tyreDeltaMax : *c.tyreDeflectionMax;
    e.constraints.push_back(worst([](const CaseMetrics& m) { return m.tyre_deflection_max_m; }) - lim);
  }
  if (c.staticStrokeLower) {
    e.constraints.push_back(*c.staticStrokeLower - staticStroke);
    e.constraints.push_back(staticStroke - *c.staticStrokeUpper);
  }
  if (c.noBottoming) e.constraints.push_back(worst([](const CaseMetrics& m) { return m.bottomed ? 1.0 : 0.0; }));
  if (c.reboundMax) e.constraints.push_back(worst([](const CaseMetrics& m) { return -m.rebound_h_min_m; }) - *c.reboundMax);
  e.ok = std::isfinite(e.objective);
  for (double g : e.constraints)
    if (!std::isfinite(g)) e.ok = false;
  if (!e.ok) e.message = "non-finite objective or constraint";
  return e;
}

Evaluation evaluateDesign(const Study& s, const std::vector<double>& x, const EvaluatorOptions& o,
                          std::vector<CaseResult>* results) {
  try {
    Scene scene;
    try {
      scene = buildScene(designDocument(s, x), s.sceneFile, s.sceneDir);
    } catch (const InputError& e) {
      Evaluation ev;
      ev.message = std::string("the scene rejects the design: ") + e.what();
      return ev;
    }
    const std::vector<DropCase> cases = designCases(s, scene);
    CaseOptions copt;
    copt.record = o.record;
    copt.stop = o.stop;
    std::vector<CaseResult> runs = runCases(scene, cases, std::max(1, o.threads), copt);
    std::vector<CaseMetrics> metrics;
    for (const auto& r : runs) metrics.push_back(r.metrics);
    double ss = kNaN;
    if (s.constraints.staticStrokeLower) {
      std::string msg;
      ss = staticStroke(scene, &msg);
      if (!std::isfinite(ss)) {
        Evaluation ev;
        ev.cases = metrics;
        ev.message = "static stroke: " + (msg.empty() ? std::string("failed") : msg);
        if (results) *results = std::move(runs);
        return ev;
      }
    }
    if (results) *results = std::move(runs);
    return reduceMetrics(s, std::move(metrics), sceneTyreDeltaMax(scene), ss);
  } catch (const std::exception& e) {
    Evaluation ev;
    ev.message = std::string("evaluation failed: ") + e.what();
    return ev;
  } catch (...) {
    Evaluation ev;
    ev.message = "evaluation failed: unknown exception";
    return ev;
  }
}

Problem makeProblem(const Study& s, const EvaluatorOptions& o) {
  Problem p;
  p.variables = s.variables;
  p.constraintNames = constraintNames(s);
  p.constraintScales = constraintScales(s);
  p.maximize = s.objective.kind == ObjectiveKind::MaxEfficiency;
  p.objectiveName = p.maximize ? "efficiency" : "peak_load_N";
  p.evaluate = [&s, o](const std::vector<double>& x) { return evaluateDesign(s, x, o); };
  return p;
}

}  // namespace lg::optim
