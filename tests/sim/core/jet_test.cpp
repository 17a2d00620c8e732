// The engine instantiated with ceres::Jet (sim/core/jet.hpp): derivatives of the final state with
// respect to design parameters seeded in the model, against central finite differences of the
// double-precision engine. Fixed-step RK4 so that both finite-difference runs take the same steps
// (an adaptive step sequence would change with the parameter and pollute the difference).
#include "sim/core/jet.hpp"
#include "tests/sim/engine_support.hpp"  // includes Catch after the sim headers (see there)

using lg::Vec3;
using lgtest::report;

namespace {

using J = ceres::Jet<double, 2>;

// A 2 kg mass on an oblique prismatic guide, held by a spring-damper to a ground point, under
// gravity; started displaced and moving. Parameters: the mass (d/dp index 0) and the stiffness k
// (index 1).
const char* kOscillator = R"(
[solver]
integrator = "rk4"
step = 1e-3

[[body]]
name = "mass"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
position = [0.6, 0.8, 0.0]

[[joint]]
type = "prismatic"
body1 = "mass"
body2 = "ground"
point = [0.6, 0.8, 0.0]
axis = [0.6, 0.8, 0.0]

[[force]]
name = "spring"
type = "spring_damper"
body1 = "mass"
point1 = [0.6, 0.8, 0.0]
body2 = "ground"
point2 = [0.0, 0.0, 0.0]
k = 50.0
c = 0.8
L0 = 1.0

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]
)";

constexpr double kT = 2.0;  // [s] simulated

lg::State<double> startState(const lg::Scene& sc) {
  lg::State<double> s = sc.initial;
  const Vec3<double> e(0.6, 0.8, 0);
  const int N = sc.model.nBodies();
  s.y.segment<3>(0) += 0.1 * e;
  s.y.segment<3>(7 * N) = 0.3 * e;
  return s;
}

// Final position along the guide for mass m and stiffness k, double precision.
double finalStroke(const lg::Scene& sc, double mass, double k) {
  lg::Model<double> m = sc.model;
  m.bodies[0].mass = mass;
  std::get<lg::SpringDamper<double>>(m.forces[m.forceIndex("spring")].type).k = k;
  lg::State<double> s = startState(sc);
  lg::Workspace<double> w(m);
  REQUIRE(lg::simulate(m, s, w, kT).ok);
  return s.y.segment<3>(0).dot(Vec3<double>(0.6, 0.8, 0));
}

// The same with the model cast to Jet, the mass seeded as derivative 0 and the stiffness as 1.
J jetFinalStroke(const lg::Scene& sc, const lg::Model<double>& md) {
  lg::Model<J> mj = md.cast<J>();
  mj.bodies[0].mass.v[0] = 1.0;
  std::get<lg::SpringDamper<J>>(mj.forces[mj.forceIndex("spring")].type).k.v[1] = 1.0;
  const lg::State<double> s0 = startState(sc);
  lg::State<J> sj(mj);
  sj.y = s0.y.cast<J>();
  sj.active = s0.active;
  lg::Workspace<J> wj(mj);
  REQUIRE(lg::simulate(mj, sj, wj, kT).ok);
  return sj.y.segment<3>(0).dot(Vec3<J>(J(0.6), J(0.8), J(0)));
}

}  // namespace

