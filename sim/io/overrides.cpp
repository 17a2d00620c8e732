// Command-line overrides and case matrices (overrides.hpp).
#include "sim/io/overrides.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>

#include "sim/drop/accuracy.hpp"  // accuracyRule
#include "sim/io/toml_reader.hpp"
#include "sim/io/toml_rewrite.hpp"

namespace lg {
namespace {

const char* kWhere = "command line";

// A whole string as a finite number; false if it is not one.
bool toNumber(const std::string& s, double& v) {
  if (s.empty()) return false;
  char* end = nullptr;
  v = std::strtod(s.c_str(), &end);
  return end == s.c_str() + s.size() && std::isfinite(v);
}

std::string trim(const std::string& s) {
  const auto a = s.find_first_not_of(" \t"), b = s.find_last_not_of(" \t");
  return a == std::string::npos ? "" : s.substr(a, b - a + 1);
}

}  // namespace

ParameterOverride parseOverride(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos)
    throw InputError(kWhere, 0, "--set", "value '" + text + "' must read PATH=VALUE, e.g. strut.f1=8e-5");
  ParameterOverride o;
  o.path = trim(text.substr(0, eq));
  const std::string value = trim(text.substr(eq + 1));
  if (o.path.empty()) throw InputError(kWhere, 0, "--set", "value '" + text + "' has no PATH before '=': PATH=VALUE, e.g. strut.f1=8e-5");
  if (o.path.rfind("solver.", 0) == 0 || o.path == "solver")
    throw InputError(kWhere, 0, "--set " + o.path,
                     "solver settings are not parameters of the scene: give them with --integrator, --rtol, --atol, "
                     "--step or --accuracy (simulate), or in the study's [solver] table");
  if (!toNumber(value, o.value))
    throw InputError(kWhere, 0, "--set " + o.path, "value '" + value + "' must be a finite number (in the parameter's SI unit)");
  return o;
}

Scene applyOverrides(const Scene& scene, const std::vector<ParameterOverride>& sets) {
  if (sets.empty()) return scene;
  toml::table doc = scene.doc;
  std::vector<std::string> paths;
  for (const auto& o : sets) paths.push_back(o.path);
  inlineTables(doc, scene, paths);
  for (const auto& o : sets) {
    try {
      setParameter(doc, o.path, o.value, kWhere);
    } catch (const InputError& e) {
      throw InputError(kWhere, 0, "--set " + o.path,
                       "'" + o.path + "' is not a numeric parameter of the scene " + scene.file + " (" + e.rule() + ")");
    }
  }
  std::string dir = std::filesystem::path(scene.file).parent_path().string();
  if (dir.empty()) dir = ".";
  try {
    Scene edited = buildScene(doc, scene.file, dir);
    edited.text = scene.text;  // the file it was read from: written scenes keep its layout
    return edited;
  } catch (const InputError& e) {  // the fault is the command line's: the scene was valid without it
    std::string given;
    for (const auto& o : sets) given += (given.empty() ? "" : " ") + o.path + "=" + fmt(o.value);
    throw InputError(kWhere, 0, "--set " + (sets.size() == 1 ? sets[0].path : std::string("...")),
                     "the scene is invalid with " + given + ": " + e.what());
  }
}

