// The force-element interface (sim/forces/force_element.hpp): every alternative of the closed set is a
// ForceElementType in both scalars the engine runs, and a type that misses a member the engine needs is
// not one.
#include "sim/core/jet.hpp"
#include "sim/forces/force_element.hpp"

#include <catch2/catch.hpp>

namespace {

using J = ceres::Jet<double, 4>;

// A spring without its stored energy: its energy balance could not close.
struct NoStoredEnergy {
  void apply(const lg::Kins<double>&, const lg::Wrenches<double>&, double*) const {}
  void events(const lg::Kins<double>&, double*) const {}
  void damping(const lg::Kins<double>&, lg::DampingTerm<double>*) const {}
  void outputs(const lg::Kins<double>&, double*) const {}
  std::vector<std::string> outputNames() const { return {}; }
  double* parameter(const std::string&) { return nullptr; }
  template <class T> NoStoredEnergy cast() const { return {}; }
};
// The same with it.
struct Whole : NoStoredEnergy {
  double stored(const lg::Kins<double>&) const { return 0; }
};

}  // namespace

TEST_CASE("force elements: the closed set meets the interface the engine asks for", "[forces]") {
  STATIC_REQUIRE(lg::AllForceElementTypes<double, lg::ForceType<double>>::value);
  STATIC_REQUIRE(lg::AllForceElementTypes<J, lg::ForceType<J>>::value);
  STATIC_REQUIRE(lg::ForceElementType<lg::Tyre<double>, double>);
  STATIC_REQUIRE_FALSE(lg::ForceElementType<NoStoredEnergy, double>);
  STATIC_REQUIRE(lg::ForceElementType<Whole, double>);
  // an element in one scalar is not one in another
  STATIC_REQUIRE_FALSE(lg::ForceElementType<lg::Tyre<double>, J>);
}