// d(final position)/d(mass) and d(final position)/d(k) from one Jet run agree with central finite
// differences to 1e-7 relative (measured 2e-11 for the mass, 5e-10 for k). The finite differences use
// a relative step of 1e-5; their error is truncation, O(h^2): 1e-6 / 5e-6 at h = 1e-3, 1e-8 / 5e-8 at
// 1e-4, 2e-11 / 5e-10 at 1e-5 (round-off there ~1e-11). The Jet run's value part equals the double
// run to round-off (measured 1.3e-16 relative, asserted 1e-13): the same operations, except that Eigen
// evaluates some small fixed-size products of doubles with vector packets, summing in another order than
// its scalar path for Jet, so components that are zero in exact arithmetic carry different round-off
// noise from the first step on.
TEST_CASE("Jet derivatives of a run match central finite differences", "[jet][derivatives]") {
  const lg::Scene sc = lgtest::inlineScene(kOscillator);
  const double mass = 2.0, k = 50.0;

  const J x = jetFinalStroke(sc, sc.model);

  const double x0 = finalStroke(sc, mass, k);
  const double hm = 1e-5 * mass, hk = 1e-5 * k;
  const double dxdm = (finalStroke(sc, mass + hm, k) - finalStroke(sc, mass - hm, k)) / (2 * hm);
  const double dxdk = (finalStroke(sc, mass, k + hk) - finalStroke(sc, mass, k - hk)) / (2 * hk);
  report("Jet: x(T) = %.15f (double %.15f); dx/dm %.12e (FD %.12e, rel. %.1e); dx/dk %.12e (FD %.12e, rel. %.1e)",
         x.a, x0, x.v[0], dxdm, std::abs(x.v[0] - dxdm) / std::abs(dxdm), x.v[1], dxdk,
         std::abs(x.v[1] - dxdk) / std::abs(dxdk));
  CHECK(std::abs(x.a - x0) <= 1e-13 * std::abs(x0));
  REQUIRE(std::abs(dxdm) > 1e-3);  // the derivatives are not trivially zero
  REQUIRE(std::abs(dxdk) > 1e-5);
  CHECK(std::abs(x.v[0] - dxdm) <= 1e-7 * std::abs(dxdm));
  CHECK(std::abs(x.v[1] - dxdk) <= 1e-7 * std::abs(dxdk));
}

// The same derivatives through the linearly implicit integrator (ros34pw2, whose W-matrix carries the
// spring-damper's term, its damping and its stiffness): the Jet run differentiates the adaptive run as it
// steps (the step sizes, chosen on values, are constants to it), so at a tight tolerance its derivatives
// approach the exact sensitivities. Reference: the central differences of the fixed-step RK4 runs above
// (truncation error about 1e-10). Asserted 5e-8 relative (measured 5.4e-9 and 4.2e-9; 8e-9 and 6e-9 with
// the damping alone in W). The value part equals the double ros34pw2 run to round-off only, not bit for
// bit: ceres::Jet divides as a * (1/b), the double run as a / b, and the W solves divide (measured
// difference 2.2e-15 relative; asserted 1e-12).
TEST_CASE("Jet derivatives through ros34pw2 match the sensitivities", "[jet][derivatives][ros34pw2]") {
  const lg::Scene sc = lgtest::inlineScene(kOscillator);
  const double mass = 2.0, k = 50.0;
  lg::Model<double> md = sc.model;
  md.settings.integrator = lg::IntegratorKind::Ros34pw2;
  md.settings.rtol = 1e-9;
  md.settings.atol = 1e-11;
  const J x = jetFinalStroke(sc, md);

  lg::State<double> sd = startState(sc);
  lg::Workspace<double> wd(md);
  REQUIRE(lg::simulate(md, sd, wd, kT).ok);
  const double xd = sd.y.segment<3>(0).dot(Vec3<double>(0.6, 0.8, 0));
  report("ros34pw2: value part %.17g, double run %.17g", x.a, xd);
  CHECK(std::abs(x.a - xd) <= 1e-12 * std::abs(xd));

  const double hm = 1e-5 * mass, hk = 1e-5 * k;
  const double dxdm = (finalStroke(sc, mass + hm, k) - finalStroke(sc, mass - hm, k)) / (2 * hm);
  const double dxdk = (finalStroke(sc, mass, k + hk) - finalStroke(sc, mass, k - hk)) / (2 * hk);
  report("ros34pw2 Jet: dx/dm %.12e (FD %.12e, rel. %.1e); dx/dk %.12e (FD %.12e, rel. %.1e)", x.v[0], dxdm,
         std::abs(x.v[0] - dxdm) / std::abs(dxdm), x.v[1], dxdk, std::abs(x.v[1] - dxdk) / std::abs(dxdk));
  CHECK(std::abs(x.v[0] - dxdm) <= 5e-8 * std::abs(dxdm));
  CHECK(std::abs(x.v[1] - dxdk) <= 5e-8 * std::abs(dxdk));
}
