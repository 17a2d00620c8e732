// The Ceres fit of a calibration, its covariance and identifiability (fit.hpp).
#include "calib/fit.hpp"

#include "calib/exact_jacobian.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>

#include <boost/math/distributions/students_t.hpp>
#include <ceres/ceres.h>
#include <glog/logging.h>

namespace lg::calib {
namespace {

std::string number(double v, int digits = 4) {
  char b[32];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// Every measurement evaluated once per point Ceres announces; the cost functions read from here. The
// point lives in the parameter blocks Ceres updates before each announcement: 'u' (the parameters over
// their scales) and one block per fitted t_shift.
class Evaluations : public ceres::EvaluationCallback {
 public:
  Evaluations(const Calibration& c, const ResidualJacobian& rj, std::vector<double>& u, std::vector<double>& shifts)
      : c_(c), rj_(rj), u_(u), shifts_(shifts) {}

  Point point() const {
    Point p;
    for (std::size_t i = 0; i < c_.parameters.size(); ++i) p.x.push_back(u_[i] * c_.parameters[i].scale);
    p.shift = shifts_;
    return p;
  }
  void PrepareForEvaluation(bool jacobians, bool) override { ensure(jacobians); }
  // Evaluates at the blocks' current point unless that point (its bits) is evaluated already.
  void ensure(bool jacobians) {
    const Point p = point();
    if (valid_ && same(p, at_) && (withJacobians_ || !jacobians)) return;
    rj_.evaluate(p, jacobians, evals_);
    at_ = p;
    valid_ = true;
    withJacobians_ = jacobians;
    ++count_;
  }
  const MeasurementEval& eval(std::size_t m) const { return evals_[m]; }
  const std::vector<MeasurementEval>& evals() const { return evals_; }
  int count() const { return count_; }

 private:
  static bool same(const Point& a, const Point& b) {
    auto eq = [](const std::vector<double>& x, const std::vector<double>& y) {
      return x.size() == y.size() && (x.empty() || std::memcmp(x.data(), y.data(), x.size() * sizeof(double)) == 0);
    };
    return eq(a.x, b.x) && eq(a.shift, b.shift);
  }
  const Calibration& c_;
  const ResidualJacobian& rj_;
  std::vector<double>& u_;
  std::vector<double>& shifts_;
  std::vector<MeasurementEval> evals_;
  Point at_;
  bool valid_ = false, withJacobians_ = false;
  int count_ = 0;
};

// Residuals [begin, begin + count) of measurement m, read from the evaluations. Blocks: u (the scaled
// parameters) and, when the measurement fits it, its t_shift.
class ResidualRange final : public ceres::CostFunction {
 public:
  ResidualRange(const Evaluations& e, const Calibration& c, std::size_t m, Eigen::Index begin, int count)
      : e_(e), c_(c), m_(m), begin_(begin) {
    set_num_residuals(count);
    mutable_parameter_block_sizes()->push_back(static_cast<int>(c.parameters.size()));
    if (c.measurements[m].shift.fit) mutable_parameter_block_sizes()->push_back(1);
  }
  bool Evaluate(double const* const*, double* residuals, double** jacobians) const override {
    const MeasurementEval& ev = e_.eval(m_);
    if (!ev.ok) return false;
    const int n = num_residuals(), np = static_cast<int>(c_.parameters.size());
    for (int k = 0; k < n; ++k) residuals[k] = ev.r[begin_ + k];
    if (!jacobians) return true;
    if (jacobians[0])
      for (int k = 0; k < n; ++k)
        for (int i = 0; i < np; ++i) jacobians[0][k * np + i] = ev.J(begin_ + k, i) * c_.parameters[static_cast<std::size_t>(i)].scale;
    if (c_.measurements[m_].shift.fit && jacobians[1])
      for (int k = 0; k < n; ++k) jacobians[1][k] = ev.Jshift[begin_ + k];
    return true;
  }

 private:
  const Evaluations& e_;
  const Calibration& c_;
  std::size_t m_;
  Eigen::Index begin_;
};

class Progress final : public ceres::IterationCallback {
 public:
  explicit Progress(const FitOptions& o) : o_(o) {}
  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override {
    if (o_.progress) o_.progress(s.iteration, s.cost);
    return o_.stop && o_.stop() ? ceres::SOLVER_ABORT : ceres::SOLVER_CONTINUE;
  }

 private:
  const FitOptions& o_;
};

ceres::LossFunction* lossFunction(const FitSettings& f) {
  switch (f.loss) {
    case Loss::Huber: return new ceres::HuberLoss(f.lossScale);
    case Loss::Cauchy: return new ceres::CauchyLoss(f.lossScale);
    case Loss::SoftL1: return new ceres::SoftLOneLoss(f.lossScale);
    case Loss::Arctan: return new ceres::ArctanLoss(f.lossScale);
    default: return nullptr;
  }
}

// The stacked weighted Jacobian in the unknowns' units (parameters, then fitted shifts).
Eigen::MatrixXd stackedJacobian(const Calibration& c, const std::vector<MeasurementEval>& evals) {
  const std::size_t np = c.parameters.size();
  Eigen::MatrixXd J = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(c.residuals()), static_cast<Eigen::Index>(c.unknowns()));
  Eigen::Index row = 0, shiftCol = static_cast<Eigen::Index>(np);
  for (std::size_t m = 0; m < c.measurements.size(); ++m) {
    const Eigen::Index n = static_cast<Eigen::Index>(c.measurements[m].residuals());
    if (n > 0) J.block(row, 0, n, static_cast<Eigen::Index>(np)) = evals[m].J;
    if (c.measurements[m].shift.fit) {
      if (n > 0) J.block(row, shiftCol, n, 1) = evals[m].Jshift;
      ++shiftCol;
    }
    row += n;
  }
  return J;
}

// Names, units, values and bounds of the unknowns at a point.
void describeUnknowns(const Calibration& c, FitResult& r) {
  for (const auto& q : c.parameters) {
    r.names.push_back(q.path);
    r.units.push_back(q.unit);
    r.lower.push_back(q.lower);
    r.upper.push_back(q.upper);
  }
  for (const auto& m : c.measurements)
    if (m.shift.fit) {
      r.names.push_back(m.name + ".t_shift");
      r.units.push_back("s");
      r.lower.push_back(m.shift.lower);
      r.upper.push_back(m.shift.upper);
    }
}
std::vector<double> unknownsAt(const Calibration& c, const Point& p) {
  std::vector<double> v = p.x;
  for (std::size_t m = 0; m < c.measurements.size(); ++m)
    if (c.measurements[m].shift.fit) v.push_back(p.shift[m]);
  return v;
}

// ceres::Covariance of the unknowns (u scaled back to the parameters' units), times s^2.
void covariance(const Calibration& c, ceres::Problem& problem, std::vector<double>& u, std::vector<double>& shifts,
                FitResult& r) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  co.num_threads = 1;
  co.null_space_rank = 0;  // a rank-deficient Jacobian is refused (identifiability() has named it already)
  ceres::Covariance cov(co);
  std::vector<const double*> blocks{u.data()};
  for (std::size_t m = 0; m < c.measurements.size(); ++m)
    if (c.measurements[m].shift.fit) blocks.push_back(&shifts[m]);
  const Eigen::Index n = static_cast<Eigen::Index>(r.names.size());
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> C(n, n);
  if (!cov.Compute(blocks, &problem) || !cov.GetCovarianceMatrix(blocks, C.data())) {
    r.covarianceMessage = "ceres::Covariance failed: the Jacobian is rank-deficient to its precision";
    return;
  }
  Eigen::VectorXd scale(n);
  for (Eigen::Index i = 0; i < n; ++i)
    scale[i] = i < static_cast<Eigen::Index>(c.parameters.size()) ? c.parameters[static_cast<std::size_t>(i)].scale : 1.0;
  r.cov = r.s2 * scale.asDiagonal() * Eigen::MatrixXd(C) * scale.asDiagonal();
  r.corr = r.cov;
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) r.corr(i, j) = r.cov(i, j) / std::sqrt(r.cov(i, i) * r.cov(j, j));
  r.covariance = true;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double sd = std::sqrt(r.cov(i, i));
    r.sd[static_cast<std::size_t>(i)] = sd;
    r.lo[static_cast<std::size_t>(i)] = r.value[static_cast<std::size_t>(i)] - r.t * sd;
    r.hi[static_cast<std::size_t>(i)] = r.value[static_cast<std::size_t>(i)] + r.t * sd;
  }
}

