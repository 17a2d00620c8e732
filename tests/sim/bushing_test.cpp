// The bushing (sim/forces/bushing.hpp): a body on a bushing to the ground against the closed-form damped
// oscillator in translation and rotation, the energy balance of a chain of bushings, the element's forces
// against the gradient of its stored energy, its damping terms against its velocity Jacobian, Jet
// derivatives against central differences, and bad input.
#include <array>
#include <cstdio>

#include "sim/core/jet.hpp"
#include "sim/forces/bushing.hpp"
#include "sim/scene/parameters.hpp"
#include "tests/sim/bad_input_support.hpp"
#include "tests/sim/engine_support.hpp"

#include <catch2/catch.hpp>  // after the sim headers (see scene_support.hpp)

using lg::Mat3;
using lg::Vec3;
using lg::Vec4;
using lg::Vec6;
using lgtest::report;

namespace {

constexpr double kG = 9.80665;

// One 2 kg body (principal axes x_axis/z_axis in the scene) on a bushing to the ground at its centre of mass.
std::string bodyOnBushing(bool groundFirst, const std::string& bodyAxes, const std::string& bushingAxes, bool gravity) {
  const std::string b1 = groundFirst ? "ground" : "mass", b2 = groundFirst ? "mass" : "ground";
  return R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "mass"
mass = 2.0
inertia = [0.1, 0.2, 0.3]
position = [0.5, 1.0, -0.2]
)" + bodyAxes + R"(

[[force]]
name = "fitting"
type = "bushing"
body1 = ")" + b1 + R"("
body2 = ")" + b2 + R"("
point = [0.5, 1.0, -0.2]
)" + bushingAxes + R"(
k_x = 800.0
k_y = 1800.0
k_z = 3200.0
c_x = 2.0
c_y = 6.0
c_z = 4.0
k_rx = 50.0
k_ry = 60.0
k_rz = 70.0
c_rx = 0.1
c_ry = 0.2
c_rz = 0.3
)" + (gravity ? "\n[[force]]\ntype = \"gravity\"\ng = [0.0, -9.80665, 0.0]\n" : "");
}

}  // namespace

// Translation: with the ground as body 1, each axis of the bushing's (oblique) frame is its own damped
// oscillator m x_k'' + c_k x_k' + k_k x_k = m g_k (the force acts at the body's centre of mass: no moment),
// from a displacement and a velocity along all three axes under gravity; with the body as body 1 (its own
// frame carries the stiffness) the same along one axis, without gravity. dopri5 at rtol 1e-10 over 3 s:
// max |x - exact| / amplitude measured 4.4e-10 (ground first) and 1.7e-9 (body first), asserted 1e-8; the
// body does not rotate (measured 1.3e-16, asserted 1e-12 rad); the energy balance closes to 1e-8 of the
// initial kinetic and elastic energy (measured 2.4e-9 and 4.2e-9: the dissipated work is integrated
// without error control, as the spring-damper's).
TEST_CASE("bushing: translation against the closed-form damped oscillator", "[bushing]") {
  const Vec3<double> ex = Vec3<double>(0.6, 0.8, 0.0), ez(0, 0, 1), ey = ez.cross(ex);
  const Vec3<double> kt(800, 1800, 3200), ct(2, 6, 4);
  const double mass = 2.0;
  for (const bool groundFirst : {true, false}) {
    INFO("ground first " << groundFirst);
    const lg::Scene sc = lgtest::inlineScene(
        bodyOnBushing(groundFirst, "", "x_axis = [0.6, 0.8, 0.0]\nz_axis = [0.0, 0.0, 1.0]", groundFirst));
    const lg::Model<double>& m = sc.model;
    lg::State<double> s = sc.initial;
    const Vec3<double> r0(0.5, 1.0, -0.2);
    const Vec3<double> x0 = groundFirst ? Vec3<double>(0.02, -0.01, 0.015) : Vec3<double>(0.02, 0, 0);
    const Vec3<double> v0 = groundFirst ? Vec3<double>(-0.1, 0.3, 0.2) : Vec3<double>(-0.1, 0, 0);
    const Mat3<double> Q = (Mat3<double>() << ex, ey, ez).finished();
    lgtest::setBody(m, s, 0, r0 + Q * x0, Vec4<double>(1, 0, 0, 0), Q * v0, Vec3<double>::Zero());
    lg::State<double> start = s;
    lg::Workspace<double> w(m);
    lgtest::Recorder rec;
    REQUIRE(lg::simulate(m, s, w, 3.0, rec).ok);
    const Vec3<double> gLocal = groundFirst ? Vec3<double>(Q.transpose() * Vec3<double>(0, -kG, 0)) : Vec3<double>::Zero();
    double err = 0, amp = 0, rot = 0;
    for (const auto& smp : rec.samples) {
      const Vec3<double> x = Q.transpose() * (Vec3<double>(smp.y.segment<3>(0)) - r0);
      for (int k = 0; k < 3; ++k) {
        const double xe = lgtest::oscillator(mass, kt[k], ct[k], mass * gLocal[k], x0[k], v0[k], smp.t);
        err = std::max(err, std::abs(x[k] - xe));
        amp = std::max(amp, std::abs(xe));
      }
      rot = std::max(rot, smp.y.segment<3>(4).norm());  // the quaternion's vector part
    }
    const double E0 = lgtest::energyOf(m, start).total();
    const auto E1 = lgtest::energyOf(m, s);
    // The scale: the initial kinetic and elastic energy (gravity's potential is an arbitrary offset).
    lg::Workspace<double> w0(m);
    lg::kinematics(m, start.y, w0);
    const double scale = lgtest::energyOf(m, start).kinetic +
                         std::get<lg::Bushing<double>>(m.forces[m.forceIndex("fitting")].type).stored(w0.kins());
    report("bushing translation (ground first %d): %zu steps, max |x - exact| / amplitude %.2e, rotation %.2e, energy "
           "balance %.2e (dissipated %.4f J)",
           int(groundFirst), rec.samples.size(), err / amp, rot, std::abs(E1.total() - E0) / scale, E1.dissipated);
    CHECK(err / amp <= 1e-8);
    CHECK(rot <= 1e-12);
    CHECK(E1.dissipated > 0.1 * scale);
    CHECK(std::abs(E1.total() - E0) <= 1e-8 * scale);
  }
}

