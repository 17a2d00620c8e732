// The optimiser: NLopt over a Problem, independent of the simulator (an analytic Problem plugs in
// the same way as a drop-test study, see tests/optim/optimizer_test.cpp).
//
// Scaling. NLopt sees u in [0, 1]^n (study.hpp: linear or log map per variable), the objective
// fhat = s f / fscale (s = -1 when maximising; fscale = |f(initial)|, or 1 if that is 0 or failed)
// and the constraints ghat_j = g_j / gscale_j <= 0.
//
// Constraints (ConstraintHandling):
//  - Native: COBYLA, ISRES, AGS and the AUGLAG family get ghat_j as nlopt inequality constraints.
//  - AugmentedLagrangian: the other local derivative-free algorithms (LN_BOBYQA, LN_SBPLX,
//    LN_NELDERMEAD, LN_PRAXIS, LN_NEWUOA_BOUND) run inside NLopt's LN_AUGLAG, which hands them smooth
//    augmented-Lagrangian subproblems (their quadratic / simplex models break on a penalty's kink).
//    maxeval and maxtime count every evaluation of the subproblems.
//  - Penalty: global algorithms without constraints (DIRECT, CRS2, ESCH, MLSL, ...) minimise the
//    exact (L1) penalty function
//        phi(u) = fhat(u) + penalty * sum_j max(0, ghat_j(u)),
//    whose minimiser is the constrained one once penalty exceeds the largest Lagrange multiplier of
//    the scaled problem (default penalty = 100).
//
// Failures. An evaluation that fails (ok = false, or a non-finite objective or constraint) is
// infeasible: fhat = kFailValue and every ghat_j = kFailValue (finite, so NLopt's models survive),
// and its message is logged. Nothing throws out of the evaluation path.
//
// Best design. Feasible (every g_j <= 0, exactly) beats infeasible; among feasible designs the best
// objective wins, among infeasible ones the smallest sum_j max(0, ghat_j); ties keep the earlier.
// The best design is tracked here over every evaluation, not taken from NLopt's return value.
#pragma once

#include <cstdint>
#include <functional>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>


