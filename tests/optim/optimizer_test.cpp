// The optimiser on analytic problems (no simulator): known optima, constraints native and by
// penalty, failures, stop reasons, forced stop and the evaluation cache.
#include <cmath>

#include "optim/optimizer.hpp"

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

using namespace lg::optim;

namespace {

// min (x - 0.7)^2 + (log10 y - 0.5)^2  s.t.  g = x - 0.5 <= 0,  x in [0, 1], y in [1, 10] (log).
// Optimum: x = 0.5, y = 10^0.5.
Problem quadratic(bool withConstraint = true) {
  Problem p;
  p.variables = {{"x", 0.0, 1.0, 0.2, false, 0}, {"y", 1.0, 10.0, 1.5, true, 0}};
  if (withConstraint) {
    p.constraintNames = {"x_max"};
    p.constraintScales = {1.0};
  }
  p.evaluate = [withConstraint](const std::vector<double>& x) {
    Evaluation e;
    e.ok = true;
    e.objective = (x[0] - 0.7) * (x[0] - 0.7) + (std::log10(x[1]) - 0.5) * (std::log10(x[1]) - 0.5) + 1.0;
    if (withConstraint) e.constraints = {x[0] - 0.5};
    return e;
  };
  return p;
}

// The quadratic with its derivatives, and a minimax of two: f = max(f1, f2) with
// f1 = (x - 0.2)^2 + (log10 y - 0.5)^2 + 1 and f2 = (x - 0.8)^2 + (log10 y - 0.5)^2 + 1, whose
// minimum is at the kink x = 0.5 (f = 1.09), where a gradient method on the max itself stalls.
Problem withGradients(Problem p, bool minimax) {
  auto value = [minimax](const std::vector<double>& x, Evaluation& e) {
    const double ly = std::log10(x[1]), dly = 1.0 / (x[1] * std::log(10.0));
    if (!minimax) {
      e.objectiveGradient = {2 * (x[0] - 0.7), 2 * (ly - 0.5) * dly};
      return;
    }
    const double f1 = (x[0] - 0.2) * (x[0] - 0.2) + (ly - 0.5) * (ly - 0.5) + 1.0;
    const double f2 = (x[0] - 0.8) * (x[0] - 0.8) + (ly - 0.5) * (ly - 0.5) + 1.0;
    e.terms = {f1, f2};
    e.termGradients = {{2 * (x[0] - 0.2), 2 * (ly - 0.5) * dly}, {2 * (x[0] - 0.8), 2 * (ly - 0.5) * dly}};
    e.objective = std::max(f1, f2);
    e.objectiveGradient = f1 >= f2 ? e.termGradients[0] : e.termGradients[1];
  };
  auto inner = p.evaluate;
  p.worstOfTerms = minimax;
  p.evaluate = [inner, value](const std::vector<double>& x) {
    Evaluation e = inner(x);
    value(x, e);
    return e;
  };
  const bool constrained = !p.constraintNames.empty();
  p.evaluateGradient = [inner, value, constrained](const std::vector<double>& x) {
    Evaluation e = inner(x);
    value(x, e);
    if (constrained) e.constraintGradients = {{1.0, 0.0}};
    e.hasGradient = true;
    return e;
  };
  return p;
}

AlgorithmSettings algo(const std::string& name, int maxeval = 400) {
  AlgorithmSettings a;
  a.name = name;
  a.maxeval = maxeval;
  a.xtolRel = 1e-7;
  a.initialStep = 0.2;
  return a;
}

}  // namespace

TEST_CASE("optimizer: scaling maps the box exactly both ways", "[optim]") {
  const Variable lin{"a", -2.0, 6.0, 0.0, false, 0};
  const Variable lg{"b", 1e-5, 1e-3, 1e-4, true, 0};
  CHECK(toPhysical(lin, 0.25) == Approx(0.0));
  CHECK(toScaled(lin, 6.0) == Approx(1.0));
  CHECK(toPhysical(lg, 0.5) == Approx(1e-4));
  CHECK(toScaled(lg, 1e-3) == Approx(1.0));
}