// Rotation about one axis of the bushing's frame, which is a principal axis of the body (both oblique in the
// scene): I theta'' + c_r theta' + k_r theta = 0 exactly for any angle (theta is the rotation vector, and
// Jr^-1 theta = theta about one axis), here from 0.4 rad at 1.5 rad/s, in both orders of the bodies, without
// gravity. dopri5 at rtol 1e-10 over 3 s: max |theta - exact| / amplitude measured 2.4e-11, asserted 1e-10;
// the rotation stays about that axis (off-axis rotation vector measured 1.4e-13, asserted 1e-12 rad) and the
// centre of mass at rest (measured 0, asserted 1e-12 m); the energy balance closes to 1e-10 (measured 4.7e-11).
TEST_CASE("bushing: rotation against the closed-form damped oscillator", "[bushing]") {
  const Vec3<double> axis = Vec3<double>(0.0, 0.6, 0.8);  // the body's and the bushing's z axis
  const std::string axes = "x_axis = [1.0, 0.0, 0.0]\nz_axis = [0.0, 0.6, 0.8]";
  const double Iz = 0.3, kr = 70.0, cr = 0.3, a0 = 0.4, w0 = 1.5;
  for (const bool groundFirst : {true, false}) {
    INFO("ground first " << groundFirst);
    const lg::Scene sc = lgtest::inlineScene(bodyOnBushing(groundFirst, axes, axes, false));
    const lg::Model<double>& m = sc.model;
    lg::State<double> s = sc.initial;
    const Vec4<double> q0 = s.y.segment<4>(3);
    // The body turned by a0 about the (world) axis from its scene pose: q = q(a0, axis) q0.
    const Vec4<double> qa = lgtest::axisAngle(axis, a0);
    const Eigen::Quaterniond Q0(q0[0], q0[1], q0[2], q0[3]);
    const Eigen::Quaterniond qq = Eigen::Quaterniond(qa[0], qa[1], qa[2], qa[3]) * Q0;
    lgtest::setBody(m, s, 0, Vec3<double>(s.y.segment<3>(0)), Vec4<double>(qq.w(), qq.x(), qq.y(), qq.z()),
                    Vec3<double>::Zero(), w0 * axis);
    const lg::State<double> start = s;
    lg::Workspace<double> w(m);
    lgtest::Recorder rec;
    REQUIRE(lg::simulate(m, s, w, 3.0, rec).ok);
    double err = 0, amp = 0, offAxis = 0, drift = 0;
    for (const auto& smp : rec.samples) {
      const Vec4<double> q = smp.y.segment<4>(3);
      const Eigen::AngleAxisd aa(Eigen::Quaterniond(q[0], q[1], q[2], q[3]) * Q0.conjugate());
      const Vec3<double> th = aa.angle() * aa.axis();
      const double a = th.dot(axis);
      const double ae = lgtest::oscillator(Iz, kr, cr, 0.0, a0, w0, smp.t);
      err = std::max(err, std::abs(a - ae));
      amp = std::max(amp, std::abs(ae));
      offAxis = std::max(offAxis, (th - a * axis).norm());
      drift = std::max(drift, (Vec3<double>(smp.y.segment<3>(0)) - start.y.segment<3>(0)).norm());
    }
    const double E0 = lgtest::energyOf(m, start).total();
    const auto E1 = lgtest::energyOf(m, s);
    report("bushing rotation (ground first %d): %zu steps, max |theta - exact| / amplitude %.2e, off-axis %.2e, drift %.2e m, "
           "energy balance %.2e (dissipated %.4f J)",
           int(groundFirst), rec.samples.size(), err / amp, offAxis, drift, std::abs(E1.total() - E0) / std::abs(E0),
           E1.dissipated);
    CHECK(err / amp <= 1e-10);
    CHECK(offAxis <= 1e-12);
    CHECK(drift <= 1e-12);
    CHECK(E1.dissipated > 0.1 * std::abs(E0));
    CHECK(std::abs(E1.total() - E0) <= 1e-10 * std::abs(E0));
  }
}

