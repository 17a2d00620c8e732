// Design parameters as data: a path "<element>.<key>" (the syntax of study variables, --set and
// calibration parameters, e.g. "strut.f1", "tyre.K", "airframe.mass", "bottoming.min_distance",
// "limit.sink_speed") resolved once against a scene to a typed place, then set in a Model<S> of any
// scalar (double for a design, ceres::Jet for its derivatives) without editing or parsing text.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/core/input_error.hpp"
#include "sim/scene/scene.hpp"

namespace lg {

struct Parameter {
  enum class Kind { BodyMass, StopLength, Force, Case, Envelope };
  std::string path;   // as written: "strut.f1"
  Kind kind = Kind::Force;
  int index = -1;     // the body, the constraint (a stop), the force element, or the scene's case
                      // (an envelope quantity "envelope.<key>": the scene's point, sim/scene/envelope.hpp)
  std::string key;    // the scene key: "f1", "mass", "min_distance", "sink_speed"
};

// Resolves a path against a scene: the element is a body, stop, force element or case named in it
// (searched in that order), the key one of its numeric scalars; or "envelope.<key>", a quantity of the
// point of the scene's [envelope] (envelopePointKeys(): temperature_C, charge, gas_volume, ...). Throws InputError(where, 0, path, rule).
Parameter resolveParameter(const Scene& scene, const std::string& path, const std::string& where = "");

// The SI unit of a parameter by its scene key ("f1" and "f1_table[3]" -> "m^2", "mass" -> "kg", "-" for a
// ratio; "?" for a key the catalogue does not know): the one table of units for every output.
std::string unitOfKey(const std::string& key);
// The unit of a parameter path "<element>.<key>" by its key (unitOfKey).
inline std::string parameterUnit(const std::string& path) {
  const auto dot = path.rfind('.');
  return unitOfKey(dot == std::string::npos ? path : path.substr(dot + 1));
}
// "strut.f1[m^2]": a column header.
inline std::string parameterHeader(const std::string& path) { return path + "[" + parameterUnit(path) + "]"; }

// The parameter's value in a scene.
double parameterValue(const Scene& scene, const Parameter& p);

// Sets a model parameter in a model of any scalar (a case parameter is no part of the model: see
// applyParameters).
template <class S> void setModelParameter(Model<S>& m, const Parameter& p, const S& v) {
  switch (p.kind) {
    case Parameter::Kind::BodyMass: m.bodies[p.index].mass = v; break;
    case Parameter::Kind::StopLength: std::get<DistanceStop<S>>(m.constraints[p.index].type).L = v; break;
    case Parameter::Kind::Force:
      *std::visit([&](auto& e) -> S* { return e.parameter(p.key); }, m.forces[p.index].type) = v;
      break;
    case Parameter::Kind::Case: break;
    case Parameter::Kind::Envelope: break;  // (applyCase applies the point)
  }
}

// A design of a scene: the parameters set to x (their SI units), what derives from them refreshed and
// every rule of the scene checked (sim/scene/check.hpp). Returns why the scene rejects the design
// ("strut.Omega0: gas volume ... must be larger ..."), or nothing.
std::optional<std::string> applyParameters(Scene& scene, const std::vector<Parameter>& ps, const std::vector<double>& x);

// Why the value x breaks the parameter's own rule (an area <= 0, a mass <= 0, a sink speed above
// 10 m/s: the rule of its key in the scene file), or nothing. A rule that ties it to another value
// (the bore above the rod, the gas volume above the swept one) is not its own: a study may cross it and
// find an infeasible design there. A study's bound must obey the parameter's own rule.
std::optional<std::string> ownRuleBroken(const Scene& scene, const Parameter& p, double x);

}  // namespace lg