// Warnings on the fitted unknowns: at a bound, an interval wider than the value.
void unknownWarnings(FitResult& r) {
  for (std::size_t i = 0; i < r.names.size(); ++i) {
    const double span = r.upper[i] - r.lower[i];
    r.atBound[i] = r.value[i] <= r.lower[i] + 1e-9 * span || r.value[i] >= r.upper[i] - 1e-9 * span;
    if (r.atBound[i])
      r.warnings.push_back(r.names[i] + " ended at its " + (r.value[i] <= r.lower[i] + 1e-9 * span ? "lower" : "upper") +
                           " bound " + number(r.value[i] <= r.lower[i] + 1e-9 * span ? r.lower[i] : r.upper[i], 6) +
                           ": the data pull it further, and its interval assumes an optimum inside the bounds");
    else if (r.covariance && r.value[i] != 0 && r.t * r.sd[i] > std::abs(r.value[i]) && r.units[i] != "s")
      r.warnings.push_back(r.names[i] + " is poorly determined: its interval +-" + number(r.t * r.sd[i]) + " " + r.units[i] +
                           " is wider than its value " + number(r.value[i]));
  }
}

}  // namespace

std::vector<ChannelStats> channelStats(const Measurement& m, const Simulated& s) {
  std::vector<ChannelStats> out(m.channels.size());
  if (!s.ok) return out;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    ChannelStats& st = out[c];
    double sum = 0, sq = 0;
    for (std::size_t i = 0; i < m.t.size(); ++i) {
      const double r = s.y[c][i] - m.y[c][i];
      sum += r;
      sq += r * r;
      if (std::abs(r) > st.maxAbs) {
        st.maxAbs = std::abs(r);
        st.tMaxAbs = m.t[i];
      }
    }
    const double n = static_cast<double>(m.t.size());
    st.mean = sum / n;
    st.rms = std::sqrt(sq / n);
    double num = 0, den = 0;
    for (std::size_t i = 0; i < m.t.size(); ++i) {
      const double d = s.y[c][i] - m.y[c][i] - st.mean;
      den += d * d;
      if (i + 1 < m.t.size()) num += d * (s.y[c][i + 1] - m.y[c][i + 1] - st.mean);
    }
    if (den > 0 && m.t.size() > 2) st.lag1 = num / den;
  }
  return out;
}

