// Oleo-pneumatic shock absorber (three chambers), acting along the line between a point B of the rod
// (body i) and a point C of the cylinder (body j) (method.md):
//
//   s     = L0 - |B - C|              stroke, positive in compression      [m]
//   sdot  = -e . (u_B - u_C),  e = (B - C)/|B - C|                          [m/s]
//   p_1   = p_01 / (1 - s F / Omega_0)^n                                    [Pa]
//           (or the two-stage gas spring's common pressure: gas_spring.hpp, when the scene declares p02)
//   P_a   = (p_1 - p_atm) F                          gas (p_atm = 0 as in the article)
//         + P_f                                      Coulomb friction, bounded by the gas force:
//                                                     F_max = mu (p_1 - p_atm) F (the seals carry p_1 - p_atm)
//         + xi_1 rho F^3   sdot|sdot| / (2 f_1^2)    main orifice (f_1 constant or f_1(s) table: C1
//                                                     Catmull-Rom through the samples f1_table[k])
//         + xi_2 rho F_2^3 sdot|sdot| / (2 f_2^2)    rebound orifice (only if the scene declares f_2; with
//                                                    f2_direction "extension" or "compression" a one-way
//                                                    orifice: 0 in the other direction, C1 at sdot = 0 too)
// Orifices by direction (a check valve; only if the scene declares an extension key): in extension
// (sdot < 0; on a Coulomb slip segment its direction sigma < 0) the orifices take their own areas and
// loss coefficients, f_1e (constant or a table f_1e(s)), xi_1e, f_2e, xi_2e (each defaulting to the
// compression one's):
//         + xi_1e rho F^3   sdot|sdot| / (2 f_1e^2) + xi_2e rho F_2^3 sdot|sdot| / (2 f_2e^2)
// Both sides vanish with their slope at sdot = 0, so the force stays C1 there (no event); without the
// keys the law and its bits are the two-orifice law's above.
// Friction, two laws (the scene's choice):
//   coulomb      exact stick/slip (friction_lock.hpp): P_f = sigma F_max while slipping in the direction
//                sigma; while stuck, the lock row's reaction (|P_f| <= F_max). Over a slip segment the
//                orifice terms use the segment's sign too, sigma sdot^2, so that the force is smooth
//                until the rate stops (an event).
//   regularised  P_f = F_max sgn_eps(sdot), sgn_eps(v) = v / sqrt(v^2 + eps^2), eps = frictionVelocity.
//   F = pi D^2/4,  F_2 = pi (D_2^2 - D^2)/4
// P_a > 0 pushes B away from C: +P_a e on the rod at B, -P_a e on the cylinder at C.
//
// Two-stage gas spring (only if the scene declares p02, Omega02): a second chamber behind a floating
// piston takes over once p_1 reaches p_02, at the stroke s* (gas_spring.hpp, its equations); one event
// function, s - s*, stops the integrator on the kink in the force's slope there. Output p_2 [Pa].
//
// Energy: stored (gas)  p_01 Omega_0/(n-1) ((1 - s F/Omega_0)^(1-n) - 1) - p_atm F s
//                       (two stages: sum_i (p_i V_i - p_i0 Omega_i0)/(n_i - 1) - p_atm F s once engaged)
//         dissipated    integral of (friction + orifice forces) * sdot dt  (>= 0)
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "sim/core/body.hpp"
#include "sim/forces/friction_lock.hpp"
#include "sim/forces/gas_spring.hpp"
#include "sim/forces/table1d.hpp"

