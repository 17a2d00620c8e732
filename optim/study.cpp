// Study files: parsing and validation at the edge (study.hpp).
#include "optim/study.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <limits>
#include <set>

#include <nlopt.h>

#include "optim/optimizer.hpp"
#include "sim/drop/accuracy.hpp"
#include "sim/io/certification.hpp"
#include "sim/io/drop_case.hpp"
#include "sim/io/files.hpp"
#include "sim/io/toml_reader.hpp"
#include "sim/drop/metrics.hpp"
#include "sim/scene/check.hpp"

namespace lg::optim {

// ---- scaling ---------------------------------------------------------------------------------------
const char* roleName(CaseRole r) {
  switch (r) {
    case CaseRole::Objective: return "objective";
    case CaseRole::Constraint: return "constraint";
    default: return "check";
  }
}
const char* originName(CaseOrigin o) {
  switch (o) {
    case CaseOrigin::Scene: return "scene";
    case CaseOrigin::Certification: return "certification";
    default: return "study";
  }
}

int Study::steeringCases() const {
  int n = 0;
  for (const auto& c : cases) n += c.steers() ? 1 : 0;
  return n;
}

namespace {

CaseRole parseRole(const TomlReader& r, const std::string& key, CaseRole def) {
  if (!r.has(key)) return def;
  const std::string v = r.string(key);
  if (v == "objective") return CaseRole::Objective;
  if (v == "constraint") return CaseRole::Constraint;
  if (v == "check") return CaseRole::Check;
  r.fail(key, "value '" + v + "' must be \"objective\", \"constraint\" or \"check\"");
}

// What the scene must declare for a metric to mean something; an empty string when it does.
std::string metricNeeds(const Scene& sc, const std::string& metric) {
  const bool tyre = !sc.roles.tyres.empty(), strut = !sc.roles.struts.empty(), airframe = !sc.roles.airframe.empty();
  bool stop = false;
  for (double S : sc.roles.strokeLimits) stop = stop || std::isfinite(S);
  if ((metric == "stroke" || metric == "strut_efficiency" || metric == "strut_force" || metric == "static_stroke") && !strut)
    return "a shock absorber";
  if (metric == "stroke_margin" && !stop) return "a strut with a bottoming stop (a min_distance stop on its two points)";
  if ((metric == "peak_load" || metric == "load_factor" || metric == "inertia_load_factor" ||
       metric == "tyre_deflection" || metric == "tyre_margin" || metric == "efficiency" || metric == "energy_absorbed") &&
      !tyre)
    return "a tyre";
  if ((metric == "h_max" || metric == "efficiency" || metric == "rebound_velocity" || metric == "energy_absorbed") &&
      !airframe)
    return "an airframe body ([scene] airframe, or a lift element)";
  if (metric == "drag_peak" || metric == "springback_peak" || metric == "drag_at_peak" || metric == "drag_ratio") {
    bool drag = false;
    for (int f : sc.roles.tyres) drag = drag || std::get<Tyre<double>>(sc.model.forces[f].type).longitudinal;
    if (!drag) return "a tyre with a longitudinal force (mu_x: wheel spin-up)";
  }
  return "";
}

// An error in a study's table laid over the scene's table 'name' (merged: its nodes carry no file): named
// at the file and line the offending key came from, the study's or the scene's ('line': the study's table).
[[noreturn]] void rethrowFromMerged(const InputError& e, const std::string& name, const toml::table& t,
                                    const std::string& file, int line, const Study& s) {
  std::string key = e.key().rfind(name + ".", 0) == 0 ? e.key().substr(name.size() + 1) : e.key();
  key = key.substr(0, key.find_first_of(".["));
  const std::string& rule = e.rule();
  if (t.contains(key)) throw InputError(file, TomlReader(t, file, "").lineOf(key), e.key(), rule);
  if (const toml::table* st = s.scene.doc[name].as_table(); st && st->contains(key))
    throw InputError(s.sceneFile, TomlReader(*st, s.sceneFile, "").lineOf(key), e.key(), rule);
  throw InputError(file, line, e.key(), rule);
}

// [certification]: the scene's table with the study's keys laid over it (role excepted).
void parseCertificationTable(const toml::table& doc, const std::string& file, Study& s) {
  const toml::table* t = tableOf(doc, "certification", file);
  if (!t) {
    s.certification = s.scene.certification;
    s.certificationRole = CaseRole::Check;
    return;
  }
  TomlReader r(*t, file, "certification");
  s.certificationRole = parseRole(r, "role", CaseRole::Constraint);
  if (s.certificationRole == CaseRole::Objective)
    r.fail("role", "the whole matrix cannot be the objective: name the cases to minimise as [[case]] with role = \"objective\"");
  toml::table merged;
  if (const toml::table* st = s.scene.doc["certification"].as_table()) merged = *st;
  for (const auto& [k, v] : *t)
    if (k.str() != "role") merged.insert_or_assign(k, v);
  if (merged.empty())
    r.fail("role", "the scene has no [certification] table: give the matrix here (basis, landing_mass, limit_load_factor, ...)");
  try {
    s.certification = std::make_shared<const Certification>(parseCertification(merged, file, s.scene));
  } catch (const InputError& e) {
    rethrowFromMerged(e, "certification", *t, file, r.line(), s);
  }
  s.scene.doc.insert_or_assign("certification", merged);  // best.toml keeps the matrix the study used
  s.scene.certification = s.certification;
}

// [envelope]: where the cases run in the scene's envelope, and the scene's keys laid over its own.
void parseEnvelopeTable(const toml::table& doc, const std::string& file, Study& s, bool nominal) {
  const toml::table* t = tableOf(doc, "envelope", file);
  if (t) {
    TomlReader r(*t, file, "envelope");
    s.envelope.line = r.line();
    auto choice = [&](const char* key, const char* a, const char* b, const char* def) {
      const std::string v = r.string(key, def);
      if (v != a && v != b) r.fail(key, "value '" + v + "' must be \"" + a + "\" or \"" + b + "\"");
      return v == a;
    };
    s.envelope.constraintsAtCorners = choice("constraints", "corners", "nominal", "corners");
    s.envelope.objectiveWorst = !choice("objective", "nominal", "worst", "nominal");
    s.envelope.checksAtCorners = choice("checks", "corners", "nominal", "corners");
    s.envelope.nominalStudy = r.boolean("nominal_study", true);
    toml::table merged;
    if (const toml::table* st = s.scene.doc["envelope"].as_table()) merged = *st;
    for (const auto& [k, v] : *t)
      if (k.str() != "constraints" && k.str() != "objective" && k.str() != "checks" && k.str() != "nominal_study")
        merged.insert_or_assign(k, v);
    if (merged.empty())
      r.fail("constraints", "the scene has no [envelope] table: declare its ranges and tolerances there or here "
                            "(service_temperature_C, landing_temperature_C, charge_tolerance, ...)");
    try {
      s.scene.envelope = parseEnvelope(merged, file, s.scene);
    } catch (const InputError& e) {
      rethrowFromMerged(e, "envelope", *t, file, r.line(), s);
    }
    s.scene.doc.insert_or_assign("envelope", merged);  // best.toml keeps the envelope the study used
    if (!s.scene.envelope.declared) s.envelope = EnvelopeUse{};
  }
  if (nominal) {
    s.envelope.constraintsAtCorners = false;
    s.envelope.objectiveWorst = false;
    s.envelope.nominalStudy = false;
  }
  if (s.scene.envelope.declared) s.corners = s.scene.envelope.corners();
}

// Each case at every point of the envelope where the study asks (nominal first, then "<case>@<corner>"),
// steering cases first. A corner copy of an objective case constrains unless the objective is the worst.
void expandCorners(Study& s) {
  for (auto& c : s.cases) {
    c.baseName = c.dropCase.name;
    c.baseRole = c.role;
  }
  if (s.corners.empty()) return;
  std::vector<StudyCase> out;
  for (const StudyCase& c : s.cases) {
    const bool expand = c.steers() ? s.envelope.constraintsAtCorners || (s.envelope.objectiveWorst && c.role == CaseRole::Objective)
                                   : s.envelope.checksAtCorners;
    if (!expand) {
      out.push_back(c);
      if (c.steers() && s.envelope.checksAtCorners)  // re-checked at the corners all the same
        for (size_t k = 1; k < s.corners.size(); ++k) {
          StudyCase x = c;
          x.role = CaseRole::Check;
          x.corner = s.corners[k].name;
          x.dropCase.corner = s.corners[k];
          x.dropCase.name += "@" + s.corners[k].name;
          out.push_back(x);
        }
      continue;
    }
    for (size_t k = 0; k < s.corners.size(); ++k) {
      StudyCase x = c;
      x.corner = s.corners[k].name;
      x.dropCase.corner = s.corners[k];
      if (k > 0) {
        x.dropCase.name += "@" + s.corners[k].name;
        if (x.role == CaseRole::Objective && !s.envelope.objectiveWorst) x.role = CaseRole::Constraint;
      }
      out.push_back(x);
    }
  }
  std::stable_partition(out.begin(), out.end(), [](const StudyCase& c) { return c.steers(); });
  s.cases = std::move(out);
}

// [[case]]: the study's cases with their roles, then every case of the scene and of the matrix that the
// study does not name (checks; the matrix's with the [certification] role). Steering cases come first.
void parseCases(const toml::table& doc, const std::string& file, Study& s) {
  const auto rows = tablesOf(doc, "case", file);
  std::set<std::string> named;
  std::vector<StudyCase> cases;
  const Certification* cert = s.certification.get();
  for (size_t i = 0; i < rows.size(); ++i) {
    TomlReader r(*rows[i], file, "case[" + std::to_string(i) + "]");
    r.allowOnly({"name", "role", "weight", "sink_speed", "drop_height", "lift_ratio", "duration", "forward_speed", "masses"});
    StudyCase c;
    c.line = r.line();
    c.role = parseRole(r, "role", CaseRole::Objective);
    c.weight = r.positive("weight", 1.0);
    const std::string name = r.name("name", "case" + std::to_string(i));
    if (name.empty()) r.fail("name", "a case needs a non-empty name");
    if (!named.insert(name).second) r.fail("name", "case '" + name + "' appears twice in the study");
    const DropCase* sceneCase = nullptr;
    for (const auto& sc : s.scene.cases)
      if (sc.name == name) sceneCase = &sc;
    const CertCase* certCase = cert ? cert->findCase(name) : nullptr;
    const std::string overrides = dropCaseKey(r);  // the first drop key it sets
    if (certCase) {
      if (!overrides.empty())
        r.fail(overrides, "'" + name + "' is a case of the certification matrix: its numbers come from [certification]; give a new "
               "case its own name to change them");
      c.origin = CaseOrigin::Certification;
      c.dropCase = certDropCase(s.scene, *cert, *certCase);
    } else if (sceneCase) {
      c.dropCase = *sceneCase;
      c.origin = overrides.empty() ? CaseOrigin::Scene : CaseOrigin::Study;
    } else {
      if (!r.has("sink_speed") && !r.has("drop_height")) {
        std::string list;
        for (const auto& sc : s.scene.cases) list += (list.empty() ? "" : ", ") + sc.name;
        if (cert)
          for (const auto& cc : cert->cases) list += (list.empty() ? "" : ", ") + cc.name;
        r.fail(r.has("name") ? "name" : "sink_speed",
               "'" + name + "' is not a case of the scene or of its certification matrix (there are: " +
                   (list.empty() ? "none" : list) + "); a new case needs sink_speed and lift_ratio");
      }
      if (!r.has("lift_ratio")) r.fail("lift_ratio", "missing required number (a new case needs sink_speed and lift_ratio)");
      c.dropCase.name = name;
      c.origin = CaseOrigin::Study;
    }
    readDropCase(r, s.scene, c.dropCase, !certCase && !sceneCase);  // (sim/io/drop_case.hpp)
    cases.push_back(c);
  }
  if (cert)
    for (const auto& cc : cert->cases)
      if (!named.count(cc.name)) {
        StudyCase c;
        c.dropCase = certDropCase(s.scene, *cert, cc);
        c.role = s.certificationRole;
        c.origin = CaseOrigin::Certification;
        cases.push_back(c);
      }
  for (const auto& sc : s.scene.cases)
    if (!named.count(sc.name)) {
      StudyCase c;
      c.dropCase = sc;
      c.role = CaseRole::Check;
      c.origin = CaseOrigin::Scene;
      cases.push_back(c);
    }
  std::stable_partition(cases.begin(), cases.end(), [](const StudyCase& c) { return c.steers(); });
  s.cases = std::move(cases);
}

// [objective]
void parseObjective(const toml::table& doc, const std::string& file, Study& s) {
  if (const toml::table* t = tableOf(doc, "objective", file)) {
    TomlReader r(*t, file, "objective");
    r.allowOnly({"kind", "aggregate"});
    const std::string kind = r.string("kind", "min_peak_load");
    if (kind == "min_peak_load") s.objective.kind = ObjectiveKind::MinPeakLoad;
    else if (kind == "max_efficiency") s.objective.kind = ObjectiveKind::MaxEfficiency;
    else r.fail("kind", "value '" + kind + "' must be \"min_peak_load\" or \"max_efficiency\"");
    const std::string agg = r.string("aggregate", "worst");
    if (agg == "worst") s.objective.aggregate = Aggregate::Worst;
    else if (agg == "weighted_sum") s.objective.aggregate = Aggregate::WeightedSum;
    else if (agg == "max" || agg == "min")
      r.fail("aggregate", "value '" + agg + "' is now \"worst\": the largest peak load, or the smallest efficiency, of "
                          "the objective cases");
    else r.fail("aggregate", "value '" + agg + "' must be \"worst\" or \"weighted_sum\"");
  }
  bool any = false;
  for (const auto& c : s.cases) any = any || c.role == CaseRole::Objective;
  if (!any)
    throw InputError(file, 0, "case",
                     "no objective case: name at least one [[case]] with role = \"objective\" (the default role)");
}

// [[constraint]], then the certification matrix's limits on its steering cases.
void parseConstraints(const toml::table& doc, const std::string& file, Study& s) {
  const auto rows = tablesOf(doc, "constraint", file);
  const int steering = s.steeringCases();
  for (size_t i = 0; i < rows.size(); ++i) {
    TomlReader r(*rows[i], file, "constraint[" + std::to_string(i) + "]");
    r.allowOnly({"metric", "min", "max", "cases"});
    const std::string metric = r.string("metric");
    const MetricInfo* info = findMetric(metric);
    const bool design = metric == "static_stroke";
    if (!info && !design)
      r.fail("metric", "value '" + metric + "' must be a case metric (" + metricNames() + ") or \"static_stroke\"");
    if (const std::string need = metricNeeds(s.scene, metric); !need.empty())
      r.fail("metric", "'" + metric + "' needs " + need + " in the scene");
    if (!r.has("min") && !r.has("max")) r.fail("metric", "give a bound: min = ... or max = ... (or both)");
    std::vector<int> idx;
    if (design) {
      if (r.has("cases")) r.fail("cases", "static_stroke is a figure of the design (the strut settled under 1 g), not of a case");
      s.staticStrokeNeeded = true;
    } else if (const toml::node* n = r.get("cases"); n && n->is_array()) {
      for (const auto& e : *n->as_array()) {
        if (!e.is_string()) r.fail("cases", "must be a list of case names, or one of \"steering\", \"objective\", \"constraint\"");
        const std::string name(*e.value<std::string>());
        int found = -1;
        for (size_t k = 0; k < s.cases.size(); ++k)  // (a case at every point of the envelope: each)
          if (s.cases[k].dropCase.name == name || s.cases[k].baseName == name) {
            found = static_cast<int>(k);
            if (!s.cases[found].steers())
              r.fail("cases", "'" + name + "' is a check case: checks never steer; give it role = \"constraint\" in a [[case]]");
            if (std::find(idx.begin(), idx.end(), found) == idx.end()) idx.push_back(found);
          }
        if (found < 0) r.fail("cases", "'" + name + "' is not a case of the study, its scene or its matrix");
      }
      if (idx.empty()) r.fail("cases", "names no case");
    } else {
      const std::string sel = n ? (n->is_string() ? std::string(*n->value<std::string>()) : std::string("?")) : "steering";
      for (int k = 0; k < steering; ++k) {
        const CaseRole role = s.cases[k].baseRole;
        if (sel == "steering" || (sel == "objective" && role == CaseRole::Objective) ||
            (sel == "constraint" && role == CaseRole::Constraint))
          idx.push_back(k);
      }
      if (sel != "steering" && sel != "objective" && sel != "constraint")
        r.fail("cases", "must be a list of case names, or one of \"steering\" (objective and constraint cases, the "
                        "default), \"objective\", \"constraint\"");
      if (idx.empty()) r.fail("cases", "\"" + sel + "\" selects no case of this study");
    }
    const double unitScale = design ? 0.01 : info->scale;
    for (const char* key : {"max", "min"}) {
      if (!r.has(key)) continue;
      ConstraintSpec c;
      c.metric = metric;
      c.upper = std::string(key) == "max";
      c.bound = r.number(key);
      // A bound the metric can never meet is a mistake of sign or of metric, not a study to run.
      const double least = design ? 0.0 : info->least, most = design ? MetricInfo::kInf : info->most;
      if (c.upper && c.bound < least) {
        const std::string margin = metric == "stroke" ? "stroke_margin" : metric == "tyre_deflection" ? "tyre_margin" : "";
        r.fail(key, "value " + fmt(c.bound) + " " + (design ? "m" : info->unit) + " can never hold: " + metric + " is >= " +
                        fmt(least) + (margin.empty() ? "" : " (a margin is " + margin + ", with min = ...)"));
      }
      if (!c.upper && c.bound > most)
        r.fail(key, "value " + fmt(c.bound) + " can never hold: " + metric + " is <= " + fmt(most));
      c.scale = std::max(std::abs(c.bound), unitScale);
      c.cases = idx;
      c.source = "study";
      c.rule = metric + (c.upper ? " <= " : " >= ") + fmt(c.bound) + " " + (design ? "m" : info->unit);
      c.line = r.lineOf(key);
      s.constraints.push_back(c);
    }
    if (r.has("min") && r.has("max") && !(r.number("min") < r.number("max")))
      r.fail("max", "max " + fmt(r.number("max")) + " must be greater than min " + fmt(r.number("min")));
  }
  if (s.certification)
    for (int k = 0; k < steering; ++k) {
      if (s.cases[k].origin != CaseOrigin::Certification) continue;
      const CertCase* cc = s.certification->findCase(s.cases[k].baseName);
      for (const Limit& l : caseLimits(*s.certification, *cc, s.scene)) {
        ConstraintSpec c;
        c.metric = l.metric;
        c.upper = l.upper;
        c.bound = l.bound;
        c.scale = std::max(std::abs(l.bound), findMetric(l.metric)->scale);
        c.cases = {k};
        c.source = "certification";
        c.rule = l.rule;
        c.line = s.certification->line;
        s.constraints.push_back(c);
      }
    }
  // The scalar constraints g_j: one per spec and case, named metric@case (unique).
  std::set<std::string> names;
  for (size_t j = 0; j < s.constraints.size(); ++j) {
    const ConstraintSpec& c = s.constraints[j];
    std::vector<int> on = c.cases.empty() ? std::vector<int>{-1} : c.cases;
    for (int k : on) {
      ConstraintItem it;
      it.spec = static_cast<int>(j);
      it.caseIndex = k;
      std::string base = c.metric + (c.upper ? "_max" : "_min") + (k >= 0 ? "@" + s.cases[k].dropCase.name : "");
      it.name = base;
      for (int n = 2; !names.insert(it.name).second; ++n) it.name = base + "#" + std::to_string(n);
      s.items.push_back(it);
    }
  }
}

// [algorithm]
void parseAlgorithm(const toml::table& doc, const std::string& file, Study& s) {
  const toml::table* t = tableOf(doc, "algorithm", file);
  if (!t) return;
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
  if (usesGradients(a.name, a.local) && s.staticStrokeNeeded)
    r.fail("name", "'" + a.name + "' needs derivatives, and the static_stroke constraint has none: use a derivative-free "
                   "algorithm (LN_COBYLA, ...)");
  if (a.name == "LD_LBFGS" && !s.items.empty())
    r.fail("name", "LD_LBFGS handles bounds only, and this study has constraints: use LD_SLSQP, LD_MMA or LD_CCSAQ");
}

// A list of strings (a single string is a list of one); errors name the key.
std::vector<std::string> stringList(const TomlReader& r, const std::string& key) {
  const toml::node* n = r.get(key);
  std::vector<std::string> out;
  if (n->is_string()) out.push_back(std::string(*n->value<std::string>()));
  else if (const toml::array* a = n->as_array()) {
    for (const auto& e : *a) {
      if (!e.is_string()) r.fail(key, "must be a list of strings");
      out.push_back(std::string(*e.value<std::string>()));
    }
  } else {
    r.fail(key, "must be a list of strings");
  }
  if (out.empty()) r.fail(key, "names nothing: leave the key out for the default");
  for (size_t i = 0; i < out.size(); ++i)
    for (size_t k = 0; k < i; ++k)
      if (out[i] == out[k]) r.fail(key, "'" + out[i] + "' appears twice");
  return out;
}

long long integerIn(const TomlReader& r, const std::string& key, long long def, long long lo, long long hi,
                    const std::string& what) {
  const long long v = r.integer(key, def);
  if (v < lo || v > hi)
    r.fail(key, "value " + std::to_string(v) + " must be in [" + std::to_string(lo) + ", " + std::to_string(hi) + "]" +
                    (what.empty() ? "" : " (" + what + ")"));
  return v;
}

// [sensitivity]: methods, metrics and cases of interest, sample sizes, seed (optim/sensitivity.hpp).
void parseSensitivity(const toml::table& doc, const std::string& file, Study& s) {
  SensitivitySettings& g = s.sensitivity;
  const toml::table* t = tableOf(doc, "sensitivity", file);
  for (const auto& m : metricCatalogue())
    if (metricNeeds(s.scene, m.name).empty()) g.metrics.push_back(m.name);
  for (int k = 0; k < s.steeringCases(); ++k) g.cases.push_back(k);
  if (!t) return;
  TomlReader r(*t, file, "sensitivity");
  r.allowOnly({"methods", "metrics", "cases", "seed", "derivatives", "step", "levels", "trajectories", "samples",
               "resamples", "confidence"});
  g.line = r.line();
  if (r.has("methods")) {
    g.local = g.morris = g.sobol = false;
    for (const std::string& m : stringList(r, "methods")) {
      if (m == "local") g.local = true;
      else if (m == "morris") g.morris = true;
      else if (m == "sobol") g.sobol = true;
      else r.fail("methods", "value '" + m + "' must be \"local\", \"morris\" or \"sobol\"");
    }
  }
  if (r.has("metrics")) {
    g.metrics = stringList(r, "metrics");
    for (const std::string& m : g.metrics) {
      if (!findMetric(m)) r.fail("metrics", "value '" + m + "' must be a case metric (" + metricNames() + ")");
      if (const std::string need = metricNeeds(s.scene, m); !need.empty())
        r.fail("metrics", "'" + m + "' needs " + need + " in the scene");
    }
  }
  if (r.has("cases")) {
    const toml::node* n = r.get("cases");
    if (n->is_string() && (*n->value<std::string>() == "steering" || *n->value<std::string>() == "all")) {
      g.cases.clear();
      const int count = *n->value<std::string>() == "all" ? static_cast<int>(s.cases.size()) : s.steeringCases();
      for (int k = 0; k < count; ++k) g.cases.push_back(k);
    } else {
      g.cases.clear();
      for (const std::string& name : stringList(r, "cases")) {
        int found = -1;
        for (size_t k = 0; k < s.cases.size(); ++k)
          if (s.cases[k].dropCase.name == name) found = static_cast<int>(k);
        if (found < 0) {
          std::string list;
          for (const auto& c : s.cases) list += (list.empty() ? "" : ", ") + c.dropCase.name;
          r.fail("cases", "'" + name + "' is not a case of the study, its scene or its matrix (there are: " + list +
                              "); or give \"steering\" (the default) or \"all\"");
        }
        g.cases.push_back(found);
      }
    }
  }
  g.seed = static_cast<unsigned long long>(integerIn(r, "seed", 1, 0, 9223372036854775807LL, ""));
  const std::string deriv = r.string("derivatives", "exact");
  if (deriv != "exact" && deriv != "central")
    r.fail("derivatives", "value '" + deriv + "' must be \"exact\" (forward mode through the run) or \"central\" (central "
                          "differences with relative step 'step')");
  g.exactDerivatives = deriv == "exact";
  if (g.exactDerivatives && r.has("step"))
    r.fail("step", "the relative step is for derivatives = \"central\"; the exact derivatives take none");
  g.step = r.positive("step", g.step);
  if (g.step > 0.5) r.fail("step", "value " + fmt(g.step) + " must be <= 0.5 (a relative step of the central differences)");
  g.levels = static_cast<int>(integerIn(r, "levels", g.levels, 2, 100, "Morris grid levels"));
  if (g.levels % 2 != 0)
    r.fail("levels", "value " + std::to_string(g.levels) + " must be even (each level then has one move of p/(2(p-1)))");
  g.trajectories = static_cast<int>(integerIn(r, "trajectories", g.trajectories, 2, 100000, "Morris trajectories r"));
  g.samples = static_cast<int>(integerIn(r, "samples", g.samples, 8, 1 << 20, "Sobol base sample N"));
  if ((g.samples & (g.samples - 1)) != 0)
    r.fail("samples", "value " + std::to_string(g.samples) + " must be a power of two (the Sobol points are then a net)");
  g.resamples = static_cast<int>(integerIn(r, "resamples", g.resamples, 10, 100000, "bootstrap replicates"));
  g.confidence = r.positive("confidence", g.confidence);
  if (!(g.confidence >= 0.5 && g.confidence < 1))
    r.fail("confidence", "value " + fmt(g.confidence) + " must be in [0.5, 1)");
}

}  // namespace

namespace {

// The setting of a scene's solver in words: "dopri5, rtol 1e-06" or "accuracy 0.001 (ros34pw2, rtol 0.000167)".
std::string describeSolver(const Settings& c) {
  const bool adaptive = c.integrator == IntegratorKind::DormandPrince || isRosenbrock(c.integrator);
  const std::string setting = integratorName(c.integrator) + (adaptive ? ", rtol " + fmt(c.rtol) : ", step " + fmt(c.step) + " s");
  return c.accuracy > 0 ? "accuracy " + fmt(c.accuracy) + " (" + setting + ")" : setting;
}

// The accuracy the study's stopping tolerances need, and the solver it runs with (Study::solverChoice).
void chooseSolver(bool studySolver, Study& s) {
  double tol = s.algorithm.xtolRel > 0 ? s.algorithm.xtolRel : std::numeric_limits<double>::infinity();
  if (s.algorithm.ftolRel > 0) tol = std::min(tol, s.algorithm.ftolRel);
  s.accuracyNeeded = std::isfinite(tol) ? std::clamp(0.1 * tol, kAccuracyMin, 1e-2) : 1e-3;
  const std::string why = std::isfinite(tol) ? "the study's xtol_rel / ftol_rel of " + fmt(tol) : "a study stopped by maxeval or maxtime";
  Settings& cfg = s.scene.model.settings;
  const double have = impliedAccuracy(cfg);
  const std::string haveWords = std::isnan(have) ? "an accuracy the calibration does not cover" : "metrics to about " + fmt(have);
  const std::string need = fmt(s.accuracyNeeded) + " that " + why + " needs";
  if (studySolver) {
    s.solverChoice = describeSolver(cfg) + ": the study's [solver], " + haveWords +
                     (!std::isnan(have) && have <= s.accuracyNeeded ? ", within the " : ", NOT within the ") + need;
  } else if (!std::isnan(have) && have <= s.accuracyNeeded) {
    s.solverChoice = describeSolver(cfg) + ": the scene's [solver], " + haveWords + ", within the " + need;
  } else {
    const std::string old = describeSolver(cfg);
    applySolverOverrides(cfg, SolverOverrides{.accuracy = s.accuracyNeeded});
    toml::table& sceneSolver = *s.scene.doc.insert("solver", toml::table{}).first->second.as_table();
    for (const char* k : {"integrator", "rtol", "atol", "max_step"}) sceneSolver.erase(k);
    sceneSolver.insert_or_assign("accuracy", s.accuracyNeeded);
    s.solverChoice = describeSolver(cfg) + ": the " + need + " (the scene's " + old + " gives " + haveWords + ")";
  }
}

}  // namespace

// ---- parsing ---------------------------------------------------------------------------------------
Study parseStudy(const std::string& text, const std::string& file, const std::string& baseDir,
                 const std::vector<ParameterOverride>& sets, bool nominal) {
  const toml::table doc = parseToml(text, file);
  Study s;
  s.file = file;
  s.sets = sets;
  TomlReader top(doc, file, "");
  if (top.has("constraints"))
    top.fail("constraints", "the [constraints] table was replaced by a list of [[constraint]] tables, one bound each, "
                            "e.g. [[constraint]] metric = \"stroke_margin\" min = 0.01 (docs/study.md)");
  top.allowOnly({"name", "description", "scene", "solver", "variable", "case", "objective", "constraint", "certification",
                 "envelope", "algorithm", "sensitivity"});
  s.name = top.name("name", safeFileStem(std::filesystem::path(file).stem().string()));
  (void)top.string("description", "");

  // scene
  {
    const std::string rel = top.string("scene");
    std::filesystem::path p(rel);
    if (p.is_relative()) p = std::filesystem::path(baseDir) / p;
    if (const std::string why = fileProblem(p.string()); !why.empty())
      top.fail("scene", "cannot read the scene file '" + p.string() + "': " + why + " (the path is relative to the study file)");
    s.sceneFile = p.lexically_normal().string();
    s.sceneDir = p.parent_path().lexically_normal().string();
    if (s.sceneDir.empty()) s.sceneDir = ".";
    s.scene = applyOverrides(loadScene(s.sceneFile), sets);  // its own errors name the scene file
  }

  // [solver]: the study's own integrator settings, written into the scene's [solver] so that every
  // design, the baseline and best.toml run with them (a fast, looser setting for long studies).
  applySolverTable(tableOf(doc, "solver", file), file, s.scene);

  parseCertificationTable(doc, file, s);
  parseEnvelopeTable(doc, file, s, nominal);

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
      s.parameters.push_back(resolveParameter(s.scene, v.path, s.sceneFile));
      sceneValue = parameterValue(s.scene, s.parameters.back());
      toml::table doc = s.scene.doc;  // best.toml writes it: the file must hold the key (a table's sample inline)
      inlineTables(doc, s.scene, {v.path});
      (void)getParameter(doc, v.path, s.sceneFile);
    } catch (const InputError& e) {
      r.fail("path", "'" + v.path + "' is not a numeric parameter of the scene (" + e.what() + ")");
    }
    v.lower = r.number("lower");
    v.upper = r.number("upper");
    v.log = r.boolean("log", false);
    if (!(v.upper > v.lower))
      r.fail("upper", "upper " + fmt(v.upper) + " must be greater than lower " + fmt(v.lower));
    if (v.log && !(v.lower > 0)) r.fail("lower", "lower " + fmt(v.lower) + " must be > 0 with log = true");
    for (const char* bound : {"lower", "upper"})
      if (const auto why = ownRuleBroken(s.scene, s.parameters.back(), r.number(bound)))
        r.fail(bound, "value " + fmt(r.number(bound)) + " breaks the rule of " + v.path + ": " + *why +
                          " (a bound is a value the design may take)");
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

