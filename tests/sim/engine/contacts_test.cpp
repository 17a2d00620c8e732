// Unilateral stops (distance stops, both forms) through the engine's contact handling
// (resolveContacts, the event functions of the integrators): resting without drift, releasing when
// pulled away, and plastic impacts that remove exactly the approaching velocity with the lost kinetic
// energy booked as dissipated.
#include "tests/sim/engine_support.hpp"  // includes Catch after the sim headers (see there)

using lg::Vec3;
using lg::Vec4;
using lgtest::inlineScene;
using lgtest::Recorder;
using lgtest::report;
using lgtest::setBody;

namespace {

constexpr double kG = 9.80665;

// A 5 kg block on a vertical guide, its centre 1 m above a ground point and held there by a
// "no nearer than 1 m" stop (the stop's C = (d.d - L^2)/2 has |dC/dp| = |d| = 1 m at contact, so its
// multiplier is the contact force in newtons). 'pull' is a constant force the tests change.
const char* kResting = R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "block"
mass = 5.0
inertia = [0.1, 0.2, 0.3]
position = [0.0, 1.0, 0.0]

[[joint]]
name = "guide"
type = "prismatic"
body1 = "block"
body2 = "ground"
point = [0.0, 1.0, 0.0]
axis = [0.0, 1.0, 0.0]

[[stop]]
name = "floor"
body1 = "block"
point1 = [0.0, 1.0, 0.0]
body2 = "ground"
point2 = [0.0, 0.0, 0.0]
min_distance = 1.0

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]

[[force]]
name = "pull"
type = "constant"
body = "block"
force = [0.0, 0.0, 0.0]
)";

// A 5 kg body hanging 1 m below a ground point on a "no farther than 1 m" stop (a rope), no guide.
const char* kHanging = R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "bob"
mass = 5.0
inertia = [0.1, 0.2, 0.3]
position = [0.0, -1.0, 0.0]

[[stop]]
name = "rope"
body1 = "bob"
point1 = [0.0, -1.0, 0.0]
body2 = "ground"
point2 = [0.0, 0.0, 0.0]
max_distance = 1.0

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]

[[force]]
name = "pull"
type = "constant"
body = "bob"
force = [0.0, 0.0, 0.0]
)";

void setPull(lg::Model<double>& m, const Vec3<double>& F) {
  std::get<lg::ConstantForce<double>>(m.forces[m.forceIndex("pull")].type).force = F;
}

// Rests for 2 s, then is pulled up by 1.5 m g. 'row' is the stop's row.
void restThenRelease(const char* text, const char* what) {
  lg::Scene sc = inlineScene(text);
  lg::Model<double> m = sc.model;
  const int row = m.rowOffset[m.constraintIndex(std::string(text) == kResting ? "floor" : "rope")];
  const double mass = 5.0, W = mass * kG;
  lg::State<double> s = sc.initial;
  const lg::VecX<double> x0 = s.y.head(m.nx());
  lg::Workspace<double> w(m);
  Recorder rest;
  REQUIRE(lg::simulate(m, s, w, 2.0, rest).ok);
  double drift = 0, lamErr = 0, speed = 0;
  bool alwaysActive = true;
  for (const auto& smp : rest.samples) {
    drift = std::max(drift, (smp.y.head(m.nx()) - x0).cwiseAbs().maxCoeff());
    speed = std::max(speed, smp.y.segment(m.nx(), m.nv()).cwiseAbs().maxCoeff());
    lamErr = std::max(lamErr, std::abs(smp.lambda[row] - W) / W);
    alwaysActive = alwaysActive && smp.active[row];
  }
  report("%s: rest 2 s in %zu steps: position drift %.2e m, speed %.2e m/s, |lambda - m g| / m g %.2e", what,
         rest.samples.size(), drift, speed, lamErr);
  CHECK(alwaysActive);
  CHECK(drift <= 1e-9);
  CHECK(speed <= 1e-9);
  CHECK(lamErr <= 1e-9);

  // Pulled away: the stop lets go at once, the body accelerates at (F - m g) / m.
  const double F = 1.5 * W, a = (F - W) / mass;
  setPull(m, Vec3<double>(0, F, 0));
  const double t1 = s.t;
  const Vec3<double> r1 = s.y.segment<3>(0);
  Recorder pulled;
  REQUIRE(lg::simulate(m, s, w, t1 + 0.5, pulled).ok);  // 0.61 m: the rope would catch it 2 m up
  double posErr = 0, lamMax = 0;
  bool everActive = false;
  for (const auto& smp : pulled.samples) {
    const double tau = smp.t - t1;
    const Vec3<double> expect = r1 + Vec3<double>(0, 0.5 * a * tau * tau, 0);
    posErr = std::max(posErr, (smp.y.segment<3>(0) - expect).norm());
    lamMax = std::max(lamMax, std::abs(smp.lambda[row]));
    everActive = everActive || smp.active[row];
  }
  const double v = s.y[m.nx() + 1];
  report("%s: pulled by 1.5 m g for 0.5 s: max |r - r_exact| %.2e m, v %.12f m/s (exact %.12f), max |lambda| %.1e",
         what, posErr, v, a * 0.5, lamMax);
  CHECK_FALSE(everActive);
  CHECK(lamMax == 0.0);
  CHECK(posErr <= 1e-9 * 0.5 * a);
  CHECK(std::abs(v - 0.5 * a) <= 1e-9 * a);

  if (text == kHanging) {
    // Kept pulled, the body passes the anchor and the rope catches it 1 m above it (t ~ 0.9 s): a
    // plastic impact onto the max_distance stop. It then hangs there with the rope pulling down by
    // F - m g; the kinetic energy at arrival, (F - m g) (2 m + contact tolerance), is the loss booked.
    REQUIRE(lg::simulate(m, s, w, t1 + 1.5).ok);
    const double loss = (F - W) * (2.0 + m.settings.contactTolerance);
    report("%s: caught 1 m above the anchor: y - 1 = %.2e m, speed %.2e m/s, lambda / (F - m g) - 1 = %.2e, "
           "loss %.9f J (expected %.9f J)",
           what, s.y[1] - 1.0, s.y.segment(m.nx(), m.nv()).norm(), s.lambda[row] / (F - W) - 1, s.impactLoss, loss);
    CHECK(s.active[row]);
    CHECK(std::abs(s.y[1] - 1.0) <= 1e-9);
    CHECK(s.y.segment(m.nx(), m.nv()).norm() <= 1e-9);
    CHECK(std::abs(s.lambda[row] - (F - W)) <= 1e-9 * (F - W));
    CHECK(std::abs(s.impactLoss - loss) <= 1e-9 * loss);
  }
}

}  // namespace

