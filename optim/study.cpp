// Study files: parsing and validation at the edge (study.hpp).
#include "optim/study.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include <nlopt.h>

#include "optim/evaluator.hpp"
#include "optim/optimizer.hpp"
#include "sim/io/toml_reader.hpp"

namespace lg::optim {

// ---- scaling ---------------------------------------------------------------------------------------
double toPhysical(const Variable& v, double u) {
  if (v.log) return std::exp(std::log(v.lower) + u * (std::log(v.upper) - std::log(v.lower)));
  return v.lower + u * (v.upper - v.lower);
}
double toScaled(const Variable& v, double x) {
  if (v.log) return (std::log(x) - std::log(v.lower)) / (std::log(v.upper) - std::log(v.lower));
  return (x - v.lower) / (v.upper - v.lower);
}
std::vector<double> toPhysical(const std::vector<Variable>& vars, const std::vector<double>& u) {
  std::vector<double> x(vars.size());
  for (size_t i = 0; i < vars.size(); ++i) x[i] = toPhysical(vars[i], u[i]);
  return x;
}
std::vector<double> toScaled(const std::vector<Variable>& vars, const std::vector<double>& x) {
  std::vector<double> u(vars.size());
  for (size_t i = 0; i < vars.size(); ++i) u[i] = std::clamp(toScaled(vars[i], x[i]), 0.0, 1.0);
  return u;
}

bool nativeConstraints(const std::string& a) {
  return a == "LN_COBYLA" || a == "GN_ISRES" || a == "GN_AGS" || a == "AUGLAG" || a == "LN_AUGLAG" ||
         a == "AUGLAG_EQ" || a == "LN_AUGLAG_EQ";
}

// ---- parsing ---------------------------------------------------------------------------------------
Study parseStudy(const std::string& text, const std::string& file, const std::string& baseDir) {
  toml::table doc;
  try {
    doc = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    throw InputError(file, static_cast<int>(e.source().begin.line), "", "TOML syntax: " + std::string(e.description()));
  }
  Study s;
  s.file = file;
  TomlReader top(doc, file, "");
  top.allowOnly({"name", "description", "scene", "solver", "variable", "case", "objective", "constraints", "algorithm"});
  s.name = top.string("name", std::filesystem::path(file).stem().string());
  (void)top.string("description", "");

  // scene
  {
    const std::string rel = top.string("scene");
    std::filesystem::path p(rel);
    if (p.is_relative()) p = std::filesystem::path(baseDir) / p;
    std::error_code ec;
    if (!std::filesystem::is_regular_file(p, ec))
      top.fail("scene", "scene file '" + p.string() + "' does not exist (the path is relative to the study file)");
    s.sceneFile = p.lexically_normal().string();
    s.sceneDir = p.parent_path().lexically_normal().string();
    if (s.sceneDir.empty()) s.sceneDir = ".";
    s.scene = loadScene(s.sceneFile);  // its own errors name the scene file
  }

  // [solver]: the study's own integrator settings, written into the scene's [solver] so that every
  // design, the baseline and best.toml run with them (a fast, looser setting for long studies).
  if (const toml::table* t = tableOf(doc, "solver", file)) {
    TomlReader r(*t, file, "solver");
    r.allowOnly({"integrator", "rtol", "atol", "step"});
    toml::table& sceneSolver = *s.scene.doc.insert("solver", toml::table{}).first->second.as_table();
    if (r.has("integrator")) {
      const std::string name = r.string("integrator");
      IntegratorKind kind;
      if (!integratorFromName(name, kind)) r.fail("integrator", "value '" + name + "' must be one of " + integratorNames());
      sceneSolver.insert_or_assign("integrator", name);
    }
    if (r.has("rtol")) {
      const double rtol = r.positive("rtol");
      sceneSolver.insert_or_assign("rtol", rtol);
      if (!r.has("atol")) sceneSolver.insert_or_assign("atol", rtol * 1e-2);
    }
    if (r.has("atol")) sceneSolver.insert_or_assign("atol", r.positive("atol"));
    if (r.has("step")) sceneSolver.insert_or_assign("step", r.positive("step"));
    s.scene = buildScene(s.scene.doc, s.sceneFile, s.sceneDir);
  }

  // [[variable]]
  const auto vars = tablesOf(doc, "variable", file);
  if (vars.empty()) throw InputError(file, 0, "variable", "a study needs at least one [[variable]]");
  std::set<std::string> paths;
  for (size_t i = 0; i < vars.size(); ++i) {
    TomlReader r(*vars[i], file, "variable[" + std::to_string(i) + "]");
    r.allowOnly({"path", "lower", "upper", "initial", "log"});
    Variable v;
    v.line = r.line();
    v.path = r.string("path");
    if (!paths.insert(v.path).second) r.fail("path", "'" + v.path + "' is already a variable of this study");
    double sceneValue = 0;
    try {
      sceneValue = getParameter(s.scene.doc, v.path, s.sceneFile);
    } catch (const InputError& e) {
      r.fail("path", "'" + v.path + "' is not a numeric parameter of the scene (" + e.what() + ")");
    }
    v.lower = r.number("lower");
    v.upper = r.number("upper");
    v.log = r.boolean("log", false);
    if (!(v.upper > v.lower))
      r.fail("upper", "upper " + fmt(v.upper) + " must be greater than lower " + fmt(v.lower));
    if (v.log && !(v.lower > 0)) r.fail("lower", "lower " + fmt(v.lower) + " must be > 0 with log = true");
    if (r.has("initial")) {
      v.initial = r.number("initial");
      if (!(v.initial >= v.lower && v.initial <= v.upper))
        r.fail("initial", "initial " + fmt(v.initial) + " must lie in [lower, upper] = [" + fmt(v.lower) + ", " +
                              fmt(v.upper) + "]");
    } else {
      v.initial = sceneValue;
      if (!(v.initial >= v.lower && v.initial <= v.upper))
        r.fail("path", "the scene value " + fmt(sceneValue) + " (the default initial) lies outside [lower, upper] = [" +
                           fmt(v.lower) + ", " + fmt(v.upper) + "]: give 'initial' or widen the bounds");
    }
    s.variables.push_back(v);
  }

  // [[case]]
  const auto cases = tablesOf(doc, "case", file);
  if (cases.empty()) throw InputError(file, 0, "case", "a study needs at least one [[case]]");
  std::set<std::string> caseNames;
  for (size_t i = 0; i < cases.size(); ++i) {
    TomlReader r(*cases[i], file, "case[" + std::to_string(i) + "]");
    r.allowOnly({"name", "sink_speed", "lift_ratio", "duration", "masses", "weight"});
    StudyCase c;
    c.line = r.line();
    c.weight = r.positive("weight", 1.0);
    const std::string name = r.string("name", "case" + std::to_string(i));
    if (!caseNames.insert(name).second) r.fail("name", "case '" + name + "' appears twice in the study");
    const DropCase* sceneCase = nullptr;
    for (const auto& sc : s.scene.cases)
      if (sc.name == name) sceneCase = &sc;
    const bool overrides = r.has("sink_speed") || r.has("lift_ratio") || r.has("duration") || r.has("masses");
    if (sceneCase) {
      c.dropCase = *sceneCase;
      c.fromScene = !overrides;
    } else {
      if (!r.has("sink_speed")) {
        std::string list;
        for (const auto& sc : s.scene.cases) list += (list.empty() ? "" : ", ") + sc.name;
        r.fail(r.has("name") ? "name" : "sink_speed",
               "'" + name + "' is not a case of the scene (it has: " + (list.empty() ? "none" : list) +
                   "); a new case needs sink_speed and lift_ratio");
      }
      if (!r.has("lift_ratio")) r.fail("lift_ratio", "missing required number (a new case needs sink_speed and lift_ratio)");
      c.dropCase.name = name;
    }
    c.dropCase.sinkSpeed = r.nonNegative("sink_speed", c.dropCase.sinkSpeed);
    c.dropCase.liftRatio = r.nonNegative("lift_ratio", c.dropCase.liftRatio);
    c.dropCase.duration = r.positive("duration", c.dropCase.duration);
    if (c.dropCase.liftRatio > 0 && s.scene.roles.lifts.empty())
      r.fail("lift_ratio", "the scene declares no lift element");
    if (const toml::node* mn = r.get("masses")) {
      const toml::table* mt = mn->as_table();
      if (!mt) r.fail("masses", "must be a table of body = mass [kg]");
      TomlReader mr(*mt, file, r.full("masses"));
      for (const auto& [k, v] : *mt) {
        const std::string body(k.str());
        if (s.scene.model.bodyIndex(body) < 0) mr.fail(body, "'" + body + "' is not a body of the scene");
        c.dropCase.masses[body] = mr.positive(body, 0.0);
      }
    }
    s.cases.push_back(c);
  }

  // [objective]
  if (const toml::table* t = tableOf(doc, "objective", file)) {
    TomlReader r(*t, file, "objective");
    r.allowOnly({"kind", "aggregate"});
    const std::string kind = r.string("kind", "min_peak_load");
    if (kind == "min_peak_load") s.objective.kind = ObjectiveKind::MinPeakLoad;
    else if (kind == "max_efficiency") s.objective.kind = ObjectiveKind::MaxEfficiency;
    else r.fail("kind", "value '" + kind + "' must be \"min_peak_load\" or \"max_efficiency\"");
    const std::string agg = r.string("aggregate", "max");
    if (agg == "max") s.objective.aggregate = Aggregate::Max;
    else if (agg == "weighted_sum") s.objective.aggregate = Aggregate::WeightedSum;
    else r.fail("aggregate", "value '" + agg + "' must be \"max\" or \"weighted_sum\"");
  }

  // [constraints]
  if (const toml::table* t = tableOf(doc, "constraints", file)) {
    TomlReader r(*t, file, "constraints");
    r.allowOnly({"stroke_max", "stroke_margin", "tyre_deflection_max", "static_stroke", "no_bottoming", "rebound_max"});
    Constraints& c = s.constraints;
    if (r.has("stroke_max")) c.strokeMax = r.positive("stroke_max", 0.0);
    c.strokeMargin = r.nonNegative("stroke_margin", 0.0);
    if (r.has("stroke_margin") && !c.strokeMax) r.fail("stroke_margin", "needs stroke_max");
    if (c.strokeMax && !(c.strokeMargin < *c.strokeMax))
      r.fail("stroke_margin", "stroke_margin " + fmt(c.strokeMargin) + " must be smaller than stroke_max " + fmt(*c.strokeMax));
    if (const toml::node* n = r.get("tyre_deflection_max")) {
      if (n->is_string()) {
        const std::string v(*n->value<std::string>());
        if (v != "delta_max") r.fail("tyre_deflection_max", "value '" + v + "' must be \"delta_max\" or a number [m]");
        if (std::isnan(sceneTyreDeltaMax(s.scene)))
          r.fail("tyre_deflection_max", "\"delta_max\" needs a tyre element in the scene");
        c.tyreDeflectionFromScene = true;
      } else {
        c.tyreDeflectionMax = r.positive("tyre_deflection_max", 0.0);
      }
    }
    if (const toml::node* n = r.get("static_stroke")) {
      const toml::array* a = n->as_array();
      if (!a || a->size() != 2) r.fail("static_stroke", "must be [lower, upper] in m");
      const double lo = r.toNumber(*a->get(0), "static_stroke"), hi = r.toNumber(*a->get(1), "static_stroke");
      if (!(lo >= 0 && hi > lo)) r.fail("static_stroke", "needs 0 <= lower < upper, got [" + fmt(lo) + ", " + fmt(hi) + "]");
      c.staticStrokeLower = lo;
      c.staticStrokeUpper = hi;
    }
    c.noBottoming = r.boolean("no_bottoming", false);
    if (r.has("rebound_max")) c.reboundMax = r.number("rebound_max");
  }

  // [algorithm]
  if (const toml::table* t = tableOf(doc, "algorithm", file)) {
    TomlReader r(*t, file, "algorithm");
    r.allowOnly({"name", "local", "maxeval", "maxtime", "xtol_rel", "ftol_rel", "seed", "penalty", "initial_step"});
    AlgorithmSettings& a = s.algorithm;
    a.name = r.string("name", a.name);
    a.local = r.string("local", "");
    if (std::string rule = checkAlgorithm(a.name, a.local); !rule.empty())
      r.fail(rule.rfind("local", 0) == 0 ? "local" : "name", rule);
    const long long me = r.integer("maxeval", a.maxeval);
    if (me < 0 || me > 100000000) r.fail("maxeval", "value " + std::to_string(me) + " must be in [0, 1e8] (0: no limit)");
    a.maxeval = static_cast<int>(me);
    a.maxtime = r.nonNegative("maxtime", a.maxtime);
    a.xtolRel = r.nonNegative("xtol_rel", a.xtolRel);
    a.ftolRel = r.nonNegative("ftol_rel", a.ftolRel);
    const long long seed = r.integer("seed", a.seed);
    if (seed < 0 || seed > 4294967295LL) r.fail("seed", "value " + std::to_string(seed) + " must be in [0, 2^32)");
    a.seed = static_cast<unsigned>(seed);
    a.penalty = r.positive("penalty", a.penalty);
    a.initialStep = r.nonNegative("initial_step", a.initialStep);
    if (a.initialStep > 1) r.fail("initial_step", "value " + fmt(a.initialStep) + " must be <= 1 (scaled units)");
    if (a.maxeval == 0 && a.maxtime == 0 && a.xtolRel == 0 && a.ftolRel == 0)
      r.fail("maxeval", "give at least one stopping rule (maxeval, maxtime, xtol_rel or ftol_rel)");
  }
  return s;
}

Study loadStudy(const std::string& path) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path, 0, "", "study file does not exist");
  const std::string text = readText(path, "study file");
  std::string base = std::filesystem::path(path).parent_path().string();
  if (base.empty()) base = ".";
  return parseStudy(text, path, base);
}

}  // namespace lg::optim
