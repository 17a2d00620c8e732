// bench_gradient [--repeat N]: what the exact gradient of the main study costs. At the shipped study's
// baseline (studies/seed_gear_min_peak.cfg: 5 variables, 3 steering cases, dopri5 rtol 1e-6), on one
// thread: one plain evaluation (the three drops), the full gradient (every variable, every case,
// forward mode through ceres::Jet), and central differences (2 x 5 more evaluations); and how far the
// differences' derivatives of the worst peak load are from the exact ones at the study's tolerance.
// Prints figures; never a test.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>

#include "apps/cli.hpp"
#include "optim/evaluator.hpp"
#include "optim/study.hpp"

namespace {
double seconds(const std::chrono::steady_clock::time_point& a) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count();
}
}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"The cost of the main study's exact gradient against one evaluation and central differences "
               "(run from the project root)"};
  lg::cli::addVersion(app, "bench_gradient");
  int repeat = 3;
  lg::cli::addInteger(app, "--repeat", repeat, "timed repetitions (median; default 3)", 1, 1000);
  if (const int rc = lg::cli::parse(app, argc, argv); rc >= 0) return rc;
  lg::optim::Study s;
  try {
    s = lg::optim::loadStudy("studies/seed_gear_min_peak.cfg");
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s (run from the project root)\n", e.what());
    return 2;
  }
  lg::optim::EvaluatorOptions o;
  o.threads = 1;
  std::vector<double> x;
  for (const auto& v : s.variables) x.push_back(v.initial);
  double tPlain = 1e300, tGrad = 1e300, tFd = 1e300;
  lg::optim::Evaluation plain, grad;
  std::vector<double> fd(x.size());
  for (int r = 0; r < repeat; ++r) {
    auto t = std::chrono::steady_clock::now();
    plain = lg::optim::evaluateDesign(s, x, o);
    tPlain = std::min(tPlain, seconds(t));
    t = std::chrono::steady_clock::now();
    grad = lg::optim::evaluateDesignGradient(s, x, o);
    tGrad = std::min(tGrad, seconds(t));
    t = std::chrono::steady_clock::now();
    for (size_t i = 0; i < x.size(); ++i) {
      const double h = 1e-4 * x[i];
      std::vector<double> a = x, b = x;
      a[i] += h;
      b[i] -= h;
      fd[i] = (lg::optim::evaluateDesign(s, a, o).objective - lg::optim::evaluateDesign(s, b, o).objective) / (2 * h);
    }
    tFd = std::min(tFd, seconds(t) + 0.0);
  }
  if (!plain.ok || !grad.ok) {
    std::fprintf(stderr, "error: the evaluation failed: %s%s\n", plain.message.c_str(), grad.message.c_str());
    return 1;
  }
  std::printf("main study at its baseline: %zu variables, %d steering cases, one thread, best of %d\n", x.size(),
              s.steeringCases(), repeat);
  std::printf("  one evaluation (values)            %8.1f ms\n", 1e3 * tPlain);
  std::printf("  exact gradient (values + d/dx)     %8.1f ms   %5.1f evaluations' worth\n", 1e3 * tGrad, tGrad / tPlain);
  std::printf("  central differences (2 x %zu runs)   %8.1f ms   %5.1f evaluations' worth\n", x.size(), 1e3 * tFd,
              tFd / tPlain);
  std::printf("  d(worst peak load)/dx: exact against central differences (relative step 1e-4, rtol 1e-6):\n");
  for (size_t i = 0; i < x.size(); ++i)
    std::printf("    %-14s exact %+.6e   differences %+.6e   rel. difference %.1e\n", s.variables[i].path.c_str(),
                grad.objectiveGradient[i], fd[i],
                std::abs(fd[i] - grad.objectiveGradient[i]) / std::max(std::abs(grad.objectiveGradient[i]), 1e-300));
  return 0;
}
