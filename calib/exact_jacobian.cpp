// The exact Jacobian of a calibration's residuals (exact_jacobian.hpp).
#include "calib/exact_jacobian.hpp"

#include <omp.h>

#include <algorithm>
#include <exception>

#include "sim/drop/gradient.hpp"

namespace lg::calib {

std::string ExactDerivatives::source() const { return "exact (forward mode through the drop test, ceres::Jet)"; }

void ExactDerivatives::evaluate(const Point& p, bool jacobians, std::vector<MeasurementEval>& out) const {
  const int n = static_cast<int>(c_.measurements.size());
  out.assign(c_.measurements.size(), MeasurementEval{});
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, threads_))
  for (int m = 0; m < n; ++m) {
    MeasurementEval& e = out[static_cast<std::size_t>(m)];
    try {
      evaluateOne(p, static_cast<std::size_t>(m), jacobians, e);
    } catch (const std::exception& ex) {
      e.ok = false;
      e.message = ex.what();
    }
  }
}

void ExactDerivatives::evaluateOne(const Point& p, std::size_t k, bool jacobians, MeasurementEval& e) const {
  const Measurement& m = c_.measurements[k];
  Scene design;
  if (const auto why = designScene(c_, p.x, design)) {
    e.message = "the scene rejects the design: " + *why;
    return;
  }
  const double shift = p.shift[k];
  const Simulated s = simulateMeasurement(c_, k, design, shift, stop_);
  e.ok = s.ok;
  e.message = s.message;
  if (!s.ok) return;
  e.r = weightedResiduals(m, s);
  if (!jacobians) return;

  // The parameters that reach this measurement: the model's, and those of its own scene case.
  const DropCase dc = m.sceneCase >= 0 ? design.cases[static_cast<std::size_t>(m.sceneCase)] : m.dropCase;
  const std::size_t np = c_.parameters.size();
  std::vector<Parameter> reach;
  std::vector<std::size_t> column;  // reach[j] is parameter column[j]
  for (std::size_t i = 0; i < np; ++i) {
    const Parameter& q = c_.parameters[i].parameter;
    if (q.kind == Parameter::Kind::Case && q.index != m.sceneCase) continue;
    reach.push_back(q);
    column.push_back(i);
  }
  const SampleRows rows = sampleRows(m, shift, dc.duration);
  const HistoryGradient g = caseHistoryGradient(design, dc, reach, rows.times, m.shift.fit);
  if (!g.ok) {
    e.ok = false;
    e.message = "case '" + dc.name + "', the derivative run: " + g.message;
    return;
  }
  // dV/dx_j, dL/dx_j of the free fall before touchdown.
  std::vector<double> dV(np, 0.0), dL(np, 0.0);
  for (std::size_t i = 0; i < np; ++i) {
    const Parameter& q = c_.parameters[i].parameter;
    if (q.kind != Parameter::Kind::Case || q.index != m.sceneCase) continue;
    (q.key == "sink_speed" ? dV : dL)[i] = q.key == "sink_speed" || q.key == "lift_ratio" ? 1.0 : 0.0;
  }
  const int hColumn = [&] {
    const auto cols = historyColumns(design);
    for (std::size_t c = 0; c < cols.size(); ++c)
      if (cols[c].name == "h") return static_cast<int>(c);
    return -1;
  }();
  const Eigen::Index nr = static_cast<Eigen::Index>(m.residuals());
  e.J = Eigen::MatrixXd::Zero(nr, static_cast<Eigen::Index>(np));
  if (m.shift.fit) e.Jshift = Eigen::VectorXd::Zero(nr);
  const double gz = design.gravity;
  Eigen::Index r = 0;
  for (const Channel& ch : m.channels) {
    if (!ch.fitted()) continue;
    const double w = ch.weight;
    const auto col = static_cast<std::size_t>(ch.historyColumn);
    const bool travel = ch.historyColumn == hColumn;
    for (std::size_t i = 0; i < m.t.size(); ++i, ++r) {
      const double ts = m.t[i] - shift;
      const std::size_t row = rows.row[i];
      for (std::size_t j = 0; j < reach.size(); ++j) e.J(r, static_cast<Eigen::Index>(column[j])) = w * g.d[row][col][j];
      if (ts > 0) {
        if (m.shift.fit && ts < dc.duration) e.Jshift[r] = -w * g.rate[row][col];
        continue;
      }
      if (!travel) continue;  // the touchdown value, whatever the shift
      for (std::size_t j = 0; j < np; ++j)
        e.J(r, static_cast<Eigen::Index>(j)) += w * (dV[j] * ts - 0.5 * dL[j] * gz * ts * ts);
      if (m.shift.fit) e.Jshift[r] = -w * (dc.sinkSpeed + (1 - dc.liftRatio) * gz * ts);
    }
  }
}

}  // namespace lg::calib
