// Drop tests: one case = one engine run from touchdown, observed step by step.
#include "sim/drop_test.hpp"

#include <omp.h>

#include <chrono>
#include <cmath>
#include <limits>

namespace lg {

Model<double> caseModel(const Scene& scene, const DropCase& c) {
  Model<double> m = scene.model;
  for (const auto& [name, mass] : c.masses) m.bodies[m.bodyIndex(name)].mass = mass;
  double G = 0;  // [kg] total mass
  for (const auto& b : m.bodies) G += b.mass;
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

// Watches a drop run: time histories, refined extrema, compression integrals, energy.
class DropObserver {
 public:
  DropObserver(const Scene& sc, const Model<double>& m, const CaseOptions& opt, CaseResult& res)
      : sc_(sc), m_(m), opt_(opt), res_(res) {
    airframe_ = sc.roles.airframe.empty() ? -1 : m.bodyIndex(sc.roles.airframe);
    for (int c : sc.roles.stops) {
      stopRows_.push_back(m.rowOffset[c]);
      const auto& st = std::get<DistanceStop<double>>(m.constraints[c].type);
      if (!st.noFarther) bottomRows_.push_back(m.rowOffset[c]);
    }
    for (int f : sc.roles.tyres) tyreOut_.push_back(m.outputOffset[f]);
    if (!sc.roles.struts.empty()) strutOut_ = m.outputOffset[sc.roles.struts[0]];
    ytmp_ = VecX<double>::Zero(m.ny());
  }

  // Channels at the workspace's current kinematics (outputs must be current).
  struct Channels {
    double t, Py, s, sdot, h, hdot, delta, ddelta, Pa;
  };
  Channels channels(double t, const Workspace<double>& w) const {
    Channels c{t, 0, 0, 0, 0, 0, 0, 0, 0};
    for (int o : tyreOut_) c.Py += w.outputs[o + 1];
    if (!tyreOut_.empty()) {
      c.delta = w.outputs[tyreOut_[0]];
      const auto& ty = std::get<Tyre<double>>(m_.forces[sc_.roles.tyres[0]].type);
      const BodyKin<double>& K = w.kin[ty.body];
      c.ddelta = -ty.normal.dot(K.pointVelocity(K.R * ty.rho));
    }
    if (strutOut_ >= 0) {
      c.s = w.outputs[strutOut_];
      c.sdot = w.outputs[strutOut_ + 1];
      c.Pa = w.outputs[strutOut_ + 3];
    }
    if (airframe_ >= 0) {
      c.h = sc_.up.dot(r0_ - w.kin[airframe_].r);
      c.hdot = -sc_.up.dot(w.kin[airframe_].v);
    }
    return c;
  }
  // Channels on the dense output at time t (poses and force outputs only: no solve). The workspace's
  // kinematics are restored at the step's end by onStep.
  Channels channelsAt(double t, Workspace<double>& w, const DenseOutput<double>& d) {
    d.at(t, ytmp_);
    poses(m_, ytmp_, w);
    const Kins<double> K = w.kins();
    for (size_t f = 0; f < m_.forces.size(); ++f)
      std::visit([&](const auto& e) { e.outputs(K, w.outputs.data() + m_.outputOffset[f]); }, m_.forces[f].type);
    return channels(t, w);
  }

  void onStart(const Model<double>& m, const State<double>& s, Workspace<double>& w) {
    if (airframe_ >= 0) r0_ = w.kin[airframe_].r;
    prev_ = channels(s.t, w);
    EnergyReport<double> e = energy(m, s, w);
    e0_ = e.total();
    ek0_ = e.kinetic;
    uExt0_ = externalPotential(w);
    record(s, w, prev_);
    res_.metrics.peak_load_N = prev_.Py;
    res_.metrics.strut_force_max_N = prev_.Pa;
    res_.metrics.stroke_max_m = prev_.s;
    res_.metrics.h_max_m = prev_.h;
    res_.metrics.tyre_deflection_max_m = prev_.delta;
    hMinAfter_ = std::numeric_limits<double>::infinity();
    checkBottom(s);
  }

  void onStep(const Model<double>& m, const State<double>& s, Workspace<double>& w, const DenseOutput<double>& d) {
    const std::vector<double> lam(stopForces(s, w));
    const double viol = violation(s, w);
    // Compression integrals (Simpson on the dense output) over [t0, t1], and refined extrema. The step's
    // end is taken on the dense output, i.e. before any jump at t1 (a plastic impact or a projection
    // changes the velocities, hence sdot, hdot and P_a, but belongs to the next step's start).
    const double t0 = prev_.t, t1 = s.t;
    const Channels end = channelsAt(t1, w, d);
    Channels mid = channelsAt(0.5 * (t0 + t1), w, d);
    workPy_ += simpson(prev_.Py, mid.Py, end.Py, prev_.h, mid.h, end.h, prev_.hdot, mid.hdot, end.hdot, t1 - t0);
    workPa_ += simpson(prev_.Pa, mid.Pa, end.Pa, prev_.s, mid.s, end.s, prev_.sdot, mid.sdot, end.sdot, t1 - t0);
    auto& M = res_.metrics;
    // Peak P_y: max of delta (P_t grows with delta) where d(delta)/dt goes from + to -.
    refine(prev_.ddelta, end.ddelta, t0, t1, w, d, [](const Channels& c) { return c.Py; }, M.peak_load_N, &M.t_peak_s,
           end.Py, end.t);
    refine(prev_.ddelta, end.ddelta, t0, t1, w, d, [](const Channels& c) { return c.delta; }, M.tyre_deflection_max_m,
           nullptr, end.delta, end.t);
    double tS = -1, tH = -1;
    if (refine(prev_.sdot, end.sdot, t0, t1, w, d, [](const Channels& c) { return c.s; }, M.stroke_max_m, &tS, end.s, end.t)) {
      workPaAtMax_ = workPa_ - (tS < t1 ? partial(t0, tS, t1, w, d, false) : 0.0);
    }
    if (refine(prev_.hdot, end.hdot, t0, t1, w, d, [](const Channels& c) { return c.h; }, M.h_max_m, &tH, end.h, end.t)) {
      workPyAtMax_ = workPy_ - (tH < t1 ? partial(t0, tH, t1, w, d, true) : 0.0);
      tHmax_ = tH;
      hMinAfter_ = std::numeric_limits<double>::infinity();
    }
    // Peak P_a (no rate channel): where this step may hold a new maximum, search it on the dense output.
    if (std::max(mid.Pa, end.Pa) > M.strut_force_max_N)
      refine(1.0, -1.0, t0, t1, w, d, [](const Channels& c) { return c.Pa; }, M.strut_force_max_N, nullptr,
             std::max(mid.Pa, end.Pa), end.t);
    if (s.t > tHmax_) hMinAfter_ = std::min(hMinAfter_, end.h);
    M.constraint_violation_max = std::max(M.constraint_violation_max, viol);
    checkBottom(s);
    // Restore the workspace's kinematics and outputs at the step's end for the record.
    kinematics(m, s.y, w);
    {
      const Kins<double> K = w.kins();
      for (size_t f = 0; f < m.forces.size(); ++f)
        std::visit([&](const auto& e) { e.outputs(K, w.outputs.data() + m.outputOffset[f]); }, m.forces[f].type);
    }
    const Channels after = channels(s.t, w);  // after any jump: the next step's start
    M.strut_force_max_N = std::max(M.strut_force_max_N, after.Pa);
    if (opt_.record) res_.samples.push_back({after.t, after.Py, after.s, after.h, after.delta, after.Pa, lam, viol});
    prev_ = after;
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
    M.energy_absorbed_J = e.dissipated;
    double G = 0;
    for (const auto& b : m_.bodies) G += b.mass;
    M.load_factor = M.peak_load_N / (G * sc_.gravity);
    M.efficiency = (M.peak_load_N > 0 && M.h_max_m > 0) ? workPyAtMax_ / (M.peak_load_N * M.h_max_m) : 0.0;
    M.strut_efficiency =
        (M.strut_force_max_N > 0 && M.stroke_max_m > 0) ? workPaAtMax_ / (M.strut_force_max_N * M.stroke_max_m) : 0.0;
    M.rebound_h_min_m = std::isfinite(hMinAfter_) ? hMinAfter_ : M.h_max_m;
  }

 private:
  void record(const State<double>& s, const Workspace<double>& w, const Channels& c) {
    if (opt_.record) res_.samples.push_back({c.t, c.Py, c.s, c.h, c.delta, c.Pa, stopForces(s, w), violation(s, w)});
  }
  // Stop force [N] = lambda |dC/dp| (the distance stop's C is in m^2).
  std::vector<double> stopForces(const State<double>& s, const Workspace<double>& w) const {
    std::vector<double> out;
    if (!opt_.record) return out;
    for (int r : stopRows_) out.push_back(s.lambda[r] * w.rows[r].Ji.head<3>().norm());
    return out;
  }
  double violation(const State<double>& s, const Workspace<double>& w) const {
    double v = 0;
    for (int k = 0; k < m_.nRows; ++k) {
      if (!s.active[k]) continue;
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
  // Simpson's rule for integral(P dx) = integral(P xdot dt) over one step.
  static double simpson(double P0, double Pm, double P1, double, double, double, double v0, double vm, double v1, double h) {
    return h / 6.0 * (P0 * v0 + 4 * Pm * vm + P1 * v1);
  }
  // The part of this step's integral after time t (Simpson on [t, t1]).
  double partial(double t0, double t, double t1, Workspace<double>& w, const DenseOutput<double>& d, bool py) {
    (void)t0;
    Channels a = channelsAt(t, w, d), m = channelsAt(0.5 * (t + t1), w, d), b = channelsAt(t1, w, d);
    return py ? simpson(a.Py, m.Py, b.Py, 0, 0, 0, a.hdot, m.hdot, b.hdot, t1 - t)
              : simpson(a.Pa, m.Pa, b.Pa, 0, 0, 0, a.sdot, m.sdot, b.sdot, t1 - t);
  }
  // Updates the running maximum 'best' of a channel. If its rate goes from + to - inside the step, the
  // maximum is located on the dense output (Brent's minimisation of -f: golden sections and parabolic
  // steps, Forsythe, Malcolm & Moler's fmin; tolerance sqrt(eps) |t| + 1e-13, where the values are equal
  // to round-off). Returns true if the maximum moved.
  template <class F>
  bool refine(double rate0, double rate1, double t0, double t1, Workspace<double>& w, const DenseOutput<double>& d, F f,
              double& best, double* tBest, double endValue, double tEnd) {
    double v = endValue, tv = tEnd;
    if (rate0 > 0 && rate1 < 0) {
      const double cgold = 0.5 * (3.0 - std::sqrt(5.0)), sqeps = std::sqrt(2.2e-16), tol = 1e-13 * std::max(1.0, t1);
      double a = t0, b = t1, x = a + cgold * (b - a), wv = x, vv = x, e = 0, dd = 0;
      double fx = -f(channelsAt(x, w, d)), fw = fx, fv = fx;
      for (int it = 0; it < 100; ++it) {
        const double xm = 0.5 * (a + b), tol1 = sqeps * std::abs(x) + tol / 3, tol2 = 2 * tol1;
        if (std::abs(x - xm) <= tol2 - 0.5 * (b - a)) break;
        bool golden = true;
        if (std::abs(e) > tol1) {  // a parabola through x, w, v
          double r = (x - wv) * (fx - fv), q = (x - vv) * (fx - fw), p = (x - vv) * q - (x - wv) * r;
          q = 2 * (q - r);
          if (q > 0) p = -p;
          q = std::abs(q);
          const double eOld = e;
          e = dd;
          if (std::abs(p) < std::abs(0.5 * q * eOld) && p > q * (a - x) && p < q * (b - x)) {
            dd = p / q;
            const double u = x + dd;
            if (u - a < tol2 || b - u < tol2) dd = xm >= x ? tol1 : -tol1;
            golden = false;
          }
        }
        if (golden) {
          e = (x >= xm ? a : b) - x;
          dd = cgold * e;
        }
        const double u = std::abs(dd) >= tol1 ? x + dd : x + (dd > 0 ? tol1 : -tol1);
        const double fu = -f(channelsAt(u, w, d));
        if (fu <= fx) {
          (u >= x ? a : b) = x;
          vv = wv, fv = fw, wv = x, fw = fx, x = u, fx = fu;
        } else {
          (u < x ? a : b) = u;
          if (fu <= fw || wv == x) {
            vv = wv, fv = fw, wv = u, fw = fu;
          } else if (fu <= fv || vv == x || vv == wv) {
            vv = u, fv = fu;
          }
        }
      }
      if (-fx > v) {
        v = -fx;
        tv = x;
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
  const CaseOptions& opt_;
  CaseResult& res_;
  int airframe_ = -1, strutOut_ = -1;
  std::vector<int> tyreOut_, stopRows_, bottomRows_;
  Vec3<double> r0_ = Vec3<double>::Zero();
  VecX<double> ytmp_;
  Channels prev_{};
  double e0_ = 0, ek0_ = 0, uExt0_ = 0;
  double workPy_ = 0, workPa_ = 0, workPyAtMax_ = 0, workPaAtMax_ = 0;
  double tHmax_ = 0, hMinAfter_ = 0;
  long steps_ = 0;
};

}  // namespace

CaseResult runCase(const Scene& scene, const DropCase& c, const CaseOptions& opt) {
  const auto start = std::chrono::steady_clock::now();
  CaseResult res;
  res.metrics.name = c.name;
  for (int ci : scene.roles.stops) res.stopNames.push_back(scene.model.constraints[ci].name);
  const Model<double> m = caseModel(scene, c);
  State<double> s = caseState(scene, m, c);
  Workspace<double> w(m);
  DropObserver obs(scene, m, opt, res);
  const RunStatus st = simulate(m, s, w, c.duration, obs);
  obs.finish(s, w);
  res.metrics.ok = st.ok;
  res.metrics.message = st.message;
  res.metrics.steps = st.steps;
  res.metrics.rhs_evaluations = w.rhsEvaluations;
  res.metrics.constraint_violation_max = std::max(res.metrics.constraint_violation_max, st.maxPositionViolation);
  auto& M = res.metrics;
  for (double v : {M.peak_load_N, M.stroke_max_m, M.h_max_m, M.tyre_deflection_max_m, M.efficiency, M.strut_efficiency,
                   M.energy_absorbed_J, M.energy_balance_error})
    if (!std::isfinite(v) && M.ok) {
      M.ok = false;
      M.message = "non-finite result";
    }
  res.metrics.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return res;
}

std::vector<CaseResult> runCases(const Scene& scene, const std::vector<DropCase>& cases, int threads,
                                 const CaseOptions& opt) {
  std::vector<CaseResult> out(cases.size());
  const int n = static_cast<int>(cases.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads))
  for (int i = 0; i < n; ++i) out[i] = runCase(scene, cases[i], opt);
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
  return r.samples.back().s;
}

}  // namespace lg
