// The engine on systems with closed-form answers: a torque-free rigid body, a spherical pendulum,
// a double pendulum on revolute hinges, a damped oscillator on a prismatic guide, and the constraint
// drift with and without projection. Scenes are inline TOML; tolerances are stated per test with the
// figures measured when they were written (LG_TEST_VERBOSE=1 prints them).
#include "tests/sim/engine_support.hpp"  // includes Catch after the sim headers (see there)

using lg::Vec3;
using lg::Vec4;
using lgtest::axisAngle;
using lgtest::DP;
using lgtest::inlineScene;
using lgtest::kDoublePendulum;
using lgtest::Recorder;
using lgtest::report;
using lgtest::setBody;

namespace {

constexpr double kG = 9.80665;

// ---- torque-free body ---------------------------------------------------------------------------
const char* kTorqueFree = R"(
[solver]
integrator = "dopri5"
rtol = 1e-11
atol = 1e-13

[[body]]
name = "block"
mass = 3.0
inertia = [1.0, 2.0, 3.5]     # distinct principal moments
position = [0.0, 0.0, 0.0]
)";

// ---- spherical pendulum: CoM 0.5 m below a ball joint at the origin ------------------------------
const char* kSpherical = R"(
[solver]
integrator = "dopri5"
rtol = 1e-11
atol = 1e-13

[[body]]
name = "bob"
mass = 2.0
inertia = [0.08, 0.05, 0.10]
position = [0.0, -0.5, 0.0]

[[joint]]
name = "ball"
type = "spherical"
body1 = "bob"
body2 = "ground"
point = [0.0, 0.0, 0.0]

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]
)";

// Puts the double pendulum at absolute angles (th1, th2) from the downward vertical, rates (w1, w2).
void setDouble(const lg::Model<double>& m, lg::State<double>& s, double th1, double th2, double w1 = 0,
               double w2 = 0) {
  const DP p;
  const Vec3<double> z(0, 0, 1);
  const Vec3<double> e1(std::sin(th1), -std::cos(th1), 0), e2(std::sin(th2), -std::cos(th2), 0);
  const Vec3<double> r1 = p.c1 * e1, hinge = p.l1 * e1, r2 = hinge + p.c2 * e2;
  const Vec3<double> W1 = w1 * z, W2 = w2 * z;
  setBody(m, s, 0, r1, axisAngle(z, th1), W1.cross(r1), W1);
  setBody(m, s, 1, r2, axisAngle(z, th2), W1.cross(hinge) + W2.cross(r2 - hinge), W2);
}

double relDiff(double a, double b) { return std::abs(a - b) / std::abs(b); }

}  // namespace

// A free body with distinct principal moments (1, 2, 3.5) spinning about a non-principal axis, close to
// the intermediate one (it tumbles): no torque, so the kinetic energy and the world angular momentum
// I_w omega are constants. dopri5 at rtol 1e-11 over 10 s: measured largest drift 6e-12 (energy) and
// 6e-12 (momentum), relative; asserted 1e-9. The body-frame angular velocity flips (change 2 |omega0|).
TEST_CASE("torque-free asymmetric body conserves energy and angular momentum", "[engine][rigid-body]") {
  lg::Scene sc = inlineScene(kTorqueFree);
  const lg::Model<double>& m = sc.model;
  lg::State<double> s = sc.initial;
  const Vec4<double> q0 = axisAngle(Vec3<double>(1, 2, 3), 0.7);
  const lg::Mat3<double> R0 = lg::rotation<double>(q0);
  // Mostly about the intermediate body axis with a small off-axis part: the classic tumbling motion.
  const Vec3<double> omegaBody(0.05, 2.0, 0.1);
  setBody(m, s, 0, Vec3<double>(0.1, 0.2, 0.3), q0, Vec3<double>(0.3, -0.2, 0.1), R0 * omegaBody);
  lg::Workspace<double> w(m);
  Recorder rec;
  const lg::RunStatus st = lg::simulate(m, s, w, 10.0, rec);
  REQUIRE(st.ok);
  REQUIRE(s.t == Approx(10.0));

  const Vec3<double> I0 = m.bodies[0].inertia;
  auto kinetic = [&](const lg::VecX<double>& y) {
    const lg::Mat3<double> R = lg::rotation<double>(Vec4<double>(y.segment<4>(3)));
    const Vec3<double> om = y.segment<3>(10);
    return 0.5 * m.bodies[0].mass * y.segment<3>(7).squaredNorm() + 0.5 * om.dot(R * I0.asDiagonal() * R.transpose() * om);
  };
  auto momentum = [&](const lg::VecX<double>& y) -> Vec3<double> {
    const lg::Mat3<double> R = lg::rotation<double>(Vec4<double>(y.segment<4>(3)));
    return R * I0.asDiagonal() * R.transpose() * Vec3<double>(y.segment<3>(10));
  };
  const double E0 = kinetic(rec.samples.front().y);
  const Vec3<double> L0 = momentum(rec.samples.front().y);
  double eE = 0, eL = 0, turned = 0;
  for (const auto& smp : rec.samples) {
    eE = std::max(eE, std::abs(kinetic(smp.y) - E0) / E0);
    eL = std::max(eL, (momentum(smp.y) - L0).norm() / L0.norm());
    const lg::Mat3<double> R = lg::rotation<double>(Vec4<double>(smp.y.segment<4>(3)));
    turned = std::max(turned, (R.transpose() * Vec3<double>(smp.y.segment<3>(10)) - omegaBody).norm() / omegaBody.norm());
  }
  report("torque-free body: %zu steps, max rel. drift energy %.2e, angular momentum %.2e", rec.samples.size(), eE, eL);
  CHECK(eE <= 1e-9);
  CHECK(eL <= 1e-9);
  // The motion is not trivial: the body-frame angular velocity flips (it tumbles) at some point.
  report("torque-free body: largest change of the body-frame angular velocity %.2f |omega0|", turned);
  CHECK(turned > 1.0);
  // The centre of mass moves uniformly.
  CHECK((s.y.segment<3>(0) - (Vec3<double>(0.1, 0.2, 0.3) + 10.0 * Vec3<double>(0.3, -0.2, 0.1))).norm() < 1e-9);
}

