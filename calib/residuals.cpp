// Residuals of a calibration and their central-difference Jacobian (residuals.hpp).
#include "calib/residuals.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <exception>

namespace lg::calib {

Point initialPoint(const Calibration& c) {
  Point p;
  for (const auto& q : c.parameters) p.x.push_back(q.initial);
  for (const auto& m : c.measurements) p.shift.push_back(m.shift.value);
  return p;
}

std::optional<std::string> designScene(const Calibration& c, const std::vector<double>& x, Scene& out) {
  out = c.scene;
  std::vector<Parameter> ps;
  for (const auto& q : c.parameters) ps.push_back(q.parameter);
  return applyParameters(out, ps, x);
}

SampleRows sampleRows(const Measurement& m, double shift, double duration) {
  // Output rows: t = 0 for the samples up to touchdown, then one per later sample (the last clamped to
  // the case's end against round-off).
  SampleRows out;
  out.row.assign(m.t.size(), 0);
  for (std::size_t i = 0; i < m.t.size(); ++i)
    if (m.t[i] - shift <= 0) {
      out.times.assign(1, 0.0);
      break;
    }
  for (std::size_t i = 0; i < m.t.size(); ++i) {
    const double ts = std::min(m.t[i] - shift, duration);
    if (ts <= 0) continue;
    if (out.times.empty() || ts > out.times.back()) out.times.push_back(ts);
    out.row[i] = out.times.size() - 1;
  }
  return out;
}

Simulated simulateMeasurement(const Calibration& c, std::size_t k, const Scene& design, double shift,
                              const std::function<bool()>& stop) {
  const Measurement& m = c.measurements[k];
  const DropCase dc = m.sceneCase >= 0 ? design.cases[static_cast<std::size_t>(m.sceneCase)] : m.dropCase;
  Simulated out;
  const SampleRows rows = sampleRows(m, shift, dc.duration);
  const std::vector<double>& times = rows.times;
  const std::vector<std::size_t>& row = rows.row;
  CaseOptions opt;
  opt.record = true;
  opt.outputTimes = times;
  opt.stop = stop;
  CaseResult r;
  try {
    r = runCase(design, dc, opt);
  } catch (const std::exception& e) {
    out.message = e.what();
    return out;
  }
  if (!r.metrics.ok) {
    out.message = "case '" + dc.name + "': " + (r.metrics.message.empty() ? "the simulation failed" : r.metrics.message);
    return out;
  }
  if (r.samples.size() != times.size()) {
    out.message = "case '" + dc.name + "': the run ended before the last sample";
    return out;
  }
  const int h = r.column("h");
  for (const Channel& ch : m.channels) {
    std::vector<double> v(m.t.size());
    for (std::size_t i = 0; i < m.t.size(); ++i) {
      const double ts = m.t[i] - shift;
      if (ts > 0) {
        v[i] = r.samples[row[i]].values[static_cast<std::size_t>(ch.historyColumn)];
        continue;
      }
      // Free fall before touchdown: the touchdown row, and the travel h = V t + (1 - L) g t^2 / 2.
      v[i] = r.samples[0].values[static_cast<std::size_t>(ch.historyColumn)];
      if (ch.historyColumn == h) v[i] += dc.sinkSpeed * ts + 0.5 * (1 - dc.liftRatio) * design.gravity * ts * ts;
    }
    out.y.push_back(std::move(v));
  }
  out.ok = true;
  return out;
}

Eigen::VectorXd weightedResiduals(const Measurement& m, const Simulated& s) {
  Eigen::VectorXd r(static_cast<Eigen::Index>(m.residuals()));
  Eigen::Index k = 0;
  for (std::size_t c = 0; c < m.channels.size(); ++c) {
    if (!m.channels[c].fitted()) continue;
    const double w = m.channels[c].weight;
    for (std::size_t i = 0; i < m.t.size(); ++i) r[k++] = w * (s.y[c][i] - m.y[c][i]);
  }
  return r;
}

namespace {

std::string number(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

// The points of one derivative: central (x - d, x + d), or one-sided of second order where a central
// step would leave [lower, upper] (x + d, x + 2d, or x - d, x - 2d).
struct Stencil {
  enum Kind { Central, Forward, Backward } kind = Central;
  double a = 0, b = 0;  // the two points
  double d = 0;         // the step
  std::string name;     // for messages: "strut.f1"
};

Stencil stencil(double x, double d, double lower, double upper, const std::string& name) {
  Stencil s;
  s.d = d;
  s.name = name;
  const bool up = x + d <= upper, down = x - d >= lower;
  if (up && !down && x + 2 * d <= upper) {
    s.kind = Stencil::Forward;
    s.a = x + d;
    s.b = x + 2 * d;
  } else if (down && !up && x - 2 * d >= lower) {
    s.kind = Stencil::Backward;
    s.a = x - d;
    s.b = x - 2 * d;
  } else {
    s.a = x - d;
    s.b = x + d;
  }
  return s;
}

// The derivative from the base residuals r0 and those at the stencil's points.
Eigen::VectorXd derivative(const Stencil& s, const Eigen::VectorXd& r0, const Eigen::VectorXd& ra, const Eigen::VectorXd& rb) {
  switch (s.kind) {
    case Stencil::Forward: return (-3 * r0 + 4 * ra - rb) / (2 * s.d);
    case Stencil::Backward: return (3 * r0 - 4 * ra + rb) / (2 * s.d);
    default: return (rb - ra) / (s.b - s.a);
  }
}

// One run of the scheme: measurement m at the point with unknown 'column' (a parameter index, the
// shift at index p, -1 none) set to 'value'.
struct Task {
  Task(std::size_t m_, int column_, double value_) : m(m_), column(column_), value(value_) {}
  std::size_t m = 0;
  int column = -1;
  double value = 0;
  bool ok = false;
  std::string message;
  Eigen::VectorXd r;
};

}  // namespace

std::string CentralDifferences::source() const {
  return "central differences, relative step h = " + number(c_.fit.jacobianStep) + " (t_shift: " +
         number(c_.fit.shiftStep) + " s)";
}

void CentralDifferences::evaluate(const Point& p, bool jacobians, std::vector<MeasurementEval>& out) const {
  run(p, jacobians, 1.0, out);
}

bool CentralDifferences::secondJacobian(const Point& p, std::vector<MeasurementEval>& out) const {
  run(p, true, 2.0, out);
  return true;
}

void CentralDifferences::run(const Point& p, bool jacobians, double stepFactor, std::vector<MeasurementEval>& out) const {
  const std::size_t np = c_.parameters.size(), nm = c_.measurements.size();
  // The stencils: one per parameter (shared by the measurements), one per fitted shift.
  std::vector<Stencil> ps;
  for (std::size_t i = 0; i < np; ++i) {
    const FitParameter& q = c_.parameters[i];
    ps.push_back(stencil(p.x[i], stepFactor * c_.fit.jacobianStep * q.scale, q.lower, q.upper, q.path));
  }
  std::vector<Stencil> ss(nm);
  std::vector<Task> tasks;
  for (std::size_t m = 0; m < nm; ++m) {
    const TimeShift& sh = c_.measurements[m].shift;
    tasks.emplace_back(m, -1, 0.0);
    if (!jacobians) continue;
    for (std::size_t i = 0; i < np; ++i) {
      tasks.emplace_back(m, static_cast<int>(i), ps[i].a);
      tasks.emplace_back(m, static_cast<int>(i), ps[i].b);
    }
    if (!sh.fit) continue;
    ss[m] = stencil(p.shift[m], stepFactor * c_.fit.shiftStep, sh.lower, sh.upper, c_.measurements[m].name + ".t_shift");
    tasks.emplace_back(m, static_cast<int>(np), ss[m].a);
    tasks.emplace_back(m, static_cast<int>(np), ss[m].b);
  }
  const int n = static_cast<int>(tasks.size());
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads_))
  for (int k = 0; k < n; ++k) {
    Task& t = tasks[static_cast<std::size_t>(k)];
    try {
      std::vector<double> x = p.x;
      double shift = p.shift[t.m];
      if (t.column >= 0 && t.column < static_cast<int>(np)) x[static_cast<std::size_t>(t.column)] = t.value;
      if (t.column == static_cast<int>(np)) shift = t.value;
      Scene design;
      if (const auto why = designScene(c_, x, design)) {
        t.message = "the scene rejects the design: " + *why;
        continue;
      }
      const Simulated s = simulateMeasurement(c_, t.m, design, shift, stop_);
      t.ok = s.ok;
      t.message = s.message;
      if (s.ok) t.r = weightedResiduals(c_.measurements[t.m], s);
    } catch (const std::exception& e) {
      t.message = e.what();
    }
  }
  // Gather in task order.
  out.assign(nm, MeasurementEval{});
  std::size_t at = 0;
  for (std::size_t m = 0; m < nm; ++m) {
    MeasurementEval& e = out[m];
    const Task& base = tasks[at++];
    e.ok = base.ok;
    e.message = base.message;
    e.r = base.r;
    if (!jacobians) continue;
    const Eigen::Index rows = static_cast<Eigen::Index>(c_.measurements[m].residuals());
    e.J.resize(rows, static_cast<Eigen::Index>(np));
    const bool shifted = c_.measurements[m].shift.fit;
    const std::size_t cols = np + (shifted ? 1 : 0);
    for (std::size_t i = 0; i < cols; ++i) {
      const Task& a = tasks[at++];
      const Task& b = tasks[at++];
      const Stencil& s = i < np ? ps[i] : ss[m];
      if (!e.ok) continue;
      if (!a.ok || !b.ok) {
        e.ok = false;
        e.message = "the Jacobian's run at " + s.name + " = " + number(a.ok ? b.value : a.value) + ": " + (a.ok ? b.message : a.message);
        continue;
      }
      const Eigen::VectorXd d = derivative(s, e.r, a.r, b.r);
      if (i < np) e.J.col(static_cast<Eigen::Index>(i)) = d;
      else e.Jshift = d;
    }
  }
}

}  // namespace lg::calib
