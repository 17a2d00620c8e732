// compliance.json, compliance.md and the terminal summary of `certify` (compliance.hpp).
#include "sim/io/compliance.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "sim/io/dossier.hpp"
#include "sim/io/files.hpp"
#include "sim/io/json.hpp"
#include "sim/io/plots.hpp"
#include "sim/drop/metrics.hpp"

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
    << ", \"mass_kg\": " << jsonNumber(v.cert.mass) << ", \"duration_s\": " << jsonNumber(v.cert.duration)
    << ", \"forward_speed_mps\": " << jsonNumber(v.cert.forwardSpeed) << ",\n";
  const auto& m = v.metrics;
  o << "      \"metrics\": {\"ok\": " << jsonBool(m.ok) << ", \"peak_load_N\": " << jsonNumber(m.peak_load_N)
    << ", \"load_factor\": " << jsonNumber(m.load_factor) << ", \"inertia_load_factor\": " << jsonNumber(m.inertia_load_factor)
    << ", \"stroke_max_m\": " << jsonNumber(m.stroke_max_m) << ", \"stroke_margin_m\": " << jsonNumber(m.stroke_margin_m)
    << ", \"tyre_deflection_max_m\": " << jsonNumber(m.tyre_deflection_max_m) << ", \"tyre_margin_m\": "
    << jsonNumber(m.tyre_margin_m) << ", \"h_max_m\": " << jsonNumber(m.h_max_m) << ", \"efficiency\": "
    << jsonNumber(m.efficiency) << ", \"energy_to_absorb_J\": " << jsonNumber(m.energy_to_absorb_J)
    << ", \"energy_absorbed_J\": " << jsonNumber(m.energy_absorbed_J) << ", \"compression_ended\": "
    << jsonBool(m.compression_ended) << ", \"bottomed\": " << jsonBool(m.bottomed);
  if (m.longitudinal)
    o << ",\n        \"drag_peak_N\": " << jsonNumber(m.drag_peak_N) << ", \"t_drag_peak_s\": " << jsonNumber(m.t_drag_peak_s)
      << ", \"springback_peak_N\": " << jsonNumber(m.springback_peak_N) << ", \"t_springback_s\": "
      << jsonNumber(m.t_springback_s) << ", \"drag_at_peak_N\": " << jsonNumber(m.drag_at_peak_N) << ", \"drag_ratio\": "
      << jsonNumber(metricValue(m, "drag_ratio")) << ", \"design_drag_N\": "
      << jsonNumber(std::max(m.drag_at_peak_N, 0.25 * m.peak_load_N));
  o << "},\n";
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

std::string cornerJson(const EnvelopeCorner& c) {
  std::ostringstream o;
  o << "{\"name\": " << jsonString(c.name) << ", \"temperature_C\": " << jsonNumber(c.at.temperature - kZeroCelsius)
    << ", \"charge\": " << jsonNumber(c.at.charge) << ", \"gas_volume\": " << jsonNumber(c.at.gasVolume)
    << ", \"oil_level_m3\": " << jsonNumber(c.at.oilLevel) << ", \"orifice\": " << jsonNumber(c.at.orifice)
    << ", \"tyre_stiffness\": " << jsonNumber(c.at.tyreStiffness) << "}";
  return o.str();
}

std::string worstJson(const WorstCorner& w) {
  const MetricInfo* info = findMetric(w.limit.metric);
  std::ostringstream o;
  o << "{\"metric\": " << jsonString(w.limit.metric) << ", \"relation\": " << jsonString(w.limit.upper ? "<=" : ">=")
    << ", \"limit\": " << jsonNumber(w.limit.bound) << ", \"unit\": " << jsonString(info ? info->unit : "")
    << ", \"worst_corner\": " << jsonString(w.corner) << ", \"value\": " << jsonNumber(w.value)
    << ", \"margin\": " << jsonNumber(w.margin) << ", \"pass\": " << jsonBool(w.pass) << ", \"rule\": "
    << jsonString(w.limit.rule) << "}";
  return o.str();
}