namespace lg::optim {

constexpr double kFailValue = 1e3;  // [-] scaled objective and constraints of a failed evaluation

// One variable of a problem between bounds (a drop-test study: a numeric scene parameter).
struct Variable {
  std::string path;      // its name (a study: the scene parameter path, e.g. "strut.f1")
  double lower = 0;      // [parameter units] lower bound
  double upper = 0;      // [parameter units] upper bound (> lower)
  double initial = 0;    // [parameter units] start value (default: the scene's value)
  bool log = false;      // optimise log(value) (needs lower > 0)
  int line = 0;          // where it was declared (a study: the line of its [[variable]] table)
};

// The optimiser works in scaled coordinates u in [0, 1]^n:
//   linear: x = lower + u (upper - lower),   log: x = lower (upper/lower)^u.
double toPhysical(const Variable& v, double u);
double toScaled(const Variable& v, double x);
std::vector<double> toPhysical(const std::vector<Variable>& vars, const std::vector<double>& u);
std::vector<double> toScaled(const std::vector<Variable>& vars, const std::vector<double>& x);

struct AlgorithmSettings {
  std::string name = "LN_COBYLA";  // NLopt algorithm name (nlopt_algorithm_from_string)
  std::string local;               // local optimiser of MLSL / AUGLAG (default LN_BOBYQA)
  int maxeval = 200;               // [-] 0: no limit
  double maxtime = 0;              // [s] 0: no limit
  double xtolRel = 1e-4;           // [-] on the scaled variables
  double ftolRel = 0;              // [-] 0: off
  unsigned seed = 1;               // nlopt::srand(seed), always called
  double penalty = 100;            // [-] exact-penalty weight (algorithms without native constraints)
  double initialStep = 0;          // [-] initial step in scaled units (0: NLopt's default)
};

// What a problem keeps of an evaluation beside its numbers (a drop-test study: the metrics of every
// case, optim/evaluator.hpp). The optimiser only carries it, and leaves it out of the history.
struct EvaluationDetail {
  virtual ~EvaluationDetail() = default;
};

// What one evaluation of a design returns (never throws).
struct Evaluation {
  bool ok = false;                  // false: the evaluation failed, 'message' says why
  std::string message;
  double objective = std::numeric_limits<double>::quiet_NaN();  // physical units
  std::vector<double> constraints;  // g_j in physical units; feasible when every g_j <= 0
  std::shared_ptr<const EvaluationDetail> detail;  // the problem's own detail (null when cached or none)
  double staticStroke = std::numeric_limits<double>::quiet_NaN();  // [m] when computed
  // The objective's terms f_i when it is their worst (Problem::worstOfTerms): the objective cases'.
  std::vector<double> terms;
  // Derivatives with respect to the variables (physical units), when evaluated with them.
  bool hasGradient = false;
  std::vector<double> objectiveGradient;                 // d objective / d x
  std::vector<std::vector<double>> termGradients;        // d f_i / d x
  std::vector<std::vector<double>> constraintGradients;  // d g_j / d x
};

// ok, finite and every constraint <= 0.
bool isFeasible(const Evaluation& e);

struct Problem {
  std::vector<Variable> variables;           // bounds, initial values, log flags
  std::vector<std::string> constraintNames;  // one per g_j
  std::vector<double> constraintScales;      // gscale_j > 0
  bool maximize = false;
  double objectiveScale = 0;                 // fscale; 0: |f(initial)| (1 if zero or failed)
  std::string objectiveName = "objective";
  // The objective is the worst of Evaluation::terms (their largest when minimising, smallest when
  // maximising): a gradient algorithm then solves NLopt's epigraph form (below).
  bool worstOfTerms = false;
  // Evaluates a design in physical units; must not throw.
  std::function<Evaluation(const std::vector<double>& x)> evaluate;
  // The same with the derivatives (hasGradient); null when the problem has none. Gradient algorithms
  // need it.
  std::function<Evaluation(const std::vector<double>& x)> evaluateGradient;
};

// One finished evaluation, as the history logs it.
struct EvaluationRecord {
  int index = 0;               // 0: the initial design; 1..: NLopt's calls in order
  std::vector<double> x;       // physical units
  Evaluation evaluation;
  bool feasible = false;
  bool cached = false;         // taken from the cache (same bits evaluated before or resumed)
  double merit = 0;            // [-] what NLopt saw (scaled; penalised where it applies)
};

// Evaluations known before the run, by the exact bits of x (resume).
using EvaluationCache = std::map<std::vector<std::uint64_t>, Evaluation>;
std::vector<std::uint64_t> bitsOf(const std::vector<double>& x);

struct Observer {
  std::function<void(const EvaluationRecord&)> onEvaluation;  // called in order, after each one
  std::function<bool()> stopRequested;                        // polled; true: nlopt forced stop
};

struct OptimizationResult {
  std::vector<double> x0;          // initial design (physical)
  Evaluation initial;
  std::vector<double> x;           // best design (physical)
  Evaluation best;
  int bestIndex = 0;
  bool feasible = false;           // best design feasible
  int evaluations = 0;             // NLopt calls (index of the last record)
  int simulations = 0;             // evaluations actually computed (not cached)
  int nloptCode = 0;               // nlopt::result
  std::string nloptName;           // e.g. "NLOPT_MAXEVAL_REACHED"
  std::string reason;              // "converged: xtol_rel reached", "stopped: maxeval reached", ...
  bool converged = false;
  bool interrupted = false;        // a stop request ended the run (Ctrl-C)
  double objectiveScale = 1;
  double wallTime = 0;             // [s]
  std::vector<EvaluationRecord> history;  // x, objective, feasibility per evaluation (no case detail)
};

// True where NLopt handles inequality constraints itself (COBYLA, ISRES, AGS, AUGLAG family); the
// other local algorithms run inside LN_AUGLAG, the global ones get an exact penalty (optimizer.hpp).
bool nativeConstraints(const std::string& algorithm);

enum class ConstraintHandling { None, Native, AugmentedLagrangian, Penalty };
ConstraintHandling constraintHandling(const std::string& algorithm);  // for a problem with constraints
std::string describeConstraintHandling(const std::string& algorithm, double penalty);

// Validates an algorithm name (and its local optimiser); returns an empty string or the rule broken.
std::string checkAlgorithm(const std::string& name, const std::string& local);

// True for the algorithms that use derivatives: LD_SLSQP, LD_MMA, LD_CCSAQ, LD_LBFGS (bounds only), and
// GD_MLSL / GD_MLSL_LDS around an LD local optimiser.
bool usesGradients(const std::string& name, const std::string& local);

// Runs NLopt; never throws for evaluation failures or NLopt stops (NLopt errors land in 'reason').
//
// Gradient algorithms. NLopt gets the derivatives of fhat and ghat_j with respect to u (the chain rule
// through the linear or log map of each variable). An objective that is the worst of several terms has a
// kink where the worst changes; a gradient method stalls there, so NLopt solves the epigraph form: one
// more variable t, the objective t, and one constraint fhat_i(u) - t <= 0 per term, t started at the
// baseline's worst term. The history logs the design at every evaluation as always.
OptimizationResult runOptimizer(const Problem& p, const AlgorithmSettings& a, const Observer& obs = {},
                                const EvaluationCache* cache = nullptr);

// "stopped: maxeval reached" etc. for an nlopt::result code.
std::string describeResult(int code, bool* converged = nullptr);

}  // namespace lg::optim
