// Joint friction from bearing reactions (sim/forces/bearing_friction.hpp): the lever case by hand, the
// energy balance of a rod sliding to rest, the seed gear's drop with bearing friction on its strut, Jet
// derivatives of a run, and bad input.
#include <array>

#include "sim/core/jet.hpp"
#include "sim/drop/run.hpp"
#include "sim/io/overrides.hpp"
#include "tests/sim/bad_input_support.hpp"
#include "tests/sim/engine_support.hpp"

#include <catch2/catch.hpp>  // after the sim headers (see scene_support.hpp)

using lg::Vec3;
using lgtest::report;

namespace {

constexpr double kG = 9.80665;

// A 10 kg rod on the y axis in a cylinder fixed to the ground (a sliding joint), under gravity and a
// side load P = 500 N along x at its centre of mass (y = 0.2 m in the scene). Upper bearing fixed to the
// cylinder at y = 1.0 m, lower bearing on the rod at y = 0.6 m (moving with it).
const char* kLever = R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "rod"
mass = 10.0
inertia = [0.5, 0.02, 0.5]
position = [0.0, 0.2, 0.0]

[[joint]]
name = "slide"
type = "sliding"
body1 = "rod"
body2 = "ground"
point = [0.0, 0.2, 0.0]
axis = [0.0, 1.0, 0.0]

[[force]]
name = "side"
type = "constant"
body = "rod"
force = [500.0, 0.0, 0.0]

[[force]]
name = "bearings"
type = "bearing_friction"
joint = "slide"
mu = 0.2
upper_bearing = [0.0, 1.0, 0.0]
lower_bearing = [0.0, 0.6, 0.0]

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]
)";

// One evaluation of the scene's rod (body 0) at (x, y), moving along the axis at v: its dy/dt, and the
// bearing-friction element's outputs (N_u, N_l, F_f, s').
struct LeverEval {
  bool ok = false;
  lg::VecX<double> ydot;
  double out[4] = {0, 0, 0, 0};
};
LeverEval evaluateLever(const lg::Scene& sc, double x, double y, double v) {
  const lg::Model<double>& m = sc.model;
  lg::State<double> st = sc.initial;
  lgtest::setBody(m, st, 0, Vec3<double>(x, y, 0), lg::Vec4<double>(1, 0, 0, 0), Vec3<double>(0, v, 0), Vec3<double>::Zero());
  lg::Workspace<double> w(m);
  LeverEval r;
  r.ydot = lg::VecX<double>::Zero(m.ny());
  r.ok = lg::evaluate(m, st.y, st.active, st.lambda, w, r.ydot);
  std::get<lg::BearingFriction<double>>(m.forces[m.forceIndex("bearings")].type).outputs(w.kins(), r.out);
  return r;
}

}  // namespace