// What the residuals at the optimum say of the noise model: s^2 far from 1 where every fitted channel's
// sigma is given (the stated noise and the residuals disagree: a sigma in other units, or a misfit); a
// channel whose fitted RMS is many sigma; residuals so autocorrelated that the intervals, which assume
// independent noise, are too narrow.
static void residualWarnings(const Calibration& c, FitResult& r) {
  bool allSigma = true, anyFitted = false;
  for (const auto& m : c.measurements)
    for (const auto& ch : m.channels)
      if (ch.fitted()) {
        anyFitted = true;
        allSigma = allSigma && std::isfinite(ch.sigma);
      }
  if (anyFitted && allSigma && (r.s2 > 4 || r.s2 < 0.25))
    r.warnings.push_back("s^2 = " + number(r.s2) + " with every sigma given (1 where the residuals are the stated noise): the "
                         "residuals are " + number(std::sqrt(r.s2)) + " times the sigma; a sigma in another unit than its "
                         "channel, or a model that misses the data (the intervals are scaled by s)");
  for (std::size_t k = 0; k < c.measurements.size() && k < r.measurements.size(); ++k) {
    const Measurement& m = c.measurements[k];
    const auto& stats = r.measurements[k].statsAfter;
    for (std::size_t j = 0; j < m.channels.size() && j < stats.size(); ++j) {
      const Channel& ch = m.channels[j];
      if (!ch.fitted()) continue;
      const std::string who = "measurement '" + m.name + "', channel " + ch.name + ": ";
      if (std::isfinite(ch.sigma) && stats[j].rms > 5 * ch.sigma)
        r.warnings.push_back(who + "the fitted RMS residual " + number(stats[j].rms) + " " + ch.unit + " is " +
                             number(stats[j].rms / ch.sigma) + " sigma (sigma = " + number(ch.sigma) + " " + ch.unit +
                             "): a channel in another unit, or a model that misses it");
      if (stats[j].lag1 > 0.8)
        r.warnings.push_back(who + "the residuals' lag-1 autocorrelation is " + number(stats[j].lag1) +
                             ": they are a slow misfit, not independent noise, and the intervals (statistical only) are too narrow");
    }
  }
}