std::string envelopeVerdictJson(const EnvelopeVerdict& ev, const std::vector<EnvelopeCorner>& corners) {
  std::ostringstream o;
  o << "{\"name\": " << jsonString(ev.name) << ", \"role\": " << jsonString(ev.role) << ", \"pass\": " << jsonBool(ev.pass)
    << ", \"failing_points\": " << ev.failing << ",\n        \"worst\": [";
  for (size_t i = 0; i < ev.worst.size(); ++i) o << (i ? ",\n          " : "") << worstJson(ev.worst[i]);
  o << "],\n        \"points\": [";
  for (size_t k = 0; k < ev.at.size(); ++k) {
    const CaseVerdict& v = ev.at[k];
    const CaseMetrics& m = v.metrics;
    o << (k ? ",\n          " : "") << "{\"corner\": " << jsonString(corners[k].name) << ", \"ok\": " << jsonBool(m.ok)
      << ", \"peak_load_N\": " << jsonNumber(m.peak_load_N) << ", \"load_factor\": " << jsonNumber(m.load_factor)
      << ", \"stroke_max_m\": " << jsonNumber(m.stroke_max_m) << ", \"stroke_margin_m\": " << jsonNumber(m.stroke_margin_m)
      << ", \"tyre_deflection_max_m\": " << jsonNumber(m.tyre_deflection_max_m) << ", \"pass\": " << jsonBool(v.pass)
      << ", \"reasons\": [";
    for (size_t i = 0; i < v.reasons.size(); ++i) o << (i ? ", " : "") << jsonString(v.reasons[i]);
    o << "]}";
  }
  o << "]}";
  return o.str();
}

std::string envelopeJson(const Compliance& c) {
  const Envelope& e = *c.envelope;
  std::ostringstream o;
  o << "  \"envelope\": {\"service_temperature_C\": " << jsonNumber(e.serviceTemperature - kZeroCelsius)
    << ", \"landing_temperature_C\": "
    << (e.temperatureRange ? "[" + jsonNumber(e.cold - kZeroCelsius) + ", " + jsonNumber(e.hot - kZeroCelsius) + "]"
                           : std::string("null"))
    << ", \"charge_tolerance\": " << jsonNumber(e.chargeTolerance) << ", \"gas_volume_tolerance\": "
    << jsonNumber(e.gasVolumeTolerance) << ", \"oil_level_tolerance_m3\": " << jsonNumber(e.oilLevelTolerance)
    << ", \"orifice_tolerance\": " << jsonNumber(e.orificeTolerance) << ", \"tyre_stiffness_tolerance\": "
    << jsonNumber(e.tyreStiffnessTolerance) << ", \"oil_expansion_per_K\": " << jsonNumber(e.oilExpansion)
    << ", \"oil_volume_m3\": " << jsonNumber(e.oilVolume) << ",\n    \"nominal_pass\": " << jsonBool(c.nominalPass)
    << ", \"pass\": " << jsonBool(c.pass) << ", \"drops\": " << c.drops << ", \"rhs_evaluations\": " << c.rhsEvaluations
    << ",\n    \"corners\": [";
  for (size_t k = 0; k < c.corners.size(); ++k) o << (k ? ",\n      " : "") << cornerJson(c.corners[k]);
  o << "],\n    \"cases\": [";
  for (size_t i = 0; i < c.envelopeCases.size(); ++i)
    o << (i ? ",\n      " : "\n      ") << envelopeVerdictJson(c.envelopeCases[i], c.corners);
  o << "],\n    \"checks\": [";
  for (size_t i = 0; i < c.envelopeChecks.size(); ++i)
    o << (i ? ",\n      " : "\n      ") << envelopeVerdictJson(c.envelopeChecks[i], c.corners);
  o << "]},\n";
  return o.str();
}

// The margin of a worst corner in its unit, for people ("0.0004 m", "0.02").
std::string marginText(const WorstCorner& w) {
  if (std::isnan(w.margin)) return "run failed";
  const MetricInfo* info = findMetric(w.limit.metric);
  const std::string unit = info && std::string(info->unit) != "-" ? std::string(" ") + info->unit : "";
  return sig(w.margin, 4) + unit;
}

