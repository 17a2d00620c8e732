// The strut at rest and its servicing chart (certify writes them; docs/certification.md, "The servicing chart"): the
// static air curve, the static stroke at 1 g of the unit's mass, the compression ratios, and the
// pressure a mechanic reads at a measured extension under the static load at several ambient
// temperatures, with the charge's tolerance band. For the first shock absorber of a scene.
//
// Static air curve (zero rate: no orifice force; no friction), the static polytropic exponent n_s
// ([envelope] static_exponent, default 1: isothermal, the gas at the ambient temperature):
//   p_s(s; T) = p_01 (T / T_s) / (1 - s F / Omega_0)^n_s,   P_a(s) = (p_s - p_atm) F            [Pa], [N]
//   (a two-stage spring: the same law of gas_spring.hpp with n_s for both chambers)
// Static stroke at 1 g: the ground load W g (W: the matrix's landing mass, else the scene's mass) on
// level ground passes through the gear's kinematic ratio r(s) = dg/ds, g = h - delta the shortening of
// the gear (the airframe's travel less the tyre's deflection), so that by virtual work
//   P_a(s) = W g r(s)                                                                              (1)
// r(s) is measured on a drop of the scene (the mechanism is rigid: g(s) is its geometry): a drop at
// 5 m/s with lift = weight, rows every 0.2 ms over the compression, r the slope of a least-squares
// line through the rows within 2 % of S_max of s. The gear's own bodies' weight is left out of the
// ratio (their share of W); a real strut's static stroke lies within its friction band around (1).
// Compression ratios (volumes): extended / static V(0) / V(s_st), static / compressed V(s_st) / V(S_max).
// Servicing chart: at ambient T the correctly charged strut reads p_s(S_max - e; T) - p_atm at the
// extension e (stroke left to the bottoming stop), between (1 -+ charge_tolerance) of it; its static
// point is the root of (1) at T.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"

namespace lg {

struct ServicingChart {
  double temperature = 0;            // [K] ambient (the gas's) temperature
  std::vector<double> pressure;      // [Pa] gauge reading at each extension (ServicingCurve::extension)
  std::vector<double> low, high;     // [Pa] the charge's tolerance band
  double staticExtension = std::numeric_limits<double>::quiet_NaN();  // [m] at W g
  double staticPressure = std::numeric_limits<double>::quiet_NaN();   // [Pa] gauge, there
};

struct ServicingCurve {
  bool ok = false;
  std::string message;               // why there is none (no strut, no bottoming stop, a failed drop)
  std::string strut;                 // its name
  double staticExponent = 1;         // [-] n_s
  double serviceTemperature = 0;     // [K] T_s
  double mass = 0;                   // [kg] W
  double strokeLimit = 0;            // [m] S_max
  double atmosphere = 0;             // [Pa] p_atm of the strut (gauge = p - p_atm)
  std::vector<double> stroke;        // [m] the curve's strokes, 0 .. S_max
  std::vector<double> pressure;      // [Pa] p_s(s; T_s), absolute
  std::vector<double> force;         // [N] P_a(s), static
  std::vector<double> ratio;         // [-] r(s) = dg/ds (NaN beyond the strokes the drop reached)
  double staticStroke = std::numeric_limits<double>::quiet_NaN();    // [m] at T_s
  double staticForce = std::numeric_limits<double>::quiet_NaN();     // [N] P_a there
  double staticRatio = std::numeric_limits<double>::quiet_NaN();     // [-] r there
  double extendedToStatic = std::numeric_limits<double>::quiet_NaN();   // [-] V(0) / V(s_st)
  double staticToCompressed = std::numeric_limits<double>::quiet_NaN(); // [-] V(s_st) / V(S_max)
  std::vector<double> extension;     // [m] the chart's extensions, S_max .. 0 in steps
  double chargeTolerance = 0;        // [-] the band
  std::vector<ServicingChart> chart; // per ambient temperature (the envelope's range in five, else T_s)
};

// The static curve, static point and servicing chart of the scene's first strut at the unit's mass W
// [kg] (never throws: ok = false with a message).
ServicingCurve servicingCurve(const Scene& scene, double mass);

}  // namespace lg