namespace {

// The residual blocks (one per measurement, or one per residual under a robust loss) on the blocks u
// and shifts, with their bounds.
void addResiduals(const Calibration& c, const Evaluations& evals, ceres::Problem& problem, std::vector<double>& u,
                  std::vector<double>& shifts) {
  for (std::size_t m = 0; m < c.measurements.size(); ++m) {
    const Measurement& meas = c.measurements[m];
    const int n = static_cast<int>(meas.residuals());
    if (n == 0) continue;
    std::vector<double*> blocks{u.data()};
    if (meas.shift.fit) blocks.push_back(&shifts[m]);
    if (c.fit.loss == Loss::None) {
      problem.AddResidualBlock(new ResidualRange(evals, c, m, 0, n), nullptr, blocks);
      continue;
    }
    for (int k = 0; k < n; ++k)  // a robust loss acts on each residual
      problem.AddResidualBlock(new ResidualRange(evals, c, m, k, 1), lossFunction(c.fit), blocks);
  }
  for (std::size_t i = 0; i < c.parameters.size(); ++i) {
    const FitParameter& q = c.parameters[i];
    problem.SetParameterLowerBound(u.data(), static_cast<int>(i), q.lower / q.scale);
    problem.SetParameterUpperBound(u.data(), static_cast<int>(i), q.upper / q.scale);
  }
  for (std::size_t m = 0; m < c.measurements.size(); ++m)
    if (c.measurements[m].shift.fit && c.measurements[m].residuals() > 0) {
      problem.SetParameterLowerBound(&shifts[m], 0, c.measurements[m].shift.lower);
      problem.SetParameterUpperBound(&shifts[m], 0, c.measurements[m].shift.upper);
    }
}

// Levenberg-Marquardt, single-threaded (the parallel work is the simulations', outside Ceres).
ceres::Solver::Summary solve(const Calibration& c, const FitOptions& o, ceres::Problem& problem) {
  ceres::Solver::Options so;
  so.minimizer_type = ceres::TRUST_REGION;
  so.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  so.linear_solver_type = ceres::DENSE_QR;
  so.num_threads = 1;
  so.max_num_iterations = c.fit.maxIterations;
  so.function_tolerance = c.fit.functionTolerance;
  so.parameter_tolerance = c.fit.parameterTolerance;
  so.gradient_tolerance = c.fit.gradientTolerance;
  so.logging_type = ceres::SILENT;
  so.minimizer_progress_to_stdout = false;
  Progress progress(o);
  so.callbacks.push_back(&progress);
  ceres::Solver::Summary summary;
  // Ceres says why it stopped in the summary, which the fit reports; its own log lines (glog, on stderr)
  // are held back meanwhile: a Ctrl-C during an evaluation fails that evaluation, and Ceres would log
  // "Terminating: Residual and Jacobian evaluation failed." beside calibrate's one line.
  const int minLogLevel = FLAGS_minloglevel;
  FLAGS_minloglevel = google::GLOG_FATAL;
  ceres::Solve(so, &problem, &summary);
  FLAGS_minloglevel = minLogLevel;
  return summary;
}

// At the optimum: s^2, the t quantile, identifiability and, when identifiable, the covariance.
void analyseOptimum(const Calibration& c, const Evaluations& evals,
                    const std::vector<MeasurementEval>& second, bool haveSecond, ceres::Problem& problem,
                    std::vector<double>& u, std::vector<double>& shifts, FitResult& r) {
  for (std::size_t m = 0; m < c.measurements.size(); ++m) {
    if (!evals.eval(m).ok) throw FitError("measurement '" + c.measurements[m].name + "' at the optimum: " + evals.eval(m).message);
    if (haveSecond && !second[m].ok)
      throw FitError("measurement '" + c.measurements[m].name + "' at the optimum: " + second[m].message);
  }
  double sq = 0;
  std::vector<double> absR;
  for (const auto& e : evals.evals()) {
    sq += e.r.squaredNorm();
    for (Eigen::Index k = 0; k < e.r.size(); ++k) absR.push_back(std::abs(e.r[k]));
  }
  r.s2 = sq / static_cast<double>(r.dof);
  if (c.fit.loss != Loss::None) {  // outliers must not inflate it: s = 1.4826 median |r| (normal-consistent)
    std::nth_element(absR.begin(), absR.begin() + static_cast<std::ptrdiff_t>(absR.size() / 2), absR.end());
    const double s = 1.482602218505602 * absR[absR.size() / 2];
    r.s2 = s * s;
  }
  r.t = boost::math::quantile(boost::math::complement(boost::math::students_t(static_cast<double>(r.dof)),
                                                      (1 - c.fit.confidence) / 2));
  const std::size_t n = r.names.size();
  r.sd.assign(n, NAN);
  r.lo.assign(n, NAN);
  r.hi.assign(n, NAN);
  r.atBound.assign(n, false);
  r.ident = identifiability(stackedJacobian(c, evals.evals()), haveSecond ? stackedJacobian(c, second) : Eigen::MatrixXd(),
                            r.value, r.names, r.units, c.fit.identifiability);
  if (r.ident.identifiable) covariance(c, problem, u, shifts, r);
  else r.covarianceMessage = "not computed: the parameters are not identifiable";
  unknownWarnings(r);
}

// Every channel of every measurement at the initial and at the fitted point, and their residual statistics.
void simulateHistories(const Calibration& c, const FitOptions& o, FitResult& r) {
  r.measurements.resize(c.measurements.size());
  for (std::size_t m = 0; m < c.measurements.size(); ++m) {
    MeasurementFit& f = r.measurements[m];
    for (const Point* p : {&r.start, &r.fitted}) {
      Scene design;
      Simulated s;
      if (const auto why = designScene(c, p->x, design)) s.message = *why;
      else s = simulateMeasurement(c, m, design, p->shift[m], o.stop);
      (p == &r.start ? f.before : f.after) = s;
    }
    f.statsBefore = channelStats(c.measurements[m], f.before);
    f.statsAfter = channelStats(c.measurements[m], f.after);
  }
}

bool stopped(const FitOptions& o) { return o.stop && o.stop(); }

}  // namespace

