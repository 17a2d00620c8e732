// Drop tests: one case = one engine run from touchdown, observed step by step.
#include "sim/drop_test.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace lg {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

std::string shortNumber(double v) {
  std::ostringstream o;
  o.precision(4);
  o << v;
  return o.str();
}
}  // namespace

bool CaseMetrics::withinLimits() const { return limitViolations().empty(); }

std::string CaseMetrics::limitViolations() const {
  std::string out;
  auto add = [&](const std::string& s) { out += (out.empty() ? "" : "; ") + s; };
  if (bottomed) add("bottomed");
  for (const auto& s : struts)
    if (s.stroke_margin_m < 0 && !bottomed)
      add("strut '" + s.name + "' stroke " + shortNumber(s.stroke_max_m) + " m > S_max " + shortNumber(s.stroke_limit_m) + " m");
  for (const auto& t : tyres)
    if (t.margin_m < 0)
      add("tyre '" + t.name + "' " + shortNumber(t.deflection_max_m) + " m > delta_max " + shortNumber(t.deflection_limit_m) +
          " m");
  return out;
}

std::vector<Column> historyColumns(const Scene& scene) {
  const Model<double>& m = scene.model;
  std::vector<Column> c;
  if (!scene.roles.tyres.empty()) c.push_back({"P_y", "N"});
  if (!scene.roles.airframe.empty()) c.push_back({"h", "m"});
  const bool manyTyres = scene.roles.tyres.size() > 1, manyStruts = scene.roles.struts.size() > 1;
  for (int f : scene.roles.tyres) {
    const std::string sfx = manyTyres ? "_" + m.forces[f].name : "";
    c.push_back({"delta" + sfx, "m"});
    if (manyTyres) c.push_back({"P_t" + sfx, "N"});
  }
  for (int f : scene.roles.struts) {
    const std::string sfx = manyStruts ? "_" + m.forces[f].name : "";
    for (const std::string& n : m.forces[f].outputNames())
      c.push_back({n + sfx, n == "s" ? "m" : n == "s_dot" ? "m/s" : n == "p_1" ? "Pa" : "N"});
  }
  for (int ci : scene.roles.stops) c.push_back({"F_" + m.constraints[ci].name, "N"});
  c.push_back({"violation", "m"});
  return c;
}

int CaseResult::column(const std::string& name) const {
  for (size_t i = 0; i < columns.size(); ++i)
    if (columns[i].name == name) return static_cast<int>(i);
  return -1;
}

double caseMass(const Scene& scene, const DropCase& c) {
  double G = 0;
  for (const auto& b : scene.model.bodies) {
    const auto it = c.masses.find(b.name);
    G += it == c.masses.end() ? b.mass : it->second;
  }
  return G;
}

Model<double> caseModel(const Scene& scene, const DropCase& c) {
  Model<double> m = scene.model;
  for (const auto& [name, mass] : c.masses) m.bodies[m.bodyIndex(name)].mass = mass;
  const double G = caseMass(scene, c);  // [kg] total mass
  for (int li : scene.roles.lifts) {
    auto& f = m.forces[li];
    auto& cf = std::get<ConstantForce<double>>(f.type);
    const Vec3<double> dir = std::get<ConstantForce<double>>(scene.model.forces[li].type).force;  // unit
    f.liftRatio = c.liftRatio;
    cf.force = dir * (c.liftRatio * G * scene.gravity);
  }
  return m;
}

State<double> caseState(const Scene& scene, const Model<double>& m, const DropCase& c) {
  State<double> s = scene.initial;
  const int N = m.nBodies();
  for (int b = 0; b < N; ++b) {
    s.y.segment<3>(7 * N + 6 * b) = -c.sinkSpeed * scene.up;
    s.y.segment<3>(7 * N + 6 * b + 3).setZero();
  }
  s.t = 0;
  return s;
}