TEST_CASE("optimizer: finds the known constrained optimum natively and by penalty", "[optim]") {
  for (const char* name : {"LN_COBYLA", "LN_BOBYQA", "LN_SBPLX", "LN_NELDERMEAD"}) {
    INFO(name);
    const OptimizationResult r = runOptimizer(quadratic(), algo(name));
    REQUIRE(r.feasible);
    CHECK(r.x[0] == Approx(0.5).margin(2e-3));
    CHECK(r.x[1] == Approx(std::sqrt(10.0)).epsilon(1e-2));
    CHECK(r.best.objective == Approx(1.0 + 0.04).margin(1e-4));
    CHECK(r.best.constraints[0] <= 0.0);
    CHECK(r.nloptCode > 0);
  }
}

TEST_CASE("optimizer: gradient algorithms find the known optimum, a minimax through its epigraph", "[optim][gradient]") {
  for (const char* name : {"LD_SLSQP", "LD_MMA", "LD_CCSAQ"}) {
    INFO(name);
    const OptimizationResult r = runOptimizer(withGradients(quadratic(), false), algo(name));
    REQUIRE(r.feasible);
    CHECK(r.x[0] == Approx(0.5).margin(1e-5));
    CHECK(r.x[1] == Approx(std::sqrt(10.0)).epsilon(1e-5));
    CHECK(r.best.objective == Approx(1.04).epsilon(1e-8));  // SLSQP 1e-15, MMA and CCSAQ 3e-9
    CHECK(r.evaluations < 60);
  }
  {
    const OptimizationResult r = runOptimizer(withGradients(quadratic(false), false), algo("LD_LBFGS"));
    CHECK(r.x[0] == Approx(0.7).margin(1e-5));
  }
  // the minimax: the epigraph (t, f_i - t <= 0) carries SLSQP to the kink
  for (const char* name : {"LD_SLSQP", "LD_MMA"}) {
    INFO(name);
    const OptimizationResult r = runOptimizer(withGradients(quadratic(false), true), algo(name));
    CHECK(r.x[0] == Approx(0.5).margin(1e-5));
    CHECK(r.x[1] == Approx(std::sqrt(10.0)).epsilon(1e-5));
    CHECK(r.best.objective == Approx(1.09).epsilon(1e-7));  // MMA 3e-8
  }
  // a gradient algorithm on a problem without derivatives says so
  const OptimizationResult none = runOptimizer(quadratic(), algo("LD_SLSQP"));
  CHECK(none.reason.find("needs the derivatives of the problem") != std::string::npos);
}

TEST_CASE("optimizer: global algorithms with a local optimiser find the optimum", "[optim]") {
  AlgorithmSettings a = algo("GN_MLSL_LDS", 1500);
  a.local = "LN_BOBYQA";
  a.xtolRel = 1e-6;
  a.seed = 7;
  const OptimizationResult r = runOptimizer(quadratic(false), a);
  CHECK(r.x[0] == Approx(0.7).margin(2e-3));
  CHECK(r.x[1] == Approx(std::sqrt(10.0)).epsilon(1e-2));
}

TEST_CASE("optimizer: maximisation", "[optim]") {
  Problem p = quadratic(false);
  p.maximize = true;
  auto inner = p.evaluate;
  p.evaluate = [inner](const std::vector<double>& x) {
    Evaluation e = inner(x);
    e.objective = 3.0 - e.objective;
    return e;
  };
  const OptimizationResult r = runOptimizer(p, algo("LN_COBYLA"));
  CHECK(r.x[0] == Approx(0.7).margin(2e-3));
  CHECK(r.best.objective == Approx(2.0).margin(1e-5));
}

TEST_CASE("optimizer: failed evaluations are infeasible, logged and never crash", "[optim]") {
  Problem p = quadratic();
  auto inner = p.evaluate;
  int failures = 0;
  p.evaluate = [inner](const std::vector<double>& x) {
    if (x[1] > 5.0) {  // a region where the "simulation" fails
      Evaluation e;
      e.message = "diverged";
      return e;
    }
    if (x[1] > 4.5) {  // and one where it returns NaN
      Evaluation e = inner(x);
      e.objective = std::nan("");
      return e;
    }
    return inner(x);
  };
  Observer obs;
  obs.onEvaluation = [&](const EvaluationRecord& r) {
    if (!r.evaluation.ok) {
      ++failures;
      CHECK_FALSE(r.feasible);
      CHECK_FALSE(r.evaluation.message.empty());
    }
  };
  AlgorithmSettings a = algo("LN_COBYLA");
  a.initialStep = 0.9;  // jumps into the failing region at once
  const OptimizationResult r = runOptimizer(p, a, obs);
  CHECK(failures > 0);
  REQUIRE(r.feasible);
  CHECK(r.x[1] <= 4.5);
}

