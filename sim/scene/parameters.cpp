// Design parameters resolved to typed places (parameters.hpp).
#include "sim/scene/parameters.hpp"

#include <map>

#include "sim/scene/check.hpp"

namespace lg {

Parameter resolveParameter(const Scene& scene, const std::string& path, const std::string& where) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    throw InputError(where, 0, path, "parameter path must read <element>.<key>, e.g. strut.f1");
  Parameter p;
  p.path = path;
  const std::string element = path.substr(0, dot);
  p.key = path.substr(dot + 1);
  const Model<double>& m = scene.model;
  auto fail = [&](const std::string& rule) -> Parameter { throw InputError(where, 0, path, rule); };
  if (element == "envelope") {
    if (!scene.envelope.declared)
      return fail("the scene has no [envelope] table: declare one (its service temperature at least) to move its quantities");
    if (!isEnvelopePointKey(p.key)) {
      std::string keys;
      for (const auto& k : envelopePointKeys()) keys += (keys.empty() ? "" : ", ") + std::string(k.key);
      return fail("the envelope has no quantity '" + p.key + "' (its: " + keys + ")");
    }
    p.kind = Parameter::Kind::Envelope;
    return p;
  }
  if (const int b = m.bodyIndex(element); b >= 0) {
    if (p.key != "mass") return fail("body '" + element + "' has no numeric parameter '" + p.key + "' (its one: mass)");
    p.kind = Parameter::Kind::BodyMass;
    p.index = b;
    return p;
  }
  if (const int c = m.constraintIndex(element); c >= 0) {
    const auto* st = std::get_if<DistanceStop<double>>(&m.constraints[c].type);
    const std::string key = st && st->noFarther ? "max_distance" : "min_distance";
    if (!st || p.key != key)
      return fail(st ? "stop '" + element + "' has no numeric parameter '" + p.key + "' (its one: " + key + ")"
                     : "joint '" + element + "' has no numeric parameter");
    p.kind = Parameter::Kind::StopLength;
    p.index = c;
    return p;
  }
  if (const int f = m.forceIndex(element); f >= 0) {
    ForceElement<double> e = m.forces[f];  // parameter() hands out a mutable field: ask a copy
    if (!std::visit([&](auto& x) { return x.parameter(p.key) != nullptr; }, e.type))
      return fail("force element '" + element + "' has no numeric design parameter '" + p.key + "'");
    p.kind = Parameter::Kind::Force;
    p.index = f;
    return p;
  }
  for (size_t c = 0; c < scene.cases.size(); ++c)
    if (scene.cases[c].name == element) {
      if (p.key != "sink_speed" && p.key != "lift_ratio" && p.key != "duration")
        return fail("case '" + element + "' has no numeric parameter '" + p.key + "' (its: sink_speed, lift_ratio, duration)");
      p.kind = Parameter::Kind::Case;
      p.index = static_cast<int>(c);
      return p;
    }
  return fail("no body, stop, force element or case named '" + element + "' in the scene");
}

std::string unitOfKey(const std::string& key) {
  static const std::map<std::string, std::string> units{
      // bodies, stops, cases
      {"mass", "kg"}, {"max_distance", "m"}, {"min_distance", "m"}, {"sink_speed", "m/s"}, {"lift_ratio", "-"},
      {"duration", "s"}, {"ratio", "-"},
      // shock absorber
      {"L0", "m"}, {"D", "m"}, {"D2", "m"}, {"p01", "Pa"}, {"Omega0", "m^3"}, {"n", "-"}, {"rho", "kg/m^3"},
      {"f1", "m^2"}, {"f1_table", "m^2"}, {"f2", "m^2"}, {"xi1", "-"}, {"xi2", "-"}, {"mu", "-"},
      {"friction_velocity", "m/s"}, {"p_atm", "Pa"}, {"p02", "Pa"}, {"Omega02", "m^3"}, {"n2", "-"},
      {"f1_extension", "m^2"}, {"f1_extension_table", "m^2"}, {"xi1_extension", "-"}, {"f2_extension", "m^2"},
      {"xi2_extension", "-"},
      // tyre
      {"radius", "m"}, {"K", "N/m"}, {"delta_max", "m"}, {"alpha", "-"}, {"ground_height", "m"}, {"exponent", "-"},
      {"damping_exponent", "-"}, {"mu_x", "-"}, {"slip_ratio", "-"},
      // spring-damper
      {"k", "N/m"}, {"c", "N s/m"},
      // bushing
      {"k_x", "N/m"}, {"k_y", "N/m"}, {"k_z", "N/m"}, {"c_x", "N s/m"}, {"c_y", "N s/m"}, {"c_z", "N s/m"},
      {"k_rx", "N m/rad"}, {"k_ry", "N m/rad"}, {"k_rz", "N m/rad"},
      {"c_rx", "N m s/rad"}, {"c_ry", "N m s/rad"}, {"c_rz", "N m s/rad"},
  };
  for (const auto& k : envelopePointKeys())
    if (key == k.key) return k.unit;
  const auto open = key.find('[');  // a table's sample: the table's unit
  const auto it = units.find(open == std::string::npos ? key : key.substr(0, open));
  return it == units.end() ? "?" : it->second;
}

