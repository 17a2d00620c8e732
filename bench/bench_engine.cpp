// Engine throughput: steps and right-hand-side evaluations per second on a 5-body system with 25
// constraint rows (a 5-link chain of revolute joints, the first hinged to the ground, hinge axes
// alternating between z and an oblique axis so that the motion is 3-D), falling under gravity from
// horizontal. For each multiplier solver (direct, Gauss-Seidel) and each integrator (semi-implicit
// Euler and RK4 at a fixed step of 1e-4 s, Dormand-Prince 5(4), ROS34PW2 and ROS2 at rtol 1e-6; the
// chain has no damper, so the Rosenbrock-W methods run with W = I) it prints the counts and
// rates of an unprofiled run, then the per-stage time breakdown of a second run with
// Settings::profile = true. Gauss-Seidel with the fixed-step integrators simulates 0.2 s instead of
// 1 s (it is ~50 times slower here). "max |C|" is the largest constraint violation seen at a step's
// end before projection. Single thread; about 6 s in all.
#include <chrono>
#include <cstdio>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "sim/engine/integrators.hpp"
#include "sim/io/scene.hpp"

namespace {

std::string chainScene() {
  std::string t = "[[force]]\ntype = \"gravity\"\n";
  const double L = 0.4;
  char buf[1024];
  for (int i = 0; i < 5; ++i) {
    std::snprintf(buf, sizeof buf,
                  "[[body]]\nname = \"link%d\"\nmass = %.3f\ninertia = [0.002, 0.02, 0.02]\nposition = [%.3f, 0.0, 0.0]\n",
                  i, 1.0 + 0.2 * i, (i + 0.5) * L);
    t += buf;
  }
  for (int i = 0; i < 5; ++i) {
    const char* axis = i % 2 == 0 ? "[0.0, 0.0, 1.0]" : "[0.0, 1.0, 1.0]";
    std::snprintf(buf, sizeof buf,
                  "[[joint]]\ntype = \"revolute\"\nbody1 = \"link%d\"\nbody2 = \"%s\"\npoint = [%.3f, 0.0, 0.0]\naxis = %s\n", i,
                  i == 0 ? "ground" : ("link" + std::to_string(i - 1)).c_str(), i * L, axis);
    t += buf;
  }
  return t;
}

struct Row {
  const char* solver;
  const char* integrator;
  long steps = 0, rhs = 0;
  double wall = 0, violation = 0;
  lg::StageTimer timer;
  double profiledWall = 0;
};

Row run(const lg::Scene& sc, lg::MultiplierSolver solver, lg::IntegratorKind integ, double duration, bool profile) {
  lg::Model<double> m = sc.model;
  m.settings.solver = solver;
  m.settings.integrator = integ;
  m.settings.step = 1e-4;
  m.settings.rtol = 1e-6;
  m.settings.profile = profile;
  lg::State<double> s = sc.initial;
  lg::Workspace<double> w(m);
  Row r;
  const auto a = std::chrono::steady_clock::now();
  const lg::RunStatus st = lg::simulate(m, s, w, duration);
  r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
  if (!st.ok) std::fprintf(stderr, "run failed: %s\n", st.message.c_str());
  r.steps = st.steps;
  r.rhs = w.rhsEvaluations;
  r.violation = st.maxPositionViolation;
  r.timer = w.timer;
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Engine throughput: steps and right-hand-side evaluations per second of a 5-body, 25-row chain for "
               "each multiplier solver and integrator, with the per-stage profile (one core, about 6 s)"};
  lg::cli::addVersion(app, "bench_engine");
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;
  const lg::Scene sc = lg::parseScene(chainScene(), "chain.toml");
  std::printf("5-link revolute chain: %d bodies, %d constraint rows, falling from horizontal\n", sc.model.nBodies(),
              sc.model.nRows);
  struct Config {
    lg::MultiplierSolver solver;
    const char* sName;
    lg::IntegratorKind integ;
    const char* iName;
    double duration;  // [s] simulated
  };
  const Config configs[] = {
      {lg::MultiplierSolver::Direct, "direct", lg::IntegratorKind::SemiImplicitEuler, "euler h=1e-4", 1.0},
      {lg::MultiplierSolver::Direct, "direct", lg::IntegratorKind::RK4, "rk4 h=1e-4", 1.0},
      {lg::MultiplierSolver::Direct, "direct", lg::IntegratorKind::DormandPrince, "dopri5 rtol=1e-6", 1.0},
      {lg::MultiplierSolver::Direct, "direct", lg::IntegratorKind::Ros34pw2, "ros34pw2 rtol=1e-6", 1.0},
      {lg::MultiplierSolver::Direct, "direct", lg::IntegratorKind::Ros2, "ros2 rtol=1e-6", 1.0},
      {lg::MultiplierSolver::GaussSeidel, "gauss-seidel", lg::IntegratorKind::SemiImplicitEuler, "euler h=1e-4", 0.2},
      {lg::MultiplierSolver::GaussSeidel, "gauss-seidel", lg::IntegratorKind::RK4, "rk4 h=1e-4", 0.2},
      {lg::MultiplierSolver::GaussSeidel, "gauss-seidel", lg::IntegratorKind::DormandPrince, "dopri5 rtol=1e-6", 1.0},
      {lg::MultiplierSolver::GaussSeidel, "gauss-seidel", lg::IntegratorKind::Ros34pw2, "ros34pw2 rtol=1e-6", 1.0},
  };
  std::printf("\n%-13s %-19s %7s %8s %10s %9s %11s %13s %10s\n", "solver", "integrator", "sim [s]", "steps", "RHS evals",
              "wall [s]", "steps/s", "RHS evals/s", "max |C|");
  std::vector<Row> rows;
  for (const Config& c : configs) {
    Row r = run(sc, c.solver, c.integ, c.duration, false);
    r.solver = c.sName;
    r.integrator = c.iName;
    std::printf("%-13s %-19s %7.2f %8ld %10ld %9.3f %11.0f %13.0f %10.1e\n", r.solver, r.integrator, c.duration, r.steps,
                r.rhs, r.wall, r.steps / r.wall, r.rhs / r.wall, r.violation);
    Row p = run(sc, c.solver, c.integ, c.duration, true);
    r.timer = p.timer;
    r.profiledWall = p.wall;
    rows.push_back(r);
  }
  std::printf("\nper-stage time, profiled runs (Settings::profile = true; %% of the profiled wall time, mean us per call)\n");
  std::printf("%-13s %-19s %9s", "solver", "integrator", "wall [s]");
  for (int st = 0; st < lg::kStageCount; ++st) std::printf(" %17s", lg::stageName(st));
  std::printf("\n");
  for (const Row& r : rows) {
    std::printf("%-13s %-19s %9.3f", r.solver, r.integrator, r.profiledWall);
    for (int st = 0; st < lg::kStageCount; ++st) {
      if (r.timer.calls[st] == 0) {
        std::printf(" %17s", "-");
        continue;
      }
      char cell[64];
      std::snprintf(cell, sizeof cell, "%4.1f%% %6.2fus", 100.0 * r.timer.seconds[st] / r.profiledWall,
                    1e6 * r.timer.seconds[st] / r.timer.calls[st]);
      std::printf(" %17s", cell);
    }
    std::printf("\n");
  }
  std::printf("(stages nest: kinematics/forces/rows/multipliers also run inside stabilise and events)\n");
  return 0;
}