namespace {

// The channels the observer reads at one time: airframe travel, the sum of the tyre loads, and each
// strut's and tyre's own. Sized once per run; copies between equal sizes do not allocate.
struct Channels {
  double t = 0, Py = 0, PyDot = 0, h = 0, hdot = 0;
  std::vector<double> s, sdot, Pa;          // per strut
  std::vector<double> delta, ddelta, Pt;    // per tyre
  Channels(size_t struts = 0, size_t tyres = 0)
      : s(struts), sdot(struts), Pa(struts), delta(tyres), ddelta(tyres), Pt(tyres) {}
};

// Watches a drop run: time histories, refined extrema, compression integrals, energy.
class DropObserver {
 public:
  DropObserver(const Scene& sc, const Model<double>& m, const DropCase& c, const CaseOptions& opt, CaseResult& res)
      : sc_(sc), m_(m), case_(c), opt_(opt), res_(res), wo_(m) {
    airframe_ = sc.roles.airframe.empty() ? -1 : m.bodyIndex(sc.roles.airframe);
    for (int ci : sc.roles.stops) {
      stopRows_.push_back(m.rowOffset[ci]);
      const auto& st = std::get<DistanceStop<double>>(m.constraints[ci].type);
      if (!st.noFarther) bottomRows_.push_back(m.rowOffset[ci]);
    }
    for (int f : sc.roles.tyres) tyreOut_.push_back(m.outputOffset[f]);
    for (int f : sc.roles.struts) {
      strutOut_.push_back(m.outputOffset[f]);
      strutOutputs_.push_back(static_cast<int>(m.forces[f].outputNames().size()));
    }
    const size_t ns = strutOut_.size(), nt = tyreOut_.size();
    prev_ = end_ = mid_ = after_ = scratch_ = Channels(ns, nt);
    workPa_.assign(ns, 0.0);
    workPaAtMax_.assign(ns, 0.0);
    auto& M = res_.metrics;
    M.struts.resize(ns);
    for (size_t k = 0; k < ns; ++k) {
      M.struts[k].name = m.forces[sc.roles.struts[k]].name;
      M.struts[k].stroke_limit_m = sc.roles.strokeLimits[k];
    }
    M.tyres.resize(nt);
    for (size_t k = 0; k < nt; ++k) {
      M.tyres[k].name = m.forces[sc.roles.tyres[k]].name;
      M.tyres[k].deflection_limit_m = std::get<Tyre<double>>(m.forces[sc.roles.tyres[k]].type).deltaMax;
    }
    ytmp_ = VecX<double>::Zero(m.ny());
    ydotTmp_ = VecX<double>::Zero(m.ny());
    lambdaTmp_ = VecX<double>::Zero(m.nRows);
    if (opt.record) res_.columns = historyColumns(sc);
  }

  void onStart(const Model<double>& m, const State<double>& s, Workspace<double>& w) {
    if (airframe_ >= 0) r0_ = w.kin[airframe_].r;
    at(s.t, s.y, prev_);
    EnergyReport<double> e = energy(m, s, w);
    e0_ = e.total();
    ek0_ = e.kinetic;
    uExt0_ = externalPotential(w);
    if (opt_.record && (opt_.outputTimes.empty() || opt_.outputTimes[0] <= 0)) {
      record(s.t, wo_, s.lambda, s.active, w);  // t = 0 in every output mode but a list without it
      nextRow_ = 1;
    }
    auto& M = res_.metrics;
    M.peak_load_N = prev_.Py;
    M.h_max_m = prev_.h;
    for (size_t k = 0; k < M.struts.size(); ++k) {
      M.struts[k].stroke_max_m = prev_.s[k];
      M.struts[k].force_max_N = prev_.Pa[k];
    }
    for (size_t k = 0; k < M.tyres.size(); ++k) {
      M.tyres[k].deflection_max_m = prev_.delta[k];
      M.tyres[k].load_max_N = prev_.Pt[k];
    }
    checkBottom(s);
  }