std::string envelopeMarkdown(const Compliance& c) {
  const Envelope& e = *c.envelope;
  std::ostringstream o;
  o << "\n## Servicing and temperature envelope\n\n";
  o << "Every case ran at the nominal point and at each of the " << c.corners.size() - 1
    << (e.declaredCorners.empty() ? " corners of the envelope (the full factorial of its extremes)" : " corners the scene declares")
    << ": " << c.drops << " drops, " << c.rhsEvaluations << " right-hand-side evaluations. The envelope (`[envelope]`):\n\n";
  for (const auto& f : e.factors()) o << "- " << f << "\n";
  o << "\nThe gas is a fixed mass charged at the service temperature with the strut extended: p01(T) = p01 (1 + charge) "
       "T / T_s (V_s / V_T), with V_s = Omega0 (1 + gas_volume) - oil_level and V_T = V_s less the oil's thermal expansion; "
       "orifice areas scale by (1 + orifice), tyre stiffness by (1 + tyre_stiffness).\n\n";
  o << "**Verdict over the envelope: " << (c.pass ? "PASS" : "FAIL") << "** (at the nominal point: "
    << (c.nominalPass ? "PASS" : "FAIL") << ")\n\n";
  o << "### Worst corner per limit\n\n| case | limit | worst corner | value | limit | margin | verdict |\n"
       "|---|---|---|---|---|---|---|\n";
  auto worstRows = [&](const std::vector<EnvelopeVerdict>& list) {
    for (const auto& ev : list)
      for (const auto& w : ev.worst)
        o << "| " << ev.name << " | " << w.limit.rule << " | " << w.corner << " | " << sig(w.value, 5) << " | "
          << (w.limit.upper ? "<= " : ">= ") << sig(w.limit.bound, 5) << " | " << marginText(w) << " | "
          << (w.pass ? "PASS" : "**FAIL**") << " |\n";
  };
  worstRows(c.envelopeCases);
  o << "\n### Every point\n\n";
  auto pointTable = [&](const EnvelopeVerdict& ev) {
    o << "**" << ev.name << "** (" << (ev.role == "check" ? "check" : "certification") << "): "
      << (ev.pass ? "PASS at every point" : "**FAIL at " + std::to_string(ev.failing) + " of " + std::to_string(ev.at.size()) + " points**")
      << "\n\n| point | P_y,max [kN] | n_g | stroke [m] | stroke margin [m] | tyre [m] | verdict |\n"
         "|---|---|---|---|---|---|---|\n";
    for (size_t k = 0; k < ev.at.size(); ++k) {
      const CaseVerdict& v = ev.at[k];
      const CaseMetrics& m = v.metrics;
      o << "| " << c.corners[k].name << " | " << fixed(m.peak_load_N / 1e3, 2) << " | " << fixed(m.load_factor, 3) << " | "
        << fixed(m.stroke_max_m, 4) << " | " << fixed(m.stroke_margin_m, 4) << " | " << fixed(m.tyre_deflection_max_m, 4)
        << " | ";
      if (v.pass) o << "PASS";
      else {
        o << "**FAIL**: ";
        for (size_t i = 0; i < v.reasons.size(); ++i) o << (i ? "; " : "") << v.reasons[i];
      }
      o << " |\n";
    }
    o << "\n";
  };
  for (const auto& ev : c.envelopeCases) pointTable(ev);
  if (!c.envelopeChecks.empty()) {
    o << "The scene's own cases over the envelope (checks, not the verdict): ";
    bool all = true;
    for (const auto& ev : c.envelopeChecks) all = all && ev.pass;
    if (all) o << "within their limits at every point.\n";
    else {
      o << "**some exceed a limit**:\n\n| case | limit | worst corner | value | limit | margin | verdict |\n"
           "|---|---|---|---|---|---|---|\n";
      worstRows(c.envelopeChecks);
    }
  }
  return o.str();
}