// The lever rule by hand: with z measured from the upper bearing along the axis (z_t of the load, z_l of
// the lower bearing), the rod's lateral balance N_u + N_l + P = 0 and its moment balance about the upper
// bearing z_l N_l + z_t P = 0 give N_l = -P z_t / z_l, N_u = P (z_t - z_l) / z_l: in the scene (z_t = -0.8,
// z_l = -0.4 m) |N_u| = 500 N, |N_l| = 1000 N, at 0.1 m further down 400 N and 900 N. The friction
// F_f = mu (|N_u| + |N_l|) sgn_eps(sdot) and the rod's acceleration -g - F_f / m agree with the engine's
// outputs and its dy/dt to round-off (asserted 1e-12); its damping term (the Rosenbrock-W integrators')
// is dF_f/dsdot: the closed form to round-off, and central differences of the engine's friction near
// sdot = 0 (measured 1e-10, asserted 1e-8).
TEST_CASE("bearing friction: the lever case by hand", "[bearing_friction]") {
  const lg::Scene sc = lgtest::inlineScene(kLever);
  const lg::Model<double>& m = sc.model;
  REQUIRE(m.bearingForces.size() == 1);
  const auto& bf = std::get<lg::BearingFriction<double>>(m.forces[m.forceIndex("bearings")].type);
  const double P = 500.0, mu = 0.2, mass = 10.0, eps = 1e-3;
  for (const double s : {0.0, -0.1})
    for (const double v : {-1.0, 0.5, 2e-4}) {
      INFO("stroke " << s << ", rate " << v);
      lg::State<double> st = sc.initial;
      lgtest::setBody(m, st, 0, Vec3<double>(0, 0.2 + s, 0), lg::Vec4<double>(1, 0, 0, 0), Vec3<double>(0, v, 0),
                      Vec3<double>::Zero());
      lg::Workspace<double> w(m);
      lg::VecX<double> ydot = lg::VecX<double>::Zero(m.ny());
      REQUIRE(lg::evaluate(m, st.y, st.active, st.lambda, w, ydot));
      double out[4];
      bf.outputs(w.kins(), out);
      const double zt = (0.2 + s) - 1.0, zl = (0.6 + s) - 1.0;
      const double Nl = std::abs(P * zt / zl), Nu = std::abs(P * (zt - zl) / zl);
      const double F = mu * (Nu + Nl) * v / std::sqrt(v * v + eps * eps);
      const double ay = -kG - F / mass;
      report("bearing lever (s = %.1f, sdot = %.1e): N_u %.12f (hand %.1f), N_l %.12f (%.1f), F_f %.12f (%.12f), a_y %.12f (%.12f)",
             s, v, out[0], Nu, out[1], Nl, out[2], F, ydot[7 + 1], ay);
      CHECK(std::abs(out[0] - Nu) <= 1e-12 * Nu);
      CHECK(std::abs(out[1] - Nl) <= 1e-12 * Nl);
      CHECK(std::abs(out[2] - F) <= 1e-12 * std::abs(F));
      CHECK(out[3] == Approx(v).epsilon(1e-15));
      CHECK(std::abs(ydot[7 + 1] - ay) <= 1e-12 * std::abs(ay));
      CHECK(std::abs(ydot[7]) <= 1e-12);  // no lateral acceleration
      CHECK(ydot[m.nx() + m.nv() + m.dissipationOffset[m.forceIndex("bearings")]] == Approx(F * v).epsilon(1e-14));
      // The damping term: G V = sdot, c = dF_f/dsdot against central differences of the engine's friction.
      lg::DampingTerm<double> dt;
      bf.damping(w.kins(), &dt);
      CHECK(dt.Gj.head<3>().dot(Vec3<double>(0, v, 0)) == Approx(v).epsilon(1e-15));
      auto friction = [&](double rate) {
        lg::State<double> q = st;
        q.y[m.nx() + 1] = rate;
        lg::Workspace<double> wq(m);
        lg::VecX<double> yd = lg::VecX<double>::Zero(m.ny());
        REQUIRE(lg::evaluate(m, q.y, q.active, q.lambda, wq, yd));
        double o[4];
        bf.outputs(wq.kins(), o);
        return o[2];
      };
      const double cExact = mu * (Nu + Nl) * eps * eps / std::pow(v * v + eps * eps, 1.5);
      CHECK(dt.c == Approx(cExact).epsilon(1e-12));
      if (std::abs(v) < 10 * eps) {  // where c is not lost in the differences' round-off
        const double h = 1e-6 * eps;
        const double c = (friction(v + h) - friction(v - h)) / (2 * h);
        report("bearing damping term: c %.10e (central difference %.10e)", dt.c, c);
        CHECK(dt.c == Approx(c).epsilon(1e-8));
      }
    }
}