FitResult runFit(const Calibration& c, const FitOptions& o) {
  FitResult r;
  const CentralDifferences differences(c, o.threads, o.stop);
  const ExactDerivatives exact(c, o.threads, o.stop);
  // The one place the Jacobian comes from: the caller's, else the file's choice.
  const ResidualJacobian& rj = o.jacobian ? *o.jacobian : c.fit.exactJacobian ? static_cast<const ResidualJacobian&>(exact)
                                                                               : differences;
  r.jacobianSource = rj.source();
  describeUnknowns(c, r);
  r.start = initialPoint(c);
  r.initial = unknownsAt(c, r.start);
  r.residuals = c.residuals();
  r.unknowns = c.unknowns();
  r.dof = r.residuals - r.unknowns;

  // Ceres's blocks: the parameters over their scales, one block per shift (fixed ones are never blocks).
  std::vector<double> u, shifts = r.start.shift;
  for (const auto& q : c.parameters) u.push_back(q.initial / q.scale);
  Evaluations evals(c, rj, u, shifts);
  evals.ensure(false);
  if (stopped(o)) {  // Ctrl-C during the first runs: their failures are no news about the model
    r.interrupted = true;
    return r;
  }
  for (std::size_t m = 0; m < c.measurements.size(); ++m)
    if (!evals.eval(m).ok)
      throw FitError("measurement '" + c.measurements[m].name + "' at the initial values: " + evals.eval(m).message);

  ceres::Problem::Options po;
  po.evaluation_callback = &evals;
  ceres::Problem problem(po);
  addResiduals(c, evals, problem, u, shifts);
  const ceres::Solver::Summary summary = solve(c, o, problem);
  r.evaluations = evals.count();
  r.termination = ceres::TerminationTypeToString(summary.termination_type);
  r.ceresMessage = summary.message;
  r.iterations = static_cast<int>(summary.iterations.size()) - 1;
  r.initialCost = summary.initial_cost;
  r.finalCost = summary.final_cost;
  r.converged = summary.termination_type == ceres::CONVERGENCE;
  if (stopped(o)) {
    r.interrupted = true;
    return r;
  }
  if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::USER_FAILURE)
    throw FitError("Ceres failed: " + summary.message);
  if (!r.converged) r.warnings.push_back("the fit stopped before converging: " + summary.message);

  // The optimum: its Jacobian and a second one for the Jacobian's error, identifiability, covariance.
  evals.ensure(true);
  r.fitted = evals.point();
  r.value = unknownsAt(c, r.fitted);
  std::vector<MeasurementEval> second;
  const bool haveSecond = rj.secondJacobian(r.fitted, second);
  if (stopped(o)) {
    r.interrupted = true;
    return r;
  }
  analyseOptimum(c, evals, second, haveSecond, problem, u, shifts, r);
  simulateHistories(c, o, r);
  residualWarnings(c, r);
  if (stopped(o)) r.interrupted = true;
  return r;
}

}  // namespace lg::calib