std::vector<double> parseValueList(const std::string& text, const std::string& flag, bool positive) {
  std::vector<double> out;
  auto check = [&](double v, const std::string& token) {
    if (positive ? !(v > 0) : !(v >= 0))
      throw InputError(kWhere, 0, flag, "value " + token + " must be " + (positive ? "> 0" : ">= 0"));
    out.push_back(v);
  };
  if (text.find(':') != std::string::npos) {
    double a, h, b;
    const auto c1 = text.find(':'), c2 = text.find(':', c1 + 1);
    if (c2 == std::string::npos || !toNumber(trim(text.substr(0, c1)), a) ||
        !toNumber(trim(text.substr(c1 + 1, c2 - c1 - 1)), h) || !toNumber(trim(text.substr(c2 + 1)), b))
      throw InputError(kWhere, 0, flag, "value '" + text + "' must read start:step:stop, e.g. 1.5:0.25:3.5");
    if (!(h > 0) || !(b >= a))
      throw InputError(kWhere, 0, flag, "range '" + text + "' needs step > 0 and stop >= start");
    const double n = std::floor((b - a) / h + 1e-9);
    if (n > 10000) throw InputError(kWhere, 0, flag, "range '" + text + "' has more than 10000 values");
    for (long i = 0; i <= static_cast<long>(n); ++i) check(a + static_cast<double>(i) * h, text);
    return out;
  }
  size_t start = 0;
  while (start <= text.size()) {
    const auto comma = text.find(',', start);
    const std::string token = trim(text.substr(start, comma == std::string::npos ? std::string::npos : comma - start));
    double v;
    if (!toNumber(token, v))
      throw InputError(kWhere, 0, flag, "value '" + token + "' in '" + text + "' must be a number (list: a,b,c; range: start:step:stop)");
    check(v, token);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return out;
}

std::vector<DropCase> caseMatrix(const std::vector<double>& sinkSpeeds, const std::vector<double>& liftRatios,
                                 double duration) {
  std::vector<DropCase> out;
  for (double V : sinkSpeeds)
    for (double L : liftRatios) {
      char name[64];
      std::snprintf(name, sizeof name, "V%.6g_L%.6g", V, L);
      DropCase c;
      c.name = name;
      c.sinkSpeed = V;
      c.liftRatio = L;
      c.duration = duration;
      out.push_back(c);
    }
  return out;
}

void relocateTablePaths(toml::table& doc, const std::string& sceneDir, const std::string& outDir) {
  namespace fs = std::filesystem;
  for (const char* arr : {"force", "body", "joint", "stop"}) {
    toml::array* a = doc[arr].as_array();
    if (!a) continue;
    for (auto& e : *a) {
      toml::table* t = e.as_table();
      if (!t) continue;
      for (auto& [k, v] : *t) {
        const std::string key(k.str());
        if (key.size() < 6 || key.compare(key.size() - 6, 6, "_table") != 0 || !v.is_string()) continue;
        fs::path p(*v.value<std::string>());
        if (p.is_absolute()) continue;
        std::error_code ec;
        const fs::path abs = fs::absolute(fs::path(sceneDir) / p, ec);
        const fs::path rel = fs::relative(abs, fs::absolute(outDir, ec), ec);
        v.as_string()->get() = (ec || rel.empty()) ? abs.lexically_normal().string() : rel.string();
      }
    }
  }
}

std::string writtenSceneText(const std::string& source, const std::string& file, const toml::table& doc) {
  const TomlRewrite kept = rewriteToml(source, file, doc);
  if (kept.text) return *kept.text;
  return "# (the scene's own layout could not be kept: " + kept.reason + "; the document is written whole)\n" +
         toTomlString(doc);
}

void applySolverTable(const toml::table* t, const std::string& file, Scene& scene) {
  if (!t) return;
  TomlReader r(*t, file, "solver");
  r.allowOnly({"integrator", "rtol", "atol", "step", "accuracy"});
  SolverOverrides o;
  if (r.has("integrator")) {
    const std::string name = r.string("integrator");
    IntegratorKind kind;
    if (!integratorFromName(name, kind)) r.fail("integrator", "value '" + name + "' must be one of " + integratorNames());
    o.integrator = kind;
  }
  for (const auto& [key, value] : {std::pair<const char*, std::optional<double>*>{"rtol", &o.rtol}, {"atol", &o.atol},
                                   {"step", &o.step}, {"accuracy", &o.accuracy}})
    if (r.has(key)) *value = r.positive(key);
  if (const auto problem = solverOverridesProblem(o)) r.fail(problem->first, problem->second);
  applySolverOverrides(scene.model.settings, o);
  // The same keys in the scene's own [solver], for the scenes written from it (best.toml, calibrated.toml).
  toml::table& sceneSolver = *scene.doc.insert("solver", toml::table{}).first->second.as_table();
  if (o.accuracy) {
    for (const char* k : {"integrator", "rtol", "atol", "max_step"}) sceneSolver.erase(k);
    sceneSolver.insert_or_assign("accuracy", *o.accuracy);
  } else if (o.integrator || o.rtol || o.atol) {
    sceneSolver.erase("accuracy");  // the study's own integrator settings replace the scene's accuracy
  }
  if (o.integrator) sceneSolver.insert_or_assign("integrator", r.string("integrator"));
  if (o.rtol) {
    sceneSolver.insert_or_assign("rtol", *o.rtol);
    if (!o.atol) sceneSolver.insert_or_assign("atol", *o.rtol * 1e-2);
  }
  if (o.atol) sceneSolver.insert_or_assign("atol", *o.atol);
  if (o.step) sceneSolver.insert_or_assign("step", *o.step);
}

}  // namespace lg