// Spherical pendulum (ball joint to the ground). Large-amplitude 3-D motion, dopri5 at rtol 1e-11:
// total energy conserved over 10 s (measured 2e-10 of the largest kinetic energy, asserted 1e-8).
// Small amplitude (theta0 = 0.01 rad) in the x-y plane: period T0 = 2 pi sqrt(I_pivot / (m g d)),
// I_pivot = I_zz + m d^2. Measured error 6.25e-6, which is exactly the finite amplitude's own
// correction theta0^2/16; asserted 1e-4 against T0 (the issue asks 0.1 %) and 1e-7 against
// T0 (1 + theta0^2/16) (measured 4e-11).
TEST_CASE("spherical pendulum: energy and small-amplitude period", "[engine][pendulum]") {
  lg::Scene sc = inlineScene(kSpherical);
  const lg::Model<double>& m = sc.model;
  const double mass = 2.0, d = 0.5, Izz = 0.10;

  SECTION("energy over 10 s of large 3-D motion") {
    lg::State<double> s = sc.initial;
    const Vec4<double> q = axisAngle(Vec3<double>(1, 0, 1), 1.0);
    const Vec3<double> r = lg::rotation<double>(q) * Vec3<double>(0, -d, 0);
    const Vec3<double> om(0.5, 2.0, -0.8);
    setBody(m, s, 0, r, q, om.cross(r), om);
    lg::Workspace<double> w(m);
    Recorder rec;
    const lg::RunStatus st = lg::simulate(m, s, w, 10.0, rec);
    REQUIRE(st.ok);
    lg::State<double> probe = s;
    auto E = [&](const Recorder::Sample& x) {
      probe.y = x.y;
      probe.impactLoss = x.impactLoss;
      return lgtest::energyOf(m, probe).total();
    };
    const double E0 = E(rec.samples.front());
    double err = 0, scale = 0;
    for (const auto& x : rec.samples) {
      err = std::max(err, std::abs(E(x) - E0));
      probe.y = x.y;
      scale = std::max(scale, lgtest::energyOf(m, probe).kinetic);
    }
    report("spherical pendulum: %zu steps, %ld projections, max |E - E0| / max KE = %.2e, max |C| %.2e",
           rec.samples.size(), st.projections, err / scale, st.maxPositionViolation);
    CHECK(err / scale <= 1e-8);
    CHECK(st.maxPositionViolation <= 1e-8);
  }

  SECTION("small-amplitude period") {
    const double th0 = 0.01;
    lg::State<double> s = sc.initial;
    const Vec3<double> z(0, 0, 1);
    setBody(m, s, 0, Vec3<double>(d * std::sin(th0), -d * std::cos(th0), 0), axisAngle(z, th0), Vec3<double>::Zero(),
            Vec3<double>::Zero());
    lg::Workspace<double> w(m);
    Recorder rec;
    rec.channel = [](const lg::VecX<double>& y) { return y[0]; };  // x of the CoM
    REQUIRE(lg::simulate(m, s, w, 10.0, rec).ok);
    const double T = 2 * M_PI * std::sqrt((Izz + mass * d * d) / (mass * kG * d));
    const double Tm = rec.period();
    report("spherical pendulum: period %.10f s (closed form %.10f s), rel. error %.2e over %zu crossings", Tm, T,
           relDiff(Tm, T), rec.upCrossings.size());
    CHECK(rec.upCrossings.size() >= 5);
    CHECK(relDiff(Tm, T) <= 1e-4);
    const double Tamp = T * (1 + th0 * th0 / 16);  // first amplitude correction of the period
    report("spherical pendulum: rel. error against T0 (1 + theta0^2/16) %.2e", relDiff(Tm, Tamp));
    CHECK(relDiff(Tm, Tamp) <= 1e-7);
  }
}

