// The strut's gas spring (sim/forces/shock_absorber.hpp): one polytropic chamber, or two with a
// floating piston between them. F = pi D^2/4 is the rod's area, s the stroke; the oil is incompressible,
// so the gas gives up the volume s F the rod displaces.
//
// Single stage (chamber 1: precharge p_01, volume Omega_0, exponent n):
//   V_1 = Omega_0 - s F,   p_1 = p_01 / (1 - s F / Omega_0)^n                              [Pa]
//   E   = p_01 Omega_0/(n-1) ((1 - s F/Omega_0)^(1-n) - 1)                                  [J]
//
// Two stages: a second chamber behind a floating piston (massless, frictionless), precharged to
// p_02 > p_01 in the volume Omega_02, exponent n_2. The piston rests on its stop (chamber 2 holds p_02,
// Omega_02) while p_1 < p_02. Both chambers together hold the gas volume the rod leaves,
//   V_1 + V_2 = Omega_0 + Omega_02 - s F                                                    (1)
// at every stroke: before engagement V_2 = Omega_02 and V_1 = Omega_0 - s F (the single stage's law).
//   Engagement: p_1 = p_02, i.e. V_1 = Omega_0 (p_01/p_02)^(1/n) at the stroke
//     s* = (Omega_0/F) (1 - (p_01/p_02)^(1/n))                                              [m]
//   After (s > s*): the piston floats, one pressure p in both chambers, V_i = Omega_i0 (p_i0/p)^(1/n_i),
//   and (1) reads, in x = ln p,
//     g(x) = Omega_0 exp((ln p_01 - x)/n) + Omega_02 exp((ln p_02 - x)/n_2) - (Omega_0 + Omega_02 - s F) = 0,
//     g'(x) = -V_1/n - V_2/n_2 < 0,  g'' > 0.
//   g is decreasing and convex, and g(ln p_02) = (s - s*) F >= 0: Newton from x = ln p_02 climbs
//   monotonically to the root (in double, to round-off). Then one Newton step in the scalar type S
//   from that root carries the derivatives of the implicit function theorem, dx = -g_theta / g_x, so
//   Jet derivatives are exact (the value moves by round-off only).
//   p_1 = p_2 = p; the force (p - p_atm) F is continuous at s*, its slope drops there (a kink: the
//   stiffness falls from n p F^2/V_1 to p F^2/(V_1/n + V_2/n_2)), so the strut declares the event
//   function s - s* and the integrator stops on it.
//   E = sum_i p_i0 Omega_i0/(n_i-1) ((Omega_i0/V_i)^(n_i-1) - 1) = sum_i (p_i V_i - p_i0 Omega_i0)/(n_i-1)
//   (chamber 2 adds 0 before engagement); dE/ds = p F on both sides, so the energy stored is exact.
// The gas lasts while Omega_0 + Omega_02 > s F (one stage: Omega_0 > s F); beyond, the pressure is NaN
// (as the single stage's law gives), never an exception.
//
// Isothermal (n = 1, any chamber): the same laws, and the energy their limit, p_0 Omega_0 ln(Omega_0 / V)
// (p V constant); written p_0 Omega_0 (L + (n - 1) L^2 / 2), L = ln(Omega_0 / V), so that its derivative
// in n is the polytropic law's limit too. isIsothermal(n) is the one branch on the value.
#pragma once

#include <cmath>

#include "sim/core/math.hpp"

