// NLopt driver (optimizer.hpp).
#include "optim/optimizer.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>

#include <nlopt.hpp>

namespace lg::optim {

bool nativeConstraints(const std::string& a) {
  return a == "LN_COBYLA" || a == "GN_ISRES" || a == "GN_AGS" || a == "AUGLAG" || a == "LN_AUGLAG" ||
         a == "AUGLAG_EQ" || a == "LN_AUGLAG_EQ" || a == "LD_SLSQP" || a == "LD_MMA" || a == "LD_CCSAQ";
}

double toPhysical(const Variable& v, double u) {
  if (v.log) return std::exp(std::log(v.lower) + u * (std::log(v.upper) - std::log(v.lower)));
  return v.lower + u * (v.upper - v.lower);
}
double toScaled(const Variable& v, double x) {
  if (v.log) return (std::log(x) - std::log(v.lower)) / (std::log(v.upper) - std::log(v.lower));
  return (x - v.lower) / (v.upper - v.lower);
}
std::vector<double> toPhysical(const std::vector<Variable>& vars, const std::vector<double>& u) {
  std::vector<double> x(vars.size());
  for (size_t i = 0; i < vars.size(); ++i) x[i] = toPhysical(vars[i], u[i]);
  return x;
}
std::vector<double> toScaled(const std::vector<Variable>& vars, const std::vector<double>& x) {
  std::vector<double> u(vars.size());
  for (size_t i = 0; i < vars.size(); ++i) u[i] = std::clamp(toScaled(vars[i], x[i]), 0.0, 1.0);
  return u;
}

namespace {

bool startsWith(const std::string& s, const char* p) { return s.rfind(p, 0) == 0; }

bool needsLocal(const std::string& a) {
  return a == "GN_MLSL" || a == "GN_MLSL_LDS" || a == "G_MLSL" || a == "G_MLSL_LDS" || a == "GD_MLSL" ||
         a == "GD_MLSL_LDS" || a == "AUGLAG" || a == "AUGLAG_EQ" || a == "LN_AUGLAG" || a == "LN_AUGLAG_EQ";
}

bool gradientLocal(const std::string& a) { return a == "LD_SLSQP" || a == "LD_MMA" || a == "LD_CCSAQ" || a == "LD_LBFGS"; }

// Sum of the positive parts of the scaled constraints.
double violation(const std::vector<double>& ghat) {
  double v = 0;
  for (double g : ghat) v += std::max(0.0, g);
  return v;
}

struct Point {  // what NLopt sees at one u
  double fhat = kFailValue;
  std::vector<double> ghat;
  std::vector<double> terms;  // scaled objective terms (epigraph)
  // derivatives with respect to u (when the evaluation has them)
  bool hasGradient = false;
  std::vector<double> dfhat;
  std::vector<std::vector<double>> dterms, dghat;
};

struct Context {
  const Problem* p = nullptr;
  const AlgorithmSettings* a = nullptr;
  const Observer* obs = nullptr;
  const EvaluationCache* resume = nullptr;
  nlopt::opt* opt = nullptr;
  bool penalised = false;
  bool gradient = false;   // the algorithm uses derivatives
  bool epigraph = false;   // NLopt's variables are (u, t): minimise t, terms - t <= 0
  size_t nv = 0;           // design variables
  size_t nTerms = 0;       // epigraph terms
  double fscale = 1;
  std::vector<double> u0, x0;  // initial design: u0 maps back to x0 exactly
  EvaluationCache seen;        // this run's evaluations
  OptimizationResult* out = nullptr;
  bool stopped = false;
  // last point whose constraints NLopt may ask for
  std::vector<double> lastU;
  Point last;
};

double clamp01(double u) { return std::isnan(u) ? 0.0 : std::min(1.0, std::max(0.0, u)); }

// u -> x, exact at the bounds and at the initial design.
std::vector<double> physical(const Context& c, const double* u) {
  const auto& vars = c.p->variables;
  std::vector<double> x(vars.size());
  for (size_t i = 0; i < vars.size(); ++i) {
    const double ui = clamp01(u[i]);
    if (ui == c.u0[i]) x[i] = c.x0[i];
    else if (ui == 0.0) x[i] = vars[i].lower;
    else if (ui == 1.0) x[i] = vars[i].upper;
    else x[i] = std::clamp(toPhysical(vars[i], ui), vars[i].lower, vars[i].upper);
  }
  return x;
}

// Marks non-finite results as failures.
void sanitize(Evaluation& e, size_t nConstraints) {
  if (e.ok && !std::isfinite(e.objective)) {
    e.ok = false;
    e.message = "non-finite objective";
  }
  if (e.ok && e.constraints.size() != nConstraints) {
    e.ok = false;
    e.message = "the evaluation returned " + std::to_string(e.constraints.size()) + " constraint values, expected " +
                std::to_string(nConstraints);
  }
  for (size_t j = 0; e.ok && j < e.constraints.size(); ++j)
    if (!std::isfinite(e.constraints[j])) {
      e.ok = false;
      e.message = "non-finite constraint value";
    }
  if (!e.ok && e.message.empty()) e.message = "evaluation failed";
}

// dx_i/du_i of the map u -> x at x.
double dxdu(const Variable& v, double x) {
  return v.log ? x * (std::log(v.upper) - std::log(v.lower)) : v.upper - v.lower;
}

Point scaledPoint(const Context& c, const Evaluation& e, const std::vector<double>* x = nullptr) {
  Point pt;
  const size_t m = c.p->constraintNames.size();
  if (!e.ok) {
    pt.fhat = kFailValue;
    pt.ghat.assign(m, kFailValue);
    pt.terms.assign(c.nTerms, kFailValue);
    return pt;
  }
  const double sign = c.p->maximize ? -1.0 : 1.0;
  pt.fhat = sign * e.objective / c.fscale;
  pt.ghat.resize(m);
  std::vector<double> gs(m, 1.0);
  for (size_t j = 0; j < m; ++j) {
    gs[j] = j < c.p->constraintScales.size() && c.p->constraintScales[j] > 0 ? c.p->constraintScales[j] : 1.0;
    pt.ghat[j] = e.constraints[j] / gs[j];
  }
  for (size_t i = 0; i < c.nTerms; ++i) pt.terms.push_back(i < e.terms.size() ? sign * e.terms[i] / c.fscale : kFailValue);
  if (e.hasGradient && x) {
    pt.hasGradient = true;
    const size_t n = c.nv;
    auto map = [&](const std::vector<double>& d, double scale) {
      std::vector<double> out(n, 0.0);
      for (size_t i = 0; i < n && i < d.size(); ++i) out[i] = d[i] * dxdu(c.p->variables[i], (*x)[i]) / scale;
      return out;
    };
    pt.dfhat = map(e.objectiveGradient, sign * c.fscale);
    for (size_t i = 0; i < c.nTerms; ++i)
      pt.dterms.push_back(i < e.termGradients.size() ? map(e.termGradients[i], sign * c.fscale) : std::vector<double>(n, 0.0));
    for (size_t j = 0; j < m; ++j)
      pt.dghat.push_back(j < e.constraintGradients.size() ? map(e.constraintGradients[j], gs[j]) : std::vector<double>(n, 0.0));
  }
  return pt;
}

// True if record a is better than b (documented in optimizer.hpp).
bool better(const Context& c, const EvaluationRecord& a, const EvaluationRecord& b) {
  if (a.feasible != b.feasible) return a.feasible;
  if (a.evaluation.ok != b.evaluation.ok) return a.evaluation.ok;
  if (!a.evaluation.ok) return false;
  if (a.feasible) {
    const double fa = c.p->maximize ? -a.evaluation.objective : a.evaluation.objective;
    const double fb = c.p->maximize ? -b.evaluation.objective : b.evaluation.objective;
    return fa < fb;
  }
  return violation(scaledPoint(c, a.evaluation).ghat) < violation(scaledPoint(c, b.evaluation).ghat);
}

// Evaluates x (through the caches; with derivatives for a gradient algorithm: a cached evaluation
// without them is evaluated again); never throws.
Evaluation evaluateCached(Context& c, const std::vector<double>& x, bool* cached) {
  const auto key = bitsOf(x);
  auto usable = [&](const Evaluation& e) { return !c.gradient || e.hasGradient || !e.ok; };
  if (auto it = c.seen.find(key); it != c.seen.end() && usable(it->second)) {
    *cached = true;
    return it->second;
  }
  Evaluation e;
  *cached = false;
  if (c.resume) {
    if (auto it = c.resume->find(key); it != c.resume->end() && usable(it->second)) {
      e = it->second;
      *cached = true;
    }
  }
  if (!*cached) {
    try {
      e = c.gradient ? c.p->evaluateGradient(x) : c.p->evaluate(x);
    } catch (const std::exception& ex) {
      e = Evaluation{};
      e.ok = false;
      e.message = std::string("evaluation threw: ") + ex.what();
    } catch (...) {
      e = Evaluation{};
      e.ok = false;
      e.message = "evaluation threw an unknown exception";
    }
    sanitize(e, c.p->constraintNames.size());
  }
  return e;
}

bool stopRequested(const Context& c) { return c.obs && c.obs->stopRequested && c.obs->stopRequested(); }

// Records one evaluation (index = out->history.size()).
void record(Context& c, const std::vector<double>& x, const Evaluation& e, bool cached, double merit) {
  EvaluationRecord r;
  r.index = static_cast<int>(c.out->history.size());
  r.x = x;
  r.evaluation = e;
  r.feasible = isFeasible(e);
  r.cached = cached;
  r.merit = merit;
  if (!cached) ++c.out->simulations;
  c.seen.insert_or_assign(bitsOf(x), e);
  if (c.out->history.empty() || better(c, r, c.out->history[c.out->bestIndex])) {
    c.out->bestIndex = r.index;
    c.out->best = e;
    c.out->x = x;
    c.out->feasible = r.feasible;
  }
  if (c.obs && c.obs->onEvaluation) c.obs->onEvaluation(r);
  EvaluationRecord light = r;
  light.evaluation.detail.reset();  // the history keeps numbers, not the problem's detail
  c.out->history.push_back(std::move(light));
  c.out->evaluations = r.index;
}

// The merit NLopt minimises at a point, and its gradient in u (when asked).
double merit(const Context& c, const Point& pt, const double* u, double* grad) {
  const size_t n = c.nv + (c.epigraph ? 1 : 0);
  if (grad) std::fill(grad, grad + n, 0.0);
  if (c.epigraph) {  // minimise t
    if (grad) grad[c.nv] = 1.0;
    return u[c.nv];
  }
  double f = pt.fhat;
  if (grad && pt.hasGradient) std::copy(pt.dfhat.begin(), pt.dfhat.end(), grad);
  if (c.penalised) {
    f += c.a->penalty * violation(pt.ghat);
    if (grad && pt.hasGradient)
      for (size_t j = 0; j < pt.ghat.size(); ++j)
        if (pt.ghat[j] > 0)
          for (size_t i = 0; i < c.nv; ++i) grad[i] += c.a->penalty * pt.dghat[j][i];
  }
  return f;
}

// The point at u: evaluated (and recorded) once, then reused by the constraints.
bool pointAt(Context& c, const double* u, unsigned n, bool recordIt, double meritForRecord = 0) {
  if (c.lastU.size() == n && std::equal(u, u + n, c.lastU.begin())) return true;
  const std::vector<double> x = physical(c, u);
  bool cached = false;
  const Evaluation e = evaluateCached(c, x, &cached);
  if (!cached && stopRequested(c)) return false;  // interrupted in the middle: not a result of the design
  c.lastU.assign(u, u + n);
  c.last = scaledPoint(c, e, &x);
  if (recordIt) record(c, x, e, cached, meritForRecord);
  else if (!cached) c.seen.insert_or_assign(bitsOf(x), e);
  return true;
}

double objectiveCallback(unsigned n, const double* u, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  if (grad) std::fill(grad, grad + n, 0.0);
  if (c.stopped || stopRequested(c)) {
    c.stopped = true;
    c.opt->force_stop();
    return kFailValue;
  }
  const std::vector<double> x = physical(c, u);
  bool cached = false;
  const Evaluation e = evaluateCached(c, x, &cached);
  if (!cached && stopRequested(c)) {  // interrupted in the middle: not a result of the design
    c.stopped = true;
    c.opt->force_stop();
    return kFailValue;
  }
  c.lastU.assign(u, u + n);
  c.last = scaledPoint(c, e, &x);
  const double f = merit(c, c.last, u, grad);
  record(c, x, e, cached, f);
  return f;
}

// The constraints NLopt sees: with the epigraph first the terms' fhat_i - t, then every ghat_j.
void constraintCallback(unsigned m, double* result, unsigned n, const double* u, double* grad, void* data) {
  Context& c = *static_cast<Context*>(data);
  if (grad) std::fill(grad, grad + static_cast<size_t>(m) * n, 0.0);
  if (!pointAt(c, u, n, false)) {  // interrupted: any value will do, NLopt is being stopped
    std::fill(result, result + m, kFailValue);
    c.stopped = true;
    c.opt->force_stop();
    return;
  }
  const Point& pt = c.last;
  unsigned row = 0;
  if (c.epigraph)
    for (size_t i = 0; i < c.nTerms; ++i, ++row) {
      result[row] = pt.terms[i] - u[c.nv];
      if (grad) {
        if (pt.hasGradient) std::copy(pt.dterms[i].begin(), pt.dterms[i].end(), grad + static_cast<size_t>(row) * n);
        grad[static_cast<size_t>(row) * n + c.nv] = -1.0;
      }
    }
  for (size_t j = 0; j < pt.ghat.size(); ++j, ++row) {
    result[row] = pt.ghat[j];
    if (grad && pt.hasGradient) std::copy(pt.dghat[j].begin(), pt.dghat[j].end(), grad + static_cast<size_t>(row) * n);
  }
}

}  // namespace

ConstraintHandling constraintHandling(const std::string& a) {
  if (nativeConstraints(a)) return ConstraintHandling::Native;
  if (startsWith(a, "LN_")) return ConstraintHandling::AugmentedLagrangian;
  return ConstraintHandling::Penalty;
}

std::string describeConstraintHandling(const std::string& a, double penalty) {
  switch (constraintHandling(a)) {
    case ConstraintHandling::Native: return "NLopt inequality constraints";
    case ConstraintHandling::AugmentedLagrangian: return "augmented Lagrangian (NLopt LN_AUGLAG around " + a + ")";
    default: {
      char b[32];
      std::snprintf(b, sizeof b, "%g", penalty);
      return std::string("exact L1 penalty, weight ") + b;
    }
  }
}

bool isFeasible(const Evaluation& e) {
  if (!e.ok || !std::isfinite(e.objective)) return false;
  for (double g : e.constraints)
    if (!(g <= 0)) return false;
  return true;
}

std::vector<std::uint64_t> bitsOf(const std::vector<double>& x) {
  std::vector<std::uint64_t> b(x.size());
  for (size_t i = 0; i < x.size(); ++i) std::memcpy(&b[i], &x[i], sizeof(double));
  return b;
}

std::string checkAlgorithm(const std::string& name, const std::string& local) {
  const nlopt_algorithm a = nlopt_algorithm_from_string(name.c_str());
  if (a < 0)
    return "'" + name + "' is not an NLopt algorithm (e.g. LN_COBYLA, LN_BOBYQA, LN_SBPLX, LN_NELDERMEAD, "
           "GN_DIRECT_L, GN_CRS2_LM, GN_ISRES, GN_MLSL_LDS)";
  if (startsWith(name, "LD_") && !gradientLocal(name))
    return "'" + name + "' is not one of the gradient algorithms supported: LD_SLSQP, LD_MMA, LD_CCSAQ, LD_LBFGS "
           "(bounds only), GD_MLSL or GD_MLSL_LDS with an LD local";
  if (startsWith(name, "GD_") && name != "GD_MLSL" && name != "GD_MLSL_LDS")
    return "'" + name + "' is not supported: use GD_MLSL or GD_MLSL_LDS with an LD local, or a GN_ algorithm";
  if (name == "LN_NEWUOA") return "'LN_NEWUOA' ignores bounds: use LN_NEWUOA_BOUND or LN_BOBYQA";
  const bool gradientGlobal = name == "GD_MLSL" || name == "GD_MLSL_LDS";
  if (!local.empty()) {
    if (!needsLocal(name)) return "local optimiser '" + local + "' is only used by MLSL and AUGLAG algorithms, not " + name;
    const nlopt_algorithm l = nlopt_algorithm_from_string(local.c_str());
    if (l < 0) return "local optimiser '" + local + "' is not an NLopt algorithm";
    if (gradientGlobal && !gradientLocal(local))
      return "local optimiser '" + local + "' of " + name + " must be a gradient algorithm: LD_SLSQP, LD_MMA, LD_CCSAQ, LD_LBFGS";
    if (!gradientGlobal && (!startsWith(local, "LN_") || local == "LN_NEWUOA" || needsLocal(local)))
      return "local optimiser '" + local + "' must be a bounded derivative-free local algorithm (e.g. LN_BOBYQA, LN_SBPLX)";
  }
  return "";
}

bool usesGradients(const std::string& name, const std::string& local) {
  return startsWith(name, "LD_") || startsWith(name, "GD_") || (needsLocal(name) && startsWith(local, "LD_"));
}

std::string describeResult(int code, bool* converged) {
  bool conv = false;
  std::string s;
  switch (code) {
    case NLOPT_SUCCESS: s = "converged: the algorithm's own stopping rule"; conv = true; break;
    case NLOPT_STOPVAL_REACHED: s = "stopped: stopval reached"; break;
    case NLOPT_FTOL_REACHED: s = "converged: ftol_rel reached"; conv = true; break;
    case NLOPT_XTOL_REACHED: s = "converged: xtol_rel reached"; conv = true; break;
    case NLOPT_MAXEVAL_REACHED: s = "stopped: maxeval reached"; break;
    case NLOPT_MAXTIME_REACHED: s = "stopped: maxtime reached"; break;
    case NLOPT_FORCED_STOP: s = "stopped: interrupted (forced stop)"; break;
    case NLOPT_ROUNDOFF_LIMITED: s = "stopped: roundoff limited (no further progress possible)"; break;
    case NLOPT_OUT_OF_MEMORY: s = "failed: out of memory"; break;
    case NLOPT_INVALID_ARGS: s = "failed: invalid arguments"; break;
    default: s = "failed: NLopt failure"; break;
  }
  if (converged) *converged = conv;
  return s;
}

OptimizationResult runOptimizer(const Problem& p, const AlgorithmSettings& a, const Observer& obs,
                                const EvaluationCache* cache) {
  const auto t0 = std::chrono::steady_clock::now();
  OptimizationResult out;
  const unsigned n = static_cast<unsigned>(p.variables.size());
  Context c;
  c.p = &p;
  c.a = &a;
  c.obs = &obs;
  c.resume = cache;
  c.out = &out;
  const ConstraintHandling mode = p.constraintNames.empty() ? ConstraintHandling::None : constraintHandling(a.name);
  c.penalised = mode == ConstraintHandling::Penalty;
  const bool wrap = mode == ConstraintHandling::AugmentedLagrangian;
  c.gradient = usesGradients(a.name, a.local) && p.evaluateGradient != nullptr;
  c.nv = n;
  // The epigraph form for a gradient method on the worst of several terms (native constraints only).
  c.epigraph = c.gradient && p.worstOfTerms && !c.penalised;
  for (const auto& v : p.variables) {
    c.x0.push_back(v.initial);
    c.u0.push_back(clamp01(toScaled(v, v.initial)));
  }
  out.x0 = c.x0;

  nlopt::srand(a.seed);  // always: stochastic algorithms and MLSL repeat bit for bit

  // The initial design (record 0) also fixes the objective scale. Cut off by a stop request, it is no
  // result of the design: nothing is recorded and the run ends there.
  {
    bool cached = false;
    const Evaluation e = evaluateCached(c, c.x0, &cached);
    if (!cached && stopRequested(c)) {
      out.nloptCode = NLOPT_FORCED_STOP;
      out.nloptName = "NLOPT_FORCED_STOP";
      out.reason = "stopped: interrupted before the baseline evaluation finished (no design evaluated)";
      out.interrupted = true;
      out.wallTime = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      return out;
    }
    out.initial = e;
    c.fscale = p.objectiveScale > 0 ? p.objectiveScale
               : (e.ok && std::isfinite(e.objective) && e.objective != 0) ? std::abs(e.objective)
                                                                          : 1.0;
    out.objectiveScale = c.fscale;
    c.nTerms = c.epigraph ? e.terms.size() : 0;
    if (c.epigraph && c.nTerms < 2) c.epigraph = false;  // one term: no kink to remove
    if (!c.epigraph) c.nTerms = 0;
    const Point pt = scaledPoint(c, e);
    record(c, c.x0, e, cached, c.penalised ? pt.fhat + a.penalty * violation(pt.ghat) : pt.fhat);
  }

  std::string error;
  if (std::string rule = checkAlgorithm(a.name, a.local); !rule.empty()) error = rule;
  if (error.empty() && usesGradients(a.name, a.local) && !p.evaluateGradient)
    error = "'" + a.name + "' needs the derivatives of the problem, and it has none";
  if (error.empty() && a.name == "LD_LBFGS" && !p.constraintNames.empty())
    error = "LD_LBFGS handles bounds only: use LD_SLSQP, LD_MMA or LD_CCSAQ for a problem with constraints";
  if (error.empty() && !out.initial.ok && c.epigraph) c.epigraph = false, c.nTerms = 0;
  if (error.empty() && !stopRequested(c)) {
    try {
      const unsigned nn = n + (c.epigraph ? 1u : 0u);
      nlopt::opt opt(wrap ? "LN_AUGLAG" : a.name.c_str(), nn);
      c.opt = &opt;
      std::vector<double> lower(nn, 0.0), upper(nn, 1.0);
      std::vector<double> u = c.u0;
      if (c.epigraph) {  // t: the worst scaled term, started at the baseline's
        const Point p0 = scaledPoint(c, out.initial);
        const double t0 = *std::max_element(p0.terms.begin(), p0.terms.end());
        lower[n] = t0 - 100.0;
        upper[n] = t0 + 100.0;
        u.push_back(t0);
      }
      opt.set_lower_bounds(lower);
      opt.set_upper_bounds(upper);
      opt.set_min_objective(objectiveCallback, &c);
      const size_t mAll = c.nTerms + p.constraintNames.size();
      if (!c.penalised && mAll > 0) opt.add_inequality_mconstraint(constraintCallback, &c, std::vector<double>(mAll, 0.0));
      if (a.maxeval > 0) opt.set_maxeval(a.maxeval);
      if (a.maxtime > 0) opt.set_maxtime(a.maxtime);
      if (a.xtolRel > 0) {
        opt.set_xtol_rel(a.xtolRel);
        opt.set_xtol_abs(std::vector<double>(nn, a.xtolRel));  // the box has width 1
      }
      if (a.ftolRel > 0) opt.set_ftol_rel(a.ftolRel);
      if (a.initialStep > 0) opt.set_initial_step(std::vector<double>(nn, a.initialStep));
      if (wrap) {  // the algorithm solves the augmented-Lagrangian subproblems
        nlopt::opt local(a.name.c_str(), n);
        if (a.xtolRel > 0) {
          local.set_xtol_rel(a.xtolRel);
          local.set_xtol_abs(std::vector<double>(n, a.xtolRel));
        }
        if (a.ftolRel > 0) local.set_ftol_rel(a.ftolRel);
        if (!(a.xtolRel > 0) && !(a.ftolRel > 0)) local.set_ftol_rel(1e-6);
        if (a.initialStep > 0) local.set_initial_step(std::vector<double>(n, a.initialStep));
        opt.set_local_optimizer(local);
      } else if (needsLocal(a.name)) {
        const bool gd = a.name == "GD_MLSL" || a.name == "GD_MLSL_LDS";
        nlopt::opt local(a.local.empty() ? (gd ? "LD_MMA" : "LN_BOBYQA") : a.local.c_str(), nn);
        if (a.xtolRel > 0) {
          local.set_xtol_rel(a.xtolRel);
          local.set_xtol_abs(std::vector<double>(n, a.xtolRel));
        }
        if (a.ftolRel > 0) local.set_ftol_rel(a.ftolRel);
        if (!(a.xtolRel > 0) && !(a.ftolRel > 0)) local.set_ftol_rel(1e-6);
        opt.set_local_optimizer(local);
      }
      double f = 0;
      try {
        opt.optimize(u, f);
      } catch (const nlopt::forced_stop&) {
      } catch (const nlopt::roundoff_limited&) {
      } catch (const std::bad_alloc&) {
        error = "out of memory";
      } catch (const std::exception& e) {
        error = e.what();
      }
      out.nloptCode = static_cast<int>(opt.last_optimize_result());
      if (c.stopped) out.nloptCode = NLOPT_FORCED_STOP;
      c.opt = nullptr;
    } catch (const std::exception& e) {
      error = e.what();
      out.nloptCode = NLOPT_FAILURE;
      c.opt = nullptr;
    }
  } else if (error.empty()) {
    out.nloptCode = NLOPT_FORCED_STOP;
  } else {
    out.nloptCode = NLOPT_INVALID_ARGS;
  }
  const char* nm = nlopt_result_to_string(static_cast<nlopt_result>(out.nloptCode));
  out.nloptName = std::string("NLOPT_") + (nm ? nm : "UNKNOWN");
  out.reason = describeResult(out.nloptCode, &out.converged);
  out.interrupted = c.stopped || out.nloptCode == NLOPT_FORCED_STOP;
  if (!error.empty() && out.nloptCode < 0) out.reason += " (" + error + ")";
  out.wallTime = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace lg::optim