std::string celsius(double K) { return sig(K - kZeroCelsius, 4) + " C"; }

std::string servicingJson(const ServicingCurve& c) {
  std::ostringstream o;
  o << "  \"servicing\": {\"ok\": " << jsonBool(c.ok) << ", \"message\": " << jsonString(c.message)
    << ", \"strut\": " << jsonString(c.strut) << ", \"static_exponent\": " << jsonNumber(c.staticExponent)
    << ", \"service_temperature_C\": " << jsonNumber(c.serviceTemperature - kZeroCelsius) << ", \"mass_kg\": "
    << jsonNumber(c.mass) << ", \"stroke_limit_m\": " << jsonNumber(c.strokeLimit) << ", \"static_stroke_m\": "
    << jsonNumber(c.staticStroke) << ", \"static_force_N\": " << jsonNumber(c.staticForce) << ", \"static_ratio\": "
    << jsonNumber(c.staticRatio) << ", \"compression_ratio_extended_static\": " << jsonNumber(c.extendedToStatic)
    << ", \"compression_ratio_static_compressed\": " << jsonNumber(c.staticToCompressed) << ",\n    \"chart\": [";
  for (size_t k = 0; k < c.chart.size(); ++k)
    o << (k ? ", " : "") << "{\"ambient_C\": " << jsonNumber(c.chart[k].temperature - kZeroCelsius)
      << ", \"static_extension_m\": " << jsonNumber(c.chart[k].staticExtension) << ", \"static_pressure_Pa\": "
      << jsonNumber(c.chart[k].staticPressure) << "}";
  o << "]},\n";
  return o.str();
}

std::string servicingMarkdown(const ServicingCurve& c) {
  std::ostringstream o;
  o << "\n## The strut at rest and its servicing chart\n\n";
  if (!c.ok) {
    o << "Not computed: " << c.message << ".\n";
    return o.str();
  }
  o << "Strut `" << c.strut << "`, the gas at rest with the static exponent n_s = " << sig(c.staticExponent, 4)
    << (c.staticExponent == 1 ? " (isothermal)" : "") << ", charged at " << celsius(c.serviceTemperature)
    << "; no orifice force, no friction (a real strut rests within its friction band around this point). The ground load W g "
       "of W = "
    << sig(c.mass, 6) << " kg passes through the gear's kinematic ratio r = dg/ds (g: the gear's shortening, measured on a "
                         "drop of this scene): P_a(s) = W g r(s). Files: `static_curve.csv`, `servicing_chart.csv`.\n\n";
  o << "| static stroke at 1 g [m] | P_a there [N] | r there | compression ratio extended / static | static / compressed |\n"
       "|---|---|---|---|---|\n| "
    << fixed(c.staticStroke, 4) << " | " << fixed(c.staticForce, 0) << " | " << fixed(c.staticRatio, 3) << " | "
    << fixed(c.extendedToStatic, 3) << " | " << fixed(c.staticToCompressed, 3) << " |\n\n";
  o << "Servicing chart: the gauge pressure [MPa] a correctly charged strut shows at its extension (the stroke left to the "
       "bottoming stop) at the ambient temperature";
  if (c.chargeTolerance > 0) o << ", with the +-" << sig(100 * c.chargeTolerance, 3) << " % charge tolerance as low / high";
  o << "; the static point at W g marked *.\n\n| extension [m] |";
  for (const auto& ch : c.chart) o << " " << celsius(ch.temperature) << " |";
  o << "\n|---|";
  for (size_t k = 0; k < c.chart.size(); ++k) o << "---|";
  o << "\n";
  for (size_t i = 0; i < c.extension.size(); i += 4) {
    o << "| " << fixed(c.extension[i], 3) << " |";
    for (const auto& ch : c.chart) {
      o << " " << fixed(ch.pressure[i] / 1e6, 2);
      if (c.chargeTolerance > 0) o << " (" << fixed(ch.low[i] / 1e6, 2) << " .. " << fixed(ch.high[i] / 1e6, 2) << ")";
      o << " |";
    }
    o << "\n";
  }
  o << "| static point * |";
  for (const auto& ch : c.chart) o << " " << fixed(ch.staticExtension, 4) << " m, " << fixed(ch.staticPressure / 1e6, 2) << " MPa |";
  o << "\n";
  return o.str();
}

