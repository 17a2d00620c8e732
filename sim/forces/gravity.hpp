// Gravity on every body: f_i = m_i g. Stored energy (potential) U = -sum m_i g . r_i.
#pragma once

#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct Gravity {
  static constexpr int kDissipation = 0;
  static constexpr int kDamping = 0;
  static constexpr int kEvents = 0;
  Vec3<S> g;  // [m/s^2] gravitational acceleration, world

  void apply(const Kins<S>& K, const Wrenches<S>& W, S* /*dissipation*/) const {
    for (int b = 0; b < K.n; ++b) W.addForce(b, K[b].mass * g);
  }
  S stored(const Kins<S>& K) const {
    S U(0);
    for (int b = 0; b < K.n; ++b) U -= K[b].mass * g.dot(K[b].r);
    return U;
  }
  void events(const Kins<S>&, S*) const {}
  void damping(const Kins<S>&, DampingTerm<S>*) const {}
  static std::vector<std::string> outputNames() { return {}; }
  void outputs(const Kins<S>&, S*) const {}
  S* parameter(const std::string&) { return nullptr; }  // vectors only: no scalar design parameter
  template <class T> Gravity<T> cast() const { return {castVec<T>(g)}; }
};

}  // namespace lg
