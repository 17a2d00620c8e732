// The closed set of constraint types, dispatched with std::variant.
#pragma once

#include <string>
#include <variant>

#include "sim/constraints/distance_stop.hpp"
#include "sim/constraints/fixed.hpp"
#include "sim/constraints/point_on_plane.hpp"
#include "sim/constraints/prismatic.hpp"
#include "sim/constraints/revolute.hpp"
#include "sim/constraints/sliding.hpp"
#include "sim/constraints/spherical.hpp"

namespace lg {

template <class S>
using ConstraintType = std::variant<Spherical<S>, PointOnPlane<S>, Sliding<S>, Revolute<S>,
                                    Prismatic<S>, Fixed<S>, DistanceStop<S>>;

template <class S> struct Constraint {
  std::string name;
  ConstraintType<S> type;

  int rows() const { return std::visit([](const auto& c) { return c.kRows; }, type); }
  bool unilateral() const { return std::visit([](const auto& c) { return c.kUnilateral; }, type); }
  int bodyI() const { return std::visit([](const auto& c) { return c.bi; }, type); }
  int bodyJ() const { return std::visit([](const auto& c) { return c.bj; }, type); }
  template <class T> Constraint<T> cast() const {
    return {name, std::visit([](const auto& c) -> ConstraintType<T> { return c.template cast<T>(); }, type)};
  }
};

}  // namespace lg
