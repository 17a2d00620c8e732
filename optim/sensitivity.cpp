// Sensitivity studies on the simulator (sensitivity.hpp).
#include "optim/sensitivity.hpp"

#include "sim/drop/gradient.hpp"
#include "sim/scene/parameters.hpp"

#include <cmath>
#include <cstdio>
#include <exception>
#include <limits>

#include "optim/evaluator.hpp"
#include "sim/io/toml_reader.hpp"
#include "sim/drop/metrics.hpp"
#include "uq/random.hpp"

namespace lg::optim {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Seed streams of the one user seed.
enum Stream : std::uint64_t { kSobolShift = 1, kMorrisDesign = 2, kSobolBootstrap = 3, kMorrisBootstrap = 4 };

std::string shortNum(double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  return b;
}

std::vector<double> physicalPoints(const Study& s, const std::vector<double>& scaled) {
  const std::size_t d = s.variables.size();
  std::vector<double> out(scaled.size());
  for (std::size_t k = 0; k < scaled.size(); ++k) out[k] = toPhysical(s.variables[k % d], scaled[k]);
  return out;
}

// Runs every design of 'points' (physical, row-major) over ranks and threads.
std::vector<uq::Outcome> runDesigns(const Study& s, const SensitivitySettings& g, const std::vector<double>& points,
                                    std::size_t outputs, const std::string& method, const SensitivityOptions& o,
                                    uq::Communicator& comm) {
  const std::size_t d = s.variables.size();
  const std::size_t runs = points.size() / d;
  uq::BatchOptions bo;
  bo.threads = o.threads;
  if (o.progress) bo.progress = [&](std::size_t done, std::size_t mine) { o.progress(method, done, mine); };
  return uq::evaluateBatch(
      runs, outputs,
      [&](std::size_t k) {
        if (o.stop && o.stop()) return uq::Outcome{std::vector<double>(outputs, kNaN), "interrupted"};
        return evaluateSensitivityDesign(s, g, std::vector<double>(points.begin() + k * d, points.begin() + (k + 1) * d),
                                         o.stop);
      },
      comm, bo);
}

// Failed runs of a method: counted per case of interest (a NaN output of the case), listed with 'where'.
MethodFailures failures(const std::vector<uq::Outcome>& runs, const std::vector<SensitivityOutput>& outs,
                        std::size_t cases, const std::function<std::string(std::size_t)>& where) {
  MethodFailures f;
  f.perCase.assign(cases, 0);
  for (std::size_t k = 0; k < runs.size(); ++k) {
    const uq::Outcome& r = runs[k];
    bool any = !r.failure.empty();
    for (std::size_t c = 0; c < cases; ++c) {
      bool failed = false;
      for (std::size_t j = c; j < outs.size(); j += cases) failed = failed || !std::isfinite(r.y[j]);
      f.perCase[c] += failed ? 1 : 0;
      any = any || failed;
    }
    if (!any) continue;
    ++f.runs;
    f.list.push_back({k, where(k), r.failure.empty() ? "non-finite metric" : r.failure});
  }
  return f;
}

std::vector<double> outputColumn(const std::vector<uq::Outcome>& runs, std::size_t j) {
  std::vector<double> y(runs.size());
  for (std::size_t k = 0; k < runs.size(); ++k) y[k] = runs[k].y[j];
  return y;
}

}  // namespace

std::vector<SensitivityOutput> sensitivityOutputs(const Study& s, const SensitivitySettings& g) {
  std::vector<SensitivityOutput> out;
  for (const std::string& m : g.metrics)
    for (int c : g.cases) {
      SensitivityOutput o;
      o.caseIndex = c;
      o.caseName = s.cases[c].dropCase.name;
      o.metric = m;
      const MetricInfo* info = findMetric(m);
      o.unit = info ? info->unit : "-";
      out.push_back(o);
    }
  return out;
}

