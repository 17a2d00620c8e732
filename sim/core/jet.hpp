// ceres::Jet as a scalar of the engine: Model<Jet> carries derivatives with respect to the design
// parameters seeded in it (Model<double>::cast<Jet>() then set the infinitesimal parts).
#pragma once

#include <ceres/jet.h>

#include "sim/core/math.hpp"

namespace lg {

template <class T, int N> struct ScalarTraits<ceres::Jet<T, N>> {
  static double value(const ceres::Jet<T, N>& x) { return static_cast<double>(x.a); }
  static bool exactZero(const ceres::Jet<T, N>& x) { return x.a == T(0) && x.v.isZero(); }
};

}  // namespace lg