namespace {

// A strut hung from the ground by a bushing, a wheel on the strut by another (oblique frames, point2 apart
// from point: preloaded), under gravity, started turning and moving in 3D.
const char* kChain = R"(
[solver]
integrator = "dopri5"
rtol = 1e-10
atol = 1e-12

[[body]]
name = "strut"
mass = 30.0
inertia = [2.0, 0.3, 2.1]
position = [0.0, -0.5, 0.0]
x_axis = [0.8, 0.0, 0.6]
z_axis = [-0.6, 0.0, 0.8]

[[body]]
name = "wheel"
mass = 12.0
inertia = [0.4, 0.4, 0.7]
position = [0.05, -1.1, 0.1]

[[force]]
name = "fitting"
type = "bushing"
body1 = "ground"
body2 = "strut"
point = [0.0, 0.0, 0.0]
x_axis = [0.0, 1.0, 0.0]
z_axis = [1.0, 0.0, 0.0]
k_x = 4.0e5
k_y = 2.0e5
k_z = 3.0e5
c_x = 200.0
c_y = 100.0
c_z = 150.0
k_rx = 3.0e4
k_ry = 2.0e4
k_rz = 2.5e4
c_rx = 20.0
c_ry = 10.0
c_rz = 15.0

[[force]]
name = "axle"
type = "bushing"
body1 = "strut"
body2 = "wheel"
point = [0.02, -1.0, 0.05]
point2 = [0.03, -1.01, 0.05]
x_axis = [0.0, 0.0, 1.0]
z_axis = [0.6, -0.8, 0.0]
k_x = 1.0e5
k_y = 1.5e5
k_z = 5.0e4
c_x = 50.0
c_y = 80.0
c_z = 30.0
k_rx = 8.0e3
k_ry = 6.0e3
k_rz = 4.0e3
c_rx = 2.0
c_ry = 3.0
c_rz = 1.0

[[force]]
type = "gravity"
g = [0.0, -9.80665, 0.0]
)";

lg::State<double> chainStart(const lg::Scene& sc) {
  lg::State<double> s = sc.initial;
  const lg::Model<double>& m = sc.model;
  lgtest::setBody(m, s, 0, Vec3<double>(s.y.segment<3>(0)) + Vec3<double>(0.003, -0.002, 0.001), s.y.segment<4>(3),
                  Vec3<double>(0.2, -0.5, 0.1), Vec3<double>(1.0, -2.0, 0.5));
  lgtest::setBody(m, s, 1, Vec3<double>(s.y.segment<3>(7)), s.y.segment<4>(10), Vec3<double>(-0.3, 0.2, 0.4),
                  Vec3<double>(3.0, 1.0, -2.0));
  return s;
}

}  // namespace