std::string derivativeSource(const SensitivitySettings& g) {
  if (g.exactDerivatives) return "exact (forward mode through the run, ceres::Jet)";
  return "central differences, relative step h = " + shortNum(g.step);
}

double sensitivityDrops(const Study& s, const SensitivitySettings& g) {
  const double D = static_cast<double>(s.variables.size());
  const double designs = (g.local ? (g.exactDerivatives ? 1 + D : 1 + 2 * D) : 0) +
                         (g.morris ? g.trajectories * (D + 1) : 0) + (g.sobol ? g.samples * (D + 2) : 0);
  return designs * static_cast<double>(std::max<std::size_t>(1, g.cases.size()));
}

void checkSensitivity(const Study& s, const SensitivitySettings& g, const std::string& samplesFlag) {
  // The size first: a study too large to hold is refused before anything is allocated.
  auto fail = [&](const std::string& key, const std::string& rule) {
    if (key == "samples" && !samplesFlag.empty()) throw InputError("command line", 0, samplesFlag, rule);
    throw InputError(s.file, g.line, "sensitivity." + key, rule);
  };
  if (const double drops = sensitivityDrops(s, g); drops > kMaxSensitivityDrops)
    fail(g.sobol ? "samples" : "trajectories",
         "the methods ask for " + fmt(drops) + " drops (" + std::to_string(s.variables.size()) + " variables, " +
             std::to_string(std::max<std::size_t>(1, g.cases.size())) + " cases" +
             (g.sobol ? ", Sobol N = " + std::to_string(g.samples) : "") + (g.morris ? ", Morris r = " + std::to_string(g.trajectories) : "") +
             "), more than " + fmt(kMaxSensitivityDrops) + ": lower N or r, or run the methods apart");
  if (g.sobol && static_cast<double>(g.resamples) * g.samples > kMaxBootstrapWork)
    fail(samplesFlag.empty() ? "resamples" : "samples",
         "the bootstrap would redraw N = " + std::to_string(g.samples) + " samples " + std::to_string(g.resamples) +
             " times (" + fmt(static_cast<double>(g.resamples) * g.samples) + " draws), more than " + fmt(kMaxBootstrapWork) +
             ": lower resamples or N");
  if (!g.local) return;
  for (std::size_t i = 0; i < s.variables.size(); ++i)
    if (s.variables[i].initial == 0)
      throw InputError(s.file, s.variables[i].line, "variable[" + std::to_string(i) + "].initial",
                       "value 0: a local sensitivity is an elasticity d ln f / d ln x, which needs a nonzero baseline; "
                       "give a nonzero initial or leave \"local\" out of [sensitivity] methods (or --method)");
  if (g.metrics.empty()) throw InputError(s.file, g.line, "sensitivity.metrics", "no metric of interest");
}

uq::Outcome evaluateSensitivityDesign(const Study& s, const SensitivitySettings& g, const std::vector<double>& x,
                                      const std::function<bool()>& stop) {
  uq::Outcome out;
  const std::size_t nc = g.cases.size();
  out.y.assign(g.metrics.size() * nc, kNaN);
  try {
    Scene scene = s.scene;  // the design as data (sim/scene/parameters.hpp)
    if (const auto why = applyParameters(scene, s.parameters, x)) {
      out.failure = "the scene rejects the design: " + *why;
      return out;
    }
    const std::vector<DropCase> all = designCases(s, scene, true);
    std::vector<DropCase> cases;
    for (int c : g.cases) cases.push_back(all[c]);
    CaseOptions copt;
    copt.stop = stop;
    const std::vector<CaseResult> runs = runCases(scene, cases, 1, copt);
    for (std::size_t c = 0; c < nc; ++c) {
      const CaseMetrics& m = runs[c].metrics;
      if (!m.ok) {
        out.failure += (out.failure.empty() ? "" : "; ") + std::string("case '") + m.name +
                       "': " + (m.message.empty() ? "simulation failed" : m.message);
        continue;
      }
      for (std::size_t k = 0; k < g.metrics.size(); ++k) out.y[k * nc + c] = metricValue(m, g.metrics[k]);
    }
  } catch (const std::exception& e) {
    out.failure = std::string("evaluation failed: ") + e.what();
  }
  return out;
}

