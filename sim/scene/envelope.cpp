// The servicing and temperature envelope (envelope.hpp): its points, corners and their checks.
#include "sim/scene/envelope.hpp"

#include <cstdio>

namespace lg {
namespace {

std::string num(double v, int digits = 6) {
  char b[48];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

}  // namespace

const std::vector<EnvelopeKey>& envelopePointKeys() {
  static const std::vector<EnvelopeKey> keys{
      {"temperature_C", "C", "gas temperature at landing"},
      {"charge", "-", "relative deviation of the pre-charge p01 (and p02) from its nominal value"},
      {"gas_volume", "-", "relative deviation of the gas volume Omega0 (the oil level)"},
      {"oil_level", "m^3", "oil volume above nominal (the gas volume is that much smaller)"},
      {"orifice", "-", "relative deviation of every orifice area (f1, f2, the metering pin and extension tables)"},
      {"tyre_stiffness", "-", "relative deviation of every tyre's stiffness K (tyre pressure)"},
  };
  return keys;
}

bool isEnvelopePointKey(const std::string& key) {
  for (const auto& k : envelopePointKeys())
    if (key == k.key) return true;
  return false;
}

EnvelopePoint<double> Envelope::nominal() const {
  EnvelopePoint<double> p;
  p.temperature = serviceTemperature;
  return p;
}

std::vector<EnvelopeCorner> Envelope::corners() const {
  std::vector<EnvelopeCorner> out{{"nominal", nominal()}};
  if (!declaredCorners.empty()) {
    out.insert(out.end(), declaredCorners.begin(), declaredCorners.end());
    return out;
  }
  struct Factor {
    const char *low, *high;
    void (*set)(EnvelopePoint<double>&, const Envelope&, bool high);
  };
  std::vector<Factor> fs;
  if (temperatureRange)
    fs.push_back({"cold", "hot", [](EnvelopePoint<double>& p, const Envelope& e, bool h) { p.temperature = h ? e.hot : e.cold; }});
  if (chargeTolerance > 0)
    fs.push_back({"lowcharge", "highcharge",
                  [](EnvelopePoint<double>& p, const Envelope& e, bool h) { p.charge = h ? e.chargeTolerance : -e.chargeTolerance; }});
  if (gasVolumeTolerance > 0)  // low oil: more gas
    fs.push_back({"lowoil", "highoil", [](EnvelopePoint<double>& p, const Envelope& e, bool h) {
                    p.gasVolume = h ? -e.gasVolumeTolerance : e.gasVolumeTolerance;
                  }});
  if (oilLevelTolerance > 0)
    fs.push_back({"lowoil", "highoil", [](EnvelopePoint<double>& p, const Envelope& e, bool h) {
                    p.oilLevel = h ? e.oilLevelTolerance : -e.oilLevelTolerance;
                  }});
  if (orificeTolerance > 0)
    fs.push_back({"smallorifice", "largeorifice", [](EnvelopePoint<double>& p, const Envelope& e, bool h) {
                    p.orifice = h ? e.orificeTolerance : -e.orificeTolerance;
                  }});
  if (tyreStiffnessTolerance > 0)
    fs.push_back({"softtyre", "stifftyre", [](EnvelopePoint<double>& p, const Envelope& e, bool h) {
                    p.tyreStiffness = h ? e.tyreStiffnessTolerance : -e.tyreStiffnessTolerance;
                  }});
  const size_t k = fs.size();
  if (k == 0) return out;
  for (size_t bits = 0; bits < (size_t{1} << k); ++bits) {
    EnvelopeCorner c{"", nominal()};
    for (size_t f = 0; f < k; ++f) {
      const bool high = (bits >> (k - 1 - f)) & 1;  // the first factor varies slowest
      fs[f].set(c.at, *this, high);
      c.name += (f ? "-" : "") + std::string(high ? fs[f].high : fs[f].low);
    }
    out.push_back(c);
  }
  return out;
}

std::vector<std::string> Envelope::factors() const {
  std::vector<std::string> out;
  const std::string ts = num(serviceTemperature - kZeroCelsius) + " C";
  if (temperatureRange)
    out.push_back("gas temperature at landing " + num(cold - kZeroCelsius) + " .. " + num(hot - kZeroCelsius) +
                  " C, serviced at " + ts);
  if (chargeTolerance > 0) out.push_back("pre-charge +-" + num(100 * chargeTolerance) + " %");
  if (gasVolumeTolerance > 0) out.push_back("gas volume (oil level) +-" + num(100 * gasVolumeTolerance) + " %");
  if (oilLevelTolerance > 0) out.push_back("oil volume +-" + num(oilLevelTolerance) + " m^3");
  if (orificeTolerance > 0) out.push_back("orifice areas +-" + num(100 * orificeTolerance) + " %");
  if (tyreStiffnessTolerance > 0) out.push_back("tyre stiffness +-" + num(100 * tyreStiffnessTolerance) + " %");
  if (oilExpansion > 0)
    out.push_back("oil thermal expansion " + num(oilExpansion) + " 1/K of " + num(oilVolume) + " m^3 of oil");
  return out;
}

std::optional<std::string> envelopePointProblem(const Envelope& env, const Model<double>& m,
                                                const std::vector<double>& strokeLimits, const EnvelopeCorner& at) {
  if (!(at.at.temperature > 0))
    return "corner '" + at.name + "': gas temperature " + num(at.at.temperature - kZeroCelsius) + " C is below absolute zero";
  Model<double> c = m;
  applyEnvelope(env, c, at.at);
  for (size_t f = 0; f < c.forces.size(); ++f) {
    const auto* a = std::get_if<ShockAbsorber<double>>(&c.forces[f].type);
    if (!a) continue;
    const std::string who = "corner '" + at.name + "', strut '" + c.forces[f].name + "': ";
    const double F = a->area();
    const double S = f < strokeLimits.size() ? strokeLimits[f] : std::nan("");
    const double gas = a->twoStage ? a->Omega0 + a->Omega02 : a->Omega0;
    if (std::isfinite(S) && !(gas > F * S))
      return who + "the gas volume " + num(gas) + " m^3 is not larger than the volume swept at the bottoming stroke, F S_max = " +
             num(F * S) + " m^3: the strut would lock before its stop (reduce the oil level or gas volume tolerance)";
    if (!(gas > 0)) return who + "no gas volume is left (" + num(gas) + " m^3)";
    if (!(a->p01 > a->pAtm))
      return who + "the pre-charge " + num(a->p01) + " Pa is not above the atmosphere's " + num(a->pAtm) + " Pa";
    if (!(a->rho > 0)) return who + "the oil density " + num(a->rho) + " kg/m^3 is not positive";
  }
  return std::nullopt;
}

}  // namespace lg