// Double pendulum on two revolute hinges. Linearised about hanging (absolute angles th1, th2):
//   M = [[a, b], [b, c]],  a = I1 + m1 c1^2 + m2 l1^2,  b = m2 l1 c2,  c = I2 + m2 c2^2
//   K = diag((m1 c1 + m2 l1) g, m2 c2 g),   K u = omega^2 M u.
// A pure mode started from its eigenvector at 1e-3 rad keeps its period T = 2 pi / omega (measured
// errors 3e-8 (slow mode) and 5e-7 (fast mode); asserted 1e-5, the issue asks 1e-3). Energy at large
// amplitude over 10 s: measured 9e-11 relative to the largest kinetic energy; asserted 1e-8.
TEST_CASE("double pendulum: energy and normal-mode periods", "[engine][pendulum]") {
  lg::Scene sc = inlineScene(kDoublePendulum);
  const lg::Model<double>& m = sc.model;
  const DP p;

  SECTION("normal-mode periods") {
    Eigen::Matrix2d M, K;
    M << p.I1 + p.m1 * p.c1 * p.c1 + p.m2 * p.l1 * p.l1, p.m2 * p.l1 * p.c2, p.m2 * p.l1 * p.c2, p.I2 + p.m2 * p.c2 * p.c2;
    K << (p.m1 * p.c1 + p.m2 * p.l1) * kG, 0, 0, p.m2 * p.c2 * kG;
    // Closed form of det(K - lambda M) = 0 and of the eigenvectors u = (lambda b, k1 - lambda a).
    const double a = M(0, 0), b = M(0, 1), c = M(1, 1), k1 = K(0, 0), k2 = K(1, 1);
    const double A = a * c - b * b, B = -(a * k2 + c * k1), Cc = k1 * k2;
    const double disc = std::sqrt(B * B - 4 * A * Cc);
    for (double lambda : {(-B - disc) / (2 * A), (-B + disc) / (2 * A)}) {
      Eigen::Vector2d u(lambda * b, k1 - lambda * a);
      u /= u.cwiseAbs().maxCoeff();
      REQUIRE((K * u - lambda * M * u).norm() < 1e-9 * K.norm());
      const double T = 2 * M_PI / std::sqrt(lambda);
      lg::State<double> s = sc.initial;
      const double amp = 1e-3;
      setDouble(m, s, amp * u[0], amp * u[1]);
      lg::Workspace<double> w(m);
      Recorder rec;
      rec.channel = [](const lg::VecX<double>& y) { return y[7]; };  // x of link 2's CoM (7 = link 2's r)
      REQUIRE(lg::simulate(m, s, w, 10.0, rec).ok);
      const double Tm = rec.period();
      // A pure mode: the two angles stay in the ratio u (link 1's x over link 2's x is constant).
      report("double pendulum: mode u = (%.4f, %.4f), period %.10f s (closed form %.10f s), rel. error %.2e, %zu crossings",
             u[0], u[1], Tm, T, relDiff(Tm, T), rec.upCrossings.size());
      CHECK(rec.upCrossings.size() >= 3);
      CHECK(relDiff(Tm, T) <= 1e-5);
      // Purity: at the end, the angles are still in the eigenvector's ratio.
      const double th1 = std::atan2(s.y[0], -s.y[1]);
      const double th2 = std::atan2(s.y[7] - p.l1 * std::sin(th1), -(s.y[8] + p.l1 * std::cos(th1)));
      CHECK(std::abs(th1 * u[1] - th2 * u[0]) <= 1e-3 * amp);
    }
  }

  SECTION("energy over 10 s at large amplitude") {
    lg::State<double> s = sc.initial;
    setDouble(m, s, 1.2, -0.7, 0.5, -1.0);
    lg::Workspace<double> w(m);
    Recorder rec;
    const lg::RunStatus st = lg::simulate(m, s, w, 10.0, rec);
    REQUIRE(st.ok);
    lg::State<double> probe = s;
    double E0 = 0, err = 0, scale = 0;
    for (size_t i = 0; i < rec.samples.size(); ++i) {
      probe.y = rec.samples[i].y;
      const auto e = lgtest::energyOf(m, probe);
      if (i == 0) E0 = e.total();
      err = std::max(err, std::abs(e.total() - E0));
      scale = std::max(scale, e.kinetic);
    }
    report("double pendulum: %zu steps, %ld projections, max |E - E0| / max KE = %.2e, max |C| %.2e",
           rec.samples.size(), st.projections, err / scale, st.maxPositionViolation);
    CHECK(err / scale <= 1e-8);
  }
}