// Resting: position constant to 1e-9 m and the multiplier equal to m g within 1e-9 relative over 2 s
// (measured: drift 0, speed 4e-15 m/s, |lambda - m g| / m g 1.5e-16). Released by a constant pull of
// 1.5 m g: the stop's multiplier is 0 from the first step and the body follows r1 + (F - m g) t^2 / 2m
// (measured error 3e-14 m over 0.5 s; asserted 1e-9 relative).
TEST_CASE("a body resting on a unilateral stop stays put and releases when pulled away", "[engine][contact]") {
  SECTION("on a min_distance stop, on a vertical guide") { restThenRelease(kResting, "min_distance stop (guided)"); }
  SECTION("hanging on a max_distance stop") { restThenRelease(kHanging, "max_distance stop (hanging)"); }
}

// Plastic impact of a free body onto a "no nearer than 1 m" stop around a ground point, under gravity,
// arriving obliquely on the lower side (gravity then pulls it away: it bounces off sideways). Before the
// impact the flight is ballistic, which dopri5 integrates exactly, so the velocity just before the
// event is v0 + g t_e. After the event the velocity along the stop normal n = p/|p| is 0 (to 1e-12 m/s,
// measured ~1e-16), the tangential velocity and the spin are unchanged (1e-12), the kinetic energy lost,
// m (v.n)^2 / 2, is booked as impact loss (1e-12 relative), and the energy balance closes (1e-12).
TEST_CASE("a plastic impact removes exactly the approaching velocity", "[engine][contact][impact]") {
  const char* text = R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "ball"
mass = 3.0
inertia = [0.1, 0.2, 0.3]
position = [-2.0, -0.6, 0.2]

[[stop]]
name = "sphere"
body1 = "ball"
point1 = [-2.0, -0.6, 0.2]
body2 = "ground"
point2 = [0.0, 0.0, 0.0]
min_distance = 1.0

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]
)";
  lg::Scene sc = inlineScene(text);
  const lg::Model<double>& m = sc.model;
  const double mass = 3.0;
  const Vec3<double> r0(-2.0, -0.6, 0.2), v0(4.0, 2.0, -0.3), w0(0, 0, 1.5), g(0, -kG, 0);
  lg::State<double> s = sc.initial;
  setBody(m, s, 0, r0, Vec4<double>(1, 0, 0, 0), v0, w0);
  const double E0 = lgtest::energyOf(m, s).total();
  lg::Workspace<double> w(m);
  Recorder rec;
  const lg::RunStatus st = lg::simulate(m, s, w, 0.6, rec);
  REQUIRE(st.ok);
  REQUIRE(st.events >= 1);
  // The step that ended on the impact: the first sample with a booked impact loss.
  size_t i = 0;
  while (i < rec.samples.size() && rec.samples[i].impactLoss == 0) ++i;
  REQUIRE(i < rec.samples.size());
  const auto& after = rec.samples[i];
  const double te = after.t;
  const Vec3<double> p = after.y.segment<3>(0), vPlus = after.y.segment<3>(7), wPlus = after.y.segment<3>(10);
  const Vec3<double> pBallistic = r0 + v0 * te + 0.5 * g * te * te;
  const Vec3<double> vMinus = v0 + g * te;
  const Vec3<double> n = p.normalized();
  const double vn = vMinus.dot(n);
  REQUIRE(vn < -1.0);  // a real impact, at more than 1 m/s
  const Vec3<double> tanMinus = vMinus - vMinus.dot(n) * n, tanPlus = vPlus - vPlus.dot(n) * n;
  const double lossExact = 0.5 * mass * vn * vn;
  const double E1 = lgtest::energyOf(m, s).total();
  // Where the event function g = C + contactTolerance |dC/dp| vanishes on the ballistic path: the
  // point has entered the stop by the contact tolerance (1e-7 m) when the event fires.
  double a = 0, b = 0.6;
  auto gEv = [&](double t) {
    const Vec3<double> q = r0 + v0 * t + 0.5 * g * t * t;
    return 0.5 * (q.squaredNorm() - 1.0) + m.settings.contactTolerance * q.norm();
  };
  for (int it = 0; it < 200; ++it) (gEv(0.5 * (a + b)) > 0 ? a : b) = 0.5 * (a + b);
  report("impact at t = %.15f s (ballistic root %.15f s), |p| - 1 = %.3e m, v.n before %.6f m/s, after %.2e m/s, "
         "tangential change %.2e m/s, spin change %.2e rad/s, loss %.12f J (exact %.12f J), energy balance %.2e",
         te, b, p.norm() - 1, vn, vPlus.dot(n), (tanPlus - tanMinus).norm(), (wPlus - w0).norm(), after.impactLoss,
         lossExact, std::abs(E1 - E0) / E0);
  CHECK(std::abs(te - b) <= 1e-11);
  CHECK((p - pBallistic).norm() <= 1e-12);
  CHECK(std::abs(vPlus.dot(n)) <= 1e-12);
  CHECK((tanPlus - tanMinus).norm() <= 1e-12);
  CHECK((wPlus - w0).norm() <= 1e-12);
  CHECK(std::abs(after.impactLoss - lossExact) <= 1e-12 * lossExact);
  CHECK(std::abs(E1 - E0) <= 1e-12 * E0);
  CHECK(s.impactLoss == after.impactLoss);  // one impact only: it bounced off
  // After the impact the stop never pulls and the body leaves it.
  for (size_t k = i; k < rec.samples.size(); ++k) CHECK_FALSE(rec.samples[k].active[0]);
  CHECK(s.y.segment<3>(0).norm() > 1.05);
}

