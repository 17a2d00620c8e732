// A linear spring-damper between a point of body i and a point of body j.
//   L = |p_j - p_i|, e = (p_j - p_i)/L, Ldot = e.(u_j - u_i)
//   tension T = k (L - L0) + c Ldot;  force +T e on body i at p_i, -T e on body j at p_j
//   stored k (L - L0)^2 / 2, dissipation rate c Ldot^2.
#pragma once

#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct SpringDamper {
  static constexpr int kDissipation = 1;
  static constexpr int kDamping = 1;
  static constexpr int kEvents = 0;
  int bi = kGround, bj = kGround;
  Vec3<S> rho_i, rho_j;  // [m] attachment points in the bodies
  S k;                   // [N/m] stiffness
  S c;                   // [N s/m] damping
  S L0;                  // [m] free length

  struct Eval { Vec3<S> a_i, a_j, e; S L, Ldot; };
  Eval eval(const Kins<S>& K) const {
    Eval r;
    r.a_i = K[bi].R * rho_i;
    r.a_j = K[bj].R * rho_j;
    const Vec3<S> d = (K[bj].r + r.a_j) - (K[bi].r + r.a_i);
    r.L = d.norm();
    r.e = d / r.L;
    r.Ldot = r.e.dot(K[bj].pointVelocity(r.a_j) - K[bi].pointVelocity(r.a_i));
    return r;
  }
  void apply(const Kins<S>& K, const Wrenches<S>& W, S* dissipation) const {
    const Eval r = eval(K);
    const S T = k * (r.L - L0) + c * r.Ldot;
    W.addAt(bi, r.a_i, T * r.e);
    W.addAt(bj, r.a_j, -T * r.e);
    dissipation[0] = c * r.Ldot * r.Ldot;
  }
  S stored(const Kins<S>& K) const {
    const S x = eval(K).L - L0;
    return k * x * x / S(2);
  }
  void events(const Kins<S>&, S*) const {}
  // Ldot = G V along the spring's axis (DampingTerm::setAxial); dT/dLdot = c, dT/dL = k.
  void damping(const Kins<S>& K, DampingTerm<S>* d) const {
    const Eval r = eval(K);
    d->setAxial(bi, bj, r.e, r.a_i, r.a_j, c, k);
  }
  static std::vector<std::string> outputNames() { return {"L", "tension"}; }
  void outputs(const Kins<S>& K, S* out) const {
    const Eval r = eval(K);
    out[0] = r.L;
    out[1] = k * (r.L - L0) + c * r.Ldot;
  }
  // The scalar a scene key names, as a design parameter (nullptr: none).
  S* parameter(const std::string& key) {
    if (key == "k") return &k;
    if (key == "c") return &c;
    if (key == "L0") return &L0;
    return nullptr;
  }
  template <class T> SpringDamper<T> cast() const {
    return {bi, bj, castVec<T>(rho_i), castVec<T>(rho_j), T(k), T(c), T(L0)};
  }
};

}  // namespace lg
