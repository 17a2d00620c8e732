// The two multiplier solvers (sim/engine/multipliers.hpp) on the same system: the seed gear at a few
// states of its limit drop (25 bilateral rows plus the strut's stops when in contact; a 3980 kg
// airframe against 12..22 kg links, which slows Gauss-Seidel down).
#include "sim/drop/run.hpp"
#include "tests/sim/engine_support.hpp"  // includes Catch after the sim headers (see there)
#include "tests/sim/scene_support.hpp"

using lgtest::inlineScene;
using lgtest::report;

// Gauss-Seidel, started from zero and iterated to a relative update of 1e-15, gives the direct
// solver's multipliers (and hence the same accelerations) to 1e-6 relative (asserted; measured 3e-15).
// Measured: it needs 650 to 2700 sweeps depending on the state (mass ratio 330); the default budget of
// 500 sweeps leaves errors up to 6e-5 near touchdown (printed, not asserted).
TEST_CASE("Gauss-Seidel and the direct solver agree on the seed gear", "[solvers][multipliers]") {
  const lg::Scene sc = lg::loadScene(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml");
  const lg::DropCase& limit = sc.cases[2];
  REQUIRE(limit.name == "limit");
  const lg::Model<double> mD = lg::caseModel(sc, limit);
  lg::Model<double> mG = mD;
  mG.settings.solver = lg::MultiplierSolver::GaussSeidel;
  mG.settings.gaussSeidelIterations = 1000000;
  mG.settings.gaussSeidelTolerance = 1e-15;
  lg::Model<double> mG500 = mG;
  mG500.settings.gaussSeidelIterations = 500;

  lg::State<double> s = lg::caseState(sc, mD, limit);
  lg::Workspace<double> wRun(mD);
  int states = 0;
  for (double t : {0.0, 0.02, 0.06, 0.12, 0.25}) {
    if (t > 0) REQUIRE(lg::simulate(mD, s, wRun, t).ok);
    else REQUIRE(lg::resolveContacts(mD, s, wRun) >= 0);  // the contact modes at touchdown, as a run starts
    int activeStops = 0;
    for (int k = 0; k < mD.nRows; ++k) activeStops += mD.rowInfo[k].unilateral && s.active[k];
    lg::Workspace<double> wD(mD), wG(mG), w5(mG500);
    lg::VecX<double> lamD = lg::VecX<double>::Zero(mD.nRows), lamG = lamD, lam5 = lamD;
    lg::VecX<double> fD = lg::VecX<double>::Zero(mD.ny()), fG = fD, f5 = fD;
    REQUIRE(lg::evaluate(mD, s.y, s.active, lamD, wD, fD));
    REQUIRE(lg::evaluate(mG, s.y, s.active, lamG, wG, fG));
    lg::evaluate(mG500, s.y, s.active, lam5, w5, f5);
    const double scale = lamD.cwiseAbs().maxCoeff();
    REQUIRE(scale > 0);
    const double eLam = (lamG - lamD).cwiseAbs().maxCoeff() / scale;
    const double eAcc = (fG - fD).cwiseAbs().maxCoeff() / fD.cwiseAbs().maxCoeff();
    const double e500 = (lam5 - lamD).cwiseAbs().maxCoeff() / scale;
    report("t = %.2f s: %d rows (%d stops active), Gauss-Seidel %d sweeps: multipliers %.2e, ydot %.2e relative; "
           "after 500 sweeps %.2e",
           t, static_cast<int>(wG.list.size()), activeStops, wG.report.iterations, eLam, eAcc, e500);
    CHECK(wG.report.ok);
    CHECK(wG.report.iterations > 1);
    CHECK(eLam <= 1e-6);
    CHECK(eAcc <= 1e-6);
    ++states;
  }
  CHECK(states == 5);
}

// The same on a small system with no mass ratio: the engine tests' double pendulum (10 rows) converges
// in few sweeps to the direct answer (measured: 40 sweeps, agreement 2e-16; asserted 1e-10 in under
// 1000 sweeps).
TEST_CASE("Gauss-Seidel and the direct solver agree on a double pendulum", "[solvers][multipliers]") {
  const lg::Scene sc = lgtest::inlineScene(lgtest::kDoublePendulum);
  lg::Model<double> mD = sc.model, mG = sc.model;
  mG.settings.solver = lg::MultiplierSolver::GaussSeidel;
  mG.settings.gaussSeidelIterations = 100000;
  mG.settings.gaussSeidelTolerance = 1e-15;
  lg::State<double> s = sc.initial;
  // Moving: angular velocities about the hinge axis (the velocity-product terms gamma enter the rhs).
  const int N = mD.nBodies();
  s.y.segment<3>(7 * N + 3) = lg::Vec3<double>(0, 0, 2.0);
  s.y.segment<3>(7 * N) = lg::Vec3<double>(0, 0, 2.0).cross(lg::Vec3<double>(0, -0.4, 0));
  s.y.segment<3>(7 * N + 9) = lg::Vec3<double>(0, 0, -1.0);
  s.y.segment<3>(7 * N + 6) = lg::Vec3<double>(0, 0, 2.0).cross(lg::Vec3<double>(0, -0.8, 0)) +
                              lg::Vec3<double>(0, 0, -1.0).cross(lg::Vec3<double>(0, -0.3, 0));
  lg::Workspace<double> wD(mD), wG(mG);
  lg::VecX<double> lamD = lg::VecX<double>::Zero(mD.nRows), lamG = lamD;
  lg::VecX<double> fD = lg::VecX<double>::Zero(mD.ny()), fG = fD;
  REQUIRE(lg::evaluate(mD, s.y, s.active, lamD, wD, fD));
  REQUIRE(lg::evaluate(mG, s.y, s.active, lamG, wG, fG));
  const double eLam = (lamG - lamD).cwiseAbs().maxCoeff() / lamD.cwiseAbs().maxCoeff();
  report("double pendulum: Gauss-Seidel %d sweeps, multipliers agree to %.2e", wG.report.iterations, eLam);
  CHECK(eLam <= 1e-10);
  CHECK(wG.report.iterations < 1000);
}

// The direct solver's sparse Cholesky (minimum-degree order over the constraint graph) against a dense
// LL^T of the same assembled J M^-1 J^T, at states with and without the stops: the same solution to
// round-off, with far fewer multiply-adds than a dense factor (seed gear in space: 630 against 1330 for 20
// rows, the supernodal factor's count over the minimum-degree order; as shipped, planar, 85 against 165
// for 10 rows: a small matrix, nearly dense, so only fewer).
TEST_CASE("the sparse factor of J M^-1 J^T solves like a dense Cholesky, with fewer operations",
          "[solvers][multipliers]") {
  for (const bool planar : {false, true}) {
    const lg::Scene sc = planar ? lg::loadScene(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml")
                                : lgtest::build(lgtest::shippedSpatialDoc("data/seed_gear.toml"));
    INFO((planar ? "planar" : "in space"));
    const lg::DropCase& limit = sc.cases[2];
    const lg::Model<double> m = lg::caseModel(sc, limit);
    lg::State<double> s = lg::caseState(sc, m, limit);
    lg::Workspace<double> wRun(m);
    for (double t : {0.0, 0.06, 0.5}) {
      if (t > 0) REQUIRE(lg::simulate(m, s, wRun, t).ok);
      lg::Workspace<double> w(m);
      lg::kinematics(m, s.y, w);
      lg::constraintRows(m, w);
      lg::listActiveRows(m, s.active, w);
      lg::computeW(m, w);
      lg::assembleA(m, w);
      const int n = static_cast<int>(w.list.size());
      Eigen::MatrixXd dense(n, n);
      for (int a = 0; a < n; ++a)
        for (int c = 0; c < n; ++c) dense(a, c) = lg::entryA(w, a, c);
      CHECK((dense - dense.transpose()).cwiseAbs().maxCoeff() == 0.0);
      // a right-hand side with entries of both signs and magnitudes
      lg::VecX<double> x(m.nRows);
      for (int a = 0; a < n; ++a) x[a] = std::sin(1.0 + 3.7 * a) * std::pow(10.0, (a % 5) - 2);
      const Eigen::VectorXd b = x.head(n);
      const Eigen::VectorXd ref = dense.llt().solve(b);
      REQUIRE(lg::factorA(w));
      lg::solveA(w, x);
      const double err = (x.head(n) - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
      const long madds = lg::factorMultiplyAdds(w);
      const long denseMadds = static_cast<long>(n) * (n - 1) * (n + 1) / 6;
      report("t = %.2f s: %d rows, sparse factor %ld multiply-adds (dense %ld), solution agrees to %.1e", t, n, madds,
             denseMadds, err);
      CHECK(err < 1e-12);
      CHECK((planar ? madds : 2 * madds) < denseMadds);
    }
  }
}

// The factor and the solves run code compiled for a supernode's width up to 16 and loops of run-time
// length beyond. A hub with K leaves on revolute hinges: every one of the 5 K rows touches the hub, so
// J M^-1 J^T is dense and its factor one supernode of width 5 K: K = 3 (15, compiled) and K = 4 (20,
// run-time), each against a dense Cholesky of the same matrix. Measured: 15 rows agree to 1.6e-16,
// 20 rows to 2.6e-16 (relative); asserted 1e-13.
TEST_CASE("the factor of J M^-1 J^T is right for supernodes of compiled and of run-time width", "[solvers][multipliers]") {
  for (int K : {3, 4}) {
    std::string toml = R"(
[[body]]
name = "hub"
mass = 10.0
inertia = [1.0, 1.5, 2.0]
position = [0.0, 0.0, 0.0]
x_axis = [0.8, 0.6, 0.0]
)";
    for (int k = 0; k < K; ++k) {
      const double th = 2.0 * M_PI * k / K, c = std::cos(th), s = std::sin(th);
      char text[768];
      std::snprintf(text, sizeof text, R"(
[[body]]
name = "leaf%d"
mass = %g
inertia = [0.2, 0.3, 0.25]
position = [%.17g, %.17g, %.17g]

[[joint]]
name = "hinge%d"
type = "revolute"
body1 = "leaf%d"
body2 = "hub"
point = [%.17g, %.17g, 0.0]
axis = [%.17g, %.17g, 0.6]
)",
                    k, 1.0 + k, 1.2 * c, 1.2 * s, 0.1 * k, k, k, 0.7 * c, 0.7 * s, -s, c);
      toml += text;
    }
    const lg::Scene sc = inlineScene(toml);
    const lg::Model<double>& m = sc.model;
    lg::Workspace<double> w(m);
    lg::kinematics(m, sc.initial.y, w);
    lg::constraintRows(m, w);
    lg::listActiveRows(m, sc.initial.active, w);
    lg::computeW(m, w);
    lg::assembleA(m, w);
    const int n = static_cast<int>(w.list.size());
    REQUIRE(n == 5 * K);
    int widest = 0;
    for (size_t q = 0; q + 1 < w.superStart.size(); ++q) widest = std::max(widest, w.superStart[q + 1] - w.superStart[q]);
    CHECK(widest == n);
    Eigen::MatrixXd dense(n, n);
    for (int a = 0; a < n; ++a)
      for (int c = 0; c < n; ++c) dense(a, c) = lg::entryA(w, a, c);
    lg::VecX<double> x(m.nRows);
    for (int a = 0; a < n; ++a) x[a] = std::cos(0.3 + 2.1 * a) * std::pow(10.0, (a % 3) - 1);
    const Eigen::VectorXd ref = dense.llt().solve(x.head(n));
    REQUIRE(lg::factorA(w));
    lg::solveA(w, x);
    const double err = (x.head(n) - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
    report("%d rows in one supernode of width %d: the solution agrees with a dense Cholesky to %.1e", n, widest, err);
    CHECK(err < 1e-13);
  }
}
