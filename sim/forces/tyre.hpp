// Tyre against a ground plane (method.md):
//   delta = R_w - (n . p - h0)         compression, positive when pressed into the ground
//   P_t   = K delta (1 + alpha (delta/delta_max)^2)   for delta > 0, 0 otherwise (never pulls)
// applied along the ground normal n at the wheel point p (the axle centre).
//   stored energy  K (delta^2/2 + alpha delta^4 / (4 delta_max^2))  for delta > 0.
// Contact start and end (delta crossing 0) is an event: P_t has a kink there.
// Outputs: delta, P_t, their rates delta' = -n . v_p and P_t' = K (1 + 3 alpha (delta/delta_max)^2) delta'
// (0 out of contact): the drop-test observer locates the peaks of P_y and delta where the rates change sign.
#pragma once

#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct Tyre {
  static constexpr int kDissipation = 0;
  static constexpr int kDamping = 0;
  static constexpr int kEvents = 1;
  int body = kGround;
  Vec3<S> rho;        // [m] wheel centre in the body frame
  Vec3<S> normal;     // [-] ground normal, world (unit)
  S groundHeight;     // [m] h0: the ground plane is n . x = h0
  S radius;           // [m] R_w
  S K;                // [N/m] stiffness
  S deltaMax;         // [m] largest allowed deflection
  S alpha;            // [-] non-linearity

  S deflection(const Kins<S>& K_) const {
    return radius - (normal.dot(K_[body].point(rho)) - groundHeight);
  }
  S load(const S& delta) const {
    const S d = positivePart(delta);
    const S x = d / deltaMax;
    return K * d * (S(1) + alpha * x * x);
  }
  void apply(const Kins<S>& K_, const Wrenches<S>& W, S*) const {
    const S P = load(deflection(K_));
    W.addAt(body, K_[body].R * rho, P * normal);
  }
  S stored(const Kins<S>& K_) const {
    const S d = positivePart(deflection(K_));
    return K * (d * d / S(2) + alpha * d * d * d * d / (S(4) * deltaMax * deltaMax));
  }
  void events(const Kins<S>& K_, S* g) const { g[0] = deflection(K_); }
  void damping(const Kins<S>&, DampingTerm<S>*) const {}
  static std::vector<std::string> outputNames() { return {"delta", "P_t", "delta_dot", "P_t_dot"}; }
  void outputs(const Kins<S>& K_, S* out) const {
    const BodyKin<S>& b = K_[body];
    out[0] = deflection(K_);
    out[1] = load(out[0]);
    out[2] = -normal.dot(b.pointVelocity(b.R * rho));
    const S x = positivePart(out[0]) / deltaMax;
    out[3] = isPositive(out[0]) ? K * (S(1) + S(3) * alpha * x * x) * out[2] : S(0);
  }
  // The scalar a scene key names, as a design parameter (nullptr: none).
  S* parameter(const std::string& key) {
    if (key == "radius") return &radius;
    if (key == "K") return &K;
    if (key == "delta_max") return &deltaMax;
    if (key == "alpha") return &alpha;
    if (key == "ground_height") return &groundHeight;
    return nullptr;
  }
  template <class T> Tyre<T> cast() const {
    return {body, castVec<T>(rho), castVec<T>(normal), T(groundHeight), T(radius), T(K), T(deltaMax), T(alpha)};
  }
};

}  // namespace lg