// The energy balance of the chain over 1 s: kinetic + gravity + the bushings' stored energy + their
// dissipated work is constant. dopri5 at rtol 1e-10: measured 1.2e-11 of the initial kinetic and stored
// energy, asserted 1e-10; ros34pw2 (the bushings' twelve terms, damping and stiffness, in its W-matrix) at
// rtol 1e-6: measured 5.0e-7, asserted 1e-6. The dampers did work (over half the initial energy).
TEST_CASE("bushing: energy balance of a chain of bushings", "[bushing][energy]") {
  for (const lg::IntegratorKind kind : {lg::IntegratorKind::DormandPrince, lg::IntegratorKind::Ros34pw2}) {
    lg::Scene sc = lgtest::inlineScene(kChain);
    if (kind == lg::IntegratorKind::Ros34pw2) {
      sc.model.settings.integrator = kind;
      sc.model.settings.rtol = 1e-6;
      sc.model.settings.atol = 1e-8;
    }
    const lg::Model<double>& m = sc.model;
    REQUIRE(m.nDamping == 12);
    lg::State<double> s = chainStart(sc);
    const lg::State<double> start = s;
    lg::Workspace<double> w(m);
    const lg::RunStatus st = lg::simulate(m, s, w, 1.0);
    REQUIRE(st.ok);
    const auto E0 = lgtest::energyOf(m, start);
    const auto E1 = lgtest::energyOf(m, s);
    const double rel = std::abs(E1.total() - E0.total()) / std::abs(E0.kinetic + E0.stored);
    report("bushing chain (%s): energy balance %.2e of %.3f J, dissipated %.3f J",
           kind == lg::IntegratorKind::Ros34pw2 ? "ros34pw2" : "dopri5", rel, E0.kinetic, E1.dissipated);
    CHECK(E1.dissipated > 0.5 * E0.kinetic);
    CHECK(rel <= (kind == lg::IntegratorKind::Ros34pw2 ? 1e-6 : 1e-10));
  }
}

namespace {

// Two bodies and the ground at general poses and velocities, and a bushing between the two bodies.
struct TwoBodies {
  std::array<lg::BodyKin<double>, 3> k{lg::BodyKin<double>::ground(), lg::BodyKin<double>::ground(),
                                       lg::BodyKin<double>::ground()};
  Vec4<double> q[2] = {Vec4<double>(0.95, 0.2, 0.1, -0.2).normalized(), Vec4<double>(0.7, -0.4, 0.5, 0.3).normalized()};
  TwoBodies() {
    k[0].r << 0.3, 0.1, -0.2;
    k[1].r << 0.35, 0.05, -0.1;
    k[0].R = lg::rotation<double>(q[0]);
    k[1].R = lg::rotation<double>(q[1]);
    k[0].v << 0.1, -0.2, 0.3;
    k[0].w << 1.0, -2.0, 0.5;
    k[1].v << -0.3, 0.2, 0.1;
    k[1].w << 0.4, 0.3, -1.2;
  }
  lg::Kins<double> kins() const { return lg::Kins<double>{k.data(), 2}; }
  // Body b turned by the world rotation vector th (or moved by dr).
  TwoBodies moved(int b, const Vec3<double>& dr, const Vec3<double>& th) const {
    TwoBodies t = *this;
    t.k[b].r += dr;
    t.k[b].R = lg::rotation<double>(lg::rotateQuaternion<double>(q[b], th));
    t.q[b] = lg::rotateQuaternion<double>(q[b], th);
    return t;
  }
};

lg::Bushing<double> sampleBushing(double angleScale) {
  lg::Bushing<double> b;
  b.bi = 0;
  b.bj = 1;
  b.rho_i = Vec3<double>(0.1, -0.2, 0.3);
  b.rho_j = Vec3<double>(-0.05, 0.15, 0.02);
  b.A_i = lg::rotation<double>(Vec4<double>(0.9, 0.1, -0.3, 0.2).normalized());
  // A_j such that the relative rotation of TwoBodies is angleScale times that of a general frame A_j0.
  const Mat3<double> Aj0 = lg::rotation<double>(Vec4<double>(0.8, -0.2, 0.3, 0.1).normalized());
  const TwoBodies t;
  const Mat3<double> Qi = t.k[0].R * b.A_i, Qj0 = t.k[1].R * Aj0;
  const Eigen::AngleAxisd rel(Mat3<double>(Qi.transpose() * Qj0));
  const Mat3<double> relScaled = Eigen::AngleAxisd(angleScale * rel.angle(), rel.axis()).toRotationMatrix();
  b.A_j = t.k[1].R.transpose() * Qi * relScaled;
  b.kt << 1000, 2000, 3000;
  b.ct << 10, 20, 30;
  b.kr << 400, 500, 600;
  b.cr << 4, 5, 6;
  return b;
}

std::array<Vec6<double>, 2> wrenchOf(const lg::Bushing<double>& b, const TwoBodies& t, double* diss = nullptr) {
  std::array<Vec6<double>, 2> w{Vec6<double>::Zero(), Vec6<double>::Zero()};
  double d[1];
  b.apply(t.kins(), lg::Wrenches<double>{w.data()}, diss ? diss : d);
  return w;
}

}  // namespace

