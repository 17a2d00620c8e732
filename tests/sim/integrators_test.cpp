// The Rosenbrock-W integrators of sim/integrators.hpp (RosenbrockTableau, stepRosenbrock) against the
// closed-form damped oscillator: a 2 kg mass on a prismatic guide along x, held by a spring-damper.
// With the error control switched off (rtol huge, max_step = step) they run at a fixed step, so the
// observed order of the global error checks the tableaus and their transformed form: 2 for ROS2, 3
// for ROS34PW2 (measured 2.10, 2.00 and 3.00, 3.00). A very stiff damper (eigenvalue -c/m = -5000 1/s
// against steps of 20 ms) checks that the W-matrix takes the damping and its coupling to the positions
// implicitly: stable and accurate (2e-8 relative) where an explicit step would need h < 0.6 ms.
#include <cmath>

#include "tests/sim/engine_support.hpp"  // includes Catch after the sim headers (see there)

namespace {

using lg::Vec3;

struct Oscillator {
  double mass = 2.0, k = 50.0, c = 0.8, x0 = 0.1, v0 = 0.3;
  // x(t) - rest length, closed form (under- or overdamped).
  double exact(double t) const {
    const double wn = std::sqrt(k / mass), zeta = c / (2 * std::sqrt(k * mass));
    if (zeta < 1) {
      const double wd = wn * std::sqrt(1 - zeta * zeta), b = (v0 + zeta * wn * x0) / wd;
      return std::exp(-zeta * wn * t) * (x0 * std::cos(wd * t) + b * std::sin(wd * t));
    }
    const double r = wn * std::sqrt(zeta * zeta - 1), l1 = -zeta * wn + r, l2 = -zeta * wn - r;
    const double a2 = (v0 - l1 * x0) / (l2 - l1), a1 = x0 - a2;
    return a1 * std::exp(l1 * t) + a2 * std::exp(l2 * t);
  }
};

// |x(T) - exact| after a run at the fixed step h (error control off) with the given integrator.
double fixedStepError(const Oscillator& o, lg::IntegratorKind kind, double h, double T, long* steps = nullptr) {
  char text[1024];
  std::snprintf(text, sizeof text, R"(
[[body]]
name = "mass"
mass = %.17g
inertia = [0.1, 0.2, 0.3]
position = [1.0, 0.0, 0.0]

[[joint]]
type = "prismatic"
body1 = "mass"
body2 = "ground"
point = [1.0, 0.0, 0.0]
axis = [1.0, 0.0, 0.0]

[[force]]
name = "spring"
type = "spring_damper"
body1 = "mass"
point1 = [1.0, 0.0, 0.0]
body2 = "ground"
point2 = [0.0, 0.0, 0.0]
k = %.17g
c = %.17g
L0 = 1.0
)",
                o.mass, o.k, o.c);
  lg::Scene sc = lgtest::inlineScene(text);
  lg::Model<double> m = sc.model;
  m.settings.integrator = kind;
  m.settings.rtol = 1e6;  // every trial step accepted: a fixed step h
  m.settings.atol = 1e6;
  m.settings.step = h;
  m.settings.maxStep = h;
  lg::State<double> s = sc.initial;
  lgtest::setBody(m, s, 0, Vec3<double>(1.0 + o.x0, 0, 0), lg::Vec4<double>(1, 0, 0, 0), Vec3<double>(o.v0, 0, 0),
                  Vec3<double>::Zero());
  lg::Workspace<double> w(m);
  const lg::RunStatus st = lg::simulate(m, s, w, T);
  REQUIRE(st.ok);
  if (steps) *steps = st.steps;
  return std::abs((s.y[0] - 1.0) - o.exact(T));
}

}  // namespace

TEST_CASE("Rosenbrock-W integrators: observed order 2 (ros2) and 3 (ros34pw2) on the damped oscillator",
          "[integrators][rosenbrock]") {
  const Oscillator o;
  const double T = 2.0;
  struct Method {
    const char* name;
    lg::IntegratorKind kind;
    double order;
  };
  for (const Method& meth : {Method{"ros2", lg::IntegratorKind::Ros2, 2.0}, Method{"ros34pw2", lg::IntegratorKind::Ros34pw2, 3.0}}) {
    const double e1 = fixedStepError(o, meth.kind, 0.004, T);
    const double e2 = fixedStepError(o, meth.kind, 0.002, T);
    const double e3 = fixedStepError(o, meth.kind, 0.001, T);
    const double p1 = std::log2(e1 / e2), p2 = std::log2(e2 / e3);
    lgtest::report("%s: |x(T) - exact| %.3e, %.3e, %.3e at h = 4, 2, 1 ms: observed order %.2f, %.2f", meth.name, e1,
                   e2, e3, p1, p2);
    INFO(meth.name << ": errors " << e1 << " " << e2 << " " << e3 << ", orders " << p1 << " " << p2);
    CHECK(std::abs(p2 - meth.order) < 0.25);
    CHECK(std::abs(p1 - meth.order) < 0.4);
  }
}

TEST_CASE("Rosenbrock-W integrators: a very stiff damper costs no small steps", "[integrators][rosenbrock]") {
  Oscillator o;
  o.c = 1.0e4;  // [N s/m] overdamped: eigenvalues -c/m = -5000 1/s and -k/c = -0.005 1/s
  const double T = 2.0, h = 0.02;  // h |lambda_fast| = 100
  for (lg::IntegratorKind kind : {lg::IntegratorKind::Ros2, lg::IntegratorKind::Ros34pw2}) {
    long steps = 0;
    const double err = fixedStepError(o, kind, h, T, &steps);
    const double scale = std::abs(o.exact(T));
    lgtest::report("stiff damper, %s: %ld steps of %.0f ms, |x(T) - exact| / |x(T)| = %.2e",
                   kind == lg::IntegratorKind::Ros2 ? "ros2" : "ros34pw2", steps, 1e3 * h, err / scale);
    CHECK(steps <= static_cast<long>(T / h) + 1);
    CHECK(err <= 1e-6 * scale);  // measured 4e-8 (ros2), 2e-8 (ros34pw2)
  }
  // The closed form's overdamped branch, checked by RK4 well inside its stability limit
  // (h |lambda_fast| = 1 < 2.8): 10000 steps for what the W-methods do in 100.
  const double errRk4 = fixedStepError(o, lg::IntegratorKind::RK4, 2e-4, T);
  CHECK(errRk4 <= 1e-6 * std::abs(o.exact(T)));
}
