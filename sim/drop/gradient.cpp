// Forward-mode derivatives of drop-test metrics (drop_gradient.hpp).
#include "sim/drop/gradient.hpp"

#include "sim/drop/accuracy.hpp"

#include <cmath>
#include <cstdio>
#include <limits>

#include "sim/core/jet.hpp"
#include "sim/drop/observer.hpp"

namespace lg {
namespace {

std::string num(double v, int digits = 4) {
  char b[40];
  std::snprintf(b, sizeof b, "%.*g", digits, v);
  return b;
}

// The figure of a gradient metric, in the run's scalar.
template <class S> S figure(const CaseFigures<S>& F, const std::string& metric, bool drag) {
  if (metric == "peak_load") return F.peak_load;
  if (metric == "t_peak") return F.t_peak;
  if (metric == "load_factor") return F.load_factor;
  if (metric == "inertia_load_factor") return F.inertia_load_factor;
  if (metric == "stroke") return F.stroke_max;
  if (metric == "stroke_margin") return F.stroke_margin;
  if (metric == "h_max") return F.h_max;
  if (metric == "tyre_deflection") return F.tyre_deflection_max;
  if (metric == "tyre_margin") return F.tyre_margin;
  if (metric == "efficiency") return F.efficiency;
  if (metric == "strut_efficiency") return F.strut_efficiency;
  if (metric == "strut_force") return F.strut_force_max;
  if (metric == "energy_absorbed") return F.energy_absorbed;
  if (metric == "rebound_velocity") return F.rebound_velocity;
  if (metric == "drag_peak" && drag) return F.drag_peak;  // (a scene without a drag load has none)
  return S(std::numeric_limits<double>::quiet_NaN());
}

// The kinks of a run at its design, per metric (values only; see drop_gradient.hpp).
struct Kinks {
  std::string humps, bottoming, stick, plateau;  // a reason each, or empty
  double tStick = -1;                   // [s] start of the first stick
};

template <class S> Kinks findKinks(const CaseFigures<S>& F, const DropCase& c, double bottomSpeed, double touchdown) {
  Kinks k;
  const double peak = value(F.peak_load), tPeak = value(F.t_peak);
  const auto [tOther, other] = secondLoadHump(F);
  if (other > 0 && peak > 0 && (peak - other) / peak < 1e-3)
    k.humps = "two maxima of P_y within " + num(100 * (peak - other) / peak, 2) + " % (at t = " + num(tPeak) + " s and " +
              num(tOther) + " s): the peak can jump between them; the derivative is the one of the hump at t = " +
              num(tPeak) + " s";
  const double Smax = std::isnan(value(F.stroke_margin)) ? 0 : value(F.stroke_max + F.stroke_margin);
  if (F.bottomed && bottomSpeed >= 0 && bottomSpeed < 1e-3 * touchdown)
    k.bottoming = "the strut reaches its bottoming stop at a speed of " + num(bottomSpeed) +
                  " m/s: bottoming begins at this design; the derivative is the bottomed side's";
  else if (!F.bottomed && Smax > 0 && value(F.stroke_margin) < 1e-3 * Smax)
    k.bottoming = "the strut stops " + num(value(F.stroke_margin)) +
                  " m short of its bottoming stop: bottoming begins near this design; the derivative is the side that "
                  "does not bottom";
  if (value(F.rebound_velocity) > 0 && std::abs(c.liftRatio - 1) < 1e-12)
    k.plateau = "lift equal to the weight: after lift-off no net force acts, and with L > 1 the largest upward velocity "
                "moves to the end of the run: its derivative in the lift ratio is one-sided (the side of L <= 1)";
  if (!F.stickIntervals.empty()) {  // (regularised friction only: exact Coulomb stick is an event, differentiated)
    k.tStick = F.stickIntervals.front().first;
    k.stick = "a strut sticks from t = " + num(k.tStick) +
              " s (|s'| within ten friction velocities): the derivative is the regularised friction's, not the Coulomb "
              "limit's";
  }
  return k;
}

// The time a metric is reached (for the stick rule): the run's end for the rebound.
template <class S> double metricTime(const CaseFigures<S>& F, const std::string& metric, double duration) {
  if (metric == "peak_load" || metric == "t_peak" || metric == "load_factor" || metric == "inertia_load_factor" ||
      metric == "tyre_deflection" || metric == "tyre_margin")
    return value(F.t_peak);
  if (metric == "strut_force") return F.tStrutForceMax;
  if (metric == "stroke" || metric == "stroke_margin" || metric == "strut_efficiency") return F.tStrokeMax;
  if (metric == "rebound_velocity") return duration;
  return F.tHMax;  // h_max, efficiency, energy_absorbed
}

// The model and state of a pass: parameters [first, first + N) seeded in components 0 .. N-1.
// An envelope quantity is seeded at the case's own point (its corner's value, or the scene's).
template <class J>
void seedPass(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params, size_t first, Model<J>& m,
              J& V, J& L, EnvelopePoint<J>& at) {
  constexpr int N = J::DIMENSION;
  at = casePoint(scene, c).template cast<J>();
  for (size_t j = first; j < std::min(params.size(), first + N); ++j) {
    const Parameter& p = params[j];
    if (p.kind == Parameter::Kind::Envelope) {
      setEnvelopeValue(at, p.key, J(envelopeValue(casePoint(scene, c), p.key), static_cast<int>(j - first)));
      continue;
    }
    const double x = parameterValue(scene, p);
    const J seeded(x, static_cast<int>(j - first));
    if (p.kind != Parameter::Kind::Case) setModelParameter(m, p, seeded);
    else if (scene.cases[p.index].name == c.name) (p.key == "sink_speed" ? V : L) = seeded;
  }
}

template <int N>
bool runPass(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params, size_t first, CaseGradient& g,
             Kinks& kinks) {
  using J = ceres::Jet<double, N>;
  Model<J> m = scene.model.template cast<J>();
  J V(c.sinkSpeed), L(c.liftRatio);
  EnvelopePoint<J> at;
  seedPass(scene, c, params, first, m, V, L, at);
  applyCase(scene, m, c, L, &at);
  State<J> s = caseState(scene, m, V, c.dropHeight);
  Workspace<J> w(m);
  bool drag = false;  // a tyre with a longitudinal force: the peak drag is a figure of the run
  for (int f : scene.roles.tyres) drag = drag || std::get<Tyre<double>>(scene.model.forces[f].type).longitudinal;
  CaseOptions opt;
  DropObserver<J> obs(scene, m, c, V, L, opt, nullptr);
  const RunStatus st = simulate(m, s, w, c.duration, obs);
  const CaseFigures<J>& F = obs.finish(s, w);
  if (first == 0) {
    g.values = caseMetrics(valuesOf(F), scene, c);
    g.values.ok = st.ok;
    g.values.message = st.message;
    g.values.steps = st.steps;
    g.values.rhs_evaluations = w.rhsEvaluations;
  }
  if (!st.ok) {
    g.ok = false;
    g.message = st.message;
    return false;
  }
  for (auto& md : g.metrics) {
    const J f = figure(F, md.metric, drag);
    md.value = f.a;
    for (size_t j = first; j < std::min(params.size(), first + N); ++j)  // (no derivative of a metric the scene has not)
      md.d[j] = std::isnan(f.a) ? f.a : f.v[static_cast<int>(j - first)];
  }
  if (first == 0) {
    kinks = findKinks(F, c, obs.bottomingSpeed(), touchdownSpeed(c, scene.gravity));
    for (auto& md : g.metrics) {
      std::string why;
      auto add = [&](const std::string& s) { why += (why.empty() ? "" : "; ") + s; };
      const bool peakBased = md.metric == "peak_load" || md.metric == "t_peak" || md.metric == "load_factor" ||
                             md.metric == "inertia_load_factor" || md.metric == "efficiency" ||
                             md.metric == "tyre_deflection" || md.metric == "tyre_margin";
      if (peakBased && !kinks.humps.empty()) add(kinks.humps);
      if (!kinks.bottoming.empty()) add(kinks.bottoming);
      if (md.metric == "rebound_velocity" && !kinks.plateau.empty()) add(kinks.plateau);
      if (!kinks.stick.empty() && kinks.tStick < metricTime(F, md.metric, c.duration)) add(kinks.stick);
      md.smooth = why.empty();
      md.note = why;
    }
  }
  return true;
}

// One pass of caseHistoryGradient: parameters [first, first + N), the time in component 'timeSlot' (-1:
// not in this pass).
template <int N>
bool historyPass(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params, size_t first, int timeSlot,
                 const std::vector<double>& times, HistoryGradient& g, CaseMetrics* firstMetrics) {
  using J = ceres::Jet<double, N>;
  Model<J> m = scene.model.template cast<J>();
  J V(c.sinkSpeed), L(c.liftRatio);
  EnvelopePoint<J> at;
  seedPass(scene, c, params, first, m, V, L, at);
  applyCase(scene, m, c, L, &at);
  State<J> s = caseState(scene, m, V, c.dropHeight);
  Workspace<J> w(m);
  CaseOptions opt;
  opt.outputTimes = times;
  DropObserver<J> obs(scene, m, c, V, L, opt, nullptr);
  std::vector<std::vector<J>> rows;
  rows.reserve(times.size());
  obs.recordRows(&rows, timeSlot);
  const RunStatus st = simulate(m, s, w, c.duration, obs);
  if (st.ok && firstMetrics) *firstMetrics = caseMetrics(valuesOf(obs.finish(s, w)), scene, c);
  if (!st.ok || rows.size() != times.size()) {
    g.ok = false;
    g.message = st.ok ? "the run ended before the last output time" : st.message;
    return false;
  }
  const bool fill = g.value.empty();
  if (fill) {
    g.value.assign(rows.size(), {});
    g.d.assign(rows.size(), {});
  }
  for (size_t r = 0; r < rows.size(); ++r) {
    const size_t nc = rows[r].size();
    if (fill) {
      g.value[r].resize(nc);
      g.d[r].assign(nc, std::vector<double>(params.size(), 0.0));
    }
    for (size_t k = 0; k < nc; ++k) {
      const J& x = rows[r][k];
      if (fill) g.value[r][k] = x.a;
      for (size_t j = first; j < std::min(params.size(), first + N); ++j) g.d[r][k][j] = x.v[static_cast<int>(j - first)];
      if (timeSlot >= 0) g.rate[r][k] = x.v[timeSlot];
    }
  }
  return true;
}

// caseHistoryGradient of a run at the scene's accuracy for the accuracy 'asked', followed by the runs
// nextAccuracy asks for; 'asked' 0 keeps the scene's settings whatever its peak.
HistoryGradient historyGradientOf(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params,
                                  const std::vector<double>& times, bool rates, int width, double asked) {
  HistoryGradient g;
  g.times = times;
  const size_t ncols = historyColumns(scene).size();
  if (rates) g.rate.assign(times.size(), std::vector<double>(ncols, 0.0));
  // Components: the parameters, then the time (with rates); at least one pass for the values.
  const size_t n = std::max<size_t>(params.size() + (rates ? 1 : 0), 1);
  for (size_t first = 0; first < n;) {
    const size_t left = n - first;
    const int w = std::min(width, left >= 4 ? 4 : left >= 2 ? (left == 2 ? 2 : 4) : 1);
    const int timeSlot = rates && params.size() >= first && params.size() < first + static_cast<size_t>(w)
                             ? static_cast<int>(params.size() - first)
                             : -1;
    bool ok = false;
    // A flat peak or two of nearly one height under an accuracy setting: the histories of runCase's
    // last run (its tighter accuracy), each run decided on the first pass's metrics of the one before.
    CaseMetrics firstMetrics;
    CaseMetrics* want = asked > 0 && first == 0 && scene.model.settings.accuracy > 0 ? &firstMetrics : nullptr;
    if (w == 1) ok = historyPass<1>(scene, c, params, first, timeSlot, times, g, want);
    else if (w == 2) ok = historyPass<2>(scene, c, params, first, timeSlot, times, g, want);
    else ok = historyPass<kJetWidth>(scene, c, params, first, timeSlot, times, g, want);
    if (!ok) break;
    const double next = want ? nextAccuracy(asked, scene.model.settings.accuracy, firstMetrics) : 0;
    if (next > 0) return historyGradientOf(withAccuracy(scene, next), c, params, times, rates, width, asked);
    first += static_cast<size_t>(w);
  }
  return g;
}

}  // namespace

HistoryGradient caseHistoryGradient(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params,
                                    const std::vector<double>& times, bool rates, int width) {
  return historyGradientOf(scene, c, params, times, rates, width, scene.model.settings.accuracy);
}

const MetricDerivative* CaseGradient::find(const std::string& metric) const {
  for (const auto& m : metrics)
    if (m.metric == metric) return &m;
  return nullptr;
}

const std::vector<MetricInfo>& gradientMetrics() {
  static const std::vector<MetricInfo> list = [] {
    std::vector<MetricInfo> out;
    for (const char* n : {"peak_load", "t_peak", "load_factor", "inertia_load_factor", "stroke", "stroke_margin", "h_max",
                          "tyre_deflection", "tyre_margin", "efficiency", "strut_efficiency", "strut_force",
                          "energy_absorbed", "rebound_velocity", "drag_peak"})
      out.push_back(*findMetric(n));
    return out;
  }();
  return list;
}

std::string parameterUnit(const Scene&, const Parameter& p) { return unitOfKey(p.key); }

void checkGradientParameter(const Parameter& p, const std::string& where) {
  if (p.kind == Parameter::Kind::Case && p.key == "duration")
    throw InputError(where, 0, p.path, "a case's duration has no derivative: choose a parameter of the model or the case's "
                                       "sink_speed or lift_ratio");
}

namespace {

// The values of the last of a case's runs, returned through the run before it (at an accuracy for
// 'asked', which asked for 'next' because of 'why'): the accuracy asked for, the last run's, and every
// reason, as runCase's.
void markLaterRun(CaseMetrics& v, const std::string& why, double asked, double next) {
  v.accuracy = asked;
  if (!std::isfinite(v.accuracy_rerun)) {  // (v is the last run's own)
    v.accuracy_rerun = next;
    v.accuracy_rerun_reason = why + undecidedPeaks(asked, next, v);
  } else {
    v.accuracy_rerun_reason = why + "; " + v.accuracy_rerun_reason;
  }
}

// caseGradient of a run at the scene's accuracy for the accuracy 'asked' (the first: the scene's own),
// followed by the runs nextAccuracy asks for; 'asked' 0 keeps the scene's settings whatever its peak.
CaseGradient gradientOf(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params, int width,
                        double asked) {
  CaseGradient g;
  g.caseName = c.name;
  for (const auto& p : params) g.parameters.push_back(p.path);
  for (const auto& info : gradientMetrics()) {
    MetricDerivative md;
    md.metric = info.name;
    md.d.assign(params.size(), 0.0);
    g.metrics.push_back(md);
  }
  Kinks kinks;
  const size_t n = std::max<size_t>(params.size(), 1);
  for (size_t first = 0; first < n;) {
    // The narrowest of the widths 1, 2, 4 (at most 'width') that holds the parameters left: 5 parameters
    // run as 4 + 1, not 4 + 4.
    const size_t left = n - first;
    const int w = std::min(width, left >= 4 ? 4 : left >= 2 ? (left == 2 ? 2 : 4) : 1);
    bool ok = false;
    if (w == 1) ok = runPass<1>(scene, c, params, first, g, kinks);
    else if (w == 2) ok = runPass<2>(scene, c, params, first, g, kinks);
    else ok = runPass<kJetWidth>(scene, c, params, first, g, kinks);
    if (!ok) break;
    if (first == 0) {
      const double ran = scene.model.settings.accuracy;
      g.values.accuracy = ran;
      // A flat peak or two of nearly one height under an accuracy setting: the case's run at the tighter
      // accuracy (as runCase does), and again while two close peaks stay unordered.
      const double next = asked > 0 ? nextAccuracy(asked, ran, g.values) : 0;
      if (next > 0) {
        CaseGradient again = gradientOf(withAccuracy(scene, next), c, params, width, asked);
        markLaterRun(again.values, nextReason(asked, ran, g.values), asked, next);
        return again;
      }
    }
    first += static_cast<size_t>(w);
  }
  return g;
}

}  // namespace

CaseGradient caseGradient(const Scene& scene, const DropCase& c, const std::vector<Parameter>& params, int width) {
  return gradientOf(scene, c, params, width, scene.model.settings.accuracy);
}

}  // namespace lg