namespace lg {

// An exponent of 1 (to 1e-12): the isothermal energy law.
template <class S> bool isIsothermal(const S& n) { return std::abs(value(n) - 1.0) < 1e-12; }

// The energy stored compressing a gas from (p_0, Omega_0) to the volume V at the pressure p [J]:
// (p V - p_0 Omega_0) / (n - 1), and at n = 1 its limit (above).
template <class S> S gasEnergy(const S& p0, const S& Omega0, const S& p, const S& V, const S& n) {
  using std::log;
  if (!isIsothermal(n)) return (p * V - p0 * Omega0) / (n - S(1));
  const S L = log(Omega0 / V);
  return p0 * Omega0 * (L + (n - S(1)) * L * L / S(2));
}

template <class S> struct GasSpring {
  const S& p01;      // [Pa] chamber 1 precharge
  const S& Omega0;   // [m^3] chamber 1 volume at s = 0
  const S& n;        // [-] chamber 1 exponent
  bool twoStage;     // a second chamber behind a floating piston
  const S& p02;      // [Pa] chamber 2 precharge (> p01)
  const S& Omega02;  // [m^3] chamber 2 volume on the stop
  const S& n2;       // [-] chamber 2 exponent

  struct Pressures {
    S p1, p2;      // [Pa] chamber pressures (equal once engaged)
    S V1, V2;      // [m^3] chamber volumes (only after engagement; before, unused)
    bool engaged = false;
  };

  // s* [m] (two stages only).
  S engagementStroke(const S& F) const {
    using std::pow;
    return Omega0 / F * (S(1) - pow(p01 / p02, S(1) / n));
  }

  // The root x = ln p of g after engagement (s > s*), in double, by Newton from ln p_02.
  double engagedLogPressure(double s, double F) const {
    using std::exp;
    using std::log;
    const double a = value(Omega0), b = value(Omega02), n1 = value(n), m2 = value(n2);
    const double l1 = log(value(p01)), l2 = log(value(p02));
    const double Vt = a + b - s * F;
    if (!(Vt > 0)) return std::nan("");
    double x = l2;
    for (int it = 0; it < 100; ++it) {
      const double V1 = a * exp((l1 - x) / n1), V2 = b * exp((l2 - x) / m2);
      const double dx = (V1 + V2 - Vt) / (V1 / n1 + V2 / m2);
      x += dx;
      if (!(std::abs(dx) > 4e-16 * std::abs(x))) break;
    }
    return x;
  }

  Pressures pressures(const S& s, const S& F) const {
    using std::exp;
    using std::log;
    using std::pow;
    Pressures r;
    if (!twoStage || !isPositive(s - engagementStroke(F))) {
      r.p1 = p01 / pow(S(1) - s * F / Omega0, n);  // the single stage's law, to the bit
      r.p2 = twoStage ? p02 : S(0);
      return r;
    }
    r.engaged = true;
    // One Newton step in S from the double root: the implicit function theorem's derivatives.
    const S x0(engagedLogPressure(value(s), value(F)));
    const S lp1 = log(p01), lp2 = log(p02);
    const S V1 = Omega0 * exp((lp1 - x0) / n), V2 = Omega02 * exp((lp2 - x0) / n2);
    const S x = x0 + (V1 + V2 - (Omega0 + Omega02 - s * F)) / (V1 / n + V2 / n2);
    r.p1 = exp(x);
    r.p2 = r.p1;
    r.V1 = Omega0 * exp((lp1 - x) / n);
    r.V2 = Omega02 * exp((lp2 - x) / n2);
    return r;
  }

  // dp_1/ds [Pa/m] at the state 'p' of pressures(s, F): p_1 V_1^n fixed and dV_1/ds = -F give
  // n p_1 F / (Omega0 - s F); engaged, with p_1 = p_2 = p and V_1 + V_2 = Omega0 + Omega02 - s F,
  // F p / (V_1/n + V_2/n2).
  S pressureRate(const S& s, const S& F, const Pressures& p) const {
    if (p.engaged) return F * p.p1 / (p.V1 / n + p.V2 / n2);
    return n * p.p1 * F / (Omega0 - s * F);
  }

  // p_1 [Pa]: the pressure the rod's seals carry.
  S pressure(const S& s, const S& F) const { return pressures(s, F).p1; }

  // E [J], without the atmosphere's share (the strut subtracts p_atm F s).
  S stored(const S& s, const S& F) const {
    using std::pow;
    if (twoStage) {
      const Pressures r = pressures(s, F);
      if (r.engaged) return gasEnergy(p01, Omega0, r.p1, r.V1, n) + gasEnergy(p02, Omega02, r.p2, r.V2, n2);
    }
    if (isIsothermal(n)) return gasEnergy(p01, Omega0, S(0), Omega0 - s * F, n);
    return p01 * Omega0 / (n - S(1)) * (pow(S(1) - s * F / Omega0, S(1) - n) - S(1));
  }
};

}  // namespace lg