// The coupling by hand: the rod's centre of mass d = 0.1 m off the joint's axis, so that the friction (on
// the axis) turns the rod and changes the bearing reactions. With z measured from the centre of mass (z_u =
// 0.8, z_l = 0.4 m, Dz = z_u - z_l), the lateral balance N_u + N_l + P = 0 and the moment balance
// d F - z_u N_u - z_l N_l = 0 give N_l = -(d F + z_u P)/Dz, and with N_u > 0 > N_l the friction
//   F = mu s (|N_u| + |N_l|) = mu s P (2 z_u - Dz)/Dz / (1 - 2 mu s d / Dz),   s = sgn_eps(sdot):
// at sdot = -1 m/s F = -272.7 N against -300 N uncoupled. The fixed-point iteration (gain 2 mu d / Dz = 0.1)
// reaches it to round-off (measured 1.4e-14 relative, asserted 1e-12). With mu = 3 (gain 1.5) it cannot
// converge: the evaluation fails and the run stops with a failed status, without an exception.
TEST_CASE("bearing friction: the coupled lever case by hand, no convergence fails cleanly", "[bearing_friction]") {
  const std::string text = lgtest::replacedText(kLever, "position = [0.0, 0.2, 0.0]", "position = [0.1, 0.2, 0.0]");
  const lg::Scene sc = lgtest::inlineScene(text);
  LeverEval e = evaluateLever(sc, 0.1, 0.2, -1.0);
  REQUIRE(e.ok);
  const double* out = e.out;
  lg::VecX<double>& ydot = e.ydot;
  const double P = 500.0, mu = 0.2, d = 0.1, zu = 0.8, zl = 0.4, Dz = zu - zl, sg = -1.0 / std::sqrt(1.0 + 1e-6);
  const double F = mu * sg * P * (2 * zu - Dz) / Dz / (1 - 2 * mu * sg * d / Dz);
  const double Nl = -(d * F + zu * P) / Dz, Nu = -P - Nl;
  report("bearing coupled lever: F %.12f (hand %.12f), N_u %.12f (%.12f), N_l %.12f (%.12f)", out[2], F, out[0], Nu, out[1], -Nl);
  CHECK(std::abs(out[2] - F) <= 1e-12 * std::abs(F));
  CHECK(std::abs(out[0] - Nu) <= 1e-12 * Nu);
  CHECK(std::abs(out[1] + Nl) <= 1e-12 * -Nl);
  CHECK(ydot[7 + 1] == Approx(-kG - F / 10.0).epsilon(1e-12));

  lg::Scene bad = lgtest::inlineScene(lgtest::replacedText(text, "mu = 0.2", "mu = 3.0"));
  lg::Workspace<double> wb(bad.model);
  lg::State<double> sb = bad.initial;
  lgtest::setBody(bad.model, sb, 0, Vec3<double>(0.1, 0.2, 0), lg::Vec4<double>(1, 0, 0, 0), Vec3<double>(0, -1.0, 0),
                  Vec3<double>::Zero());
  CHECK_FALSE(lg::evaluate(bad.model, sb.y, sb.active, sb.lambda, wb, ydot));
  lg::RunStatus rs;
  CHECK_NOTHROW(rs = lg::simulate(bad.model, sb, wb, 0.1));
  CHECK_FALSE(rs.ok);
}

// The same reactions and friction with the Gauss-Seidel multipliers (the iteration's other solve).
TEST_CASE("bearing friction: the lever case with Gauss-Seidel multipliers", "[bearing_friction]") {
  lg::Scene sc = lgtest::inlineScene(kLever);
  sc.model.settings.solver = lg::MultiplierSolver::GaussSeidel;
  const LeverEval e = evaluateLever(sc, 0.0, 0.1, -1.0);
  REQUIRE(e.ok);
  const double* out = e.out;
  const double F = 0.2 * 1300.0 * -1.0 / std::sqrt(1.0 + 1e-6);
  CHECK(out[0] == Approx(400.0).epsilon(1e-8));  // the Gauss-Seidel tolerance (1e-9 of the right-hand side)
  CHECK(out[1] == Approx(900.0).epsilon(1e-8));
  CHECK(out[2] == Approx(F).epsilon(1e-8));
  CHECK(e.ydot[7 + 1] == Approx(-kG - F / 10.0).epsilon(1e-8));
}