// Landing: the guided block dropped from 0.2 m onto its min_distance stop comes to rest on it. The
// impact stops it dead (velocity 0 to 1e-12 m/s), the loss booked is the kinetic energy at arrival
// (m g times the drop height plus the contact tolerance the event allows the stop to be entered by),
// then the block rests with lambda = m g. The energy balance closes to m g times the contact tolerance
// (1e-7 m): the projection that puts the block back on C = 0 after the event lifts it by that much.
TEST_CASE("a body landing on a stop stops dead and the energy balance closes", "[engine][contact][impact]") {
  lg::Scene sc = inlineScene(kResting);
  const lg::Model<double>& m = sc.model;
  const double mass = 5.0, W = mass * kG, h = 0.2;
  lg::State<double> s = sc.initial;
  setBody(m, s, 0, Vec3<double>(0, 1.0 + h, 0), Vec4<double>(1, 0, 0, 0), Vec3<double>::Zero(), Vec3<double>::Zero());
  const double E0 = lgtest::energyOf(m, s).total();
  lg::Workspace<double> w(m);
  Recorder rec;
  REQUIRE(lg::simulate(m, s, w, 1.0, rec).ok);
  size_t i = 0;
  while (i < rec.samples.size() && rec.samples[i].impactLoss == 0) ++i;
  REQUIRE(i < rec.samples.size());
  const auto& after = rec.samples[i];
  const double expectLoss = W * (h + m.settings.contactTolerance);
  const double E1 = lgtest::energyOf(m, s).total();
  report("landing: impact at t = %.12f s (free fall %.12f s), speed after %.2e, loss %.9f J (m g (h + tol) %.9f J), "
         "final y - 1 = %.2e, lambda / m g - 1 = %.2e, |E1 - E0| = %.2e J (m g tol = %.2e J)",
         after.t, std::sqrt(2 * h / kG), after.y.segment(m.nx(), m.nv()).norm(), after.impactLoss, expectLoss,
         s.y[1] - 1.0, s.lambda[m.rowOffset[m.constraintIndex("floor")]] / W - 1, std::abs(E1 - E0),
         W * m.settings.contactTolerance);
  CHECK(after.y.segment(m.nx(), m.nv()).norm() <= 1e-12);
  CHECK(std::abs(after.impactLoss - expectLoss) <= 1e-9 * expectLoss);
  CHECK(std::abs(s.y[1] - 1.0) <= 1e-9);
  CHECK(std::abs(s.lambda[m.rowOffset[m.constraintIndex("floor")]] - W) <= 1e-9 * W);
  CHECK(std::abs(E1 - E0) <= 1.01 * W * m.settings.contactTolerance);
  CHECK(s.impactLoss == after.impactLoss);  // plastic: no bounce, no second impact
}