// A mass on a prismatic guide to the ground, pulled by a spring-damper along the guide:
//   x'' + (c/m) x' + (k/m) x = g.e,   x(0) = x0, x'(0) = v0
// (x the stretch of the spring; with gravity the equilibrium is x_eq = m g.e / k). Closed form
//   x - x_eq = exp(-zeta wn t) ((x0 - x_eq) cos wd t + (v0 + zeta wn (x0 - x_eq)) / wd sin wd t).
// dopri5 at rtol 1e-10 over 5 s: measured max |x - x_exact| / max |x - x_eq| 5e-10; asserted 1e-6.
// The energy balance (kinetic + stored + dissipated) closes to 1.2e-9 of the initial energy (the
// dissipated energy is a state integrated without error control); asserted 1e-8.
TEST_CASE("mass on a spring-damper matches the damped oscillator", "[engine][spring]") {
  const double mass = 2.0, k = 50.0, c = 0.8, L0 = 1.0, x0 = 0.1, v0 = 0.3;
  struct Variant {
    const char* name;
    Vec3<double> axis;
    bool gravity;
  };
  for (const Variant& var : {Variant{"along x, no gravity", Vec3<double>(1, 0, 0), false},
                             Variant{"oblique guide, with gravity", Vec3<double>(1, -2, 0.5).normalized(), true}}) {
    DYNAMIC_SECTION(var.name) {
      const Vec3<double> e = var.axis, anchor(0.2, 0.3, -0.1), body = anchor + L0 * e;
      char text[2048];
      std::snprintf(text, sizeof text, R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "mass"
mass = %.17g
inertia = [0.1, 0.2, 0.3]
position = [%.17g, %.17g, %.17g]

[[joint]]
type = "prismatic"
body1 = "mass"
body2 = "ground"
point = [%.17g, %.17g, %.17g]
axis = [%.17g, %.17g, %.17g]

[[force]]
name = "spring"
type = "spring_damper"
body1 = "mass"
point1 = [%.17g, %.17g, %.17g]
body2 = "ground"
point2 = [%.17g, %.17g, %.17g]
k = %.17g
c = %.17g
L0 = %.17g
%s
)",
                    mass, body[0], body[1], body[2], body[0], body[1], body[2], e[0], e[1], e[2], body[0], body[1], body[2],
                    anchor[0], anchor[1], anchor[2], k, c, L0,
                    var.gravity ? "[[force]]\ntype = \"gravity\"\ng = [0.0, -9.80665, 0.0]\n" : "");
      lg::Scene sc = inlineScene(text);
      const lg::Model<double>& m = sc.model;
      lg::State<double> s = sc.initial;
      setBody(m, s, 0, body + x0 * e, Vec4<double>(1, 0, 0, 0), v0 * e, Vec3<double>::Zero());
      lg::Workspace<double> w(m);
      Recorder rec;
      REQUIRE(lg::simulate(m, s, w, 5.0, rec).ok);

      const double g_e = var.gravity ? Vec3<double>(0, -kG, 0).dot(e) : 0.0;
      const double xeq = mass * g_e / k;
      const double wn = std::sqrt(k / mass), zeta = c / (2 * std::sqrt(k * mass)), wd = wn * std::sqrt(1 - zeta * zeta);
      auto exact = [&](double t) {
        const double a = x0 - xeq, b = (v0 + zeta * wn * a) / wd;
        return xeq + std::exp(-zeta * wn * t) * (a * std::cos(wd * t) + b * std::sin(wd * t));
      };
      double err = 0, amp = 0, off = 0;
      for (const auto& smp : rec.samples) {
        const Vec3<double> d = smp.y.segment<3>(0) - body;
        const double x = d.dot(e);
        err = std::max(err, std::abs(x - exact(smp.t)));
        amp = std::max(amp, std::abs(exact(smp.t) - xeq));
        off = std::max(off, (d - x * e).norm());  // stays on the guide
      }
      lg::State<double> probe = s;
      probe.y = rec.samples.front().y;
      const double E0 = lgtest::energyOf(m, probe).total();
      const auto E1 = lgtest::energyOf(m, s);
      report("spring-damper (%s): %zu steps, max |x - exact| / amplitude %.2e, off-guide %.2e, energy balance %.2e "
             "(dissipated %.4f J)",
             var.name, rec.samples.size(), err / amp, off, std::abs(E1.total() - E0) / std::abs(E0), E1.dissipated);
      CHECK(err / amp <= 1e-6);
      CHECK(off <= 1e-9);
      CHECK(E1.dissipated > 0.1 * std::abs(E0));  // the damper did work
      CHECK(std::abs(E1.total() - E0) <= 1e-8 * std::abs(E0));
    }
  }
}

