// Design evaluation on the simulator (evaluator.hpp).
#include "optim/evaluator.hpp"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>

#include "sim/drop/gradient.hpp"
#include "sim/drop/metrics.hpp"

namespace lg::optim {
namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

toml::table designDocument(const Study& s, const std::vector<double>& x) {
  toml::table doc = s.scene.doc;
  std::vector<std::string> paths;
  for (const auto& v : s.variables) paths.push_back(v.path);
  inlineTables(doc, s.scene, paths);
  for (size_t i = 0; i < s.variables.size(); ++i) setParameter(doc, s.variables[i].path, x[i], s.file);
  return doc;
}

std::vector<DropCase> designCases(const Study& s, const Scene& designScene, bool checks) {
  std::vector<DropCase> out;
  for (const auto& c : s.cases) {
    if (!checks && !c.steers()) continue;
    DropCase d = c.dropCase;
    if (c.origin == CaseOrigin::Scene) {
      for (const auto& sc : designScene.cases)
        if (sc.name == c.baseName) d = sc;  // design variables may edit scene cases ("limit.sink_speed")
    } else if (c.origin == CaseOrigin::Certification && s.certification) {
      d = certDropCase(designScene, *s.certification, *s.certification->findCase(c.baseName));  // W on this design
    }
    d.name = c.dropCase.name;  // (at a corner: "<case>@<corner>")
    d.corner = c.dropCase.corner;
    out.push_back(d);
  }
  return out;
}

std::vector<std::string> constraintNames(const Study& s) {
  std::vector<std::string> n;
  for (const auto& it : s.items) n.push_back(it.name);
  return n;
}

std::vector<double> constraintScales(const Study& s) {
  std::vector<double> k;
  for (const auto& it : s.items) k.push_back(s.constraints[it.spec].scale);
  return k;
}

const std::vector<CaseMetrics>& caseMetricsOf(const Evaluation& e) {
  static const std::vector<CaseMetrics> none;
  const auto* d = dynamic_cast<const CaseDetail*>(e.detail.get());
  return d ? d->cases : none;
}

namespace {
std::shared_ptr<const CaseDetail> caseDetail(std::vector<CaseMetrics> cases) {
  auto d = std::make_shared<CaseDetail>();
  d->cases = std::move(cases);
  return d;
}
}  // namespace

Evaluation reduceMetrics(const Study& s, std::vector<CaseMetrics> metrics, double staticStroke) {
  Evaluation e;
  e.staticStroke = staticStroke;
  const auto detail = caseDetail(std::move(metrics));
  e.detail = detail;
  const std::vector<CaseMetrics>& cases = detail->cases;
  const int steering = s.steeringCases();
  if (static_cast<int>(cases.size()) < steering) {
    e.message = "metrics of " + std::to_string(cases.size()) + " cases for " + std::to_string(steering) + " steering cases";
    return e;
  }
  for (int i = 0; i < steering; ++i) {
    const CaseMetrics& m = cases[i];
    if (!m.ok) {
      e.message = "case '" + m.name + "': " + (m.message.empty() ? "simulation failed" : m.message);
      return e;
    }
  }
  // Objective over the objective cases, in case order (no parallel reduction).
  const bool peak = s.objective.kind == ObjectiveKind::MinPeakLoad;
  double f = kNaN;
  for (int i = 0; i < steering; ++i) {
    if (s.cases[i].role != CaseRole::Objective) continue;
    const double fi = peak ? cases[i].peak_load_N : cases[i].efficiency;
    if (s.objective.aggregate == Aggregate::Worst) e.terms.push_back(fi);
    if (s.objective.aggregate == Aggregate::WeightedSum) f = (std::isnan(f) ? 0.0 : f) + s.cases[i].weight * fi;
    else if (std::isnan(f)) f = fi;
    else f = peak ? std::max(f, fi) : std::min(f, fi);  // the worst case
  }
  e.objective = f;
  // Constraints g_j <= 0: one per spec and case.
  for (const auto& it : s.items) {
    const ConstraintSpec& c = s.constraints[it.spec];
    const double v = it.caseIndex < 0 ? staticStroke : metricValue(cases[it.caseIndex], c.metric);
    e.constraints.push_back(c.upper ? v - c.bound : c.bound - v);
  }
  e.ok = std::isfinite(e.objective);
  for (size_t j = 0; j < e.constraints.size(); ++j)
    if (!std::isfinite(e.constraints[j])) {
      e.ok = false;
      e.message = "non-finite constraint " + s.items[j].name;
    }
  if (!std::isfinite(e.objective)) e.message = "non-finite objective";
  return e;
}

Evaluation evaluateDesign(const Study& s, const std::vector<double>& x, const EvaluatorOptions& o,
                          std::vector<CaseResult>* results) {
  try {
    Scene scene = s.scene;  // the design: the variables set as data in the model, no text parsed
    if (const auto why = applyParameters(scene, s.parameters, x)) {
      Evaluation ev;
      ev.message = "the scene rejects the design: " + *why;
      return ev;
    }
    const std::vector<DropCase> cases = designCases(s, scene, o.checks);
    CaseOptions copt;
    copt.record = o.record;
    copt.stop = o.stop;
    std::vector<CaseResult> runs = runCases(scene, cases, std::max(1, o.threads), copt);
    std::vector<CaseMetrics> metrics;
    for (const auto& r : runs) metrics.push_back(r.metrics);
    double ss = kNaN;
    if (s.staticStrokeNeeded) {
      std::string msg;
      ss = staticStroke(scene, &msg);
      if (!std::isfinite(ss)) {
        Evaluation ev;
        ev.detail = caseDetail(metrics);
        ev.message = "static stroke: " + (msg.empty() ? std::string("failed") : msg);
        if (results) *results = std::move(runs);
        return ev;
      }
    }
    if (results) *results = std::move(runs);
    return reduceMetrics(s, std::move(metrics), ss);
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

Evaluation evaluateDesignGradient(const Study& s, const std::vector<double>& x, const EvaluatorOptions& o) {
  try {
    Scene scene = s.scene;
    if (const auto why = applyParameters(scene, s.parameters, x)) {
      Evaluation ev;
      ev.message = "the scene rejects the design: " + *why;
      return ev;
    }
    const std::vector<DropCase> cases = designCases(s, scene, false);
    std::vector<CaseGradient> g(cases.size());
    const int n = static_cast<int>(cases.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, o.threads))
    for (int i = 0; i < n; ++i) g[i] = caseGradient(scene, cases[i], s.parameters);
    std::vector<CaseMetrics> metrics;
    for (const auto& cg : g) metrics.push_back(cg.values);
    Evaluation e = reduceMetrics(s, std::move(metrics), kNaN);
    if (!e.ok) return e;
    // The same reduction on the derivatives (the worst term's where the objective is their worst:
    // one-sided at a tie, which the epigraph form of a gradient study avoids).
    const bool peak = s.objective.kind == ObjectiveKind::MinPeakLoad;
    const std::string objectiveMetric = peak ? "peak_load" : "efficiency";
    e.objectiveGradient.assign(x.size(), 0.0);
    double worst = kNaN;
    const std::vector<CaseMetrics>& values = caseMetricsOf(e);
    for (int i = 0; i < n; ++i) {
      if (s.cases[i].role != CaseRole::Objective) continue;
      const std::vector<double>& d = g[i].find(objectiveMetric)->d;
      const double fi = peak ? values[i].peak_load_N : values[i].efficiency;
      if (s.objective.aggregate == Aggregate::WeightedSum) {
        for (size_t k = 0; k < d.size(); ++k) e.objectiveGradient[k] += s.cases[i].weight * d[k];
      } else {
        e.termGradients.push_back(d);
        if (std::isnan(worst) || (peak ? fi > worst : fi < worst)) {
          worst = fi;
          e.objectiveGradient = d;
        }
      }
    }
    for (const auto& it : s.items) {
      const ConstraintSpec& c = s.constraints[it.spec];
      const std::vector<double>& d = g[it.caseIndex].find(c.metric)->d;
      std::vector<double> dg(d.size());
      for (size_t k = 0; k < d.size(); ++k) dg[k] = c.upper ? d[k] : -d[k];
      e.constraintGradients.push_back(dg);
    }
    e.hasGradient = true;
    return e;
  } catch (const std::exception& ex) {
    Evaluation ev;
    ev.message = std::string("evaluation failed: ") + ex.what();
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
  EvaluatorOptions steering = o;
  steering.checks = false;
  p.evaluate = [&s, steering](const std::vector<double>& x) { return evaluateDesign(s, x, steering); };
  p.worstOfTerms = s.objective.aggregate == Aggregate::Worst;
  if (!s.staticStrokeNeeded)
    p.evaluateGradient = [&s, steering](const std::vector<double>& x) { return evaluateDesignGradient(s, x, steering); };
  return p;
}

}  // namespace lg::optim
