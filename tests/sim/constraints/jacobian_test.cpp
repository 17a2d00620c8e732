// Every constraint type against finite differences of its own constraint function.
//
// For random poses (r, q) and random velocities (v, omega) of two bodies (or of one body and the
// ground as body 2) the motion x(eps) is r += eps v, q += eps quaternionRate(q, omega) renormalised
// (its tangent at eps = 0 is the rigid motion with velocity V). Then
//   (C(+eps) - C(-eps)) / 2 eps            must equal J V,
//   ((J V)(+eps) - (J V)(-eps)) / 2 eps    must equal gamma = dJ/dt V   (V held fixed),
// row by row, to 1e-7 relative (relative to the largest magnitude among the constraint's rows).
// The derivative is the fourth-order central stencil (Richardson extrapolation of two central
// differences) with eps = 1e-3: the plain central difference at its best eps (~5e-6) is only good to
// ~5e-8 relative on single-row constraints whose J V happens to be small (truncation eps^2 f'''/6
// against round-off 1e-16 |f| / eps), too close to the 1e-7 bound to tell a bug from noise.
// Measured over 200 random samples per type and per body-2 kind: worst relative error 8e-9 (distance
// stops, body-body), 2e-9 (point on plane), 1e-10 or less for the multi-row joints.
#include <catch2/catch.hpp>

#include <cstdio>
#include <cstdlib>
#include <random>
#include <tuple>

#include "sim/constraints/constraint.hpp"
#include "sim/forces/friction_lock.hpp"

