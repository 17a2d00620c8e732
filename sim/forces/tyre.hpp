// Tyre against a ground plane (method.md), with the options of a tyre from data:
//
//   delta  = R_w - (n . p - h0)        compression, positive when pressed into the ground (p: axle centre)
//   delta' = -n . u_p                  its rate (u_p: velocity of the wheel point)
//   vertical load of the carcass, one law (the scene's `law`):
//     polynomial  P_s = K delta (1 + alpha (delta/delta_max)^2)          method.md (the default)
//     power       P_s = K delta_max (delta/delta_max)^m,  m >= 1        K: secant stiffness at delta_max
//     table       P_s = the C1 curve through the samples (delta, P) of a CSV file, from (0, 0) on
//                 (curve_table.hpp: cubic Hermite, linear beyond the last sample)
//   damping (optional)  P_d = c_d(delta) delta', its coefficient one law (the scene's `damping_law`):
//     power       c_d = c (delta/delta_max)^q                          q = 0: viscous; q > 0: it grows
//                                                                      with the footprint (0 at contact)
//     stiffness   c_d = 2 zeta sqrt(k_t(delta) m),  k_t = dP_s/ddelta    a damping ratio zeta of the tyre's
//                                                                      own stiffness with the mass m on it
//     and its direction (`damping_direction`): both, or compression only: P_d = c_d max(delta', 0)
//   P_t = max(P_s + P_d, 0) for delta > 0, 0 otherwise                   the tyre never pulls
// applied along the ground normal n at p.
//   stored energy  E_s = integral from 0 to delta of P_s:  K (delta^2/2 + alpha delta^4 / (4 delta_max^2)),
//                  K delta_max^2 (delta/delta_max)^(m+1) / (m+1), or the curve's exact antiderivative
//   dissipation rate (P_t - P_s) delta' >= 0: c (delta/delta_max)^q delta'^2 while P_s + P_d > 0, and
//                  -P_s delta' (delta' < 0) while the damping would make the tyre pull (P_t = 0)
//
// Longitudinal force (optional, mu_x > 0: wheel spin-up and spring-back). The gear stands on the drop
// rig; the aircraft's forward speed V_x is the ground moving at -V_x t under it (t: the unit forward
// direction, in the ground plane; V_x per drop case). At the contact point c = p - (n . p - h0) n of the
// wheel (its material point there, lever arm a_c = c - r_wheel):
//   v_s  = t . (u_c - v_ground) = t . (v + w x a_c) + V_x            slip velocity (> 0: the tyre slides
//                                                                      forward over the ground)
//   P_x  = mu_x P_t v_s / sqrt(v_s^2 + eps^2),  eps = kappa_0 max(V_x, 1 m/s)
//   force -P_x t on the wheel at c                                     P_x: the drag load, positive aft
// The regularisation is one of slip ratio: the friction reaches 71 % of mu_x P_t at a slip ratio
// v_s / V_x = kappa_0 (`slip_ratio`, default 0.05, a tyre's longitudinal slip stiffness mu_x P_t / kappa_0),
// and Coulomb's law as kappa_0 -> 0. The wheel's spin is the wheel body's own rotation (its revolute
// hinge): spin-up is the friction's moment a_c x (-P_x t) on it.
//   dissipation rate  P_x v_s >= 0 (the slip); and the moving ground's work on the tyre, rate
//   -P_x V_x (its own channel: energy put in, booked with a minus sign so that the balance closes)
//
// Events: contact start and end (delta crossing 0); with damping, P_s + P_d crossing 0 (the clamp); with
// compression-only damping, delta' crossing 0 (its kink: the largest deflection).
// Outputs: delta, P_t, their rates delta' and P_t' = dP_s/ddelta delta' (0 out of contact; with damping
// the rate of the elastic part and of the power law's coefficient only, the term c delta'' needs the
// wheel's acceleration: the drop-test observer takes a damped tyre's load rate on the dense output), and
// with a longitudinal force P_x and v_s.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "sim/core/body.hpp"
#include "sim/forces/curve_table.hpp"