// The rod thrown down at 2 m/s slides to rest (the friction, up to 300 N, exceeds its weight) and creeps
// at the regularised rate: kinetic + gravity's potential + the friction's dissipated work stay constant,
// dopri5 at rtol 1e-10: measured 3.1e-12 of the initial kinetic energy, asserted 1e-11. ros34pw2 (the
// friction's damping term in its W-matrix) at rtol 1e-6: measured 1.9e-6 (its dissipated work is
// integrated without error control), asserted 3e-6.
TEST_CASE("bearing friction: energy balance of a rod sliding to rest", "[bearing_friction][energy]") {
  for (const lg::IntegratorKind kind : {lg::IntegratorKind::DormandPrince, lg::IntegratorKind::Ros34pw2}) {
    lg::Scene sc = lgtest::inlineScene(lgtest::replacedText(kLever, "mu = 0.2\n", "mu = 0.2\nfriction_velocity = 1e-2\n"));
    if (kind == lg::IntegratorKind::Ros34pw2) {
      sc.model.settings.integrator = kind;
      sc.model.settings.rtol = 1e-6;
      sc.model.settings.atol = 1e-8;
    }
    const lg::Model<double>& m = sc.model;
    lg::State<double> s = sc.initial;
    lgtest::setBody(m, s, 0, Vec3<double>(0, 0.2, 0), lg::Vec4<double>(1, 0, 0, 0), Vec3<double>(0, -2.0, 0),
                    Vec3<double>::Zero());
    const lg::State<double> start = s;
    lg::Workspace<double> w(m);
    const lg::RunStatus st = lg::simulate(m, s, w, 0.5);
    REQUIRE(st.ok);
    const auto E0 = lgtest::energyOf(m, start), E1 = lgtest::energyOf(m, s);
    const double rel = std::abs(E1.total() - E0.total()) / E0.kinetic;
    const double vEnd = s.y[m.nx() + 1];
    report("bearing friction slide (%s): energy balance %.2e of %.1f J, dissipated %.3f J, final rate %.2e m/s",
           kind == lg::IntegratorKind::Ros34pw2 ? "ros34pw2" : "dopri5", rel, E0.kinetic, E1.dissipated, vEnd);
    CHECK(E1.dissipated > E0.kinetic);  // the kinetic energy and the potential of the fall
    CHECK(std::abs(vEnd) < 0.01);       // at rest up to the regularised creep
    CHECK(rel <= (kind == lg::IntegratorKind::Ros34pw2 ? 3e-6 : 1e-11));
  }
}

// The seed gear with bearing friction (mu = 0.1) on its strut's sliding joint v (upper bearing on the
// cylinder 0.25 m above B, lower bearing on the rod 0.45 m above B): the limit drop runs, its energy balance
// closes below 1e-6 (measured 2.6e-7) with the bearings' work in it, and the friction changes the peak load
// (measured 86253.69 -> 86281.63 N). Its history has the columns N_upper, N_lower, F_friction [N], s_dot [m/s]
// (suffixed by the element's name), the friction law holding in every row (measured 1.4e-14 N of 66 N).
// Without the element nothing changes (the seed gear's results are bit for bit those of a scene without it:
// the stage costs one branch).
TEST_CASE("bearing friction: the seed gear's drop with bearing friction on the strut", "[bearing_friction][drop]") {
  // (in space: a planar model cannot hold bearing friction, which reads its joint's out-of-plane reactions)
  std::string text = lgtest::spatialText(lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml")));
  const lg::Scene seed = lg::parseScene(text, lgtest::sourcePath("data/seed_gear.toml"));
  text += R"(
[[force]]
name = "bearings"
type = "bearing_friction"
joint = "v"
mu = 0.1
upper_bearing = [-0.35, 0.65, 0.0]
lower_bearing = [-0.47, 0.81, 0.0]
)";
  const lg::Scene sc = lg::parseScene(text, lgtest::sourcePath("data/seed_gear.toml"));
  const auto p = lg::runCase(seed, lgtest::findCase(seed, "limit")).metrics;
  lg::CaseOptions opt;
  opt.record = true;
  const lg::CaseResult rb = lg::runCase(sc, lgtest::findCase(sc, "limit"), opt);
  const auto& b = rb.metrics;
  // The history's columns of the element, with their units. The seed strut's friction is exact (Coulomb), so
  // the bearings share its lock: F_f = mu (N_u + N_l) sigma while the slide slips (sigma the sign of s'
  // wherever s' is not 0), 0 while it sticks or a stop holds it, in every row.
  const int cu = rb.column("N_upper_bearings"), cl = rb.column("N_lower_bearings"), cf = rb.column("F_friction_bearings"),
            cv = rb.column("s_dot_bearings");
  REQUIRE(cu >= 0);
  REQUIRE(cl == cu + 1);
  REQUIRE(cf == cu + 2);
  REQUIRE(cv == cu + 3);
  CHECK(rb.columns[cu].unit == "N");
  CHECK(rb.columns[cv].unit == "m/s");
  double worst = 0, largest = 0;
  int slipping = 0, stuck = 0, wrongWay = 0;
  for (const auto& smp : rb.samples) {
    const double v = smp.values[cv], F = smp.values[cf], full = 0.1 * (smp.values[cu] + smp.values[cl]);
    if (F == 0.0) {
      ++stuck;
      continue;
    }
    ++slipping;
    worst = std::max(worst, std::abs(std::abs(F) - full));
    largest = std::max(largest, full);
    if (std::abs(v) > 1e-9 && (F > 0) != (v > 0)) ++wrongWay;
  }
  report("seed gear with bearing friction: largest friction %.3f N, law in %d slipping rows to %.1e N, %d rows without",
         largest, slipping, worst, stuck);
  CHECK(largest > 1.0);
  CHECK(worst <= 1e-9 * largest);
  CHECK(wrongWay == 0);
  CHECK(slipping > 10);
  report("seed gear limit drop with bearing friction: peak %.3f -> %.3f N, stroke %.5f -> %.5f m, E_bal %.1e, steps %ld -> %ld",
         p.peak_load_N, b.peak_load_N, p.stroke_max_m, b.stroke_max_m, b.energy_balance_error, long(p.steps), long(b.steps));
  REQUIRE(b.ok);
  CHECK(b.energy_balance_error < 1e-6);
  CHECK(b.peak_load_N != p.peak_load_N);
}

