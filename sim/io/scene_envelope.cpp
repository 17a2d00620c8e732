// The [envelope] table of a scene (declared in sim/io/scene.hpp; the physics in sim/scene/envelope.hpp):
//
//   [envelope]
//   service_temperature_C = 15.0             # [C] gas temperature at which the pre-charge is set (default 15)
//   landing_temperature_C = [-40.0, 50.0]    # [C] gas temperature range at landing (a factor: cold | hot)
//   oil_expansion = 7.0e-4                   # [1/K] volumetric thermal expansion of the oil (default 0: off)
//   oil_volume = 1.2e-3                      # [m^3] oil in the strut (needed with oil_expansion)
//   charge_tolerance = 0.05                  # [-] +- pre-charge, relative (a factor: lowcharge | highcharge)
//   gas_volume_tolerance = 0.01              # [-] +- gas volume from the oil level, relative (lowoil | highoil)
//   oil_level_tolerance = 2.0e-5             # [m^3] ... or absolute, as oil volume (not both)
//   orifice_tolerance = 0.02                 # [-] +- every orifice area, relative (smallorifice | largeorifice)
//   tyre_stiffness_tolerance = 0.05          # [-] +- every tyre's K, relative (softtyre | stifftyre)
//   static_exponent = 1.0                    # [-] the gas at rest: the static curve and servicing chart (1: isothermal)
//   temperature_C = 15.0, charge = 0.0, ...  # the point of the scene's plain runs (default: nominal)
//   [[envelope.corner]]                      # optional: the corners instead of the full factorial
//   name = "cold-day", temperature_C = -40.0, charge = -0.05, ...
#include <cmath>
#include <set>

#include "sim/io/scene.hpp"
#include "sim/io/toml_reader.hpp"
#include "sim/scene/check.hpp"