// The drag loads of the cases with wheel spin-up (a tyre that declares mu_x), or nothing.
std::string dragMarkdown(const Compliance& c) {
  bool any = false;
  for (const auto& v : c.cases) any = any || v.metrics.longitudinal;
  for (const auto& v : c.checks) any = any || v.metrics.longitudinal;
  if (!any) return "";
  std::ostringstream o;
  o << "\n## Drag loads: wheel spin-up and spring-back\n\nThe tyres that declare `mu_x` spin the wheel up from rest "
       "on ground moving aft at V_x; the drag P_x (positive aft) peaks during spin-up, the forward load -P_x at "
       "spring-back. The rules' design drag at the largest vertical load is at least 0.25 P_y,max (design drag = "
       "max(P_x, 0.25 P_y) at t_peak; reported, not a limit of the verdict). Forward speed of the matrix: "
    << sig(c.spec->forwardSpeed, 4) << " m/s (" << c.spec->forwardSpeedSource << ").\n\n"
    << "| case | V_x [m/s] | drag peak (spin-up) [kN] | at t [s] | spring-back [kN] | at t [s] | P_x at P_y,max [kN] | "
       "P_x / P_y | design drag [kN] |\n|---|---|---|---|---|---|---|---|---|\n";
  auto row = [&](const CaseVerdict& v) {
    const CaseMetrics& m = v.metrics;
    if (!m.longitudinal) return;
    o << "| " << v.name << " | " << fixed(v.cert.forwardSpeed, 1) << " | " << fixed(m.drag_peak_N / 1e3, 2) << " | "
      << fixed(m.t_drag_peak_s, 4) << " | " << fixed(m.springback_peak_N / 1e3, 2) << " | " << fixed(m.t_springback_s, 4)
      << " | " << fixed(m.drag_at_peak_N / 1e3, 2) << " | " << fixed(metricValue(m, "drag_ratio"), 3) << " | "
      << fixed(std::max(m.drag_at_peak_N, 0.25 * m.peak_load_N) / 1e3, 2) << " |\n";
  };
  for (const auto& v : c.cases) row(v);
  for (const auto& v : c.checks) row(v);
  return o.str();
}

const char* kTableHead =
    "| case | kind | V [m/s] | L | W [kg] | E to absorb [kJ] | absorbed [kJ] | n_g | n | stroke / limit [m] | "
    "tyre / limit [m] | eta | verdict |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|\n";

}  // namespace

