// The closed set of force elements, dispatched with std::variant. Each returns its forces, the rate
// of the energy it dissipates, the energy it stores, event functions and named outputs, so that every
// run can close its energy balance. How many dissipation channels, damping terms and event functions an
// element has is its type's constant (kDissipation, kDamping, kEvents), or, for an element whose optional
// parts a scene may leave out (a tyre without damping has no damping channel), what its instance says
// (dissipationChannels(), dampingTerms(), eventCount()): what a scene does not declare costs nothing.
#pragma once

#include <concepts>
#include <string>
#include <type_traits>
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

// What the engine asks of every force element E in the scalar S, its equations in its own header:
//   apply(K, W, dissipation)  its forces and moments on the bodies (into W) and the rate [W] of each of its
//                             dissipation channels (dissipation[0 .. channels))
//   stored(K)                 the energy [J] it stores (springs, gas, the potential of gravity and lift)
//   events(K, out)            its event functions (stops engaging, damping letting go, slip reversing)
//   damping(K, terms)         its damping (and stiffness) terms for the linearly implicit integrators
//   outputs(K, out), outputNames()  its named outputs, columns of the time histories
//   parameter(key)            the place of a numeric design parameter ("f1", "K"), null for none
//   cast<double>()            the same element in another scalar (a model with derivatives)
// A type missing one does not compile, and the message names the requirement it misses.
template <class E, class S>
concept ForceElementType = requires(E& e, const E& ce, const Kins<S>& K, const Wrenches<S>& W, S* out,
                                    DampingTerm<S>* terms, const std::string& key) {
  ce.apply(K, W, out);
  { ce.stored(K) } -> std::convertible_to<S>;
  ce.events(K, out);
  ce.damping(K, terms);
  ce.outputs(K, out);
  { ce.outputNames() } -> std::convertible_to<std::vector<std::string>>;
  { e.parameter(key) } -> std::same_as<S*>;
  ce.template cast<double>();
};

template <class S>
using ForceType = std::variant<Gravity<S>, ConstantForce<S>, ShockAbsorber<S>, Tyre<S>, SpringDamper<S>,
                               Bushing<S>, BearingFriction<S>, StopPad<S>>;

// Every alternative of the closed set is a force element, in both scalars the engine runs.
template <class S, class V> struct AllForceElementTypes;
template <class S, class... E>
struct AllForceElementTypes<S, std::variant<E...>> : std::bool_constant<(ForceElementType<E, S> && ...)> {};
static_assert(AllForceElementTypes<double, ForceType<double>>::value,
              "an alternative of ForceType misses a member the engine needs (see ForceElementType)");

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