  parseCases(doc, file, s);
  expandCorners(s);
  if (s.envelope.robust())
    for (size_t i = 0; i < s.variables.size(); ++i)
      if (s.parameters[i].kind == Parameter::Kind::Envelope)
        throw InputError(file, s.variables[i].line, "variable[" + std::to_string(i) + "].path",
                         "'" + s.variables[i].path + "' is a point of the envelope, and this study runs at its corners: "
                         "a robust design cannot choose its servicing (set [envelope] constraints = \"nominal\")");
  parseObjective(doc, file, s);
  if (s.envelope.objectiveWorst && s.objective.aggregate != Aggregate::Worst)
    throw InputError(file, s.envelope.line, "envelope.objective",
                     "the worst corner's objective needs [objective] aggregate = \"worst\" (a weighted sum over the "
                     "corners is no worst case)");
  parseConstraints(doc, file, s);
  parseAlgorithm(doc, file, s);
  parseSensitivity(doc, file, s);
  chooseSolver(tableOf(doc, "solver", file) != nullptr, s);
  return s;
}

Study loadStudy(const std::string& path, const std::vector<ParameterOverride>& sets, bool nominal) {
  const std::string text = readText(path, "study file");
  std::string base = std::filesystem::path(path).parent_path().string();
  if (base.empty()) base = ".";
  return parseStudy(text, path, base, sets, nominal);
}

}  // namespace lg::optim