// A prismatic joint to the ground keeps its rows when it has bearing friction (else it is eliminated into
// its body's mobility and has no multipliers).
TEST_CASE("bearing friction: a prismatic joint to the ground keeps its rows", "[bearing_friction]") {
  std::string text = lgtest::replacedText(kLever, "type = \"sliding\"", "type = \"prismatic\"");
  const lg::Scene with = lgtest::inlineScene(text);
  CHECK(with.model.rowOffset[with.model.constraintIndex("slide")] >= 0);
  CHECK(with.model.mobility[0] == lg::kFree);
  const auto& bf = std::get<lg::BearingFriction<double>>(with.model.forces[with.model.forceIndex("bearings")].type);
  CHECK(bf.rows == 5);
  const std::string plain = lgtest::replacedText(
      text, "[[force]]\nname = \"bearings\"\ntype = \"bearing_friction\"\njoint = \"slide\"\nmu = 0.2\nupper_bearing = [0.0, 1.0, 0.0]\n"
            "lower_bearing = [0.0, 0.6, 0.0]\n", "");
  const lg::Scene without = lgtest::inlineScene(plain);
  CHECK(without.model.rowOffset[without.model.constraintIndex("slide")] == -1);
  // The prismatic rod's lever case: the same reactions as with the sliding joint.
  const LeverEval e = evaluateLever(with, 0.0, 0.2, -1.0);
  REQUIRE(e.ok);
  const double* out = e.out;
  CHECK(out[0] == Approx(500.0).epsilon(1e-12));
  CHECK(out[1] == Approx(1000.0).epsilon(1e-12));
}

