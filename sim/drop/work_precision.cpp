// Work-precision data of a scene (sim/drop/work_precision.hpp).
#include "sim/drop/work_precision.hpp"

#include <algorithm>
#include <chrono>

#include "sim/drop/run.hpp"

namespace lg {

namespace {

struct Sweep {
  IntegratorKind kind;
  std::vector<double> tolerances;
};

// The settings of a work-precision diagram: each integrator from loose to tight.
std::vector<Sweep> sweeps(bool fast) {
  if (fast)
    return {{IntegratorKind::DormandPrince, {1e-2, 1e-4, 1e-6}},
            {IntegratorKind::Ros34pw2, {1e-2, 1e-3, 1e-4}},
            {IntegratorKind::Ros2, {1e-2, 1e-3}},
            {IntegratorKind::RK4, {1e-3, 2e-4}},
            {IntegratorKind::SemiImplicitEuler, {1e-4, 2e-5}}};
  return {{IntegratorKind::DormandPrince, {1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7}},
          {IntegratorKind::Ros34pw2, {3e-2, 1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5}},
          {IntegratorKind::Ros2, {3e-2, 1e-2, 3e-3, 1e-3, 1e-4}},
          {IntegratorKind::RK4, {1e-3, 5e-4, 2e-4, 1e-4}},
          {IntegratorKind::SemiImplicitEuler, {1e-4, 3e-5, 1e-5}}};
}

}  // namespace

std::vector<WorkPrecisionPoint> workPrecision(const Scene& scene, const std::vector<DropCase>& cases,
                                              const WorkPrecisionOptions& opt) {
  std::vector<WorkPrecisionPoint> points;
  for (const DropCase& c : cases) {
    const CaseMetrics ref = runCase(withSolver(scene, IntegratorKind::DormandPrince, opt.referenceRtol), c).metrics;
    for (const Sweep& sw : sweeps(opt.fast)) {
      for (double tol : sw.tolerances) {
        const Scene sc = withSolver(scene, sw.kind, tol);
        WorkPrecisionPoint p;
        p.caseName = c.name;
        p.integrator = integratorName(sw.kind);
        p.tolerance = tol;
        // Timed runs: the median of up to 'repetitions', fewer for a slow setting (0.3 s of runs at most).
        std::vector<double> times;
        CaseMetrics m;
        double spent = 0;
        for (int r = 0; r < std::max(1, opt.repetitions) && (r == 0 || spent < 0.3); ++r) {
          const auto a = std::chrono::steady_clock::now();
          m = runCase(sc, c).metrics;
          times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count());
          spent += times.back();
        }
        std::sort(times.begin(), times.end());
        p.timePerDrop = times[times.size() / 2];
        p.ok = m.ok && ref.ok;
        p.message = !ref.ok ? "reference run failed: " + ref.message : m.message;
        p.errors = metricErrors(m, ref);
        p.steps = m.steps;
        p.rhsEvaluations = m.rhs_evaluations;
        points.push_back(p);
      }
    }
  }
  return points;
}

}  // namespace lg
