// The closed set of force elements, dispatched with std::variant. Each returns its forces, the rate
// of the energy it dissipates, the energy it stores, event functions and named outputs, so that every
// run can close its energy balance.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "sim/forces/constant_force.hpp"
#include "sim/forces/gravity.hpp"
#include "sim/forces/shock_absorber.hpp"
#include "sim/forces/spring_damper.hpp"
#include "sim/forces/tyre.hpp"

namespace lg {

template <class S>
using ForceType = std::variant<Gravity<S>, ConstantForce<S>, ShockAbsorber<S>, Tyre<S>, SpringDamper<S>>;

template <class S> struct ForceElement {
  std::string name;
  ForceType<S> type;
  bool isLift = false;      // a ConstantForce whose magnitude the drop case sets (liftRatio * G * g)
  S liftRatio = S(0);       // for a lift element: the current ratio L

  int dissipationChannels() const { return std::visit([](const auto& f) { return f.kDissipation; }, type); }
  int dampingTerms() const { return std::visit([](const auto& f) { return f.kDamping; }, type); }
  int eventCount() const { return std::visit([](const auto& f) { return f.kEvents; }, type); }
  std::vector<std::string> outputNames() const {
    return std::visit([](const auto& f) { return f.outputNames(); }, type);
  }
  // Exact Coulomb friction (sim/forces/friction_lock.hpp): elements that have it declare a lock row.
  FrictionLockInfo frictionLock() const {
    return std::visit(
        [](const auto& f) -> FrictionLockInfo {
          if constexpr (requires { f.frictionLock(); }) return f.frictionLock();
          else return {};
        },
        type);
  }
  void setLockRow(int row) {
    std::visit([&](auto& f) { if constexpr (requires { f.lockRow; }) f.lockRow = row; }, type);
  }
  template <class T> ForceElement<T> cast() const {
    return {name, std::visit([](const auto& f) -> ForceType<T> { return f.template cast<T>(); }, type), isLift,
            T(liftRatio)};
  }
};

}  // namespace lg