// d(final height)/d(mu) of the rod thrown down (fixed-step RK4, 0.1 s, still sliding) by the Jet engine
// against central differences of the double runs (relative step 1e-5): measured 2.9e-11 relative, asserted
// 1e-9. The fixed-point iteration carries the derivatives with the values.
TEST_CASE("bearing friction: Jet derivative of a run in mu", "[bearing_friction][jet]") {
  using J = ceres::Jet<double, 1>;
  std::string text = lgtest::replacedText(kLever, "integrator = \"dopri5\"\nrtol = 1e-10\natol = 1e-12\n", "integrator = \"rk4\"\nstep = 1e-4\n");
  const lg::Scene sc = lgtest::inlineScene(text);
  auto start = [&](const lg::Model<double>& m) {
    lg::State<double> s = sc.initial;
    lgtest::setBody(m, s, 0, Vec3<double>(0, 0.2, 0), lg::Vec4<double>(1, 0, 0, 0), Vec3<double>(0, -2.0, 0), Vec3<double>::Zero());
    return s;
  };
  auto finalY = [&](double mu) {
    lg::Model<double> m = sc.model;
    std::get<lg::BearingFriction<double>>(m.forces[m.forceIndex("bearings")].type).mu = mu;
    lg::State<double> s = start(m);
    lg::Workspace<double> w(m);
    REQUIRE(lg::simulate(m, s, w, 0.1).ok);
    return s.y[1];
  };
  lg::Model<J> mj = sc.model.cast<J>();
  std::get<lg::BearingFriction<J>>(mj.forces[mj.forceIndex("bearings")].type).mu.v[0] = 1.0;
  const lg::State<double> s0 = start(sc.model);
  lg::State<J> sj(mj);
  sj.y = s0.y.cast<J>();
  sj.active = s0.active;
  lg::Workspace<J> wj(mj);
  REQUIRE(lg::simulate(mj, sj, wj, 0.1).ok);
  const double h = 1e-5 * 0.2;
  const double fd = (finalY(0.2 + h) - finalY(0.2 - h)) / (2 * h);
  report("bearing friction Jet: dy/dmu %.10e (FD %.10e, rel. %.1e)", sj.y[1].v[0], fd, std::abs(sj.y[1].v[0] - fd) / std::abs(fd));
  CHECK(std::abs(sj.y[1].a - finalY(0.2)) <= 1e-13);
  REQUIRE(std::abs(fd) > 1e-3);
  CHECK(std::abs(sj.y[1].v[0] - fd) <= 1e-9 * std::abs(fd));
}

TEST_CASE("bearing friction: bad input names file, line, key and rule, exit status 2", "[bearing_friction][input]") {
  lgtest::TempDir dir("bearing_bad");
  const std::string good = kLever;
  (void)lgtest::inlineScene(good);
  auto with = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(good, from, to); };
  lgtest::checkBadInputs(
      {
          {"no such joint", with("joint = \"slide\"", "joint = \"guide\""), "joint = \"guide\"", "force[1].joint",
           "'guide' is not a joint of this scene"},
          {"not a slide", with("type = \"sliding\"", "type = \"revolute\""), "joint = \"slide\"", "force[1].joint",
           "must be a sliding or prismatic joint"},
          {"bearing off the axis", with("upper_bearing = [0.0, 1.0, 0.0]", "upper_bearing = [0.01, 1.0, 0.0]"), "upper_bearing",
           "force[1].upper_bearing", "m off the axis of joint 'slide'"},
          {"bearings together", with("lower_bearing = [0.0, 0.6, 0.0]", "lower_bearing = [0.0, 1.0, 0.0]"), "lower_bearing",
           "force[1].lower_bearing", "must be at least 1e-3 m from upper_bearing"},
          {"negative mu", with("mu = 0.2", "mu = -0.2"), "mu = -0.2", "force[1].mu", "value -0.2 must be >= 0"},
          {"unknown key", with("mu = 0.2", "mu = 0.2\nseal = 1.0"), "seal = 1.0", "force[1].seal", "unknown key"},
      },
      dir);
}

// On the slide of a Coulomb strut the two frictions share one lock: the strut must run along the slide, and
// the regularised sign's friction_velocity does not apply.
TEST_CASE("bearing friction: joined to a Coulomb strut, bad input is refused", "[bearing_friction][input]") {
  lgtest::TempDir dir("bearing_joined_bad");
  const std::string good = lgtest::readFile(lgtest::sourcePath("data/friction_gear.toml"));
  (void)lg::parseScene(good, lgtest::sourcePath("data/friction_gear.toml"));
  auto with = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(good, from, to); };
  lgtest::checkBadInputs(
      {
          {"friction_velocity", with("mu = 0.1                       # [-]", "mu = 0.1\nfriction_velocity = 1e-3"),
           "friction_velocity = 1e-3", "force[4].friction_velocity", "applies to bearing friction alone (on this slide it shares "
                                                                    "the exact Coulomb friction of strut 'shock')"},
          {"strut off the slide", with("cylinder_point = [0.0, 1.0, 0.0]    # C", "cylinder_point = [0.02, 1.0, 0.0]    # C"),
           "joint = \"strut\"", "force[4].joint", "the Coulomb strut 'shock' on this slide has a point 0.02 m off the joint's axis"},
      },
      dir);
}

