// An elastic extension stop (a [[stop]] with `stiffness`): a penalty pad that keeps a point of body i
// and a point of body j from moving much farther apart than L, as a real stop's rubber or spring pad
// does, where the rigid stop (sim/constraints/distance_stop.hpp) allows no overtravel at all.
//
//   d = p_j - p_i,  e = d/|d|,  x = |d| - L         overtravel, positive when the pad is pressed
//   x' = e.(u_j - u_i)                               its rate
//   F = max(k x + c x', 0) for x > 0, 0 otherwise    the pad never pulls the points apart
//   force +F e on body i at p_i, -F e on body j at p_j  (it draws the points together)
//   stored     k x^2 / 2 for x > 0
//   dissipation rate (F - k x) x' >= 0: c x'^2 while k x + c x' > 0, and -k x x' (x' < 0, the pad
//              springing back faster than its damping lets it push) while it would pull (F = 0)
// Events: x crossing 0 (contact, its end); with damping, k x + c x' crossing 0 (the clamp), continued
// by c x' where x <= 0 (continuous at contact).
// Outputs: F [N] and x [m] (the drop-test histories' F_<stop> and x_<stop>).
// At a drop's release the gear hangs on its pads at rest (sim/drop/hang.hpp): x = F/k with F the load the
// rigid stop would carry there.
#pragma once

#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct StopPad {
  static constexpr int kDamping = 1;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;  // [m] the two points, in their bodies
  S L;                   // [m] the distance at which the pad starts to act
  S k;                   // [N/m] its stiffness
  bool damped = false;   // the scene declares c
  S c = S(0);            // [N s/m] its damping

  int dissipationChannels() const { return damped ? 1 : 0; }
  int eventCount() const { return damped ? 2 : 1; }
  // The damping's dissipation has kinks of its own (the clamp, the contact's end).
  bool dissipationErrorControlled() const { return damped; }

  struct Eval { Vec3<S> a_i, a_j, e; S x, rate, F; };
  Eval eval(const Kins<S>& K) const {
    Eval r;
    r.a_i = K[bi].R * rho_i;
    r.a_j = K[bj].R * rho_j;
    const Vec3<S> d = (K[bj].r + r.a_j) - (K[bi].r + r.a_i);
    const S dist = d.norm();
    r.e = d / dist;
    r.x = dist - L;
    r.rate = r.e.dot(K[bj].pointVelocity(r.a_j) - K[bi].pointVelocity(r.a_i));
    r.F = isPositive(r.x) ? positivePart(damped ? k * r.x + c * r.rate : k * r.x) : S(0);
    return r;
  }
  void apply(const Kins<S>& K, const Wrenches<S>& W, S* dissipation) const {
    const Eval r = eval(K);
    W.addAt(bi, r.a_i, r.F * r.e);
    W.addAt(bj, r.a_j, -r.F * r.e);
    if (damped) dissipation[0] = isPositive(r.x) ? (r.F - k * r.x) * r.rate : S(0);
  }
  S stored(const Kins<S>& K) const {
    const S x = positivePart(eval(K).x);
    return k * x * x / S(2);
  }
  void events(const Kins<S>& K, S* g) const {
    const Eval r = eval(K);
    g[0] = r.x;
    if (damped) g[1] = isPositive(r.x) ? k * r.x + c * r.rate : c * r.rate;
  }
  // x' = G V along e (DampingTerm::setAxial): dF/dx' = c, dF/dx = k while the pad pushes, else 0.
  void damping(const Kins<S>& K, DampingTerm<S>* d) const {
    const Eval r = eval(K);
    const bool on = isPositive(r.F);
    d->setAxial(bi, bj, r.e, r.a_i, r.a_j, on && damped ? c : S(0), on ? k : S(0));
  }
  std::vector<std::string> outputNames() const { return {"F", "x"}; }
  std::string outputUnit(const std::string& name) const { return name == "F" ? "N" : "m"; }
  void outputs(const Kins<S>& K, S* out) const {
    const Eval r = eval(K);
    out[0] = r.F;
    out[1] = r.x;
  }
  // The scalar a scene key names, as a design parameter (nullptr: none).
  S* parameter(const std::string& key) {
    if (key == "max_distance") return &L;
    if (key == "stiffness") return &k;
    if (key == "damping" && damped) return &c;
    return nullptr;
  }
  template <class T> StopPad<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), T(L), T(k), damped, T(c)};
  }
};

}  // namespace lg