TEST_CASE("optimizer: a maxeval stop says so, not converged", "[optim]") {
  const OptimizationResult r = runOptimizer(quadratic(), algo("LN_COBYLA", 5));
  CHECK(r.evaluations == 5);
  CHECK(r.reason == "stopped: maxeval reached");
  CHECK_FALSE(r.converged);
  CHECK(r.nloptName == "NLOPT_MAXEVAL_REACHED");
}

TEST_CASE("optimizer: a stop request ends the run with the best design so far", "[optim]") {
  int n = 0;
  Observer obs;
  obs.onEvaluation = [&](const EvaluationRecord&) { ++n; };
  obs.stopRequested = [&] { return n >= 8; };
  const OptimizationResult r = runOptimizer(quadratic(), algo("LN_COBYLA"), obs);
  CHECK(r.reason.rfind("stopped: interrupted", 0) == 0);
  CHECK(r.evaluations == 7);
  CHECK(r.history.size() == 8u);
  CHECK(r.feasible);
  CHECK(std::isfinite(r.best.objective));
}

TEST_CASE("optimizer: same seed, same bits, and a cache replays a run without evaluating", "[optim]") {
  AlgorithmSettings a = algo("GN_CRS2_LM", 200);
  a.seed = 42;
  const OptimizationResult r1 = runOptimizer(quadratic(), a);
  const OptimizationResult r2 = runOptimizer(quadratic(), a);
  REQUIRE(r1.history.size() == r2.history.size());
  for (size_t i = 0; i < r1.history.size(); ++i) CHECK(bitsOf(r1.history[i].x) == bitsOf(r2.history[i].x));
  EvaluationCache cache;
  for (const auto& h : r1.history) cache.emplace(bitsOf(h.x), h.evaluation);
  Problem p = quadratic();
  int calls = 0;
  auto inner = p.evaluate;
  p.evaluate = [&](const std::vector<double>& x) { ++calls; return inner(x); };
  const OptimizationResult r3 = runOptimizer(p, a, {}, &cache);
  CHECK(calls == 0);
  CHECK(r3.simulations == 0);
  CHECK(bitsOf(r3.x) == bitsOf(r1.x));
}

TEST_CASE("optimizer: algorithm names are checked", "[optim]") {
  CHECK(checkAlgorithm("LN_COBYLA", "").empty());
  CHECK(checkAlgorithm("GN_MLSL_LDS", "LN_BOBYQA").empty());
  CHECK_FALSE(checkAlgorithm("LN_FOO", "").empty());
  CHECK(checkAlgorithm("LD_MMA", "").empty());
  CHECK(checkAlgorithm("LD_SLSQP", "").empty());
  CHECK(checkAlgorithm("GD_MLSL_LDS", "LD_SLSQP").empty());
  CHECK_FALSE(checkAlgorithm("LD_TNEWTON", "").empty());
  CHECK_FALSE(checkAlgorithm("GD_STOGO", "").empty());
  CHECK_FALSE(checkAlgorithm("GD_MLSL", "LN_BOBYQA").empty());
  CHECK_FALSE(checkAlgorithm("GN_MLSL", "LD_MMA").empty());
  CHECK(usesGradients("LD_SLSQP", ""));
  CHECK(usesGradients("GD_MLSL", "LD_MMA"));
  CHECK_FALSE(usesGradients("LN_COBYLA", ""));
  CHECK_FALSE(checkAlgorithm("LN_COBYLA", "LN_BOBYQA").empty());
  CHECK_FALSE(checkAlgorithm("GN_MLSL_LDS", "GN_DIRECT").empty());
}