// Every friction on one slide (data/friction_gear.toml): the strut's exact seal friction and bearing friction
// loaded by the spin-up drag's bending (tens of kN), sharing the strut's lock, with an impact on each stop.
// At the scene's own settings every drop ends in a bounded number of steps (measured 417 .. 456; before
// the two shared a lock, the bearings' regularised sign made the slide a stiff damper of mu N / eps and
// the runs failed or ran on), its energy balance closes (measured 8e-8), and:
//  - while the slide sticks (s' = 0 to round-off between the stops), the lock's reaction stays within the one bound
//    mu_s (p_1 - p_atm) F + mu (N_u + N_l), and in the limit drop, stuck at its largest stroke, exceeds the
//    strut's own share before it slips back: the bearings' share is needed to hold it;
//  - the "bottoming" drop strikes the bottoming stop (s = S_max) and, rebounding, the extension stop
//    (s = 0): the rate jumps to 0 on each (a plastic impact).
TEST_CASE("bearing friction: every friction on one slide with an impact on each stop", "[bearing_friction][drop][energy]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/friction_gear.toml"));
  const auto& strut = std::get<lg::ShockAbsorber<double>>(sc.model.forces[sc.model.forceIndex("shock")].type);
  const double F = strut.area(), Smax = 0.15;
  lg::CaseOptions opt;
  opt.record = true;
  for (const auto& c : sc.cases) {
    INFO(c.name);
    const lg::CaseResult r = lg::runCase(sc, c, opt);
    const lg::CaseMetrics& mt = r.metrics;
    REQUIRE(mt.ok);
    report("friction gear %s: %ld steps, E_bal %.1e, peak %.1f N, s_max %.5f m", c.name.c_str(), long(mt.steps),
           mt.energy_balance_error, mt.peak_load_N, mt.stroke_max_m);
    CHECK(mt.steps < 600);
    CHECK(mt.energy_balance_error < 2e-7);
    const int cs = r.column("s"), cv = r.column("s_dot"), cp = r.column("p_1"), cf = r.column("P_friction"),
              cu = r.column("N_upper_bearings"), cl = r.column("N_lower_bearings"), cb = r.column("F_friction_bearings");
    REQUIRE(cs >= 0);
    REQUIRE(cu >= 0);
    int stuckRows = 0, needsBearings = 0, over = 0, extensionImpacts = 0, bottomingImpacts = 0;
    for (size_t i = 0; i < r.samples.size(); ++i) {
      const auto& v = r.samples[i].values;
      const double strutShare = strut.mu * v[cp] * F, bearingShare = 0.1 * (v[cu] + v[cl]);
      if (std::abs(v[cv]) < 1e-9 && v[cs] > 1e-6 && v[cs] < Smax - 1e-6 && v[cb] == 0.0) {
        ++stuckRows;
        if (std::abs(v[cf]) > (strutShare + bearingShare) * (1 + 1e-9)) ++over;
        if (std::abs(v[cf]) > strutShare * (1 + 1e-6)) ++needsBearings;
      }
      if (i == 0) continue;
      const auto& u = r.samples[i - 1].values;
      if (u[cv] < -0.1 && std::abs(v[cv]) < 1e-9 && v[cs] < 1e-6) ++extensionImpacts;
      if (u[cv] > 0.1 && std::abs(v[cv]) < 1e-9 && v[cs] > Smax - 1e-6) ++bottomingImpacts;
    }
    report("  %d stuck rows, %d beyond the strut's own bound, impacts: extension %d, bottoming %d", stuckRows, needsBearings,
           extensionImpacts, bottomingImpacts);
    CHECK(over == 0);
    if (c.name != "bottoming") CHECK(stuckRows > 0);  // (measured 3 and 30 rows; "bottoming" is held by its stop)
    if (c.name == "limit") CHECK(needsBearings > 0);   // (measured: 1 row, 1061.9 N against the strut's 1055.2 N)
    if (c.name == "bottoming") {
      CHECK(mt.bottomed);
      CHECK(bottomingImpacts >= 1);
      CHECK(extensionImpacts >= 1);
    }
  }
}