namespace {

using lg::BodyKin;
using lg::Mat3;
using lg::Row;
using lg::Vec3;
using lg::Vec4;
using lg::Vec6;

struct Pose {
  Vec3<double> r, v, w;
  Vec4<double> q;
};

struct Rng {
  std::mt19937_64 gen{20240611};
  double uniform(double a = -1, double b = 1) { return std::uniform_real_distribution<double>(a, b)(gen); }
  Vec3<double> vec(double s = 1) { return Vec3<double>(uniform(-s, s), uniform(-s, s), uniform(-s, s)); }
  Vec3<double> unit() {
    Vec3<double> u;
    do u = vec(); while (u.norm() < 0.1);
    return u.normalized();
  }
  Vec4<double> quat() {
    Vec4<double> q;
    do q = Vec4<double>(uniform(), uniform(), uniform(), uniform()); while (q.norm() < 0.1);
    return q.normalized();
  }
  Pose pose() { return {vec(1.0), vec(1.0), vec(2.0), quat()}; }
  // An orthonormal pair (n_a, n_b) perpendicular to the unit axis e.
  void planes(const Vec3<double>& e, Vec3<double>& na, Vec3<double>& nb) { lg::orthonormalBasis(e, na, nb); }
};

BodyKin<double> kinOf(const Pose& p) {
  BodyKin<double> k = BodyKin<double>::ground();
  k.r = p.r;
  k.R = lg::rotation<double>(p.q);
  k.v = p.v;
  k.w = p.w;
  k.mass = 1;
  k.invMass = 1;
  return k;
}

// The pose moved by eps along its own velocity (first-order quaternion step, renormalised).
Pose moved(const Pose& p, double eps) {
  Pose m = p;
  m.r = p.r + eps * p.v;
  m.q = (p.q + eps * lg::quaternionRate<double>(p.q, p.w)).normalized();
  return m;
}

template <class Con> std::vector<Row<double>> rowsAt(const Con& c, const Pose& pi, const Pose* pj) {
  std::vector<Row<double>> rows(Con::kRows);
  const BodyKin<double> Ki = kinOf(pi);
  const BodyKin<double> Kj = pj ? kinOf(*pj) : BodyKin<double>::ground();
  c.write(Ki, Kj, rows.data());
  return rows;
}

double rowRate(const Row<double>& row, const Pose& pi, const Pose* pj) {
  Vec6<double> Vi, Vj = Vec6<double>::Zero();
  Vi << pi.v, pi.w;
  if (pj) Vj << pj->v, pj->w;
  return row.Ji.dot(Vi) + row.Jj.dot(Vj);
}

struct Errors {
  double J = 0, gamma = 0;  // largest relative error seen
  int samples = 0;
};

// The derivative of f at 0 along the motion: the fourth-order central stencil
// (8 (f(e) - f(-e)) - (f(2e) - f(-2e))) / 12 e, truncation ~ e^4 |f^(5)| / 30.
template <class F> double centralDerivative(F f, double eps) {
  return (8 * (f(eps) - f(-eps)) - (f(2 * eps) - f(-2 * eps))) / (12 * eps);
}

// Checks J and gamma of constraint c at one configuration; pj == nullptr means "body 2 is the ground".
template <class Con> void checkAt(const Con& c, const Pose& pi, const Pose* pj, Errors& worst) {
  // eps = 1e-3: truncation ~ 1e-12 |f^(5)| / 30 ~ 1e-11 for |omega| <= 3.5 rad/s and O(1) lengths;
  // round-off ~ 1e-16 |f| / eps ~ 1e-13.
  const double eps = 1e-3;
  const auto r0 = rowsAt(c, pi, pj);
  // Row k's C and J V at the configuration moved by e along the motion (velocities held).
  auto at = [&](double e, int k, bool rate) {
    const Pose a = moved(pi, e);
    Pose b;
    if (pj) b = moved(*pj, e);
    const auto rows = rowsAt(c, a, pj ? &b : nullptr);
    return rate ? rowRate(rows[k], a, pj ? &b : nullptr) : rows[k].C;
  };
  // Scales: the largest |J V| and |gamma| over the constraint's rows (a row can be ~0 by chance).
  double sJ = 0, sG = 0;
  for (int k = 0; k < Con::kRows; ++k) {
    sJ = std::max(sJ, std::abs(rowRate(r0[k], pi, pj)));
    sG = std::max(sG, std::abs(r0[k].gamma));
  }
  REQUIRE(sJ > 1e-3);  // a degenerate sample would make the check vacuous
  REQUIRE(sG > 1e-3);
  for (int k = 0; k < Con::kRows; ++k) {
    const double JV = rowRate(r0[k], pi, pj);
    const double fdC = centralDerivative([&](double e) { return at(e, k, false); }, eps);
    const double fdJV = centralDerivative([&](double e) { return at(e, k, true); }, eps);
    const double eJ = std::abs(fdC - JV) / sJ;
    const double eG = std::abs(fdJV - r0[k].gamma) / sG;
    INFO("row " << k << ": J V = " << JV << ", FD of C = " << fdC << "; gamma = " << r0[k].gamma
                << ", FD of J V = " << fdJV);
    CHECK(eJ <= 1e-7);
    CHECK(eG <= 1e-7);
    worst.J = std::max(worst.J, eJ);
    worst.gamma = std::max(worst.gamma, eG);
  }
  ++worst.samples;
}

// Runs 'make' (which builds a constraint with random parameters for bodies (0, bj)) over many random
// configurations, against body 1 and against the ground.
template <class Make> void checkType(const char* name, Make make) {
  Rng rng;
  for (int ground = 0; ground < 2; ++ground) {
    Errors worst;
    for (int sample = 0; sample < 200; ++sample) {
      const auto c = make(rng, ground ? lg::kGround : 1);
      const Pose pi = rng.pose();
      const Pose pj = rng.pose();
      checkAt(c, pi, ground ? nullptr : &pj, worst);
    }
    INFO(name << (ground ? " against the ground" : " between two bodies") << ": " << worst.samples
              << " samples, worst relative error J " << worst.J << ", gamma " << worst.gamma);
    CHECK(worst.J <= 1e-7);
    CHECK(worst.gamma <= 1e-7);
    if (std::getenv("LG_TEST_VERBOSE"))
      std::printf("%-20s %-8s worst rel. error J %.2e  gamma %.2e\n", name, ground ? "ground" : "body", worst.J, worst.gamma);
  }
}

}  // namespace

TEST_CASE("spherical joint: J and gamma match finite differences of C", "[constraints][jacobian]") {
  checkType("spherical", [](Rng& g, int bj) { return lg::Spherical<double>{0, bj, g.vec(), g.vec()}; });
}

TEST_CASE("point on plane: J and gamma match finite differences of C", "[constraints][jacobian]") {
  checkType("point_on_plane",
            [](Rng& g, int bj) { return lg::PointOnPlane<double>{0, bj, g.vec(), g.vec(), g.unit()}; });
}

TEST_CASE("sliding joint: J and gamma match finite differences of C", "[constraints][jacobian]") {
  checkType("sliding", [](Rng& g, int bj) {
    const Vec3<double> e = g.unit();
    Vec3<double> na, nb;
    g.planes(g.unit(), na, nb);
    const Vec3<double> p1 = g.vec();
    return lg::Sliding<double>{0, bj, p1, p1 + e, g.vec(), na, nb};
  });
}

