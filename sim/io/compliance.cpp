// compliance.json, compliance.md and the terminal summary of `certify` (compliance.hpp).
#include "sim/io/compliance.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "sim/io/json.hpp"
#include "sim/io/plots.hpp"

namespace lg {
namespace {

std::string fixed(double v, int decimals) {
  if (!std::isfinite(v)) return "-";
  char b[48];
  std::snprintf(b, sizeof b, "%.*f", decimals, v);
  return b;
}
std::string sig(double v, int digits = 6) {
  if (!std::isfinite(v)) return "-";
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

std::string basisTitle(const Certification& c) {
  switch (c.basis) {
    case CertBasis::Part25: return "14 CFR Part 25";
    case CertBasis::CS25: return "CS-25";
    case CertBasis::Part23: return "14 CFR Part 23";
    case CertBasis::CS23: return "CS-23";
    default: return "custom matrix";
  }
}

// The least stroke limit a case is held to: min over struts of S_max - margin (NaN: no stop).
double strokeBound(const CaseVerdict& v, double margin) {
  double b = NAN;
  for (const auto& s : v.metrics.struts)
    if (std::isfinite(s.stroke_limit_m)) b = std::isnan(b) ? s.stroke_limit_m - margin : std::min(b, s.stroke_limit_m - margin);
  return b;
}
double tyreBound(const CaseVerdict& v, const Certification* c) {
  if (c && c->tyreLimit > 0) return c->tyreLimit;
  double b = NAN;
  for (const auto& t : v.metrics.tyres) b = std::isnan(b) ? t.deflection_limit_m : std::min(b, t.deflection_limit_m);
  return b;
}

std::string verdictJson(const CaseVerdict& v) {
  std::ostringstream o;
  o << "{\"name\": " << jsonString(v.name) << ", \"role\": " << jsonString(v.role)
    << ", \"kind\": " << jsonString(v.role == "check" ? "check" : certKindName(v.cert.kind))
    << ", \"rule\": " << jsonString(v.cert.rule) << ",\n";
  o << "      \"sink_speed_mps\": " << jsonNumber(v.cert.sinkSpeed) << ", \"lift_ratio\": " << jsonNumber(v.cert.liftRatio)
    << ", \"mass_kg\": " << jsonNumber(v.cert.mass) << ", \"duration_s\": " << jsonNumber(v.cert.duration) << ",\n";
  const auto& m = v.metrics;
  o << "      \"metrics\": {\"ok\": " << jsonBool(m.ok) << ", \"peak_load_N\": " << jsonNumber(m.peak_load_N)
    << ", \"load_factor\": " << jsonNumber(m.load_factor) << ", \"inertia_load_factor\": " << jsonNumber(m.inertia_load_factor)
    << ", \"stroke_max_m\": " << jsonNumber(m.stroke_max_m) << ", \"stroke_margin_m\": " << jsonNumber(m.stroke_margin_m)
    << ", \"tyre_deflection_max_m\": " << jsonNumber(m.tyre_deflection_max_m) << ", \"tyre_margin_m\": "
    << jsonNumber(m.tyre_margin_m) << ", \"h_max_m\": " << jsonNumber(m.h_max_m) << ", \"efficiency\": "
    << jsonNumber(m.efficiency) << ", \"energy_to_absorb_J\": " << jsonNumber(m.energy_to_absorb_J)
    << ", \"energy_absorbed_J\": " << jsonNumber(m.energy_absorbed_J) << ", \"compression_ended\": "
    << jsonBool(m.compression_ended) << ", \"bottomed\": " << jsonBool(m.bottomed) << "},\n";
  o << "      \"limits\": [";
  for (size_t i = 0; i < v.limits.size(); ++i) {
    const auto& l = v.limits[i];
    const MetricInfo* info = findMetric(l.limit.metric);
    o << (i ? ", " : "") << "{\"metric\": " << jsonString(l.limit.metric) << ", \"value\": " << jsonNumber(l.value)
      << ", \"relation\": " << jsonString(l.limit.upper ? "<=" : ">=") << ", \"limit\": " << jsonNumber(l.limit.bound)
      << ", \"unit\": " << jsonString(info ? info->unit : "") << ", \"pass\": " << jsonBool(l.pass)
      << ", \"rule\": " << jsonString(l.limit.rule) << "}";
  }
  o << "],\n      \"pass\": " << jsonBool(v.pass) << ", \"reasons\": [";
  for (size_t i = 0; i < v.reasons.size(); ++i) o << (i ? ", " : "") << jsonString(v.reasons[i]);
  o << "]}";
  return o.str();
}

std::string row(const CaseVerdict& v, const Certification* c) {
  const auto& m = v.metrics;
  std::ostringstream o;
  const double sb = strokeBound(v, c ? c->strokeMargin : 0.0), tb = tyreBound(v, c);
  o << "| " << v.name << " | " << (v.role == "check" ? "check" : certKindName(v.cert.kind)) << " | "
    << fixed(v.cert.sinkSpeed, 3) << " | " << sig(v.cert.liftRatio, 3) << " | " << fixed(v.cert.mass, 0) << " | "
    << fixed(m.energy_to_absorb_J / 1e3, 2) << " | " << fixed(m.energy_absorbed_J / 1e3, 2) << " | "
    << fixed(m.load_factor, 3) << " | " << fixed(m.inertia_load_factor, 3) << " | " << fixed(m.stroke_max_m, 4) << " / "
    << fixed(sb, 4) << " | " << fixed(m.tyre_deflection_max_m, 4) << " / " << fixed(tb, 4) << " | "
    << fixed(m.efficiency, 3) << " | ";
  if (v.pass) o << "PASS";
  else {
    o << "**FAIL**: ";
    for (size_t i = 0; i < v.reasons.size(); ++i) o << (i ? "; " : "") << v.reasons[i];
  }
  o << " |\n";
  return o.str();
}

const char* kTableHead =
    "| case | kind | V [m/s] | L | W [kg] | E to absorb [kJ] | absorbed [kJ] | n_g | n | stroke / limit [m] | "
    "tyre / limit [m] | eta | verdict |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

}  // namespace

std::string complianceJson(const Compliance& c) {
  const Certification& s = *c.spec;
  std::ostringstream o;
  o << "{\n  \"scene\": " << jsonString(c.scene) << ",\n  \"basis\": " << jsonString(s.basisName) << ",\n";
  o << "  \"lift_method\": \"constant force L W g on the airframe\",\n";
  o << "  \"declared\": {\"landing_mass_kg\": " << jsonNumber(s.landingMass) << ", \"takeoff_mass_kg\": "
    << jsonNumber(s.takeoffMass) << ", \"wing_loading_kg_m2\": " << jsonNumber(s.part23() ? s.wingLoading : NAN)
    << ", \"lift_ratio\": " << jsonNumber(s.liftRatio) << ", \"reserve_lift_ratio\": " << jsonNumber(s.reserveLiftRatio)
    << ", \"limit_load_factor\": " << jsonNumber(s.limitLoadFactor) << ", \"limit_ground_load_factor\": "
    << jsonNumber(s.limitGroundFactor()) << ", \"ultimate_factor\": " << jsonNumber(s.ultimateFactor)
    << ", \"stroke_margin_m\": " << jsonNumber(s.strokeMargin) << ", \"tyre_limit_m\": "
    << (s.tyreLimit > 0 ? jsonNumber(s.tyreLimit) : std::string("\"delta_max of each tyre\"")) << ", \"mass_body\": "
    << jsonString(s.massBody) << "},\n";
  o << "  \"pass\": " << jsonBool(c.pass) << ",\n  \"checks_pass\": " << jsonBool(c.checksPass) << ",\n";
  o << "  \"unit\": [";
  for (size_t i = 0; i < c.unit.size(); ++i) {
    const auto& u = c.unit[i];
    o << (i ? ", " : "") << "{\"name\": " << jsonString(u.name) << ", \"value\": " << jsonNumber(u.value)
      << ", \"relation\": \">=\", \"limit\": " << jsonNumber(u.bound) << ", \"pass\": " << jsonBool(u.pass)
      << ", \"rule\": " << jsonString(u.rule) << "}";
  }
  o << "],\n  \"cases\": [\n";
  for (size_t i = 0; i < c.cases.size(); ++i) o << "    " << verdictJson(c.cases[i]) << (i + 1 < c.cases.size() ? ",\n" : "\n");
  o << "  ],\n  \"checks\": [\n";
  for (size_t i = 0; i < c.checks.size(); ++i) o << "    " << verdictJson(c.checks[i]) << (i + 1 < c.checks.size() ? ",\n" : "\n");
  o << "  ]\n}\n";
  return o.str();
}

std::string complianceMarkdown(const Compliance& c, const std::string& pictures) {
  const Certification& s = *c.spec;
  std::ostringstream o;
  int failed = 0;
  for (const auto& v : c.cases) failed += v.pass ? 0 : 1;
  for (const auto& u : c.unit) failed += u.pass ? 0 : 1;
  o << "# Drop-test compliance: " << basisTitle(s) << "\n\n";
  o << "- scene: `" << c.scene << "`\n";
  o << "- basis: `" << s.basisName << "`";
  if (s.basis != CertBasis::Custom) {
    o << "; design landing mass " << sig(s.landingMass) << " kg";
    if (!s.part23()) o << ", design takeoff mass " << sig(s.takeoffMass) << " kg";
    else o << ", wing loading " << sig(s.wingLoading) << " kg/m^2 (" << sig(s.wingLoading * 0.204816, 4) << " lb/ft^2)";
  }
  o << "\n- design limit load factor: " << (s.part23() ? "n = " : "n_g = ") << sig(s.limitLoadFactor)
    << " (limit ground load factor n_g,lim = " << sig(s.limitGroundFactor()) << ", ultimate " << sig(s.ultimateFactor)
    << " x = " << sig(s.ultimateFactor * s.limitGroundFactor()) << ")\n";
  o << "- stroke margin to every bottoming stop: " << sig(s.strokeMargin) << " m; tyre limit: "
    << (s.tyreLimit > 0 ? sig(s.tyreLimit) + " m" : std::string("each tyre's delta_max")) << "\n";
  o << "- lift: a constant force L W g on the airframe (the reduced-mass method of drop rigs is not used); W is set "
       "through the mass of `" << s.massBody << "`\n";
  o << "- energy to absorb E = W V^2/2 + (1 - L) W g h_max; absorbed = the gear's work integral(P_y dh) over the "
       "compression\n\n";
  o << "**Verdict: " << (c.pass ? "PASS" : "FAIL") << "**";
  if (!c.pass) o << " (" << failed << " item" << (failed == 1 ? "" : "s") << " fail)";
  o << "\n\n## Certification cases\n\n" << kTableHead;
  for (const auto& v : c.cases) o << row(v, &s);
  o << "\nRules: ";
  for (size_t i = 0; i < c.cases.size(); ++i) o << (i ? "; " : "") << c.cases[i].name << ": " << c.cases[i].cert.rule;
  o << ".\n";
  if (!c.unit.empty()) {
    o << "\n## Unit\n\n| requirement | value | floor | verdict |\n|---|---|---|---|\n";
    for (const auto& u : c.unit)
      o << "| " << u.name << " (" << u.rule << ") | " << sig(u.value, 4) << " | " << sig(u.bound, 4) << " | "
        << (u.pass ? "PASS" : "**FAIL**") << " |\n";
  }
  if (!c.checks.empty()) {
    o << "\n## Checks: the scene's own cases\n\nHeld to the same stroke and tyre limits; their conditions are not the "
         "rules', so they do not decide the verdict, and a violation is shown here: "
      << (c.checksPass ? "all within their limits." : "**some exceed a limit.**") << "\n\n"
      << kTableHead;
    for (const auto& v : c.checks) o << row(v, &s);
  }
  o << "\n## Pictures\n\n" << pictures << "\n";
  return o.str();
}

std::string complianceSummary(const Compliance& c) {
  std::ostringstream o;
  char b[256];
  std::snprintf(b, sizeof b, "%-20s %-8s %7s %5s %7s %7s %7s %9s %9s  %s\n", "case", "kind", "V[m/s]", "L", "W[kg]", "n_g",
                "n", "s_max[m]", "delta[m]", "verdict");
  o << b;
  auto line = [&](const CaseVerdict& v) {
    std::snprintf(b, sizeof b, "%-20s %-8s %7.3f %5.3g %7.0f %7.3f %7.3f %9.4f %9.4f  ", v.name.c_str(),
                  v.role == "check" ? "check" : certKindName(v.cert.kind), v.cert.sinkSpeed, v.cert.liftRatio, v.cert.mass,
                  v.metrics.load_factor, v.metrics.inertia_load_factor, v.metrics.stroke_max_m,
                  v.metrics.tyre_deflection_max_m);
    o << b;
    if (v.pass) o << "PASS";
    else {
      o << "FAIL: ";
      for (size_t i = 0; i < v.reasons.size(); ++i) o << (i ? "; " : "") << v.reasons[i];
    }
    o << "\n";
  };
  for (const auto& v : c.cases) line(v);
  for (const auto& u : c.unit) o << "unit: " << u.name << " = " << sig(u.value, 4) << " >= " << sig(u.bound, 4) << ": " << (u.pass ? "PASS" : "FAIL") << "\n";
  for (const auto& v : c.checks) line(v);
  o << (c.pass ? "PASS" : "FAIL") << ": " << c.spec->basisName << " matrix"
    << (c.checks.empty() ? "" : c.checksPass ? "; the scene's own cases within their limits"
                                             : "; some of the scene's own cases exceed a limit (checks, not the verdict)")
    << "\n";
  return o.str();
}

PlotLimits compliancePlotLimits(const Scene& scene, const Certification& spec, const CaseVerdict& v) {
  PlotLimits l = sceneLimits(scene);
  const double Wg = v.cert.mass * scene.gravity;
  if (v.role != "check") {
    l.loadLimit = spec.limitGroundFactor() * Wg;
    l.loadUltimate = spec.ultimateFactor * spec.limitGroundFactor() * Wg;
  }
  if (std::isfinite(l.strokeLimit)) l.strokeMargin = l.strokeLimit - spec.strokeMargin;
  if (spec.tyreLimit > 0) l.tyreLimit = spec.tyreLimit;
  return l;
}

}  // namespace lg
