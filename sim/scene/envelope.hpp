// The servicing and temperature envelope of a gear (a scene's [envelope] table, docs/certification.md, "The servicing and temperature envelope"):
// a real strut never lands with its nominal gas charge. Its nitrogen is charged at a servicing
// temperature T_s and lands anywhere from a cold to a hot day; servicing leaves the pre-charge and the
// oil level within a tolerance; orifices are made to a tolerance; the tyre is inflated within one.
// A point of the envelope says where one run sits in it; a corner is a point at the declared extremes.
//
// A point P = (T, c, v, o_l, a, k): gas temperature at landing T [K], the pre-charge's relative
// deviation c [-], the gas volume's relative deviation v [-] (or the oil volume's absolute one o_l
// [m^3]: more oil, less gas), every orifice area's relative deviation a [-], the tyre stiffness's k [-].
// Applied to every shock absorber and tyre of a model after the design's own values (applyEnvelope):
//
//   servicing (at T_s, the strut extended):   V_s   = Omega_0 (1 + v) - o_l               [m^3]
//                                             p_s   = p_01 (1 + c)                          [Pa]
//   oil expansion to T (coefficient beta [1/K], oil volume V_oil [m^3]; 0 unless declared):
//                                             V_T   = V_s - beta V_oil (T - T_s)            [m^3]
//                                             rho_T = rho / (1 + beta (T - T_s))            [kg/m^3]
//   the gas, a fixed mass (ideal gas, p V / T constant):
//                                             p_01(T) = p_s (T / T_s) (V_s / V_T)           [Pa]
//                                             Omega_0(T) = V_T
//   a two-stage spring's second chamber (no oil; its volume fixed): p_02(T) = p_02 (1 + c) T / T_s
//   orifices, metering-pin and extension tables: f (1 + a);  tyre: K (1 + k)
//
// At the nominal point (T = T_s, every deviation 0) every factor is exactly 1: the run is the same bits
// as the scene's. A scene without [envelope] applies nothing (its runs cost nothing more).
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "sim/model/state.hpp"

namespace lg {

constexpr double kZeroCelsius = 273.15;  // [K]
constexpr int kMaxCorners = 64;          // [-] corners of an envelope, the nominal point not counted

// Where one run sits in the envelope (see the header's equations).
template <class S> struct EnvelopePoint {
  S temperature = S(kZeroCelsius + 15);  // [K] gas temperature at landing
  S charge = S(0);                       // [-] relative deviation of the pre-charge (p_01, p_02)
  S gasVolume = S(0);                    // [-] relative deviation of the gas volume Omega_0
  S oilLevel = S(0);                     // [m^3] oil volume above nominal (less gas)
  S orifice = S(0);                      // [-] relative deviation of every orifice area
  S tyreStiffness = S(0);                // [-] relative deviation of every tyre's K
  template <class T> EnvelopePoint<T> cast() const {
    return {T(temperature), T(charge), T(gasVolume), T(oilLevel), T(orifice), T(tyreStiffness)};
  }
  bool operator==(const EnvelopePoint&) const = default;
};

// The envelope quantities as parameters (paths "envelope.<key>": --set, --gradient, study variables,
// sensitivity studies): the point of the scene's plain runs. Key, unit, meaning.
struct EnvelopeKey {
  const char* key;
  const char* unit;
  const char* meaning;
};
const std::vector<EnvelopeKey>& envelopePointKeys();
// The field of a point a key names (temperature_C is kept in kelvin: the value is key's - 273.15 ...).
// Value in the key's unit (temperature_C in C), and its setter.
template <class S> S envelopeValue(const EnvelopePoint<S>& p, const std::string& key) {
  if (key == "temperature_C") return p.temperature - S(kZeroCelsius);
  if (key == "charge") return p.charge;
  if (key == "gas_volume") return p.gasVolume;
  if (key == "oil_level") return p.oilLevel;
  if (key == "orifice") return p.orifice;
  return p.tyreStiffness;  // "tyre_stiffness"
}
template <class S> void setEnvelopeValue(EnvelopePoint<S>& p, const std::string& key, const S& v) {
  if (key == "temperature_C") p.temperature = v + S(kZeroCelsius);
  else if (key == "charge") p.charge = v;
  else if (key == "gas_volume") p.gasVolume = v;
  else if (key == "oil_level") p.oilLevel = v;
  else if (key == "orifice") p.orifice = v;
  else p.tyreStiffness = v;
}
bool isEnvelopePointKey(const std::string& key);

struct EnvelopeCorner {
  std::string name;               // "nominal", "cold-lowcharge-lowoil-largeorifice", or a declared name
  EnvelopePoint<double> at;
};

struct Envelope {
  bool declared = false;
  std::string file;               // where the table was read (messages)
  int line = 0;
  double serviceTemperature = kZeroCelsius + 15;  // [K] T_s, where the charge is set
  bool temperatureRange = false;  // a landing temperature range is declared
  double cold = kZeroCelsius + 15, hot = kZeroCelsius + 15;  // [K] its ends
  double oilExpansion = 0;        // [1/K] beta, volumetric thermal expansion of the oil
  double oilVolume = 0;           // [m^3] V_oil
  double chargeTolerance = 0;     // [-] +- relative, pre-charge
  double gasVolumeTolerance = 0;  // [-] +- relative, gas volume
  double oilLevelTolerance = 0;   // [m^3] +- absolute, oil volume (either this or gasVolumeTolerance)
  double orificeTolerance = 0;    // [-] +- relative, every orifice area
  double tyreStiffnessTolerance = 0;  // [-] +- relative, every tyre's K
  double staticExponent = 1;      // [-] n_s of the strut at rest (the static curve, the servicing chart): 1 isothermal
  EnvelopePoint<double> point;    // where the scene's plain runs sit (default: nominal)
  std::vector<EnvelopeCorner> declaredCorners;  // [[envelope.corner]]: the corners instead of the factorial

