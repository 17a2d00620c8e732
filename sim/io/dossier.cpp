// The dossier's sections (dossier.hpp).
#include "sim/io/dossier.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>
#include <vector>

#include "sim/drop/accuracy.hpp"
#include "sim/io/json.hpp"
#include "sim/scene/parameters.hpp"

namespace lg {
namespace {

std::string sig(double v, int digits = 6) {
  if (!std::isfinite(v)) return "-";
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// A TOML value as the configuration table writes it.
std::string valueText(const toml::node& n) {
  if (auto d = n.value<double>()) return sig(*d, 10);
  if (auto s = n.value<std::string>()) return "\"" + *s + "\"";
  if (auto b = n.value<bool>()) return *b ? "true" : "false";
  if (const toml::array* a = n.as_array()) {
    std::string out = "[";
    for (size_t i = 0; i < a->size(); ++i) out += (i ? ", " : "") + valueText(*a->get(i));
    return out + "]";
  }
  if (const toml::table* t = n.as_table()) {
    std::string out = "{";
    bool first = true;
    for (const auto& [k, v] : *t) {
      out += (first ? "" : ", ") + std::string(k.str()) + " = " + valueText(v);
      first = false;
    }
    return out + "}";
  }
  return "?";
}

// The unit of a scene key where the catalogue knows one (positions and directions: m, and -).
std::string unitOf(const std::string& key) {
  if (key == "inertia") return "kg m^2";
  if (key == "position" || key == "point" || key == "point1" || key == "point2" || key == "rod_point" ||
      key == "cylinder_point")
    return "m";
  if (key == "g") return "m/s^2";
  if (key == "x_axis" || key == "axis" || key == "normal" || key == "plane_normal") return "-";
  const std::string u = unitOfKey(key);
  return u == "?" ? "" : u;
}

std::string integratorWords(const Settings& s) {
  const bool adaptive = s.integrator == IntegratorKind::DormandPrince || isRosenbrock(s.integrator);
  std::string w = integratorName(s.integrator) + (adaptive ? ", rtol " + sig(s.rtol) + ", atol " + sig(s.atol) + ", largest step " +
                                                                 sig(s.maxStep) + " s"
                                                           : ", step " + sig(s.step) + " s");
  if (s.accuracy > 0) w = "accuracy " + sig(s.accuracy) + " (" + w + ")";
  return w;
}

}  // namespace

std::string ruleParagraphs(const Certification& c, const CertCase& cc) {
  const bool reserve = cc.kind == CertKind::Reserve;
  const bool takeoff = cc.name == "cert-limit-takeoff";
  switch (c.basis) {
    case CertBasis::Part25:
      return reserve ? "14 CFR 25.723(b) (reserve energy: 12 ft/s at the design landing weight, lift not above the weight; "
                       "25.727 before amendment 25-103)"
             : takeoff ? "14 CFR 25.473(a)(2)(ii) (6 ft/s at the design takeoff weight), 25.723(a) (25.725 before amendment 25-103)"
                       : "14 CFR 25.473(a)(2)(i) (10 ft/s at the design landing weight), 25.723(a) (25.725 before amendment 25-103)";
    case CertBasis::CS25:
      return reserve ? "CS 25.723(b) (reserve energy: 3.7 m/s at the design landing weight, lift not above the weight)"
             : takeoff ? "CS 25.473(a)(2)(ii) (1.83 m/s at the design takeoff weight), CS 25.723(a)"
                       : "CS 25.473(a)(2)(i) (3.05 m/s at the design landing weight), CS 25.723(a)";
    case CertBasis::Part23:
      return reserve ? "14 CFR 23.727 (reserve energy: 1.44 x the limit drop height), as before amendment 23-64 (now "
                       "means of compliance)"
                     : "14 CFR 23.473 (n >= 2.67, n_g >= 2.0 at the design maximum weight), 23.725 (limit drop height "
                       "h = 3.6 (W/S)^(1/2) in, 9.2 .. 18.7 in), as before amendment 23-64 (now means of compliance)";
    case CertBasis::CS23:
      return reserve ? "CS 23.727 (reserve energy: 1.44 x the limit drop height), as before CS-23 amendment 5"
                     : "CS 23.473, CS 23.725 (limit drop height h = 3.6 (W/S)^(1/2) in, 9.2 .. 18.7 in), as before CS-23 "
                       "amendment 5";
    default: return "custom case: no rule paragraph (the table's own numbers)";
  }
}

double dropHeight(double V, double g) { return V * V / (2 * g); }
double effectiveMass(double W, double L, double h, double d) { return W * (h + (1 - L) * d) / (h + d); }

// Every value of the scene's document: element, key, value, unit.
struct ConfigRow {
  std::string element, key, value, unit;
};
std::vector<ConfigRow> configuration(const Scene& scene) {
  std::vector<ConfigRow> out;
  for (const char* arr : {"body", "joint", "stop", "force"}) {
    const toml::array* a = scene.doc[arr].as_array();
    if (!a) continue;
    for (const auto& e : *a) {
      const toml::table* t = e.as_table();
      if (!t) continue;
      const std::string name = (*t)["name"].value<std::string>().value_or((*t)["type"].value<std::string>().value_or("?"));
      for (const auto& [k, v] : *t) {
        const std::string key(k.str());
        if (key != "name") out.push_back({std::string(arr) + " " + name, key, valueText(v), unitOf(key)});
      }
    }
  }
  for (const char* table : {"solver", "envelope"})
    if (const toml::table* t = scene.doc[table].as_table())
      for (const auto& [k, v] : *t) out.push_back({"[" + std::string(table) + "]", std::string(k.str()), valueText(v), unitOf(std::string(k.str()))});
  return out;
}

std::string configurationMarkdown(const Scene& scene) {
  std::ostringstream o;
  o << "\n## Configuration under test\n\nEvery value of the scene `" << scene.name
    << "` as the cases ran it (file, `--set` and a study's design included), with its unit:\n\n"
       "| element | key | value | unit |\n|---|---|---|---|\n";
  for (const ConfigRow& r : configuration(scene)) o << "| " << r.element << " | " << r.key << " | " << r.value << " | " << r.unit << " |\n";
  o << "\nDerived:\n\n| element | quantity | value | unit |\n|---|---|---|---|\n";
  for (size_t k = 0; k < scene.roles.struts.size(); ++k) {
    const auto& f = scene.model.forces[scene.roles.struts[k]];
    const auto& a = std::get<ShockAbsorber<double>>(f.type);
    const double S = k < scene.roles.strokeLimits.size() ? scene.roles.strokeLimits[k] : NAN;
    o << "| strut `" << f.name << "` | rod area F = pi D^2/4 | " << sig(a.area()) << " | m^2 |\n";
    if (a.reboundOrifice) o << "| strut `" << f.name << "` | annulus F_2 = pi (D_2^2 - D^2)/4 | " << sig(a.annularArea()) << " | m^2 |\n";
    o << "| strut `" << f.name << "` | extended length L0 | " << sig(a.L0) << " | m |\n";
    if (std::isfinite(S)) {
      o << "| strut `" << f.name << "` | stroke to the bottoming stop S_max | " << sig(S) << " | m |\n";
      o << "| strut `" << f.name << "` | volume swept at S_max, F S_max | " << sig(a.area() * S) << " | m^3 |\n";
      o << "| strut `" << f.name << "` | gas volume left at S_max, Omega0 - F S_max | " << sig(a.Omega0 - a.area() * S)
        << " | m^3 |\n";
    }
    o << "| strut `" << f.name << "` | extended gas force p01 F | " << sig(a.p01 * a.area()) << " | N |\n";
  }
  for (int t : scene.roles.tyres) {
    const auto& f = scene.model.forces[t];
    const auto& ty = std::get<Tyre<double>>(f.type);
    o << "| tyre `" << f.name << "` | load at delta_max | " << sig(ty.load(ty.deltaMax)) << " | N |\n";
  }
  double W = 0;
  for (const auto& b : scene.model.bodies) W += b.mass;
  o << "| scene | total mass of the bodies | " << sig(W) << " | kg |\n";
  return o.str();
}

std::string methodMarkdown(const Scene& scene, const Compliance& c) {
  const Settings& s = scene.model.settings;
  std::ostringstream o;
  o << "\n## Model, solver and the accuracy achieved\n\n"
    << "Rigid bodies in maximal coordinates, Lagrange's equations of the first kind: the joints' and the enforced "
       "stops' rows are solved for their multipliers at every evaluation ("
    << (s.solver == MultiplierSolver::Direct ? "direct sparse factorisation" : "Gauss-Seidel")
    << "), the positions kept on the constraints by "
    << (s.stabilization == Stabilization::Projection ? "projection" : s.stabilization == Stabilization::Baumgarte ? "Baumgarte stabilisation" : "nothing")
    << "; force elements as declared (the strut's gas, orifices and friction, the tyre); stops engage as plastic impacts; "
       "events (stops, stick and slip, a second gas stage) are located and stepped on; peaks are refined on the integrator's "
       "dense output. Integrator: "
    << integratorWords(s)
    << ". The accuracy of each run is shown by its energy balance (the energy in at touchdown against kinetic, stored "
       "and dissipated energy at the end, relative) and the largest violation of an enforced constraint:\n\n"
       "| case | energy balance error | constraint violation [m] | steps | evaluations |\n|---|---|---|---|---|\n";
  auto row = [&](const CaseVerdict& v) {
    const CaseMetrics& m = v.metrics;
    o << "| " << v.name << " | " << sig(m.energy_balance_error, 3) << " | " << sig(m.constraint_violation_max, 3) << " | "
      << m.steps << " | " << m.rhs_evaluations << " |\n";
  };
  for (const auto& v : c.cases) row(v);
  for (const auto& v : c.checks) row(v);
  return o.str();
}

std::string derivationMarkdown(const Scene& scene, const Compliance& c) {
  const Certification& s = *c.spec;
  std::ostringstream o;
  o << "\n## The cases: rules and derivation\n\nW is the mass on the unit: the scene's bodies with `" << s.massBody
    << "` made up to it. V is the sink speed at touchdown, L the lift ratio (lift L W g on the airframe throughout), h = "
       "V^2 / (2 g) the free-drop height of the same V, d the vertical travel after touchdown (the case's h_max), and W_e = "
       "W [h + (1 - L) d] / (h + d) the effective mass a drop rig's reduced-mass method would drop from h (for the "
       "physical test; this analysis applies the lift as a force).\n\n"
       "| case | rule | W [kg] | V [m/s] | L | h [m] | d [m] | W_e [kg] | V_x [m/s] |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const auto& v : c.cases) {
    const double h = dropHeight(v.cert.sinkSpeed, scene.gravity), d = v.metrics.h_max_m;
    o << "| " << v.name << " | " << ruleParagraphs(s, v.cert) << "; " << v.cert.rule << " | " << sig(v.cert.mass) << " | "
      << sig(v.cert.sinkSpeed, 4) << " | " << sig(v.cert.liftRatio, 3) << " | " << sig(h, 4) << " | " << sig(d, 4) << " | "
      << sig(effectiveMass(v.cert.mass, v.cert.liftRatio, h, d), 5) << " | " << sig(v.cert.forwardSpeed, 3) << " |\n";
  }
  double sceneMass = 0;
  for (const auto& b : scene.model.bodies) sceneMass += b.mass;
  bool differs = false;
  for (const auto& v : c.checks) differs = differs || std::abs(v.cert.mass - s.landingMass) > 1e-9;
  if (!c.checks.empty() && differs)
    o << "\nThe scene's own cases (checks) run at their own masses (the scene's bodies, " << sig(sceneMass)
      << " kg, and their `masses`), not at the matrix's " << sig(s.landingMass) << " kg.\n";
  return o.str();
}

std::string assumptionsMarkdown(const Scene& scene, const Compliance& c) {
  const Certification& s = *c.spec;
  std::ostringstream o;
  o << "\n## Assumptions and exclusions\n\n"
    << "- A drop on a rig: the airframe is guided vertically (no pitch, roll or yaw), in level attitude, onto level, rigid "
       "ground; the gear's bodies are rigid (compliant elements only where the scene declares them).\n"
    << "- Lift: a constant force L W g on the airframe for the whole drop (the reduced-mass method of drop rigs is not "
       "used; W_e is given for the physical test).\n"
    << "- W: the whole mass on the unit, the gear's own bodies included, made up through `" << s.massBody << "`.\n";
  if (s.basis == CertBasis::Part25 || s.basis == CertBasis::CS25)
    o << "- The design takeoff mass, " << sig(s.takeoffMass) << " kg, is the table's value (this project's choice where "
         "the aircraft gives none).\n";
  o << "- \"Must not fail\" in the reserve-energy drop is read as: the load factor within the ultimate factor ("
    << sig(s.ultimateFactor) << " x n_g,lim), the stroke clear of every bottoming stop by the stroke margin, every tyre "
       "within its limit, and the compression ending within the run; structural strength is not analysed.\n"
    << "- The strut: incompressible oil, a polytropic gas (exponent as declared), turbulent orifice flow with constant loss "
       "coefficients, seal friction as declared; no cavitation, aeration or oil compressibility; nitrogen at "
    << (c.envelope ? "every point of the servicing and temperature envelope below" : "its nominal charge and temperature")
    << ".\n"
    << "- The tyre: its declared load-deflection law on flat ground; "
    << (s.forwardSpeed > 0 ? "wheel spin-up at V_x = " + sig(s.forwardSpeed, 4) + " m/s (" + s.forwardSpeedSource + ")"
                           : "no forward speed (no spin-up or spring-back drag)")
    << ".\n"
    << "- Each case runs " << sig(s.duration, 3) << " s from touchdown; the rebound is measured by the airframe's upward "
       "velocity, not a second impact.\n";
  return o.str();
}

std::string footnotesMarkdown(const Compliance& c) {
  std::ostringstream o;
  o << "\n## Notes to the tables\n\n"
    << "- n_g = P_y,max / (W g), the ground-reaction load factor. n = n_g + L, the inertia load factor of Part 23 "
       "(23.473); for a Part 25 or CS-25 matrix it is given for information only.\n"
    << "- \"E to absorb\" = W V^2/2 + (1 - L) W g h_max counts all of W moving with the airframe; \"absorbed\" = integral(P_y "
       "dh) is the ground load along the airframe's travel. They differ by the unsprung bodies' share: P_y carries their "
       "weight and inertia too, integrated along the airframe's travel rather than their own (0.3 .. 0.8 % on the seed "
       "gear); neither is a limit.\n"
    << "- Every stroke margin is S_max - s_max against the stroke margin required; a margin of a worst corner is the distance "
       "to the limit in the limit's unit (negative breaks it).\n";
  return o.str();
}

std::string dossierJson(const Scene& scene, const Compliance& c) {
  std::ostringstream o;
  const Settings& s = scene.model.settings;
  o << "  \"method\": {\"formulation\": \"rigid bodies in maximal coordinates, Lagrange equations of the first kind\", "
       "\"integrator\": " << jsonString(integratorWords(s)) << "},\n";
  o << "  \"rules\": {";
  for (size_t i = 0; i < c.cases.size(); ++i)
    o << (i ? ", " : "") << jsonString(c.cases[i].name) << ": " << jsonString(ruleParagraphs(*c.spec, c.cases[i].cert));
  o << "},\n  \"derivation\": [";
  for (size_t i = 0; i < c.cases.size(); ++i) {
    const auto& v = c.cases[i];
    const double h = dropHeight(v.cert.sinkSpeed, scene.gravity), d = v.metrics.h_max_m;
    o << (i ? ", " : "") << "{\"case\": " << jsonString(v.name) << ", \"drop_height_m\": " << jsonNumber(h)
      << ", \"travel_m\": " << jsonNumber(d) << ", \"effective_mass_kg\": "
      << jsonNumber(effectiveMass(v.cert.mass, v.cert.liftRatio, h, d)) << "}";
  }
  o << "],\n  \"configuration\": [";
  const std::vector<ConfigRow> rows = configuration(scene);
  for (size_t i = 0; i < rows.size(); ++i)
    o << (i ? ",\n    " : "\n    ") << "{\"element\": " << jsonString(rows[i].element) << ", \"key\": " << jsonString(rows[i].key)
      << ", \"value\": " << jsonString(rows[i].value) << ", \"unit\": " << jsonString(rows[i].unit) << "}";
  o << "],\n";
  return o.str();
}

}  // namespace lg