std::string complianceJson(const Compliance& c) {
  const Certification& s = *c.spec;
  std::ostringstream o;
  o << "{\n";
  if (!c.provenanceJson.empty()) o << c.provenanceJson << ",\n";
  o << "  \"scene\": " << jsonString(c.scene) << ",\n  \"basis\": " << jsonString(s.basisName) << ",\n";
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
  if (c.sceneRun) o << dossierJson(*c.sceneRun, c);
  o << "  \"unit\": [";
  for (size_t i = 0; i < c.unit.size(); ++i) {
    const auto& u = c.unit[i];
    o << (i ? ", " : "") << "{\"name\": " << jsonString(u.name) << ", \"value\": " << jsonNumber(u.value)
      << ", \"relation\": \">=\", \"limit\": " << jsonNumber(u.bound) << ", \"pass\": " << jsonBool(u.pass)
      << ", \"rule\": " << jsonString(u.rule) << "}";
  }
  o << "],\n";
  if (c.envelope) o << envelopeJson(c);
  if (c.servicing) o << servicingJson(*c.servicing);
  o << "  \"cases\": [\n";
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
  if (!c.provenanceMarkdown.empty()) o << c.provenanceMarkdown << "\n## Configuration and verdict\n\n";
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
  if (c.envelope) o << " over the servicing and temperature envelope (" << c.corners.size() << " points: below)";
  o << "\n\n## Certification cases" << (c.envelope ? " at the nominal point" : "") << "\n\n" << kTableHead;
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
  o << dragMarkdown(c);
  if (c.envelope) o << envelopeMarkdown(c);
  if (c.servicing) o << servicingMarkdown(*c.servicing);
  if (c.sceneRun)
    o << derivationMarkdown(*c.sceneRun, c) << methodMarkdown(*c.sceneRun, c) << assumptionsMarkdown(*c.sceneRun, c)
      << footnotesMarkdown(c) << configurationMarkdown(*c.sceneRun);
  o << "\n## Pictures" << (c.envelope ? " (the nominal point)" : "") << "\n\n" << pictures << "\n";
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
    if (v.metrics.longitudinal) {  // wheel spin-up: the drag loads under the case
      std::snprintf(b, sizeof b, "%-20s drag at V_x = %.1f m/s: spin-up %.1f kN, spring-back %.1f kN, P_x/P_y at P_y,max %.3f\n",
                    "", v.cert.forwardSpeed, v.metrics.drag_peak_N / 1e3, v.metrics.springback_peak_N / 1e3,
                    metricValue(v.metrics, "drag_ratio"));
      o << b;
    }
  };
  for (const auto& v : c.cases) line(v);
  for (const auto& u : c.unit) o << "unit: " << u.name << " = " << sig(u.value, 4) << " >= " << sig(u.bound, 4) << ": " << (u.pass ? "PASS" : "FAIL") << "\n";
  for (const auto& v : c.checks) line(v);
  for (const auto& v : c.checks)
    if (std::abs(v.cert.mass - c.spec->landingMass) > 1e-9 * c.spec->landingMass && c.spec->landingMass > 0) {
      std::snprintf(b, sizeof b, "note: the scene's own cases run at their own masses (%s: %.0f kg), the matrix at W = %.0f kg\n",
                    v.name.c_str(), v.cert.mass, c.spec->landingMass);
      o << b;
      break;
    }
  auto over = [&](const EnvelopeVerdict& ev) {
    o << "envelope: " << ev.name << ": " << (ev.pass ? "PASS" : "FAIL") << " at " << ev.at.size() - ev.failing << " of "
      << ev.at.size() << " points";
    for (const auto& w : ev.worst)
      if (w.limit.metric == "stroke_margin" || !w.pass)
        o << "; " << w.limit.metric << " worst at " << w.corner << " (margin " << marginText(w) << ")";
    o << "\n";
  };
  for (const auto& ev : c.envelopeCases) over(ev);
  for (const auto& ev : c.envelopeChecks)
    if (!ev.pass) over(ev);
  o << (c.pass ? "PASS" : "FAIL") << ": " << c.spec->basisName << " matrix" << (c.envelope ? " over the envelope" : "")
    << (c.checks.empty() ? "" : c.checksPass ? "; the scene's own cases within their limits"
                                             : "; some of the scene's own cases exceed a limit (checks, not the verdict)")
    << "\n";
  return o.str();
}

std::string staticCurveCsv(const ServicingCurve& c) {
  std::ostringstream o;
  o << "s[m],p_1[Pa],P_a[N],r[-]\n";
  for (size_t i = 0; i < c.stroke.size(); ++i)
    o << sig(c.stroke[i], 10) << "," << sig(c.pressure[i], 10) << "," << sig(c.force[i], 10) << ","
      << (std::isfinite(c.ratio[i]) ? sig(c.ratio[i], 10) : std::string()) << "\n";
  return o.str();
}