namespace lg {

template <class S> struct ShockAbsorber {
  static constexpr int kDissipation = 1;
  static constexpr int kDamping = 1;
  int bi = kGround;  // rod
  int bj = kGround;  // cylinder
  Vec3<S> rho_i;     // [m] B in the rod frame
  Vec3<S> rho_j;     // [m] C in the cylinder frame
  S L0;              // [m] extended length |B - C| at s = 0
  S D;               // [m] rod (plunger) diameter
  S D2;              // [m] bore of the annular chamber 3
  S p01;             // [Pa] initial gas pressure
  S Omega0;          // [m^3] initial gas volume
  S n;               // [-] polytropic exponent
  S rho;             // [kg/m^3] fluid density
  S f1;              // [m^2] main orifice area (when no table)
  S f2;              // [m^2] rebound orifice area (when declared)
  S xi1, xi2;        // [-] loss coefficients
  S mu;              // [-] friction coefficient
  S pAtm;            // [Pa] atmospheric pressure (0: off)
  double frictionVelocity = 1e-3;      // [m/s] eps of sgn_eps (regularised friction)
  std::shared_ptr<const Table1D> f1Table;  // [m -> m^2] metering pin f_1(s), or null: its stroke grid
  std::vector<S> f1Values;                 // [m^2] the table's areas (design parameters "f1_table[k]")
  bool reboundOrifice = false;             // the scene declares f2: the rebound-orifice term exists
  bool coulomb = false;                    // exact stick/slip friction (else regularised)
  int lockRow = -1;                        // its friction-lock row (set by Model::finalize)
  bool checkValve = false;                 // the scene declares an extension orifice law
  // Which extension values the scene gives (the others are the compression ones, design moves included).
  bool ownF1e = false, ownXi1e = false, ownF2e = false, ownXi2e = false;
  S f1e = S(0), xi1e = S(0);               // [m^2], [-] main orifice in extension (f1e when no table)
  S f2e = S(0), xi2e = S(0);               // [m^2], [-] rebound orifice in extension
  std::shared_ptr<const Table1D> f1eTable;  // [m -> m^2] f_1e(s), or null
  std::vector<S> f1eValues;                 // [m^2] its areas
  // Two-stage gas spring (gas_spring.hpp): the scene declares p02 and Omega02 (n2 defaults to n).
  bool twoStage = false;
  S p02 = S(0);       // [Pa] second chamber's precharge (> p01)
  S Omega02 = S(0);   // [m^3] second chamber's volume, the floating piston on its stop
  S n2 = S(0);        // [-] second chamber's polytropic exponent
  int f2Direction = 0;  // the rebound orifice acts in: 0 both directions, 1 compression only, -1 extension only

  int eventCount() const { return twoStage ? 1 : 0; }  // s - s*: what a single stage does not declare costs nothing
  GasSpring<S> gasSpring() const { return {p01, Omega0, n, twoStage, p02, Omega02, n2}; }

  bool declaresReboundOrifice() const { return reboundOrifice; }

  struct Eval {
    Vec3<S> a_i, a_j, e;
    S s, sdot, gas, friction, orifice1, orifice2;
    typename GasSpring<S>::Pressures pressures;  // p_1, p_2 (and the volumes once engaged)
    int sigma = 0;  // the slip direction of a Coulomb segment (0: stuck, held, or regularised)
    S force() const { return gas + friction + orifice1 + orifice2; }
  };

  S area() const { return S(M_PI) * D * D / S(4); }
  S annularArea() const { return S(M_PI) * (D2 * D2 - D * D) / S(4); }
  S mainOrifice(const S& s) const { return f1Table ? interpolate(*f1Table, f1Values, s) : f1; }
  S mainOrificeExtension(const S& s) const {
    if (!ownF1e) return mainOrifice(s);
    return f1eTable ? interpolate(*f1eTable, f1eValues, s) : f1e;
  }
  S xi1Extension() const { return ownXi1e ? xi1e : xi1; }
  S f2Extension() const { return ownF2e ? f2e : f2; }
  S xi2Extension() const { return ownXi2e ? xi2e : xi2; }
  // The check valve's side: extension (the direction of a Coulomb slip segment, else the sign of sdot).
  bool extending(const Eval& r) const { return checkValve && (r.sigma != 0 ? r.sigma < 0 : value(r.sdot) < 0.0); }
  // The rebound orifice acts in this direction (declared: f2Direction; the direction as extending()'s).
  bool reboundActs(const Eval& r) const {
    if (!reboundOrifice) return false;
    if (f2Direction == 0) return true;
    const bool out = r.sigma != 0 ? r.sigma < 0 : value(r.sdot) < 0.0;
    return out == (f2Direction < 0);
  }

  Eval eval(const Kins<S>& K) const {
    Eval r;
    r.a_i = K[bi].R * rho_i;
    r.a_j = K[bj].R * rho_j;
    const Vec3<S> d = (K[bi].r + r.a_i) - (K[bj].r + r.a_j);
    const S L = d.norm();
    r.e = d / L;
    r.s = L0 - L;
    r.sdot = -r.e.dot(K[bi].pointVelocity(r.a_i) - K[bj].pointVelocity(r.a_j));
    const S F = area();
    r.pressures = gasSpring().pressures(r.s, F);
    r.gas = (r.pressures.p1 - pAtm) * F;
    r.sigma = coulomb ? K.slipOf(lockRow) : 0;
    if (coulomb) r.friction = S(r.sigma) * mu * r.gas;  // 0 when stuck (the lock reacts) or held
    else r.friction = mu * r.gas * smoothSign(r.sdot, frictionVelocity);
    const S sq = r.sigma != 0 ? S(r.sigma) * r.sdot * r.sdot : signedSquare(r.sdot);
    if (extending(r)) {  // the check valve's extension law
      const S fe = mainOrificeExtension(r.s);
      r.orifice1 = xi1Extension() * rho * F * F * F * sq / (S(2) * fe * fe);
      r.orifice2 = S(0);
      if (reboundActs(r)) {
        const S F2 = annularArea(), a2 = f2Extension();
        r.orifice2 = xi2Extension() * rho * F2 * F2 * F2 * sq / (S(2) * a2 * a2);
      }
      return r;
    }
    const S fa = mainOrifice(r.s);
    r.orifice1 = xi1 * rho * F * F * F * sq / (S(2) * fa * fa);
    r.orifice2 = S(0);
    if (reboundActs(r)) {  // declared by the scene (and, one-way, the direction of the rate)
      const S F2 = annularArea();
      r.orifice2 = xi2 * rho * F2 * F2 * F2 * sq / (S(2) * f2 * f2);
    }
    return r;
  }
  // Exact friction: the lock row, the friction bound F_max, and the lock's reaction as a force P_f.
  FrictionLockInfo frictionLock() const { return {coulomb, bi, bj}; }
  void writeLock(const Kins<S>& K, Row<S>& row) const {
    writeAxialLock(K[bi], Vec3<S>(K[bi].R * rho_i), K[bj], Vec3<S>(K[bj].R * rho_j), row);
  }
  S frictionBound(const Kins<S>& K) const {
    const Vec3<S> d = (K[bi].r + K[bi].R * rho_i) - (K[bj].r + K[bj].R * rho_j);
    const S s = L0 - d.norm();
    return mu * (gasSpring().pressure(s, area()) - pAtm) * area();
  }
  S lockForce(const Kins<S>& K) const { return coulomb ? -K.lambdaOf(lockRow) : S(0); }
  void apply(const Kins<S>& K, const Wrenches<S>& W, S* dissipation) const {
    const Eval r = eval(K);
    const S P = r.force();
    W.addAt(bi, r.a_i, P * r.e);
    W.addAt(bj, r.a_j, -P * r.e);
    dissipation[0] = (r.friction + r.orifice1 + r.orifice2) * r.sdot;
  }
  S stored(const Kins<S>& K) const {
    const Eval r = eval(K);
    const S F = area();
    return gasSpring().stored(r.s, F) - pAtm * F * r.s;
  }
  void events(const Kins<S>& K, S* g) const {
    if (!twoStage) return;
    const Vec3<S> d = (K[bi].r + K[bi].R * rho_i) - (K[bj].r + K[bj].R * rho_j);
    g[0] = (L0 - d.norm()) - gasSpring().engagementStroke(area());
  }
  // sdot = G V along the strut axis (DampingTerm::setAxial); c = dP_a/dsdot =
  // mu (p_1 - p_atm) F eps^2 / (sdot^2 + eps^2)^(3/2) (regularised friction only) + 2 (k_1 + k_2) |sdot|
  // (on a Coulomb slip segment 2 (k_1 + k_2) sigma sdot, the derivative of its continued law);
  // k = dP_a/ds = F dp_1/ds (1 + mu sign) through the gas and the friction it loads (sign: sigma on a
  // Coulomb slip segment, 0 stuck; the regularised sign), the metering pin's dependence on s left out.
  void damping(const Kins<S>& K, DampingTerm<S>* d) const {
    const Eval r = eval(K);
    const S F = area();
    const S frictionShare = coulomb ? S(r.sigma) * mu : mu * smoothSign(r.sdot, frictionVelocity);
    const S k = F * gasSpring().pressureRate(r.s, F, r.pressures) * (S(1) + frictionShare);
    const S v2 = r.sdot * r.sdot, e2 = S(frictionVelocity * frictionVelocity);
    const S q = v2 + e2;
    S c = coulomb ? S(0) : mu * (r.pressures.p1 - pAtm) * F * e2 / (q * sqrt(q));
    const bool ext = extending(r);
    const S fa = ext ? mainOrificeExtension(r.s) : mainOrifice(r.s);
    const S speed = r.sigma != 0 ? S(r.sigma) * r.sdot : magnitude(r.sdot);
    c += (ext ? xi1Extension() : xi1) * rho * F * F * F * speed / (fa * fa);
    if (reboundActs(r)) {
      const S F2 = annularArea();
      const S a2 = ext ? f2Extension() : f2;
      c += (ext ? xi2Extension() : xi2) * rho * F2 * F2 * F2 * speed / (a2 * a2);
    }
    d->setAxial(bi, bj, r.e, r.a_i, r.a_j, c, k);
  }
  std::vector<std::string> outputNames() const {
    std::vector<std::string> names{"s", "s_dot", "p_1", "P_a", "P_gas", "P_friction", "P_orifice1"};
    if (reboundOrifice) names.push_back("P_orifice2");
    if (twoStage) names.push_back("p_2");
    return names;
  }
  void outputs(const Kins<S>& K, S* out) const {
    const Eval r = eval(K);
    const S lock = lockForce(K);  // a stuck Coulomb friction (the lock's reaction from the last solve)
    out[0] = r.s;
    out[1] = r.sdot;
    out[2] = r.pressures.p1;
    out[3] = r.force() + lock;
    out[4] = r.gas;
    out[5] = r.friction + lock;
    out[6] = r.orifice1;
    if (reboundOrifice) out[7] = r.orifice2;
    if (twoStage) out[reboundOrifice ? 8 : 7] = r.pressures.p2;
  }
  // "<table>[k]": sample k (from 0) of a table's areas, or nullptr.
  static S* tableSample(const std::string& key, const std::string& table, std::vector<S>& values) {
    if (key.size() < table.size() + 3 || key.compare(0, table.size() + 1, table + "[") != 0 || key.back() != ']')
      return nullptr;
    const std::string digits = key.substr(table.size() + 1, key.size() - table.size() - 2);
    if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) return nullptr;
    const size_t k = std::stoul(digits);
    return k < values.size() ? &values[k] : nullptr;
  }
  // The scalar a scene key names, as a design parameter (nullptr: none; friction_velocity and the tables'
  // stroke grids are not design parameters; their areas are, sample by sample: "f1_table[k]",
  // "f1_extension_table[k]").
  S* parameter(const std::string& key) {
    if (key == "L0") return &L0;
    if (key == "D") return &D;
    if (key == "D2") return &D2;
    if (key == "p01") return &p01;
    if (key == "Omega0") return &Omega0;
    if (key == "n") return &n;
    if (key == "rho") return &rho;
    if (key == "f1") return f1Table ? nullptr : &f1;
    if (f1Table)
      if (S* v = tableSample(key, "f1_table", f1Values)) return v;
    if (f1eTable)
      if (S* v = tableSample(key, "f1_extension_table", f1eValues)) return v;
    if (key == "f2") return reboundOrifice ? &f2 : nullptr;
    if (key == "xi1") return &xi1;
    if (key == "xi2") return &xi2;
    if (key == "mu") return &mu;
    if (key == "p_atm") return &pAtm;
    if (key == "f1_extension") return ownF1e && !f1eTable ? &f1e : nullptr;
    if (key == "xi1_extension") return ownXi1e ? &xi1e : nullptr;
    if (key == "f2_extension") return ownF2e ? &f2e : nullptr;
    if (key == "xi2_extension") return ownXi2e ? &xi2e : nullptr;
    if (key == "p02") return twoStage ? &p02 : nullptr;
    if (key == "Omega02") return twoStage ? &Omega02 : nullptr;
    if (key == "n2") return twoStage ? &n2 : nullptr;
    return nullptr;
  }
  template <class T> ShockAbsorber<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), T(L0), T(D), T(D2), T(p01), T(Omega0), T(n), T(rho),
            T(f1), T(f2), T(xi1), T(xi2), T(mu), T(pAtm), frictionVelocity, f1Table,
            std::vector<T>(f1Values.begin(), f1Values.end()), reboundOrifice, coulomb, lockRow, checkValve, ownF1e, ownXi1e, ownF2e, ownXi2e, T(f1e), T(xi1e),
            T(f2e), T(xi2e), f1eTable, std::vector<T>(f1eValues.begin(), f1eValues.end()), twoStage, T(p02), T(Omega02),
            T(n2), f2Direction};
  }
};

}  // namespace lg
