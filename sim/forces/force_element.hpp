// The closed set of force elements, dispatched with std::variant. Each returns its forces, the rate
// of the energy it dissipates, the energy it stores, event functions and named outputs, so that every
// run can close its energy balance. How many dissipation channels, damping terms and event functions an
// element has is its type's constant (kDissipation, kDamping, kEvents), or, for an element whose optional
// parts a scene may leave out (a tyre without damping has no damping channel), what its instance says
// (dissipationChannels(), dampingTerms(), eventCount()): what a scene does not declare costs nothing.
#pragma once

#include <string>
#include <variant>
#include <vector>

#include "sim/forces/bearing_friction.hpp"
#include "sim/forces/bushing.hpp"
#include "sim/forces/constant_force.hpp"
#include "sim/forces/gravity.hpp"
#include "sim/forces/shock_absorber.hpp"
#include "sim/forces/spring_damper.hpp"
#include "sim/forces/stop_pad.hpp"
#include "sim/forces/tyre.hpp"

namespace lg {

template <class S>
using ForceType = std::variant<Gravity<S>, ConstantForce<S>, ShockAbsorber<S>, Tyre<S>, SpringDamper<S>,
                               Bushing<S>, BearingFriction<S>, StopPad<S>>;

template <class S> struct ForceElement {
  std::string name;
  ForceType<S> type;
  bool isLift = false;      // a ConstantForce whose magnitude the drop case sets (liftRatio * G * g)
  S liftRatio = S(0);       // for a lift element: the current ratio L

  int dissipationChannels() const {
    return std::visit(
        [](const auto& f) {
          if constexpr (requires { f.dissipationChannels(); }) return f.dissipationChannels();
          else return f.kDissipation;
        },
        type);
  }
  int dampingTerms() const {
    return std::visit(
        [](const auto& f) {
          if constexpr (requires { f.dampingTerms(); }) return f.dampingTerms();
          else return f.kDamping;
        },
        type);
  }
  // Whether the integrators control the error of its dissipated energies like that of the positions and
  // velocities: an element whose dissipation rate has kinks of its own (a tyre's damping that lets go)
  // needs its steps to resolve them; the strut's and the spring-damper's are left out as they always were.
  bool dissipationErrorControlled() const {
    return std::visit(
        [](const auto& f) {
          if constexpr (requires { f.dissipationErrorControlled(); }) return f.dissipationErrorControlled();
          else return false;
        },
        type);
  }
  // Of its dissipation channels, how many (the last ones) hold the work that moving surroundings put in
  // (the ground under a rolling tyre), booked with a minus sign: the energy report keeps them apart.
  int inputChannels() const {
    return std::visit(
        [](const auto& f) {
          if constexpr (requires { f.inputChannels(); }) return f.inputChannels();
          else return 0;
        },
        type);
  }
  int eventCount() const {
    return std::visit(
        [](const auto& f) {
          if constexpr (requires { f.eventCount(); }) return f.eventCount();
          else return f.kEvents;
        },
        type);
  }
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