  void onStep(const Model<double>& m, const State<double>& s, Workspace<double>& w, const DenseOutput<double>& d) {
    const double viol = violation(s, w);
    // Compression integrals (Simpson on the dense output) over [t0, t1], and refined extrema. The step's
    // end is taken on the dense output, i.e. before any jump at t1 (a plastic impact or a projection
    // changes the velocities, hence the rates and P_a, but belongs to the next step's start).
    const double t0 = prev_.t, t1 = s.t;
    channelsAt(t1, w, d, end_);
    channelsAt(0.5 * (t0 + t1), w, d, mid_);
    const double h = t1 - t0;
    workPy_ += simpson(prev_.Py * prev_.hdot, mid_.Py * mid_.hdot, end_.Py * end_.hdot, h);
    auto& M = res_.metrics;
    // Peak P_y where its rate (the sum of the tyres' P_t') goes from + to -.
    refine(prev_.PyDot, end_.PyDot, t0, t1, w, d, [](const Channels& c) { return c.Py; }, M.peak_load_N, &M.t_peak_s,
           end_.Py, t1);
    for (size_t k = 0; k < M.tyres.size(); ++k) {
      // P_t grows with delta: both peak where delta' goes from + to -.
      auto& T = M.tyres[k];
      refine(prev_.ddelta[k], end_.ddelta[k], t0, t1, w, d, [k](const Channels& c) { return c.delta[k]; },
             T.deflection_max_m, nullptr, end_.delta[k], t1);
      refine(prev_.ddelta[k], end_.ddelta[k], t0, t1, w, d, [k](const Channels& c) { return c.Pt[k]; }, T.load_max_N,
             nullptr, end_.Pt[k], t1);
    }
    for (size_t k = 0; k < M.struts.size(); ++k) {
      auto& S = M.struts[k];
      workPa_[k] += simpson(prev_.Pa[k] * prev_.sdot[k], mid_.Pa[k] * mid_.sdot[k], end_.Pa[k] * end_.sdot[k], h);
      double tS = -1;
      if (refine(prev_.sdot[k], end_.sdot[k], t0, t1, w, d, [k](const Channels& c) { return c.s[k]; }, S.stroke_max_m,
                 &tS, end_.s[k], t1))
        workPaAtMax_[k] = workPa_[k] - (tS < t1 ? partialStrut(k, tS, t1, w, d) : 0.0);
      // Peak P_a (no rate channel): where this step may hold a new maximum, search it on the dense output.
      if (std::max(mid_.Pa[k], end_.Pa[k]) > S.force_max_N)
        refine(1.0, -1.0, t0, t1, w, d, [k](const Channels& c) { return c.Pa[k]; }, S.force_max_N, nullptr,
               std::max(mid_.Pa[k], end_.Pa[k]), t1);
    }
    double tH = -1;
    if (prev_.hdot > 0 && end_.hdot <= 0) M.compression_ended = true;
    if (refine(prev_.hdot, end_.hdot, t0, t1, w, d, [](const Channels& c) { return c.h; }, M.h_max_m, &tH, end_.h, t1)) {
      workPyAtMax_ = workPy_ - (tH < t1 ? partialGear(tH, t1, w, d) : 0.0);
      tHmax_ = tH;
      reboundV_ = 0;  // a new maximum of h: the rebound starts again from there
    }
    // Rebound: the largest upward airframe velocity -h' after the compression; refined on the dense
    // output where the step's midpoint is above both ends.
    if (t1 > tHmax_) {
      double v = std::max(0.0, -end_.hdot);
      if (-mid_.hdot > v && -mid_.hdot > -prev_.hdot)
        refine(1.0, -1.0, std::max(t0, tHmax_), t1, w, d, [](const Channels& c) { return -c.hdot; }, v, nullptr, v, t1);
      reboundV_ = std::max(reboundV_, v);
    }
    M.constraint_violation_max = std::max(M.constraint_violation_max, viol);
    checkBottom(s);
    if (opt_.record && denseRows()) recordDense(m, t0, t1, s, d);
    at(s.t, s.y, after_);  // after any jump at t1: the next step's start
    for (size_t k = 0; k < M.struts.size(); ++k) M.struts[k].force_max_N = std::max(M.struts[k].force_max_N, after_.Pa[k]);
    if (opt_.record && !denseRows()) record(s.t, wo_, s.lambda, s.active, w);
    std::swap(prev_, after_);
    ++steps_;
  }