TEST_CASE("revolute joint: J and gamma match finite differences of C", "[constraints][jacobian]") {
  checkType("revolute", [](Rng& g, int bj) {
    Vec3<double> na, nb;
    g.planes(g.unit(), na, nb);
    const Vec3<double> p = g.vec();
    return lg::Revolute<double>{0, bj, p, g.vec(), p + g.unit(), na, nb};
  });
}

TEST_CASE("prismatic joint: J and gamma match finite differences of C", "[constraints][jacobian]") {
  checkType("prismatic", [](Rng& g, int bj) {
    const Vec3<double> e = g.unit();
    Vec3<double> na, nb;
    g.planes(g.unit(), na, nb);
    const Vec3<double> p = g.vec();
    return lg::Prismatic<double>{0, bj, p, p + e, p + na, g.vec(), na, nb};
  });
}

TEST_CASE("fixed joint: J and gamma match finite differences of C", "[constraints][jacobian]") {
  checkType("fixed", [](Rng& g, int bj) {
    const Vec3<double> p = g.vec();
    Vec3<double> ty, tz;
    g.planes(g.unit(), ty, tz);
    return lg::Fixed<double>{0, bj, p, g.vec(), p + g.unit(), p + g.unit(), ty, tz};
  });
}

TEST_CASE("distance stop, both forms: J and gamma match finite differences of C", "[constraints][jacobian]") {
  SECTION("no farther than L (max_distance)") {
    checkType("distance stop max",
              [](Rng& g, int bj) { return lg::DistanceStop<double>{0, bj, g.vec(), g.vec(), g.uniform(0.2, 2.0), true}; });
  }
  SECTION("no nearer than L (min_distance)") {
    checkType("distance stop min",
              [](Rng& g, int bj) { return lg::DistanceStop<double>{0, bj, g.vec(), g.vec(), g.uniform(0.2, 2.0), false}; });
  }
}

// The FD check above would pass for J = 0 and gamma = 0 if C were constant; make sure the check
// itself can fail: a wrong sign of one J block must be caught.
// The friction lock of a force element along the line of two points (sim/forces/friction_lock.hpp): its
// C is 0 (a velocity-level lock), so its J and gamma are checked against the rate it locks, sdot = -dL/dt:
// C here is -L. (Its gamma carries 1/L: the second point is put 6 m out in its body, so that L >= 0.8 m
// for the sampled poses, as for a strut, and the finite differences stay within their truncation bound.)
struct AxialLockRow {
  static constexpr int kRows = 1;
  int bi, bj;
  Vec3<double> rho_i, rho_j;
  void write(const BodyKin<double>& Ki, const BodyKin<double>& Kj, Row<double>* rows) const {
    const Vec3<double> a_i = Ki.R * rho_i, a_j = Kj.R * rho_j;
    lg::writeAxialLock(Ki, a_i, Kj, a_j, rows[0]);
    rows[0].C = -((Ki.r + a_i) - (Kj.r + a_j)).norm();
  }
};

TEST_CASE("friction lock: J and gamma match finite differences of the rate it locks", "[constraints][jacobian]") {
  checkType("friction lock", [](Rng& g, int bj) { return AxialLockRow{0, bj, g.vec(), 6.0 * g.unit()}; });
}

TEST_CASE("the finite-difference check detects a wrong Jacobian", "[constraints][jacobian]") {
  Rng g;
  const lg::Spherical<double> c{0, 1, g.vec(), g.vec()};
  const Pose pi = g.pose(), pj = g.pose();
  auto r0 = rowsAt(c, pi, &pj);
  const double eps = 1e-5;
  Pose pip = moved(pi, eps), pim = moved(pi, -eps), pjp = moved(pj, eps), pjm = moved(pj, -eps);
  const auto rp = rowsAt(c, pip, &pjp), rm = rowsAt(c, pim, &pjm);
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    Row<double> bad = r0[k];
    bad.Ji.tail<3>() = -bad.Ji.tail<3>();  // flipped lever-arm term
    worst = std::max(worst, std::abs((rp[k].C - rm[k].C) / (2 * eps) - rowRate(bad, pi, &pj)));
  }
  CHECK(worst > 1e-3);
}
