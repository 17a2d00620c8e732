// The tyre element (sim/forces/tyre.hpp): method.md's law, never pulling, stored energy consistent
// with the force, and the contact event function.
#include <array>

#include "reference/reduced_common.hpp"
#include "sim/forces/tyre.hpp"

#include <catch2/catch.hpp>  // after the sim headers (see scene_support.hpp)

namespace {

struct OneBody {
  std::array<lg::BodyKin<double>, 2> k{lg::BodyKin<double>::ground(), lg::BodyKin<double>::ground()};
  explicit OneBody(double y) {
    k[0].r = lg::Vec3<double>(0.1, y, -0.2);
    k[0].R = Eigen::AngleAxisd(0.7, lg::Vec3<double>(0, 0, 1)).toRotationMatrix();  // a spinning wheel
  }
  lg::Kins<double> kins() const { return {k.data(), 1}; }
};

lg::Tyre<double> seedTyre() {
  lg::Tyre<double> t;
  t.body = 0;
  t.rho.setZero();
  t.normal = lg::Vec3<double>(0, 1, 0);
  t.groundHeight = 0;
  t.radius = 0.30;
  t.K = 8.0e5;
  t.deltaMax = 0.10;
  t.alpha = 0.5;
  return t;
}

}  // namespace

TEST_CASE("tyre force follows method.md and never pulls", "[tyre]") {
  const lg::Tyre<double> t = seedTyre();
  const ref::TyreLaw law{8.0e5, 0.10, 0.5};
  for (double delta : {-0.05, -1e-9, 0.0, 1e-9, 0.01, 0.05, 0.1, 0.13}) {
    const OneBody b(0.30 - delta);
    INFO("delta = " << delta);
    CHECK(t.deflection(b.kins()) == Approx(delta).margin(1e-15));
    const double P = t.load(delta);
    CHECK(P >= 0.0);
    if (delta <= 0) CHECK(P == 0.0);
    else CHECK(P == Approx(8.0e5 * delta * (1 + 0.5 * (delta / 0.1) * (delta / 0.1))).epsilon(1e-14));
    CHECK(P == Approx(law.force(delta)).epsilon(1e-14));
    // Stored energy: its derivative along delta is the force.
    const double h = 1e-7;
    if (std::abs(delta) > 2 * h) {
      const double dE = (t.stored(OneBody(0.30 - delta - h).kins()) - t.stored(OneBody(0.30 - delta + h).kins())) / (2 * h);
      CHECK(dE == Approx(P).epsilon(1e-6).margin(1e-6));
    }
    // Event function: the deflection (contact starts / ends where it crosses 0).
    double g = 1;
    t.events(b.kins(), &g);
    CHECK(g == Approx(delta).margin(1e-15));
    // Outputs: delta, P_t and their rates, with the wheel moving down at 1.3 m/s (and spinning): delta'
    // = 1.3 m/s, P_t' = dP_t/ddelta delta' (against a central difference of the load law; 0 off the ground).
    OneBody moving(0.30 - delta);
    moving.k[0].v = lg::Vec3<double>(0.4, -1.3, 0.0);
    moving.k[0].w = lg::Vec3<double>(0.0, 0.0, 9.0);
    double out[4];
    REQUIRE(t.outputNames().size() == 4);
    t.outputs(moving.kins(), out);
    CHECK(out[0] == t.deflection(moving.kins()));
    CHECK(out[1] == t.load(out[0]));
    CHECK(out[2] == Approx(1.3).epsilon(1e-14));
    const double rate = delta > 2 * h ? (t.load(delta + h) - t.load(delta - h)) / (2 * h) * 1.3 : 0.0;
    if (delta <= 0) CHECK(out[3] == 0.0);
    else if (delta > 2 * h) CHECK(out[3] == Approx(rate).epsilon(1e-7));
  }
}

TEST_CASE("tyre force acts along the ground normal at the wheel centre", "[tyre]") {
  const lg::Tyre<double> t = seedTyre();
  const OneBody b(0.25);
  std::array<lg::Vec6<double>, 1> w{lg::Vec6<double>::Zero()};
  t.apply(b.kins(), lg::Wrenches<double>{w.data()}, nullptr);
  CHECK(w[0][0] == 0.0);
  CHECK(w[0][1] == Approx(t.load(0.05)));
  CHECK(w[0][2] == 0.0);
  CHECK(w[0].tail<3>().norm() == 0.0);  // through the centre: no moment on the wheel
}