  bool stopRequested() const { return opt_.stop && (steps_ % 64 == 0) && opt_.stop(); }

  void finish(const State<double>& s, Workspace<double>& w) {
    auto& M = res_.metrics;
    kinematics(m_, s.y, w);
    EnergyReport<double> e = energy(m_, s, w);
    const double uExt = externalPotential(w);
    const double input = ek0_ + std::abs(uExt0_ - uExt);
    M.energy_balance_error = std::abs(e.total() - e0_) / std::max(input, 1e-300);
    M.energy_dissipated_J = e.dissipated;
    M.energy_absorbed_J = workPyAtMax_;
    double G = 0;
    for (const auto& b : m_.bodies) G += b.mass;
    M.sink_speed_mps = case_.sinkSpeed;
    M.lift_ratio = case_.liftRatio;
    M.mass_kg = G;
    M.energy_to_absorb_J = 0.5 * G * case_.sinkSpeed * case_.sinkSpeed + (1 - case_.liftRatio) * G * sc_.gravity * M.h_max_m;
    M.load_factor = M.peak_load_N / (G * sc_.gravity);
    M.inertia_load_factor = M.load_factor + case_.liftRatio;
    M.efficiency = (M.peak_load_N > 0 && M.h_max_m > 0) ? workPyAtMax_ / (M.peak_load_N * M.h_max_m) : 0.0;
    M.rebound_velocity_mps = reboundV_;
    // Per strut and tyre, then the gear's worst.
    M.stroke_max_m = M.strut_force_max_N = 0;
    M.strut_efficiency = M.struts.empty() ? 0.0 : std::numeric_limits<double>::infinity();
    M.stroke_margin_m = kNaN;
    for (size_t k = 0; k < M.struts.size(); ++k) {
      auto& S = M.struts[k];
      S.work_J = workPaAtMax_[k];
      S.efficiency = (S.force_max_N > 0 && S.stroke_max_m > 0) ? S.work_J / (S.force_max_N * S.stroke_max_m) : 0.0;
      S.stroke_margin_m = S.stroke_limit_m - S.stroke_max_m;  // NaN without a bottoming stop
      M.stroke_max_m = std::max(M.stroke_max_m, S.stroke_max_m);
      M.strut_force_max_N = std::max(M.strut_force_max_N, S.force_max_N);
      M.strut_efficiency = std::min(M.strut_efficiency, S.efficiency);
      if (!std::isnan(S.stroke_margin_m))
        M.stroke_margin_m = std::isnan(M.stroke_margin_m) ? S.stroke_margin_m : std::min(M.stroke_margin_m, S.stroke_margin_m);
    }
    M.tyre_deflection_max_m = 0;
    M.tyre_margin_m = kNaN;
    for (auto& T : M.tyres) {
      T.margin_m = T.deflection_limit_m - T.deflection_max_m;
      M.tyre_deflection_max_m = std::max(M.tyre_deflection_max_m, T.deflection_max_m);
      M.tyre_margin_m = std::isnan(M.tyre_margin_m) ? T.margin_m : std::min(M.tyre_margin_m, T.margin_m);
    }
  }