namespace lg {

enum class TyreLaw { Polynomial, Power, Table };

// The tyre damping coefficient's law.
enum class TyreDampingLaw { Power, Stiffness };

template <class S> struct Tyre {
  int body = kGround;
  Vec3<S> rho;        // [m] wheel centre in the body frame
  Vec3<S> normal;     // [-] ground normal, world (unit)
  S groundHeight;     // [m] h0: the ground plane is n . x = h0
  S radius;           // [m] R_w
  S K;                // [N/m] stiffness (polynomial: initial; power: secant at delta_max)
  S deltaMax;         // [m] largest allowed deflection
  S alpha;            // [-] non-linearity (polynomial)
  TyreLaw law = TyreLaw::Polynomial;
  S exponent = S(1);                         // [-] m (power)
  std::shared_ptr<const CurveTable> curve;   // [m -> N] P_s(delta) (table)
  bool damped = false;                       // the scene declares c
  S c = S(0);                                // [N s/m] damping coefficient
  S dampingExponent = S(0);                  // [-] q
  TyreDampingLaw dampingLaw = TyreDampingLaw::Power;
  S dampingRatio = S(0);                     // [-] zeta (stiffness law)
  S dampingMass = S(0);                      // [kg] m (stiffness law)
  bool compressionOnly = false;              // damping_direction = "compression"
  bool longitudinal = false;                 // the scene declares mu_x
  S muX = S(0);                              // [-] longitudinal friction coefficient
  S slipRatio = S(0.05);                     // [-] kappa_0
  Vec3<S> forward = Vec3<S>(S(1), S(0), S(0));  // [-] t, world, in the ground plane (unit)
  S groundSpeed = S(0);                      // [m/s] V_x (the drop case's forward speed)

  int dissipationChannels() const { return (damped ? 1 : 0) + (longitudinal ? 2 : 0); }
  int dampingTerms() const { return 1 + (longitudinal ? 1 : 0); }  // the vertical term carries the stiffness
  int eventCount() const { return damped ? (compressionOnly ? 3 : 2) : 1; }
  int inputChannels() const { return longitudinal ? 1 : 0; }  // the ground's work (the last channel)
  // The dissipation of damping and slip has kinks (the clamp, the contact's end): the steps must resolve them.
  bool dissipationErrorControlled() const { return damped || longitudinal; }

  S deflection(const Kins<S>& K_) const {
    return radius - (normal.dot(K_[body].point(rho)) - groundHeight);
  }
  // P_s(delta): the carcass's elastic load, 0 for delta <= 0.
  S load(const S& delta) const {
    const S d = positivePart(delta);
    if (law == TyreLaw::Power) return isPositive(d) ? K * deltaMax * pow(d / deltaMax, exponent) : S(0);
    if (law == TyreLaw::Table) return isPositive(d) ? (*curve)(d) : S(0);
    const S x = d / deltaMax;
    return K * d * (S(1) + alpha * x * x);
  }
  // dP_s/ddelta for delta > 0 (0 otherwise).
  S stiffness(const S& delta) const {
    if (!isPositive(delta)) return S(0);
    if (law == TyreLaw::Power) return K * exponent * pow(delta / deltaMax, exponent - S(1));
    if (law == TyreLaw::Table) return curve->slope(delta);
    const S x = delta / deltaMax;
    return K * (S(1) + S(3) * alpha * x * x);
  }
  // c_d(delta) for delta > 0 (its law).
  S dampingCoefficient(const S& delta) const {
    if (dampingLaw == TyreDampingLaw::Stiffness) return S(2) * dampingRatio * sqrt(stiffness(delta) * dampingMass);
    return c * pow(delta / deltaMax, dampingExponent);
  }
  // The rate the damping acts on: delta', or its positive part when it acts in compression only.
  S dampedRate(const S& rate) const { return compressionOnly ? positivePart(rate) : rate; }
  // P_d(delta, delta'), 0 off the ground.
  S dampingForce(const S& delta, const S& rate) const {
    return isPositive(delta) ? dampingCoefficient(delta) * dampedRate(rate) : S(0);
  }

  // Everything at one instant (the options' parts only where declared).
  struct Contact {
    Vec3<S> arm, armContact;
    S delta, rate, Ps, P, Px, vSlip;
  };
  Contact contact(const Kins<S>& K_) const {
    const BodyKin<S>& b = K_[body];
    Contact r;
    r.arm = b.R * rho;
    const S height = normal.dot(b.r + r.arm) - groundHeight;
    r.delta = radius - height;
    r.rate = -normal.dot(b.pointVelocity(r.arm));
    r.Ps = load(r.delta);
    r.P = damped ? positivePart(r.Ps + dampingForce(r.delta, r.rate)) : r.Ps;
    r.Px = r.vSlip = S(0);
    if (longitudinal) {
      r.armContact = r.arm - height * normal;
      r.vSlip = forward.dot(b.pointVelocity(r.armContact)) + groundSpeed;
      r.Px = muX * r.P * r.vSlip / sqrt(r.vSlip * r.vSlip + slipVelocity() * slipVelocity());
    }
    return r;
  }
  // [m/s] eps = kappa_0 max(V_x, 1 m/s)
  S slipVelocity() const { return slipRatio * (value(groundSpeed) > 1.0 ? groundSpeed : S(1)); }

  void apply(const Kins<S>& K_, const Wrenches<S>& W, S* dissipation) const {
    if (!damped && !longitudinal) {  // method.md's tyre
      const S P = load(deflection(K_));
      W.addAt(body, K_[body].R * rho, P * normal);
      return;
    }
    const Contact r = contact(K_);
    W.addAt(body, r.arm, r.P * normal);
    int ch = 0;
    if (damped) dissipation[ch++] = (r.P - r.Ps) * r.rate;
    if (longitudinal) {
      W.addAt(body, r.armContact, -r.Px * forward);
      dissipation[ch++] = r.Px * r.vSlip;
      dissipation[ch++] = -r.Px * groundSpeed;
    }
  }
  S stored(const Kins<S>& K_) const {
    const S d = positivePart(deflection(K_));
    if (law == TyreLaw::Power)
      return isPositive(d) ? K * deltaMax * deltaMax * pow(d / deltaMax, exponent + S(1)) / (exponent + S(1)) : S(0);
    if (law == TyreLaw::Table) return isPositive(d) ? curve->integral(d) : S(0);
    return K * (d * d / S(2) + alpha * d * d * d * d / (S(4) * deltaMax * deltaMax));
  }
  void events(const Kins<S>& K_, S* g) const {
    if (!damped) {
      g[0] = deflection(K_);
      return;
    }
    const Contact r = contact(K_);
    g[0] = r.delta;
    // P_s + P_d, continued off the ground by its limit at contact, c_d(0+) delta' (continuous there).
    const S atContact = dampingCoefficient(S(std::numeric_limits<double>::min()));
    g[1] = isPositive(r.delta) ? r.Ps + dampingForce(r.delta, r.rate) : atContact * dampedRate(r.rate);
    if (compressionOnly) g[2] = r.rate;
  }
  // delta' = G V with G = -(n, a x n) on the wheel (DampingTerm::setAxial with e = n against the ground):
  // k = dP_s/ddelta and, if damped, c_d = c (delta/delta_max)^q while the tyre is loaded (and unclamped),
  // both 0 off the ground. v_s = G V with G = (t, a_c x t): c_x = dP_x/dv_s = mu_x P_t eps^2 / (v_s^2 + eps^2)^(3/2).
  void damping(const Kins<S>& K_, DampingTerm<S>* d) const {
    const Contact r = contact(K_);
    const bool on = isPositive(r.delta) && isPositive(r.P);
    d[0].setAxial(body, kGround, normal, r.arm, Vec3<S>::Zero(),
                  on && damped && (!compressionOnly || isPositive(r.rate)) ? dampingCoefficient(r.delta) : S(0),
                  on ? stiffness(r.delta) : S(0));
    if (longitudinal) {
      const S e2 = slipVelocity() * slipVelocity(), q = r.vSlip * r.vSlip + e2;
      d[1].setAxial(body, kGround, Vec3<S>(-forward), r.armContact, Vec3<S>::Zero(), muX * r.P * e2 / (q * sqrt(q)));
    }
  }
  std::vector<std::string> outputNames() const {
    std::vector<std::string> names{"delta", "P_t", "delta_dot", "P_t_dot"};
    if (longitudinal) {
      names.push_back("P_x");
      names.push_back("v_slip");
    }
    return names;
  }
  void outputs(const Kins<S>& K_, S* out) const {
    if (!damped && !longitudinal) {
      const BodyKin<S>& b = K_[body];
      out[0] = deflection(K_);
      out[1] = load(out[0]);
      out[2] = -normal.dot(b.pointVelocity(b.R * rho));
      out[3] = isPositive(out[0]) ? stiffness(out[0]) * out[2] : S(0);
      return;
    }
    const Contact r = contact(K_);
    out[0] = r.delta;
    out[1] = r.P;
    out[2] = r.rate;
    out[3] = isPositive(r.P) ? stiffness(r.delta) * r.rate : S(0);
    if (damped && dampingLaw == TyreDampingLaw::Power && isPositive(r.P) && value(dampingExponent) != 0.0)
      out[3] += c * dampingExponent * pow(r.delta / deltaMax, dampingExponent - S(1)) / deltaMax * r.rate * dampedRate(r.rate);
    if (longitudinal) {
      out[4] = r.Px;
      out[5] = r.vSlip;
    }
  }
  // The scalar a scene key names, as a design parameter (nullptr: none, or not this tyre's law).
  S* parameter(const std::string& key) {
    if (key == "radius") return &radius;
    if (key == "K") return law != TyreLaw::Table ? &K : nullptr;
    if (key == "delta_max") return &deltaMax;
    if (key == "alpha") return law == TyreLaw::Polynomial ? &alpha : nullptr;
    if (key == "exponent") return law == TyreLaw::Power ? &exponent : nullptr;
    if (key == "ground_height") return &groundHeight;
    const bool power = damped && dampingLaw == TyreDampingLaw::Power, stiff = damped && dampingLaw == TyreDampingLaw::Stiffness;
    if (key == "c") return power ? &c : nullptr;
    if (key == "damping_exponent") return power ? &dampingExponent : nullptr;
    if (key == "damping_ratio") return stiff ? &dampingRatio : nullptr;
    if (key == "damping_mass") return stiff ? &dampingMass : nullptr;
    if (key == "mu_x") return longitudinal ? &muX : nullptr;
    if (key == "slip_ratio") return longitudinal ? &slipRatio : nullptr;
    return nullptr;
  }
  template <class T> Tyre<T> cast() const {
    return {body,      castVec<T>(rho), castVec<T>(normal), T(groundHeight), T(radius),
            T(K),      T(deltaMax),     T(alpha),           law,             T(exponent),
            curve,     damped,          T(c),               T(dampingExponent), dampingLaw,
            T(dampingRatio), T(dampingMass), compressionOnly, longitudinal,
            T(muX),    T(slipRatio),    castVec<T>(forward), T(groundSpeed)};
  }
};

}  // namespace lg