// The elastic wrench is minus the gradient of the stored energy (central differences of E in the position
// and a rotation vector of each body, step 1e-6): relative difference measured 5.8e-10 at a relative rotation
// of 3.1 rad, 7.1e-11 at 0.031 rad and 5.8e-11 at 3.1e-5 rad (the series branches), asserted 2e-9 of the
// largest component. The dissipation rate equals minus the damping wrench's power (asserted 1e-13). The six
// damping terms give the velocity Jacobian of the wrench: -sum c G^T G against central differences in V
// (linear: measured 7.5e-12 of the largest entry, asserted 5e-11).
TEST_CASE("bushing: forces are the gradient of the energy, damping terms the velocity Jacobian", "[bushing][jacobian]") {
  for (const double scale : {1.0, 1e-2, 1e-5}) {
    const lg::Bushing<double> b = sampleBushing(scale);
    const TwoBodies t;
    lg::Bushing<double> elastic = b;
    elastic.ct.setZero();
    elastic.cr.setZero();
    const auto W = wrenchOf(elastic, t);
    double worst = 0, big = 0;
    for (int body = 0; body < 2; ++body)
      for (int c = 0; c < 6; ++c) {
        const double h = 1e-6;
        Vec3<double> e = Vec3<double>::Zero();
        e[c % 3] = h;
        const TwoBodies p = c < 3 ? t.moved(body, e, Vec3<double>::Zero()) : t.moved(body, Vec3<double>::Zero(), e);
        const TwoBodies mi = c < 3 ? t.moved(body, -e, Vec3<double>::Zero()) : t.moved(body, Vec3<double>::Zero(), -e);
        const double g = -(b.stored(p.kins()) - b.stored(mi.kins())) / (2 * h);
        worst = std::max(worst, std::abs(g - W[body][c]));
        big = std::max(big, std::abs(W[body][c]));
      }
    const double theta = b.eval(t.kins()).theta.norm();
    report("bushing gradient at |theta| = %.2e: max |f + dE/dq| / max |f| = %.2e", theta, worst / big);
    CHECK(worst <= 2e-9 * big);

    lg::Bushing<double> damper = b;
    damper.kt.setZero();
    damper.kr.setZero();
    double diss = 0;
    const auto Wd = wrenchOf(damper, t, &diss);
    double power = 0;
    for (int i = 0; i < 2; ++i) power += Wd[i].head<3>().dot(t.k[i].v) + Wd[i].tail<3>().dot(t.k[i].w);
    CHECK(diss > 0);
    CHECK(std::abs(power + diss) <= 1e-13 * diss);

    lg::DampingTerm<double> dt[6];
    b.damping(t.kins(), dt);
    for (int k = 0; k < 3; ++k) {  // each term's stiffness: its axis's
      CHECK(dt[k].k == b.kt[k]);
      CHECK(dt[3 + k].k == b.kr[k]);
    }
    Eigen::Matrix<double, 12, 12> M = Eigen::Matrix<double, 12, 12>::Zero(), F;
    for (const auto& d : dt) {
      Eigen::Matrix<double, 12, 1> G = Eigen::Matrix<double, 12, 1>::Zero();
      G.segment<6>(6 * d.bi) = d.Gi;
      G.segment<6>(6 * d.bj) = d.Gj;
      M -= d.c * G * G.transpose();
    }
    for (int c = 0; c < 12; ++c) {
      auto gen = [&](double s) {
        TwoBodies p = t;
        (c % 6 < 3 ? p.k[c / 6].v : p.k[c / 6].w)[c % 3] += s;
        const auto w = wrenchOf(b, p);
        Eigen::Matrix<double, 12, 1> o;
        o << w[0], w[1];
        return o;
      };
      F.col(c) = (gen(1e-3) - gen(-1e-3)) / 2e-3;
    }
    const double jac = (F - M).cwiseAbs().maxCoeff() / M.cwiseAbs().maxCoeff();
    report("bushing damping Jacobian: max difference %.2e of the largest entry", jac);
    CHECK(jac <= 5e-11);
  }
}