std::string servicingChartCsv(const ServicingCurve& c) {
  std::ostringstream o;
  o << "extension[m]";
  for (const auto& ch : c.chart) {
    const std::string t = sig(ch.temperature - kZeroCelsius, 4) + "C";
    o << ",p_" << t << "[Pa],p_" << t << "_low[Pa],p_" << t << "_high[Pa]";
  }
  o << "\n";
  for (size_t i = 0; i < c.extension.size(); ++i) {
    o << sig(c.extension[i], 10);
    for (const auto& ch : c.chart) o << "," << sig(ch.pressure[i], 10) << "," << sig(ch.low[i], 10) << "," << sig(ch.high[i], 10);
    o << "\n";
  }
  return o.str();
}

bool drawServicingChart(const ServicingCurve& c, const std::string& dir, const std::string& stem, bool run, std::string* why) {
  namespace fs = std::filesystem;
  std::ostringstream d, g;
  for (size_t i = 0; i < c.extension.size(); ++i) {
    d << sig(c.extension[i], 10);
    for (const auto& ch : c.chart) d << " " << sig(ch.pressure[i] / 1e6, 10) << " " << sig(ch.low[i] / 1e6, 10) << " "
                                     << sig(ch.high[i] / 1e6, 10);
    d << "\n";
  }
  d << "\n\n";  // block 1: the static points
  for (const auto& ch : c.chart) d << sig(ch.staticExtension, 10) << " " << sig(ch.staticPressure / 1e6, 10) << "\n";
  writeFileAtomic((fs::path(dir) / (stem + ".dat")).string(), d.str());
  g << "set terminal pngcairo size 900,600\nset output " << gnuplotQuoted(stem + ".png") << "\n";
  double top = 0;  // the static points' range, not the bottoming end's steep rise
  for (const auto& ch : c.chart) top = std::max(top, std::isfinite(ch.staticPressure) ? ch.staticPressure / 1e6 : 0.0);
  if (top > 0) g << "set yrange [0:" << sig(2.5 * top, 4) << "]\n";
  g << "set title " << gnuplotQuoted("Servicing chart, strut '" + c.strut + "': gauge pressure at the extension, W = " +
                                     sig(c.mass, 6) + " kg, n_s = " + sig(c.staticExponent, 3))
    << "\nset xlabel 'extension (stroke left to the bottoming stop) [m]'\nset ylabel 'gauge pressure [MPa]'\n"
       "set key top right\nset grid\n";
  g << "plot ";
  for (size_t k = 0; k < c.chart.size(); ++k) {
    const int col = 2 + 3 * static_cast<int>(k);
    g << (k ? ", \\\n     " : "") << gnuplotQuoted(stem + ".dat") << " index 0 using 1:" << col + 1 << ":" << col + 2
      << " with filledcurves fs transparent solid 0.15 lc " << k + 1 << " notitle, \\\n     " << gnuplotQuoted(stem + ".dat")
      << " index 0 using 1:" << col << " with lines lw 2 lc " << k + 1 << " title "
      << gnuplotQuoted(sig(c.chart[k].temperature - kZeroCelsius, 4) + " C");
  }
  g << ", \\\n     " << gnuplotQuoted(stem + ".dat") << " index 1 using 1:2 with points pt 7 ps 1.5 lc rgb 'black' title 'static point (W g)'\n";
  writeFileAtomic((fs::path(dir) / (stem + ".gp")).string(), g.str());
  return run ? runGnuplot(dir, stem, why) : false;
}

PlotLimits compliancePlotLimits(const Scene& scene, const Certification& spec, const CaseVerdict& v) {
  PlotLimits l = sceneLimits(scene);
  const double Wg = v.cert.mass * scene.gravity;
  if (v.role != "check") {
    // (the reserve-energy drop is held to the ultimate load: the limit load is no limit of it, and not drawn)
    l.loadLimit = v.cert.kind == CertKind::Reserve ? std::nan("") : spec.limitGroundFactor() * Wg;
    l.loadUltimate = spec.ultimateFactor * spec.limitGroundFactor() * Wg;
  }
  if (std::isfinite(l.strokeLimit)) l.strokeMargin = l.strokeLimit - spec.strokeMargin;
  if (spec.tyreLimit > 0) l.tyreLimit = spec.tyreLimit;
  return l;
}

}  // namespace lg
