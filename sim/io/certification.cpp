// The [certification] table of a scene (sim/io/certification.hpp): read, checked, and the matrix made
// of it by the rules (sim/drop/certification.hpp).
#include "sim/io/certification.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "sim/io/drop_case.hpp"  // declaresSpinUp, kMaxForwardSpeed
#include "sim/io/toml_reader.hpp"

namespace lg {

Certification parseCertification(const toml::table& t, const std::string& file, const Scene& scene,
                                 const std::string& basisOverride) {
  TomlReader r(t, file, "certification");
  r.allowOnly({"basis", "landing_mass", "takeoff_mass", "wing_loading", "lift_ratio", "reserve_lift_ratio",
               "limit_load_factor", "stroke_margin", "tyre_limit", "mass_body", "duration", "case", "forward_speed"});
  Certification c;
  c.file = file;
  c.line = r.line();
  c.basisName = basisOverride.empty() ? r.string("basis") : basisOverride;
  if (!certBasisFromName(c.basisName, c.basis)) {
    if (!basisOverride.empty())
      throw InputError("command line", 0, "--basis", "value '" + basisOverride + "' must be one of " + certBasisNames());
    r.fail("basis", "value '" + c.basisName + "' must be one of " + certBasisNames());
  }
  if (c.part23() && !r.has("wing_loading"))
    r.fail("wing_loading", "basis '" + c.basisName + "' needs the wing loading W/S [kg/m^2] for its sink speed");
  // The body that makes W up, and the mass of the rest of the gear.
  c.massBody = r.string("mass_body", scene.roles.airframe);
  if (c.massBody.empty()) r.fail("mass_body", "missing: the scene names no airframe, so give the body whose mass makes up W");
  const int mb = scene.model.bodyIndex(c.massBody);
  if (mb < 0) r.fail("mass_body", "'" + c.massBody + "' is not a body of the scene");
  double rest = 0;  // [kg]
  for (int b = 0; b < scene.model.nBodies(); ++b)
    if (b != mb) rest += scene.model.bodies[b].mass;
  auto mass = [&](const std::string& key, double def) {
    const double W = r.has(key) ? r.positive(key) : def;
    if (!(W > rest))
      r.fail(key, "value " + fmt(W) + " kg must exceed the mass of the gear's other bodies, " + fmt(rest) +
                      " kg (W is the whole mass on the unit; '" + c.massBody + "' takes W - " + fmt(rest) + " kg)");
    return W;
  };
  const bool p23 = c.part23();
  const bool custom = c.basis == CertBasis::Custom;
  c.landingMass = custom && !r.has("landing_mass") ? 0.0 : mass("landing_mass", 0.0);
  c.takeoffMass = r.has("takeoff_mass") ? mass("takeoff_mass", 0.0) : c.landingMass;  // the same rule on every basis
  if (c.takeoffMass < c.landingMass && (c.basis == CertBasis::Part25 || c.basis == CertBasis::CS25))
    r.fail("takeoff_mass", "value " + fmt(c.takeoffMass) + " kg must not be below landing_mass " + fmt(c.landingMass) + " kg");
  // Part 23 (23.725, the effective weight): a lift "not more than 0.667" times the weight; the default is 2/3 itself, and the
  // bound is the rule's written 0.667.
  const double maxL = p23 ? 0.667 : 1.0;
  c.liftRatio = r.nonNegative("lift_ratio", p23 ? 2.0 / 3.0 : 1.0);
  if (c.liftRatio > maxL)
    r.fail("lift_ratio", "value " + fmt(c.liftRatio) + " must be <= " + (p23 ? "0.667 (Part 23 limit drop: 23.725 takes L \"not more than 0.667\")" : "1"));
  c.reserveLiftRatio = r.nonNegative("reserve_lift_ratio", 1.0);
  if (c.reserveLiftRatio > 1) r.fail("reserve_lift_ratio", "value " + fmt(c.reserveLiftRatio) + " must be <= 1");
  if ((c.liftRatio > 0 || c.reserveLiftRatio > 0) && scene.roles.lifts.empty())
    r.fail(r.has("lift_ratio") ? "lift_ratio" : "basis",
           "the matrix applies lift (L = " + fmt(std::max(c.liftRatio, c.reserveLiftRatio)) +
               ") but the scene declares no lift element: add a [[force]] of type \"lift\" on the airframe");
  c.limitLoadFactor = r.positive("limit_load_factor");
  if (p23 && !(c.limitLoadFactor > c.liftRatio))
    r.fail("limit_load_factor", "value " + fmt(c.limitLoadFactor) + " must exceed the lift ratio " + fmt(c.liftRatio) +
                                    " (Part 23: n = n_g + L)");
  c.strokeMargin = r.nonNegative("stroke_margin", 0.0);
  for (size_t k = 0; k < scene.roles.struts.size(); ++k) {
    const double S = scene.roles.strokeLimits[k];
    // S comes out of the stops' distances (0.60 - 0.44 = 0.15999999999999998): a margin equal to the
    // stroke as written is the whole stroke, and refused, whichever way the subtraction rounded.
    if (std::isfinite(S) && !(c.strokeMargin < S - 1e-12 * std::max(1.0, S)))
      r.fail("stroke_margin", "value " + fmt(c.strokeMargin) + " m must be smaller than the stroke S_max = " + fmt(S) +
                                  " m of strut '" + scene.model.forces[scene.roles.struts[k]].name + "'");
  }
  c.tyreLimit = r.has("tyre_limit") ? r.positive("tyre_limit") : 0.0;
  if (scene.roles.tyres.empty() && r.has("tyre_limit")) r.fail("tyre_limit", "the scene has no tyre");
  c.duration = r.duration("duration", 0.8);
  // The forward speed of the drops: declared, or the scene's own cases' (the spin-up they model).
  const bool spinUp = declaresSpinUp(scene);
  if (r.has("forward_speed")) {
    c.forwardSpeed = r.nonNegative("forward_speed", 0.0);
    if (c.forwardSpeed > 0 && !spinUp)
      r.fail("forward_speed", "no tyre of this scene declares the longitudinal friction coefficient mu_x (wheel spin-up)");
    if (c.forwardSpeed > kMaxForwardSpeed)
      r.fail("forward_speed", "value " + fmt(c.forwardSpeed) + " m/s is not a landing speed (at most 150 m/s)");
    c.forwardSpeedSource = "declared in [certification]";
  } else {
    for (const auto& sc : scene.cases) c.forwardSpeed = std::max(c.forwardSpeed, sc.forwardSpeed);
    c.forwardSpeedSource = c.forwardSpeed > 0 ? "the scene's own cases' (the largest)" : "none: no case of the scene has one";
  }

  if (custom) {
    if (r.has("wing_loading")) r.fail("wing_loading", "is used by the part23 and cs23 bases only");
    const auto rows = tablesOf(t, "case", file);
    if (rows.empty()) r.fail("case", "basis \"custom\" needs its cases: [[certification.case]] with name, kind, sink_speed, lift_ratio, mass");
    std::set<std::string> names;
    for (size_t i = 0; i < rows.size(); ++i) {
      TomlReader cr(*rows[i], file, "certification.case[" + std::to_string(i) + "]");
      cr.allowOnly({"name", "kind", "sink_speed", "lift_ratio", "mass", "duration"});
      CertCase cc;
      cc.name = cr.name("name");
      if (cc.name.empty() || !names.insert(cc.name).second) cr.fail("name", "'" + cc.name + "' is empty or used twice");
      for (const auto& sc : scene.cases)
        if (sc.name == cc.name) cr.fail("name", "'" + cc.name + "' is already a case of the scene: give the matrix case its own name");
      const std::string kind = cr.string("kind");
      if (kind == "limit") cc.kind = CertKind::Limit;
      else if (kind == "reserve") cc.kind = CertKind::Reserve;
      else cr.fail("kind", "value '" + kind + "' must be \"limit\" or \"reserve\"");
      cc.sinkSpeed = cr.positive("sink_speed");
      cc.liftRatio = cr.nonNegative("lift_ratio", 0.0);
      if (cc.liftRatio > 1) cr.fail("lift_ratio", "value " + fmt(cc.liftRatio) + " must be <= 1");
      if (cc.liftRatio > 0 && scene.roles.lifts.empty()) cr.fail("lift_ratio", "the scene declares no lift element");
      cc.mass = cr.positive("mass");
      if (!(cc.mass > rest)) cr.fail("mass", "value " + fmt(cc.mass) + " kg must exceed the gear's other bodies, " + fmt(rest) + " kg");
      cc.duration = cr.duration("duration", c.duration);
      cc.forwardSpeed = c.forwardSpeed;
      cc.rule = "custom case";
      c.cases.push_back(cc);
    }
    return c;
  }
  if (r.has("case")) r.fail("case", "matrix cases are generated from the basis; [[certification.case]] needs basis = \"custom\"");
  if (p23) c.wingLoading = r.positive("wing_loading");
  else if (r.has("wing_loading")) r.fail("wing_loading", "is used by the part23 and cs23 bases only");
  c.cases = basisCases(c);
  return c;
}

}  // namespace lg
