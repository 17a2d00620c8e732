// A constant force at the centre of mass of one body: the lift P_H on the airframe.
// Stored energy (potential of a constant force) U = -F . r.
// For a lift element, F = liftRatio * G * |g| along 'direction', with G the total mass of the
// scene; the drop case sets liftRatio (see sim/drop/run.hpp, applyCase).
#pragma once

#include <string>
#include <vector>

#include "sim/core/body.hpp"

namespace lg {

template <class S> struct ConstantForce {
  static constexpr int kDissipation = 0;
  static constexpr int kDamping = 0;
  static constexpr int kEvents = 0;
  int body = kGround;
  Vec3<S> force;  // [N] world

  void apply(const Kins<S>& /*K*/, const Wrenches<S>& W, S*) const { W.addForce(body, force); }
  S stored(const Kins<S>& K) const { return -force.dot(K[body].r); }
  void events(const Kins<S>&, S*) const {}
  void damping(const Kins<S>&, DampingTerm<S>*) const {}
  static std::vector<std::string> outputNames() { return {}; }
  void outputs(const Kins<S>&, S*) const {}
  S* parameter(const std::string&) { return nullptr; }  // vectors only: no scalar design parameter
  template <class T> ConstantForce<T> cast() const { return {body, castVec<T>(force)}; }
};

}  // namespace lg