double parameterValue(const Scene& scene, const Parameter& p) {
  const Model<double>& m = scene.model;
  switch (p.kind) {
    case Parameter::Kind::BodyMass: return m.bodies[p.index].mass;
    case Parameter::Kind::StopLength: return std::get<DistanceStop<double>>(m.constraints[p.index].type).L;
    case Parameter::Kind::Force: {
      ForceElement<double> e = m.forces[p.index];
      return *std::visit([&](auto& x) { return x.parameter(p.key); }, e.type);
    }
    case Parameter::Kind::Case: {
      const DropCase& c = scene.cases[p.index];
      return p.key == "sink_speed" ? c.sinkSpeed : p.key == "lift_ratio" ? c.liftRatio : c.duration;
    }
    case Parameter::Kind::Envelope: return envelopeValue(scene.envelope.point, p.key);
  }
  return 0;
}

std::optional<std::string> ownRuleBroken(const Scene& scene, const Parameter& p, double x) {
  if (p.kind == Parameter::Kind::Envelope) return std::nullopt;
  Scene s = scene;
  if (p.kind == Parameter::Kind::Case) {
    DropCase& c = s.cases[p.index];
    (p.key == "sink_speed" ? c.sinkSpeed : p.key == "lift_ratio" ? c.liftRatio : c.duration) = x;
  } else {
    setModelParameter(s.model, p, x);
  }
  const auto problem = checkScene(s);
  if (!problem) return std::nullopt;
  const char* array = p.kind == Parameter::Kind::BodyMass ? "body"
                      : p.kind == Parameter::Kind::Force  ? "force"
                      : p.kind == Parameter::Kind::Case   ? "case"
                                                          : "stop";
  const std::string key = p.key.substr(0, p.key.find('['));  // a table's sample: the table's key
  // Its own rule: a rule of its element and key about its value alone (a case's speed, ratio and duration
  // rules; "value X must be > 0" or ">= 0" of any other key), never one that compares it with another
  // value ("gas volume ... must be larger than the volume swept").
  auto endsWith = [&](const char* tail) {
    const std::string t(tail);
    return problem->rule.size() >= t.size() && problem->rule.compare(problem->rule.size() - t.size(), t.size(), t) == 0;
  };
  const bool valueAlone = p.kind == Parameter::Kind::Case ||
                          (problem->rule.rfind("value ", 0) == 0 && (endsWith(" must be > 0") || endsWith(" must be >= 0")));
  const bool own = problem->array == array && problem->key.substr(0, problem->key.find('[')) == key &&
                   (p.kind == Parameter::Kind::StopLength || problem->index == p.index) && valueAlone;
  if (!own) return std::nullopt;
  return problem->rule;
}

std::optional<std::string> applyParameters(Scene& scene, const std::vector<Parameter>& ps, const std::vector<double>& x) {
  for (size_t i = 0; i < ps.size(); ++i) {
    const Parameter& p = ps[i];
    if (p.kind == Parameter::Kind::Envelope) {
      setEnvelopeValue(scene.envelope.point, p.key, x[i]);
      continue;
    }
    if (p.kind != Parameter::Kind::Case) {
      setModelParameter(scene.model, p, x[i]);
      continue;
    }
    DropCase& c = scene.cases[p.index];
    (p.key == "sink_speed" ? c.sinkSpeed : p.key == "lift_ratio" ? c.liftRatio : c.duration) = x[i];
  }
  if (const auto problem = checkScene(scene)) return describe(scene, *problem);
  if (const auto why = envelopeProblem(scene)) return "envelope: " + *why;
  return std::nullopt;
}

}  // namespace lg