// Jet derivatives of the wrench and the stored energy in k_x, c_ry, k_rz and a rotation of body j about x,
// against central differences (steps about 1e-6 of the parameters, 1e-7 rad): measured 3.5e-9 relative,
// asserted 1e-8; the value parts equal the double evaluation (asserted 1e-14). At the unloaded pose
// (theta = 0 exactly, the series branches) the derivative of theta in the rotation is the identity.
TEST_CASE("bushing: Jet derivatives against central differences", "[bushing][jet]") {
  using J = ceres::Jet<double, 4>;
  const lg::Bushing<double> b = sampleBushing(0.3);
  const TwoBodies t;
  lg::Bushing<J> bj = b.cast<J>();
  bj.kt[0].v[0] = 1.0;
  bj.cr[1].v[1] = 1.0;
  bj.kr[2].v[2] = 1.0;
  std::array<lg::BodyKin<J>, 3> kj{lg::BodyKin<J>::ground(), lg::BodyKin<J>::ground(), lg::BodyKin<J>::ground()};
  for (int i = 0; i < 2; ++i) {
    kj[i].r = t.k[i].r.cast<J>();
    kj[i].v = t.k[i].v.cast<J>();
    kj[i].w = t.k[i].w.cast<J>();
    Vec4<J> q = t.q[i].cast<J>();
    if (i == 1) q = lg::rotateQuaternion<J>(q, Vec3<J>(J(0.0, 3), J(0.0), J(0.0)));
    kj[i].R = lg::rotation<J>(q);
  }
  std::array<Vec6<J>, 2> wj{Vec6<J>::Zero(), Vec6<J>::Zero()};
  J dj[1];
  const lg::Kins<J> KJ{kj.data(), 2};
  bj.apply(KJ, lg::Wrenches<J>{wj.data()}, dj);
  const J E = bj.stored(KJ);
  auto fd = [&](int p) {
    const double h = p == 0 ? 1e-3 : p == 1 ? 5e-6 : p == 2 ? 6e-4 : 1e-7;
    auto at = [&](double s) {
      lg::Bushing<double> x = b;
      TwoBodies tt = t;
      if (p == 0) x.kt[0] += s;
      if (p == 1) x.cr[1] += s;
      if (p == 2) x.kr[2] += s;
      if (p == 3) tt = t.moved(1, Vec3<double>::Zero(), Vec3<double>(s, 0, 0));
      double d[1];
      const auto w = wrenchOf(x, tt, d);
      Eigen::Matrix<double, 14, 1> o;
      o << w[0], w[1], x.stored(tt.kins()), d[0];
      return o;
    };
    return Eigen::Matrix<double, 14, 1>((at(h) - at(-h)) / (2 * h));
  };
  double worstVal = 0, worst = 0;
  double d0[1];
  const auto w0 = wrenchOf(b, t, d0);
  for (int p = 0; p < 4; ++p) {
    const auto g = fd(p);
    Eigen::Matrix<double, 14, 1> jv;
    for (int i = 0; i < 6; ++i) {
      jv[i] = wj[0][i].v[p];
      jv[6 + i] = wj[1][i].v[p];
    }
    jv[12] = E.v[p];
    jv[13] = dj[0].v[p];
    const double rel = (jv - g).cwiseAbs().maxCoeff() / g.cwiseAbs().maxCoeff();
    report("bushing Jet: parameter %d, max |jet - FD| / max |FD| %.2e", p, rel);
    REQUIRE(g.cwiseAbs().maxCoeff() > 1e-6);
    worst = std::max(worst, rel);
  }
  for (int i = 0; i < 6; ++i)
    worstVal = std::max({worstVal, std::abs(wj[0][i].a - w0[0][i]), std::abs(wj[1][i].a - w0[1][i])});
  CHECK(worst <= 1e-8);
  CHECK(worstVal <= 1e-14 * w0[1].cwiseAbs().maxCoeff());
  CHECK(E.a == Approx(b.stored(t.kins())).epsilon(1e-14));

  // At theta = 0 exactly: d theta / d phi_j = Q_j^T (here identity frames and bodies).
  lg::Bushing<J> z = b.cast<J>();
  z.A_i = z.A_j = Mat3<J>::Identity();
  std::array<lg::BodyKin<J>, 3> k0{lg::BodyKin<J>::ground(), lg::BodyKin<J>::ground(), lg::BodyKin<J>::ground()};
  k0[0].R = Mat3<J>::Identity();
  k0[1].R = lg::rotation<J>(lg::rotateQuaternion<J>(Vec4<J>(J(1), J(0), J(0), J(0)), Vec3<J>(J(0, 0), J(0, 1), J(0, 2))));
  const Vec3<J> th = z.eval(lg::Kins<J>{k0.data(), 2}).theta;
  for (int r = 0; r < 3; ++r) {
    CHECK(th[r].a == 0.0);
    for (int c = 0; c < 3; ++c) CHECK(th[r].v[c] == Approx(r == c ? 1.0 : 0.0).margin(1e-15));
  }
}