namespace lg {
namespace {

// A temperature [C] at 'key' (a number or 'n' of an array), above absolute zero; in kelvin.
double kelvin(const TomlReader& r, const std::string& key, double celsius) {
  if (!(celsius > -kZeroCelsius))
    r.fail(key, "value " + fmt(celsius) + " C is at or below absolute zero (-273.15 C)");
  if (celsius > 1000) r.fail(key, "value " + fmt(celsius) + " C is above 1000 C: a temperature in C, not K?");
  return celsius + kZeroCelsius;
}

// A relative tolerance in [0, 1).
double tolerance(const TomlReader& r, const std::string& key) {
  const double v = r.nonNegative(key, 0.0);
  if (!(v < 1)) r.fail(key, "value " + fmt(v) + " must be below 1 (a relative tolerance: 0.05 is +-5 %)");
  if (v > 0.5) r.fail(key, "value " + fmt(v) + " is a tolerance of more than 50 %: a relative tolerance, 0.05 is +-5 %");
  return v;
}

// The point keys of a table (the scene's point, a declared corner), over 'p'.
void readPoint(const TomlReader& r, EnvelopePoint<double>& p) {
  if (r.has("temperature_C")) p.temperature = kelvin(r, "temperature_C", r.number("temperature_C"));
  for (const char* key : {"charge", "gas_volume", "orifice", "tyre_stiffness"})
    if (r.has(key)) {
      const double v = r.number(key);
      if (!(v > -1 && v < 1)) r.fail(key, "value " + fmt(v) + " must lie in (-1, 1): a relative deviation (-0.05 is 5 % low)");
      setEnvelopeValue(p, key, v);
    }
  if (r.has("oil_level")) p.oilLevel = r.number("oil_level");
}

}  // namespace

Envelope parseEnvelope(const toml::table& t, const std::string& file, const Scene& scene) {
  TomlReader r(t, file, "envelope");
  r.allowOnly({"service_temperature_C", "landing_temperature_C", "oil_expansion", "oil_volume", "charge_tolerance",
               "gas_volume_tolerance", "oil_level_tolerance", "orifice_tolerance", "tyre_stiffness_tolerance",
               "temperature_C", "charge", "gas_volume", "oil_level", "orifice", "tyre_stiffness", "corner",
               "static_exponent"});
  Envelope e;
  e.declared = true;
  e.file = file;
  e.line = r.line();
  if (scene.roles.struts.empty())
    throw InputError(file, r.line(), "envelope",
                     "the scene has no shock absorber: an envelope moves a strut's gas charge, oil and orifices (remove "
                     "[envelope])");
  e.serviceTemperature = kelvin(r, "service_temperature_C", r.number("service_temperature_C", 15.0));
  if (r.has("landing_temperature_C")) {
    const toml::array* a = r.get("landing_temperature_C")->as_array();
    if (!a || a->size() != 2)
      r.fail("landing_temperature_C", "must be a range [cold, hot] of two temperatures in C, e.g. [-40.0, 50.0]");
    e.cold = kelvin(r, "landing_temperature_C", r.toNumber(*a->get(0), "landing_temperature_C"));
    e.hot = kelvin(r, "landing_temperature_C", r.toNumber(*a->get(1), "landing_temperature_C"));
    if (!(e.cold < e.hot))
      r.fail("landing_temperature_C", "the range [" + fmt(e.cold - kZeroCelsius) + ", " + fmt(e.hot - kZeroCelsius) +
                                          "] C must read [cold, hot] with cold < hot");
    e.temperatureRange = true;
  }
  e.oilExpansion = r.nonNegative("oil_expansion", 0.0);
  if (e.oilExpansion > 0.01)
    r.fail("oil_expansion", "value " + fmt(e.oilExpansion) + " 1/K is not an oil's volumetric expansion (about 7e-4 1/K)");
  e.oilVolume = r.nonNegative("oil_volume", 0.0);
  if (e.oilExpansion > 0 && !(e.oilVolume > 0))
    r.fail(r.has("oil_volume") ? "oil_volume" : "oil_expansion",
           "the oil's expansion needs the oil volume in the strut: oil_volume [m^3] > 0");
  if (e.oilVolume > 0 && !(e.oilExpansion > 0))
    r.fail("oil_volume", "is used with oil_expansion [1/K] only (the oil's thermal expansion)");
  e.chargeTolerance = tolerance(r, "charge_tolerance");
  e.gasVolumeTolerance = tolerance(r, "gas_volume_tolerance");
  e.oilLevelTolerance = r.nonNegative("oil_level_tolerance", 0.0);
  if (r.has("gas_volume_tolerance") && r.has("oil_level_tolerance"))
    r.fail("oil_level_tolerance", "give the oil level's tolerance once: gas_volume_tolerance (relative) or "
                                  "oil_level_tolerance [m^3] (absolute)");
  e.orificeTolerance = tolerance(r, "orifice_tolerance");
  e.tyreStiffnessTolerance = tolerance(r, "tyre_stiffness_tolerance");
  if (e.tyreStiffnessTolerance > 0) {
    if (scene.roles.tyres.empty()) r.fail("tyre_stiffness_tolerance", "the scene has no tyre");
    for (int f : scene.roles.tyres)
      if (std::get<Tyre<double>>(scene.model.forces[f].type).law == TyreLaw::Table)
        r.fail("tyre_stiffness_tolerance", "tyre '" + scene.model.forces[f].name +
                                               "' is a load table, without a stiffness K to scale: leave the key out");
  }
  e.staticExponent = r.number("static_exponent", 1.0);
  if (!(e.staticExponent >= 1 && e.staticExponent <= 5.0 / 3.0))
    r.fail("static_exponent", "value " + fmt(e.staticExponent) + " must lie in [1, 5/3]: 1 for isothermal (the gas at rest at "
                              "the ambient temperature), up to the adiabatic exponent");
  e.point = e.nominal();
  readPoint(r, e.point);
  if (r.has("tyre_stiffness") && scene.roles.tyres.empty()) r.fail("tyre_stiffness", "the scene has no tyre");

  const auto rows = tablesOf(t, "corner", file);
  if (static_cast<int>(rows.size()) > kMaxCorners)
    r.fail("corner", std::to_string(rows.size()) + " corners: at most " + std::to_string(kMaxCorners) + " are allowed");
  std::set<std::string> names{"nominal"};
  for (size_t i = 0; i < rows.size(); ++i) {
    TomlReader cr(*rows[i], file, "envelope.corner[" + std::to_string(i) + "]");
    cr.allowOnly({"name", "temperature_C", "charge", "gas_volume", "oil_level", "orifice", "tyre_stiffness"});
    EnvelopeCorner c;
    c.name = cr.name("name");
    if (!names.insert(c.name).second)
      cr.fail("name", "'" + c.name + "' is used twice (\"nominal\" is the nominal point's own name)");
    c.at = e.nominal();
    readPoint(cr, c.at);
    e.declaredCorners.push_back(c);
  }
  int factors = 0;
  for (bool f : {e.temperatureRange, e.chargeTolerance > 0, e.gasVolumeTolerance > 0 || e.oilLevelTolerance > 0,
                 e.orificeTolerance > 0, e.tyreStiffnessTolerance > 0})
    factors += f ? 1 : 0;
  if (!rows.empty() && factors > 0)
    r.fail("corner", "give the corners either as [[envelope.corner]] or as ranges and tolerances (their full factorial), "
                     "not both");
  // Every corner and the scene's point must run: a strut that locks is the envelope's mistake.
  Scene probe = scene;
  probe.envelope = e;
  if (const auto why = envelopeProblem(probe)) {
    std::string key = e.oilLevelTolerance > 0 ? "oil_level_tolerance" : e.gasVolumeTolerance > 0 ? "gas_volume_tolerance" : "";
    if (!rows.empty()) key = "corner";
    if (key.empty() || !r.has(key)) key = "";
    throw InputError(file, key.empty() ? r.line() : r.lineOf(key), key.empty() ? "envelope" : r.full(key), *why);
  }
  return e;
}

}  // namespace lg