 private:
  // Channels at the workspace's current kinematics (outputs must be current).
  void channels(double t, const Workspace<double>& w, Channels& c) const {
    c.t = t;
    c.Py = c.PyDot = 0;
    for (size_t k = 0; k < tyreOut_.size(); ++k) {
      const double* o = w.outputs.data() + tyreOut_[k];  // delta, P_t, delta', P_t'
      c.delta[k] = o[0];
      c.Pt[k] = o[1];
      c.ddelta[k] = o[2];
      c.Py += o[1];
      c.PyDot += o[3];
    }
    for (size_t k = 0; k < strutOut_.size(); ++k) {
      const double* o = w.outputs.data() + strutOut_[k];  // s, s', p_1, P_a, ...
      c.s[k] = o[0];
      c.sdot[k] = o[1];
      c.Pa[k] = o[3];
    }
    c.h = c.hdot = 0;
    if (airframe_ >= 0) {
      c.h = sc_.up.dot(r0_ - w.kin[airframe_].r);
      c.hdot = -sc_.up.dot(w.kin[airframe_].v);
    }
  }
  void forceOutputs(Workspace<double>& w) const {
    const Kins<double> K = w.kins();
    for (size_t f = 0; f < m_.forces.size(); ++f)
      std::visit([&](const auto& e) { e.outputs(K, w.outputs.data() + m_.outputOffset[f]); }, m_.forces[f].type);
  }
  // Channels at (t, y) on the observer's own workspace (poses and force outputs only: no solve), so that
  // the integrator's workspace is never touched.
  void at(double t, const VecX<double>& y, Channels& c) {
    poses(m_, y, wo_);
    forceOutputs(wo_);
    channels(t, wo_, c);
  }
  void channelsAt(double t, Workspace<double>&, const DenseOutput<double>& d, Channels& c) {
    d.at(t, ytmp_);
    at(t, ytmp_, c);
  }
  // One row of the time histories from a workspace whose poses and force outputs are current, the
  // multipliers, and the workspace holding the constraint rows at that state (the columns of
  // historyColumns, in order).
  void record(double t, const Workspace<double>& wk, const VecX<double>& lambda, const std::vector<char>& active,
              const Workspace<double>& rowsW) {
    Sample row;
    row.t = t;
    row.values.reserve(res_.columns.size());
    const double* o = wk.outputs.data();
    double Py = 0;
    for (int off : tyreOut_) Py += o[off + 1];
    if (!tyreOut_.empty()) row.values.push_back(Py);
    if (airframe_ >= 0) row.values.push_back(sc_.up.dot(r0_ - wk.kin[airframe_].r));
    for (int off : tyreOut_) {
      row.values.push_back(o[off]);
      if (tyreOut_.size() > 1) row.values.push_back(o[off + 1]);
    }
    for (size_t k = 0; k < strutOut_.size(); ++k)
      for (int i = 0; i < strutOutputs_[k]; ++i) row.values.push_back(o[strutOut_[k] + i]);
    for (int r : stopRows_) row.values.push_back(lambda[r] * rowsW.rows[r].Ji.head<3>().norm());  // [N]: C is in m^2
    row.values.push_back(violationOf(active, rowsW));
    res_.samples.push_back(std::move(row));
  }
  // Rows on the dense output (outputTimes or outputInterval) rather than one per step.
  bool denseRows() const { return !opt_.outputTimes.empty() || opt_.outputInterval > 0; }
  // The time of output row k: outputTimes[k] (infinity past its end), or k DT.
  double rowTime(long k) const {
    if (opt_.outputTimes.empty()) return static_cast<double>(k) * opt_.outputInterval;
    return k < static_cast<long>(opt_.outputTimes.size()) ? opt_.outputTimes[k] : std::numeric_limits<double>::infinity();
  }
  // Rows at the output times inside (t0, t1], each from the dense output with its multipliers solved
  // on the observer's workspace (the contact mode is the step's).
  void recordDense(const Model<double>& m, double t0, double t1, const State<double>& s, const DenseOutput<double>& d) {
    for (;; ++nextRow_) {
      const double t = rowTime(nextRow_);
      if (t > t1 * (1 + 1e-12) || t > case_.duration * (1 + 1e-12)) break;
      if (t <= t0) continue;
      d.at(std::min(t, t1), ytmp_);
      lambdaTmp_ = s.lambda;
      evaluate(m, ytmp_, s.active, lambdaTmp_, wo_, ydotTmp_);
      forceOutputs(wo_);
      record(t, wo_, lambdaTmp_, s.active, wo_);
    }
  }
  double violation(const State<double>& s, const Workspace<double>& w) const { return violationOf(s.active, w); }
  double violationOf(const std::vector<char>& active, const Workspace<double>& w) const {
    double v = 0;
    for (int k = 0; k < m_.nRows; ++k) {
      if (!active[k]) continue;
      v = std::max(v, std::abs(w.rows[k].C) / std::max(1e-12, w.rows[k].Ji.head<3>().norm()));
    }
    return v;
  }
  void checkBottom(const State<double>& s) {
    for (int r : bottomRows_)
      if (s.active[r]) res_.metrics.bottomed = true;
  }
  double externalPotential(const Workspace<double>& w) const {
    const Kins<double> K = w.kins();
    double U = 0;
    for (const auto& f : m_.forces) {
      if (const auto* g = std::get_if<Gravity<double>>(&f.type)) U += g->stored(K);
      if (const auto* c = std::get_if<ConstantForce<double>>(&f.type)) U += c->stored(K);
    }
    return U;
  }
  // Simpson's rule for integral(P dx) = integral(P xdot dt) over one step of length h.
  static double simpson(double f0, double fm, double f1, double h) { return h / 6.0 * (f0 + 4 * fm + f1); }
  // The part of this step's integral after time t (Simpson on [t, t1]).
  double partialGear(double t, double t1, Workspace<double>& w, const DenseOutput<double>& d) {
    Channels& a = scratch_;
    channelsAt(t, w, d, a);
    const double fa = a.Py * a.hdot;
    channelsAt(0.5 * (t + t1), w, d, a);
    const double fm = a.Py * a.hdot;
    channelsAt(t1, w, d, a);
    return simpson(fa, fm, a.Py * a.hdot, t1 - t);
  }
  double partialStrut(size_t k, double t, double t1, Workspace<double>& w, const DenseOutput<double>& d) {
    Channels& a = scratch_;
    channelsAt(t, w, d, a);
    const double fa = a.Pa[k] * a.sdot[k];
    channelsAt(0.5 * (t + t1), w, d, a);
    const double fm = a.Pa[k] * a.sdot[k];
    channelsAt(t1, w, d, a);
    return simpson(fa, fm, a.Pa[k] * a.sdot[k], t1 - t);
  }
  // Updates the running maximum 'best' of a channel. If its rate goes from + to - inside the step, the
  // maximum is located on the dense output (golden section). Returns true if the maximum moved.
  template <class F>
  bool refine(double rate0, double rate1, double t0, double t1, Workspace<double>& w, const DenseOutput<double>& d, F f,
              double& best, double* tBest, double endValue, double tEnd) {
    double v = endValue, tv = tEnd;
    if (rate0 > 0 && rate1 < 0) {
      auto at = [&](double t) {
        channelsAt(t, w, d, scratch_);
        return f(scratch_);
      };
      const double gr = 0.5 * (std::sqrt(5.0) - 1);
      double a = t0, b = t1;
      double c = b - gr * (b - a), e = a + gr * (b - a);
      double fc = at(c), fe = at(e);
      for (int it = 0; it < 60 && b - a > 1e-13 * std::max(1.0, t1); ++it) {
        if (fc > fe) {
          b = e;
          e = c;
          fe = fc;
          c = b - gr * (b - a);
          fc = at(c);
        } else {
          a = c;
          c = e;
          fc = fe;
          e = a + gr * (b - a);
          fe = at(e);
        }
      }
      const double tm = 0.5 * (a + b), vm = at(tm);
      if (vm > v) {
        v = vm;
        tv = tm;
      }
    }
    if (v > best) {
      best = v;
      if (tBest) *tBest = tv;
      return true;
    }
    return false;
  }