// The whole run differentiated: the oscillator of the translation test with fixed-step RK4, the final
// displacement along the bushing's x axis in k_x and c_x (Jet) against central differences of the double
// runs (relative step 1e-5): measured 1.5e-9 (k_x) and 2.5e-9 (c_x) relative, asserted 1e-8. The design parameters resolve by the
// scene's keys with their units.
TEST_CASE("bushing: Jet derivatives of a run, design parameters", "[bushing][jet]") {
  using J = ceres::Jet<double, 2>;
  std::string text = bodyOnBushing(true, "", "x_axis = [0.6, 0.8, 0.0]\nz_axis = [0.0, 0.0, 1.0]", true);
  text = lgtest::replacedText(text, "integrator = \"dopri5\"\nrtol = 1e-10\natol = 1e-12\n", "integrator = \"rk4\"\nstep = 1e-3\n");
  const lg::Scene sc = lgtest::inlineScene(text);
  const Vec3<double> ex(0.6, 0.8, 0.0), r0(0.5, 1.0, -0.2);
  auto start = [&](const lg::Model<double>& m) {
    lg::State<double> s = sc.initial;
    lgtest::setBody(m, s, 0, r0 + 0.02 * ex, Vec4<double>(1, 0, 0, 0), -0.1 * ex, Vec3<double>::Zero());
    return s;
  };
  auto finalX = [&](double kx, double cx) {
    lg::Model<double> m = sc.model;
    auto& b = std::get<lg::Bushing<double>>(m.forces[m.forceIndex("fitting")].type);
    b.kt[0] = kx;
    b.ct[0] = cx;
    lg::State<double> s = start(m);
    lg::Workspace<double> w(m);
    REQUIRE(lg::simulate(m, s, w, 1.0).ok);
    return (Vec3<double>(s.y.segment<3>(0)) - r0).dot(ex);
  };
  lg::Model<J> mj = sc.model.cast<J>();
  auto& bj = std::get<lg::Bushing<J>>(mj.forces[mj.forceIndex("fitting")].type);
  bj.kt[0].v[0] = 1.0;
  bj.ct[0].v[1] = 1.0;
  const lg::State<double> s0 = start(sc.model);
  lg::State<J> sj(mj);
  sj.y = s0.y.cast<J>();
  sj.active = s0.active;
  lg::Workspace<J> wj(mj);
  REQUIRE(lg::simulate(mj, sj, wj, 1.0).ok);
  const J x = (Vec3<J>(sj.y.segment<3>(0)) - r0.cast<J>()).dot(ex.cast<J>());
  const double hk = 1e-5 * 800, hc = 1e-5 * 2;
  const double dk = (finalX(800 + hk, 2) - finalX(800 - hk, 2)) / (2 * hk);
  const double dc = (finalX(800, 2 + hc) - finalX(800, 2 - hc)) / (2 * hc);
  report("bushing run Jet: dx/dk_x %.10e (FD %.10e, rel. %.1e), dx/dc_x %.10e (FD %.10e, rel. %.1e)", x.v[0], dk,
         std::abs(x.v[0] - dk) / std::abs(dk), x.v[1], dc, std::abs(x.v[1] - dc) / std::abs(dc));
  CHECK(std::abs(x.a - finalX(800, 2)) <= 1e-12 * std::abs(x.a));
  REQUIRE(std::abs(dk) > 1e-8);
  REQUIRE(std::abs(dc) > 1e-6);
  CHECK(std::abs(x.v[0] - dk) <= 1e-8 * std::abs(dk));
  CHECK(std::abs(x.v[1] - dc) <= 1e-8 * std::abs(dc));

  const lg::Parameter p = lg::resolveParameter(sc, "fitting.k_rx", "test");
  CHECK(lg::parameterValue(sc, p) == 50.0);
  CHECK(lg::unitOfKey("k_rx") == "N m/rad");
  CHECK(lg::unitOfKey("c_y") == "N s/m");
  CHECK_THROWS_AS(lg::resolveParameter(sc, "fitting.k", "test"), lg::InputError);
  const auto names = sc.model.outputNames;
  CHECK(std::find(names.begin(), names.end(), "fitting.M_z") != names.end());
  // The history columns of a bushing, with their units.
  const auto cols = lg::historyColumns(sc);
  auto unitOf = [&](const std::string& n) {
    for (const auto& c : cols)
      if (c.name == n) return c.unit;
    return std::string("absent");
  };
  CHECK(unitOf("F_x_fitting") == "N");
  CHECK(unitOf("M_z_fitting") == "N m");
  CHECK(unitOf("d_y_fitting") == "m");
  CHECK(unitOf("theta_z_fitting") == "rad");
}