namespace {

// The exact local study: one run at the baseline with the derivatives of every output (each case of
// interest on its own thread; every rank computes the same bits).
void runLocalExact(const Study& s, const SensitivitySettings& g, const SensitivityOptions& o, SensitivityResult& r) {
  LocalStudy L;
  for (const auto& v : s.variables) L.x0.push_back(v.initial);
  L.exact = true;
  L.points = L.x0;
  const std::size_t nc = g.cases.size(), d = L.x0.size();
  uq::Outcome run;
  run.y.assign(g.metrics.size() * nc, kNaN);
  std::vector<CaseGradient> grads(nc);
  Scene scene = s.scene;
  if (const auto why = applyParameters(scene, s.parameters, L.x0)) {
    run.failure = "the scene rejects the design: " + *why;
  } else {
    const std::vector<DropCase> all = designCases(s, scene, true);
#pragma omp parallel for schedule(dynamic, 1) num_threads(std::max(1, o.threads))
    for (int c = 0; c < static_cast<int>(nc); ++c) grads[c] = caseGradient(scene, all[g.cases[c]], s.parameters);
    for (std::size_t c = 0; c < nc; ++c) {
      if (!grads[c].ok) {
        run.failure += (run.failure.empty() ? "" : "; ") + std::string("case '") + grads[c].caseName + "': " + grads[c].message;
        continue;
      }
      for (std::size_t k = 0; k < g.metrics.size(); ++k) run.y[k * nc + c] = grads[c].find(g.metrics[k])->value;
    }
  }
  L.runs.push_back(run);
  for (std::size_t j = 0; j < r.outputs.size(); ++j) {
    const SensitivityOutput& out = r.outputs[j];
    const std::size_t c = j % nc;
    uq::Elasticities e;
    e.baseline = run.y[j];
    e.E.assign(d, kNaN);
    e.derivative.assign(d, kNaN);
    e.why.assign(d, "");
    const MetricDerivative* md = grads[c].ok ? grads[c].find(out.metric) : nullptr;
    for (std::size_t i = 0; i < d; ++i) {
      if (!md) e.why[i] = "the run failed";
      else if (e.baseline == 0) e.why[i] = "the output is 0 at the baseline: no logarithm";
      else {
        e.derivative[i] = md->d[i];
        e.E[i] = L.x0[i] / e.baseline * md->d[i];
      }
    }
    L.outputs.push_back(e);
    L.oneSided.push_back(md && !md->smooth ? md->note : "");
  }
  r.localFailures = failures(L.runs, r.outputs, nc, [](std::size_t) { return std::string("baseline"); });
  r.local = std::move(L);
}

void runLocal(const Study& s, const SensitivitySettings& g, const SensitivityOptions& o, uq::Communicator& comm,
              SensitivityResult& r) {
  if (g.exactDerivatives) return runLocalExact(s, g, o, r);
  LocalStudy L;
  for (const auto& v : s.variables) L.x0.push_back(v.initial);
  L.exact = false;
  L.h = g.step;
  L.points = uq::localDesign(L.x0, L.h);
  L.runs = runDesigns(s, g, L.points, r.outputs.size(), "local", o, comm);
  for (std::size_t j = 0; j < r.outputs.size(); ++j)
    L.outputs.push_back(uq::elasticities(L.x0, L.h, outputColumn(L.runs, j)));
  r.localFailures = failures(L.runs, r.outputs, g.cases.size(), [&](std::size_t k) {
    if (k == 0) return std::string("baseline");
    return s.variables[(k - 1) / 2].path + ((k - 1) % 2 == 0 ? " +h" : " -h");
  });
  L.oneSided.assign(r.outputs.size(), "");
  r.local = std::move(L);
}

void runMorris(const Study& s, const SensitivitySettings& g, const SensitivityOptions& o, uq::Communicator& comm,
               SensitivityResult& r) {
  const std::size_t d = s.variables.size();
  MorrisStudy M;
  M.design = uq::morrisDesign(static_cast<std::size_t>(g.trajectories), d, g.levels, uq::streamSeed(g.seed, kMorrisDesign));
  M.points = physicalPoints(s, M.design.points);
  M.runs = runDesigns(s, g, M.points, r.outputs.size(), "morris", o, comm);
  const uq::BootstrapOptions bo{g.resamples, g.confidence, uq::streamSeed(g.seed, kMorrisBootstrap)};
  for (std::size_t j = 0; j < r.outputs.size(); ++j)
    M.outputs.push_back(uq::morrisIndices(M.design, outputColumn(M.runs, j), bo));
  r.morrisFailures = failures(M.runs, r.outputs, g.cases.size(), [&](std::size_t k) {
    return "trajectory " + std::to_string(k / (d + 1)) + " point " + std::to_string(k % (d + 1));
  });
  r.morris = std::move(M);
}

void runSobol(const Study& s, const SensitivitySettings& g, const SensitivityOptions& o, uq::Communicator& comm,
              SensitivityResult& r) {
  const std::size_t d = s.variables.size(), K = r.outputs.size(), N = static_cast<std::size_t>(g.samples);
  SobolStudy S;
  S.design = uq::saltelliDesign(N, d, uq::streamSeed(g.seed, kSobolShift));
  S.points = physicalPoints(s, S.design.points);
  S.runs = runDesigns(s, g, S.points, K, "sobol", o, comm);
  const uq::BootstrapOptions bo{g.resamples, g.confidence, uq::streamSeed(g.seed, kSobolBootstrap)};
  std::vector<std::vector<double>> ys;
  for (std::size_t j = 0; j < K; ++j) ys.push_back(outputColumn(S.runs, j));
  for (std::size_t j = 0; j < K; ++j) S.outputs.push_back(uq::sobolIndices(ys[j], N, d, bo));
  for (std::size_t n = N / 8; n <= N; n *= 2) {  // the convergence table: prefixes of the blocks
    if (n < 4) continue;
    S.convergenceN.push_back(n);
    std::vector<uq::SobolIndices> level;
    for (std::size_t j = 0; j < K; ++j) level.push_back(uq::sobolIndices(ys[j], N, d, uq::BootstrapOptions{0, 0.95, 0}, n));
    S.convergence.push_back(std::move(level));
  }
  r.sobolFailures = failures(S.runs, r.outputs, g.cases.size(), [&](std::size_t k) {
    const std::size_t m = uq::saltelliMatrix(k, d);
    return "block " + std::to_string(uq::saltelliBlock(k, d)) + " " +
           (m == 0 ? std::string("A") : m == 1 ? std::string("B") : "AB^" + std::to_string(m - 1) + " (" + s.variables[m - 2].path + ")");
  });
  r.sobol = std::move(S);
}

}  // namespace

SensitivityResult runSensitivity(const Study& s, const SensitivitySettings& g, const SensitivityOptions& o) {
  uq::SingleProcess single;
  uq::Communicator& comm = o.comm ? *o.comm : single;
  SensitivityResult r;
  r.settings = g;
  r.outputs = sensitivityOutputs(s, g);
  if (g.local) runLocal(s, g, o, comm, r);
  if (g.morris) runMorris(s, g, o, comm, r);
  if (g.sobol) runSobol(s, g, o, comm, r);
  for (std::size_t designs : {r.local ? r.local->runs.size() : 0, r.morris ? r.morris->runs.size() : 0,
                              r.sobol ? r.sobol->runs.size() : 0}) {
    r.designs += designs;
    r.drops += designs * g.cases.size();
  }
  return r;
}

}  // namespace lg::optim