  EnvelopePoint<double> nominal() const;
  // The nominal point, then the corners: the declared list, or the full factorial of the declared
  // extremes (2^k for k factors with a range; named factor by factor in the order temperature, charge,
  // oil level, orifice, tyre: cold|hot, lowcharge|highcharge, lowoil|highoil, smallorifice|largeorifice,
  // softtyre|stifftyre). An envelope without factors has the nominal point only.
  std::vector<EnvelopeCorner> corners() const;
  // The factors with a range, in words ("landing temperature -40 .. 50 C (serviced at 15 C)", ...).
  std::vector<std::string> factors() const;
};

// The point a case runs at: its corner, or the scene's point.
// Applies a point of the envelope to a model of any scalar (the header's equations); nothing where the
// envelope is not declared.
template <class S> void applyEnvelope(const Envelope& env, Model<S>& m, const EnvelopePoint<S>& p) {
  if (!env.declared) return;
  const S Ts(env.serviceTemperature);
  const S dT = p.temperature - Ts;
  const S thermal = p.temperature / Ts;
  const S beta(env.oilExpansion), Voil(env.oilVolume);
  const S area = S(1) + p.orifice;
  for (auto& f : m.forces) {
    if (auto* a = std::get_if<ShockAbsorber<S>>(&f.type)) {
      const S Vs = a->Omega0 * (S(1) + p.gasVolume) - p.oilLevel;
      const S VT = Vs - beta * Voil * dT;
      a->p01 = a->p01 * (S(1) + p.charge) * thermal * (Vs / VT);
      a->Omega0 = VT;
      a->rho = a->rho / (S(1) + beta * dT);
      if (a->twoStage) a->p02 = a->p02 * (S(1) + p.charge) * thermal;
      a->f1 *= area;
      a->f2 *= area;
      a->f1e *= area;
      a->f2e *= area;
      for (S& v : a->f1Values) v *= area;
      for (S& v : a->f1eValues) v *= area;
    } else if (auto* t = std::get_if<Tyre<S>>(&f.type)) {
      t->K *= S(1) + p.tyreStiffness;
    }
  }
}

// Why a point of the envelope cannot run on a model (a strut whose gas volume at that point is gone
// before its bottoming stop: it would lock; a pre-charge at or below the atmosphere's), or nothing.
// 'strokeLimits' are the scene's S_max per force element index (NaN: none).
std::optional<std::string> envelopePointProblem(const Envelope& env, const Model<double>& m,
                                                const std::vector<double>& strokeLimits, const EnvelopeCorner& at);

}  // namespace lg