TEST_CASE("bushing: bad input names file, line, key and rule, exit status 2", "[bushing][input]") {
  lgtest::TempDir dir("bushing_bad");
  const std::string good = bodyOnBushing(true, "", "", true);
  lg::Scene ok = lgtest::inlineScene(good);
  REQUIRE(ok.model.forces.size() == 2);
  auto with = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(good, from, to); };
  lgtest::checkBadInputs(
      {
          {"negative stiffness", with("k_y = 1800.0", "k_y = -1.0"), "k_y = -1.0", "force[0].k_y", "value -1 must be >= 0"},
          {"negative rotational damping", with("c_rz = 0.3", "c_rz = -0.3"), "c_rz = -0.3", "force[0].c_rz",
           "value -0.3 must be >= 0"},
          {"unknown key", with("k_x = 800.0", "k_x = 800.0\nk = 5.0"), "k = 5.0", "force[0].k", "unknown key"},
          {"same body twice", with("body1 = \"ground\"", "body1 = \"mass\""), "body2 = \"mass\"", "force[0].body2",
           "a bushing needs two different bodies"},
          {"axes not perpendicular", with("point = [0.5, 1.0, -0.2]\n", "point = [0.5, 1.0, -0.2]\nx_axis = [1.0, 0.0, 0.0]\nz_axis = [0.6, 0.0, 0.8]\n"),
           "z_axis = [0.6", "force[0].z_axis", "must be perpendicular to x_axis"},
          {"no body", with("body2 = \"mass\"", "body2 = \"strut\""), "body2 = \"strut\"", "force[0].body2", "is not a body"},
          {"nothing stiff or damped",
           with("k_x = 800.0\nk_y = 1800.0\nk_z = 3200.0\nc_x = 2.0\nc_y = 6.0\nc_z = 4.0\nk_rx = 50.0\nk_ry = 60.0\nk_rz = 70.0\n"
                "c_rx = 0.1\nc_ry = 0.2\nc_rz = 0.3\n",
                "k_x = 0.0\n"),
           "k_x = 0.0", "force[0].k_x", "a bushing needs at least one stiffness or damping > 0"},
      },
      dir);
}