// The same slide with the Rosenbrock-W integrator, at the scene's mu = 0.1 and at 0.5: every drop runs (before,
// the fixed point of the bearings' reactions failed at its round-off floor, "non-finite state", from mu = 0.2
// on, and with ros2 and rk4 too), and agrees with the scene's own run (dopri5 at rtol 1e-6) on the peak load.
TEST_CASE("bearing friction: every friction on one slide with ros34pw2", "[bearing_friction][drop]") {
  for (const double mu : {0.1, 0.5}) {
    const lg::Scene sc = lg::applyOverrides(lg::loadScene(lgtest::sourcePath("data/friction_gear.toml")), {{"bearings.mu", mu}});
    lg::Scene ros = sc;
    ros.model.settings.integrator = lg::IntegratorKind::Ros34pw2;
    for (const auto& c : sc.cases) {
      INFO(c.name << " at mu = " << mu);
      const lg::CaseMetrics a = lg::runCase(sc, c).metrics, b = lg::runCase(ros, c).metrics;
      REQUIRE(a.ok);
      REQUIRE(b.ok);
      report("friction gear %s, mu %.1f, ros34pw2: %ld steps, peak %.3f vs %.3f N (%.1e)", c.name.c_str(), mu, long(b.steps),
             b.peak_load_N, a.peak_load_N, b.peak_load_N / a.peak_load_N - 1);
      CHECK(b.peak_load_N == Approx(a.peak_load_N).epsilon(3e-6));  // (measured 2.6e-8 .. 1.8e-6: both at rtol 1e-6)
    }
  }
}

// Zero load: a telescopic nose gear whose strut carries no bending (the wheel under its axis) has zero
// bearing reactions, so its bearing friction is zero and the drop is the frictionless one, with the
// strut's exact Coulomb friction on the same slide (the gland on the cylinder below the rod's bearing,
// as on a real strut: they move apart as the strut compresses).
TEST_CASE("bearing friction: at zero load the drop equals the frictionless run", "[bearing_friction][drop]") {
  toml::table doc = lgtest::shippedSpatialDoc("data/nose_gear.toml");
  const lg::Scene plain = lgtest::build(doc);
  doc["force"].as_array()->push_back(toml::table{{"name", "bearings"}, {"type", "bearing_friction"}, {"joint", "slide"}, {"mu", 0.1},
                                                 {"upper_bearing", toml::array{0.0, 0.65, 0.0}},
                                                 {"lower_bearing", toml::array{0.0, 0.90, 0.0}}});
  const lg::Scene withBearings = lgtest::build(doc);
  for (const auto& c : plain.cases) {
    INFO(c.name);
    const lg::CaseMetrics a = lg::runCase(plain, c).metrics, b = lg::runCase(withBearings, c).metrics;
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    // (the same drop to the integration's tolerance: the two runs' adaptive steps differ by round-off,
    // 1.5e-8 at most measured at rtol 1e-6)
    CHECK(b.peak_load_N == Approx(a.peak_load_N).epsilon(1e-7));
    CHECK(b.stroke_max_m == Approx(a.stroke_max_m).epsilon(1e-7));
    CHECK(b.h_max_m == Approx(a.h_max_m).epsilon(1e-7));
    CHECK(b.energy_balance_error < 1e-6);
  }
}

// Bearings that meet within the stroke (the lever rule would divide by their zero distance there) are
// refused at load, with the stroke range, not left to fail a run with a non-finite state.
TEST_CASE("bearing friction: bearings that meet within the stroke are refused", "[bearing_friction][input]") {
  toml::table doc = lgtest::shippedSpatialDoc("data/nose_gear.toml");
  doc["force"].as_array()->push_back(toml::table{{"name", "bearings"}, {"type", "bearing_friction"}, {"joint", "slide"}, {"mu", 0.1},
                                                 {"upper_bearing", toml::array{0.0, 0.95, 0.0}},
                                                 {"lower_bearing", toml::array{0.0, 0.75, 0.0}}});
  const int index = static_cast<int>(doc["force"].as_array()->size()) - 1;
  try {
    (void)lgtest::build(doc);
    FAIL("no InputError");
  } catch (const lg::InputError& e) {
    CHECK(e.key() == "force[" + std::to_string(index) + "].lower_bearing");
    CHECK(std::string(e.what()).find("the bearings meet within the stroke: their distance along the axis goes from 0.2 m at "
                                     "s = 0 to -0.1 m at S_max = 0.3 m") != std::string::npos);
  }
}