  const Scene& sc_;
  const Model<double>& m_;
  const DropCase& case_;
  const CaseOptions& opt_;
  CaseResult& res_;
  int airframe_ = -1;
  std::vector<int> tyreOut_, strutOut_, stopRows_, bottomRows_;
  Vec3<double> r0_ = Vec3<double>::Zero();
  Workspace<double> wo_;                  // the observer's own: dense-output channels and output rows
  VecX<double> ytmp_, ydotTmp_, lambdaTmp_;
  std::vector<int> strutOutputs_;         // per strut: its number of outputs
  long nextRow_ = 0;                      // next dense output row (outputTimes, outputInterval)
  Channels prev_, end_, mid_, after_, scratch_;
  double e0_ = 0, ek0_ = 0, uExt0_ = 0;
  double workPy_ = 0, workPyAtMax_ = 0;
  std::vector<double> workPa_, workPaAtMax_;
  double tHmax_ = 0, reboundV_ = 0;
  long steps_ = 0;
};

}  // namespace

CaseResult runCase(const Scene& scene, const DropCase& c, const CaseOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  for (size_t k = 0; k < opt.outputTimes.size(); ++k) {
    const double t = opt.outputTimes[k];
    if (!(t >= 0 && t <= c.duration) || (k > 0 && !(t > opt.outputTimes[k - 1])))
      throw std::invalid_argument("output time " + shortNumber(t) + " s (row " + std::to_string(k) +
                                  "): the times must increase strictly within [0, duration = " + shortNumber(c.duration) + " s]");
  }
  CaseResult res;
  res.metrics.name = c.name;
  const Model<double> m = caseModel(scene, c);
  State<double> s = caseState(scene, m, c);
  Workspace<double> w(m);
  DropObserver obs(scene, m, c, opt, res);
  const RunStatus st = simulate(m, s, w, c.duration, obs);
  obs.finish(s, w);
  res.metrics.ok = st.ok;
  res.metrics.message = st.message;
  res.metrics.steps = st.steps;
  res.metrics.rhs_evaluations = w.rhsEvaluations;
  res.metrics.constraint_violation_max = std::max(res.metrics.constraint_violation_max, st.maxPositionViolation);
  auto& M = res.metrics;
  for (double v : {M.peak_load_N, M.stroke_max_m, M.h_max_m, M.tyre_deflection_max_m, M.efficiency, M.strut_efficiency,
                   M.energy_absorbed_J, M.energy_dissipated_J, M.energy_balance_error, M.rebound_velocity_mps})
    if (!std::isfinite(v) && M.ok) {
      M.ok = false;
      M.message = "non-finite result";
    }
  res.metrics.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

std::vector<CaseResult> runCases(const Scene& scene, const std::vector<DropCase>& cases, int threads,
                                 const CaseOptions& opt) {
  // Cases that differ only by name (same sink speed, lift ratio, duration and effective masses: a
  // scene's "limit" and the matrix's limit case, say) run once; their results are copied, renamed.
  auto key = [&](const DropCase& c) {
    std::vector<double> k{c.sinkSpeed, c.liftRatio, c.duration};
    for (const auto& b : scene.model.bodies) {
      const auto it = c.masses.find(b.name);
      k.push_back(it == c.masses.end() ? b.mass : it->second);
    }
    return k;
  };
  std::vector<int> first(cases.size());
  std::vector<int> unique;
  for (size_t i = 0; i < cases.size(); ++i) {
    first[i] = static_cast<int>(i);
    for (int u : unique)
      if (key(cases[u]) == key(cases[i])) first[i] = u;
    if (first[i] == static_cast<int>(i)) unique.push_back(static_cast<int>(i));
  }
  std::vector<CaseResult> out(cases.size());
  const int n = static_cast<int>(unique.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads))
  for (int i = 0; i < n; ++i) out[unique[i]] = runCase(scene, cases[unique[i]], opt);
  for (size_t i = 0; i < cases.size(); ++i)
    if (first[i] != static_cast<int>(i)) {
      out[i] = out[first[i]];
      out[i].metrics.name = cases[i].name;
    }
  return out;
}

double staticStroke(const Scene& scene, std::string* message, double duration) {
  if (scene.roles.struts.empty()) {
    if (message) *message = "the scene has no shock absorber";
    return std::numeric_limits<double>::quiet_NaN();
  }
  DropCase c;
  c.name = "static";
  c.sinkSpeed = 0;
  c.liftRatio = 0;
  c.duration = duration;
  CaseOptions opt;
  opt.record = true;
  CaseResult r = runCase(scene, c, opt);
  if (!r.metrics.ok || r.samples.empty()) {
    if (message) *message = r.metrics.message;
    return std::numeric_limits<double>::quiet_NaN();
  }
  const int col = r.column(r.column("s") >= 0 ? "s" : "s_" + scene.model.forces[scene.roles.struts[0]].name);
  return r.samples.back().values[col];
}

}  // namespace lg