// Drift: without stabilisation the index-1 equations let C drift away from 0 (only C'' = 0 is
// enforced); projection keeps it at the projection tolerance. 20 s of large-amplitude double pendulum
// with dopri5 at the default rtol 1e-6: with projection the largest |C| seen at a step end (before the
// projection) stays below 1e-8 (measured 3.5e-9) and |C| after it below projectionTolerance = 1e-9
// (measured 6e-10 in the last 5 s); with stabilization "none" the violation grows with time (measured
// max 4.9e-7 over [0, 5] s, 6.5e-6 over [15, 20] s) and ends >100 times larger than anything
// projection lets through.
TEST_CASE("constraint drift: bounded with projection, growing without", "[engine][drift]") {
  std::string text = kDoublePendulum;
  const std::string from = "rtol = 1e-10\natol = 1e-12\n";
  text.replace(text.find(from), from.size(), "rtol = 1e-6\natol = 1e-8\n");
  auto run = [&](lg::Stabilization stab, std::vector<double>& violations, std::vector<double>& times) {
    lg::Scene sc = inlineScene(text);
    sc.model.settings.stabilization = stab;
    const lg::Model<double>& m = sc.model;
    lg::State<double> s = sc.initial;
    setDouble(m, s, 1.5, -1.0, 1.0, -2.0);
    lg::Workspace<double> w(m);
    Recorder rec;
    const lg::RunStatus st = lg::simulate(m, s, w, 20.0, rec);
    REQUIRE(st.ok);
    for (const auto& smp : rec.samples) {
      lg::State<double> probe = s;
      probe.y = smp.y;
      violations.push_back(lgtest::positionViolation(m, probe));
      times.push_back(smp.t);
    }
    return st;
  };
  std::vector<double> vp, tp, vn, tn;
  const lg::RunStatus sp = run(lg::Stabilization::Projection, vp, tp);
  const lg::RunStatus sn = run(lg::Stabilization::None, vn, tn);
  auto maxOver = [](const std::vector<double>& v, const std::vector<double>& t, double a, double b) {
    double x = 0;
    for (size_t i = 0; i < v.size(); ++i)
      if (t[i] >= a && t[i] <= b) x = std::max(x, v[i]);
    return x;
  };
  const double pFirst = maxOver(vp, tp, 0, 5), pLast = maxOver(vp, tp, 15, 20);
  const double nFirst = maxOver(vn, tn, 0, 5), nLast = maxOver(vn, tn, 15, 20);
  report("drift, projection: %ld projections, max |C| before projection %.2e, after: [0,5] s %.2e, [15,20] s %.2e",
         sp.projections, sp.maxPositionViolation, pFirst, pLast);
  report("drift, none:       max |C| [0,5] s %.2e, [15,20] s %.2e, at 20 s %.2e", nFirst, nLast, vn.back());
  CHECK(sp.projections > 0);
  CHECK(sp.maxPositionViolation <= 1e-8);
  CHECK(pLast <= 1e-9);
  CHECK(vp.back() <= 1e-9);
  CHECK(sn.projections == 0);
  CHECK(nLast > 3 * nFirst);          // it grows
  CHECK(vn.back() > 100 * sp.maxPositionViolation);
}
