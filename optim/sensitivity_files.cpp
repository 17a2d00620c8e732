// CSV and JSON outputs of a sensitivity study (sensitivity_report.hpp).
#include <sstream>
#include <stdexcept>

#include "sim/core/format.hpp"
#include "optim/sensitivity_report.hpp"
#include "sim/scene/parameters.hpp"  // parameterUnit
#include "sim/io/json.hpp"

namespace lg::optim {
namespace {

std::string outputHeader(const SensitivityOutput& o) { return o.label() + "[" + o.unit + "]"; }

std::string designColumns(const Study& s, const std::vector<SensitivityOutput>& outs) {
  std::string h;
  for (const auto& v : s.variables) h += "," + parameterHeader(v.path);
  for (const auto& o : outs) h += "," + outputHeader(o);
  return h + ",failure";
}

std::string designRow(const Study& s, const std::vector<double>& points, const uq::Outcome& run, std::size_t k) {
  const std::size_t d = s.variables.size();
  std::string l;
  for (std::size_t i = 0; i < d; ++i) l += "," + exactNumber(points[k * d + i]);
  for (double y : run.y) l += "," + exactNumber(y);
  return l + "," + (run.failure.empty() ? std::string() : csvField(run.failure));
}

std::string jsonInterval(const uq::Interval& i) { return "[" + jsonNumber(i.lo) + ", " + jsonNumber(i.hi) + "]"; }

std::string failuresJson(const MethodFailures& f, const SensitivityResult& r) {
  std::ostringstream j;
  j << "{\"failed_runs\": " << f.runs << ", \"per_case\": {";
  for (std::size_t c = 0; c < f.perCase.size(); ++c)
    j << (c ? ", " : "") << jsonString(r.outputs[c].caseName) << ": " << f.perCase[c];
  j << "}, \"runs\": [";
  for (std::size_t k = 0; k < f.list.size(); ++k)
    j << (k ? ", " : "") << "{\"run\": " << f.list[k].run << ", \"where\": " << jsonString(f.list[k].where)
      << ", \"message\": " << jsonString(f.list[k].message) << "}";
  return j.str() + "]}";
}

std::string outputHead(const SensitivityOutput& o) {
  return "{\"metric\": " + jsonString(o.metric) + ", \"case\": " + jsonString(o.caseName) + ", \"unit\": " +
         jsonString(o.unit);
}

void localJson(std::ostream& j, const Study& s, const SensitivityResult& r) {
  const LocalStudy& L = *r.local;
  j << "  \"local\": {\"derivative_source\": " << jsonString(derivativeSource(r.settings)) << ", \"h\": "
    << (L.exact ? std::string("null") : jsonNumber(L.h)) << ", \"runs\": " << L.runs.size() << ", \"failures\": " << failuresJson(r.localFailures, r)
    << ",\n    \"outputs\": [\n";
  for (std::size_t k = 0; k < r.outputs.size(); ++k) {
    const uq::Elasticities& e = L.outputs[k];
    j << "      " << outputHead(r.outputs[k]) << ", \"baseline\": " << jsonNumber(e.baseline) << ", \"one_sided\": "
      << jsonString(k < L.oneSided.size() ? L.oneSided[k] : "") << ", \"variables\": [";
    for (std::size_t i = 0; i < s.variables.size(); ++i)
      j << (i ? ", " : "") << "{\"variable\": " << jsonString(s.variables[i].path) << ", \"elasticity\": "
        << jsonNumber(e.E[i]) << ", \"derivative\": " << jsonNumber(e.derivative[i]) << ", \"derivative_unit\": "
        << jsonString(r.outputs[k].unit + "/" + parameterUnit(s.variables[i].path)) << ", \"undefined\": "
        << jsonString(e.why[i]) << "}";
    j << "]}" << (k + 1 < r.outputs.size() ? "," : "") << "\n";
  }
  j << "    ]}";
}

void morrisJson(std::ostream& j, const Study& s, const SensitivityResult& r) {
  const MorrisStudy& M = *r.morris;
  j << "  \"morris\": {\"levels\": " << M.design.levels << ", \"delta\": " << jsonNumber(M.design.delta)
    << ", \"trajectories\": " << M.design.r << ", \"runs\": " << M.runs.size() << ", \"bootstrap\": {\"resamples\": "
    << r.settings.resamples << ", \"confidence\": " << jsonNumber(r.settings.confidence)
    << "}, \"effects_unit\": \"output unit per unit of the scaled variable (its whole range)\", \"failures\": "
    << failuresJson(r.morrisFailures, r) << ",\n    \"outputs\": [\n";
  for (std::size_t k = 0; k < r.outputs.size(); ++k) {
    const uq::MorrisIndices& m = M.outputs[k];
    j << "      " << outputHead(r.outputs[k]) << ", \"variables\": [";
    for (std::size_t i = 0; i < s.variables.size(); ++i)
      j << (i ? ", " : "") << "{\"variable\": " << jsonString(s.variables[i].path) << ", \"mu\": " << jsonNumber(m.mu[i])
        << ", \"mu_star\": " << jsonNumber(m.muStar[i]) << ", \"sigma\": " << jsonNumber(m.sigma[i])
        << ", \"mu_star_ci\": " << jsonInterval(m.muStarCi[i]) << ", \"effects\": " << m.effects[i] << "}";
    j << "]}" << (k + 1 < r.outputs.size() ? "," : "") << "\n";
  }
  j << "    ]}";
}

void sobolJson(std::ostream& j, const Study& s, const SensitivityResult& r) {
  const SobolStudy& S = *r.sobol;
  const std::size_t d = s.variables.size();
  j << "  \"sobol\": {\"N\": " << S.design.n << ", \"runs\": " << S.runs.size() << ", \"runs_formula\": \"N(d+2)\""
    << ", \"sequence\": \"Sobol (Boost.Random sobol_engine, Joe-Kuo directions), random digital shift\""
    << ", \"first_order\": \"Saltelli 2010\", \"total\": \"Jansen\", \"bootstrap\": {\"resamples\": "
    << r.settings.resamples << ", \"confidence\": " << jsonNumber(r.settings.confidence) << "}"
    << ", \"failed_sample_rule\": \"a non-finite output drops its whole block (A, B and every AB^i of that base point) from that output's estimate\""
    << ", \"failures\": " << failuresJson(r.sobolFailures, r) << ",\n    \"outputs\": [\n";
  for (std::size_t k = 0; k < r.outputs.size(); ++k) {
    const uq::SobolIndices& x = S.outputs[k];
    j << "      " << outputHead(r.outputs[k]) << ", \"mean\": " << jsonNumber(x.mean) << ", \"variance\": "
      << jsonNumber(x.variance) << ", \"blocks_used\": " << x.blocks - x.dropped.size() << ", \"blocks_dropped\": [";
    for (std::size_t b = 0; b < x.dropped.size(); ++b) j << (b ? ", " : "") << x.dropped[b];
    j << "], \"constant\": " << jsonBool(x.constant) << ", \"variables\": [";
    for (std::size_t i = 0; i < d; ++i) {
      const uq::Interval none{NAN, NAN};
      j << (i ? ", " : "") << "{\"variable\": " << jsonString(s.variables[i].path) << ", \"S1\": " << jsonNumber(x.S1[i])
        << ", \"S1_ci\": " << jsonInterval(x.S1ci.empty() ? none : x.S1ci[i]) << ", \"ST\": " << jsonNumber(x.ST[i])
        << ", \"ST_ci\": " << jsonInterval(x.STci.empty() ? none : x.STci[i]) << ", \"convergence\": {";
      for (std::size_t c = 0; c < S.convergenceN.size(); ++c)
        j << (c ? ", " : "") << "\"" << S.convergenceN[c] << "\": [" << jsonNumber(S.convergence[c][k].S1[i]) << ", "
          << jsonNumber(S.convergence[c][k].ST[i]) << "]";
      j << "}}";
    }
    j << "]}" << (k + 1 < r.outputs.size() ? "," : "") << "\n";
  }
  j << "    ]}";
}

}  // namespace

std::string sensitivityJson(const Study& s, const SensitivityResult& r) {
  std::ostringstream j;
  j << "{\n  \"study\": " << jsonString(s.name) << ",\n  \"study_file\": " << jsonString(s.file) << ",\n  \"scene\": "
    << jsonString(s.sceneFile) << ",\n  \"seed\": " << r.settings.seed << ",\n";
  j << "  \"sampling\": \"uniform in each variable's scaled coordinate: uniform between its bounds, log-uniform with log = true\",\n";
  j << "  \"variables\": [\n";
  for (std::size_t i = 0; i < s.variables.size(); ++i) {
    const Variable& v = s.variables[i];
    j << "    {\"path\": " << jsonString(v.path) << ", \"unit\": " << jsonString(parameterUnit(v.path)) << ", \"lower\": "
      << jsonNumber(v.lower) << ", \"upper\": " << jsonNumber(v.upper) << ", \"log\": " << jsonBool(v.log)
      << ", \"baseline\": " << jsonNumber(v.initial) << "}" << (i + 1 < s.variables.size() ? "," : "") << "\n";
  }
  j << "  ],\n  \"outputs\": [";
  for (std::size_t k = 0; k < r.outputs.size(); ++k) j << (k ? ", " : "") << outputHead(r.outputs[k]) << "}";
  j << "],\n  \"designs\": " << r.designs << ",\n  \"drops\": " << r.drops;
  if (r.local) localJson(j << ",\n", s, r);
  if (r.morris) morrisJson(j << ",\n", s, r);
  if (r.sobol) sobolJson(j << ",\n", s, r);
  return j.str() + "\n}\n";
}

std::string samplesCsv(const Study& s, const SensitivityResult& r, const std::string& method) {
  std::ostringstream c;
  const std::size_t d = s.variables.size();
  if (method == "local" && r.local) {
    c << "run,point" << designColumns(s, r.outputs) << "\n";
    for (std::size_t k = 0; k < r.local->runs.size(); ++k)
      c << k << "," << csvField(k == 0 ? "baseline" : s.variables[(k - 1) / 2].path + ((k - 1) % 2 ? " -h" : " +h"))
        << designRow(s, r.local->points, r.local->runs[k], k) << "\n";
  } else if (method == "morris" && r.morris) {
    c << "run,trajectory,step,moved" << designColumns(s, r.outputs) << "\n";
    const MorrisStudy& M = *r.morris;
    for (std::size_t k = 0; k < M.runs.size(); ++k) {
      const std::size_t t = k / (d + 1), st = k % (d + 1);
      c << k << "," << t << "," << st << "," << (st == 0 ? std::string() : csvField(s.variables[M.design.moved[t * d + st - 1]].path))
        << designRow(s, M.points, M.runs[k], k) << "\n";
    }
  } else if (method == "sobol" && r.sobol) {
    c << "run,block,matrix" << designColumns(s, r.outputs) << "\n";
    for (std::size_t k = 0; k < r.sobol->runs.size(); ++k) {
      const std::size_t m = uq::saltelliMatrix(k, d);
      c << k << "," << uq::saltelliBlock(k, d) << "," << (m == 0 ? "A" : m == 1 ? "B" : "AB_" + s.variables[m - 2].path)
        << designRow(s, r.sobol->points, r.sobol->runs[k], k) << "\n";
    }
  } else {
    throw std::invalid_argument("samplesCsv: no " + method + " results");
  }
  return c.str();
}

std::string indicesCsv(const Study& s, const SensitivityResult& r, const std::string& method) {
  std::ostringstream c;
  const std::size_t d = s.variables.size();
  if (method == "local" && r.local) {
    c << "metric,case,unit,variable,variable_unit,baseline_metric[unit],baseline_variable[variable_unit],elasticity[-],derivative[unit/variable_unit],undefined,source\n";
    for (std::size_t k = 0; k < r.outputs.size(); ++k)
      for (std::size_t i = 0; i < d; ++i) {
        const uq::Elasticities& e = r.local->outputs[k];
        c << r.outputs[k].metric << "," << csvField(r.outputs[k].caseName) << "," << r.outputs[k].unit << ","
          << s.variables[i].path << "," << parameterUnit(s.variables[i].path) << "," << exactNumber(e.baseline) << ","
          << exactNumber(r.local->x0[i]) << "," << exactNumber(e.E[i]) << "," << exactNumber(e.derivative[i]) << ","
          << csvField(e.why[i]) << "," << csvField(derivativeSource(r.settings)) << "\n";
      }
  } else if (method == "morris" && r.morris) {
    c << "metric,case,unit,variable,mu[unit],mu_star[unit],sigma[unit],mu_star_lo[unit],mu_star_hi[unit],effects\n";
    for (std::size_t k = 0; k < r.outputs.size(); ++k)
      for (std::size_t i = 0; i < d; ++i) {
        const uq::MorrisIndices& m = r.morris->outputs[k];
        c << r.outputs[k].metric << "," << csvField(r.outputs[k].caseName) << "," << r.outputs[k].unit << ","
          << s.variables[i].path << "," << exactNumber(m.mu[i]) << "," << exactNumber(m.muStar[i]) << ","
          << exactNumber(m.sigma[i]) << "," << exactNumber(m.muStarCi[i].lo) << "," << exactNumber(m.muStarCi[i].hi) << ","
          << m.effects[i] << "\n";
      }
  } else if (method == "sobol" && r.sobol) {
    c << "metric,case,unit,variable,S1[-],S1_lo[-],S1_hi[-],ST[-],ST_lo[-],ST_hi[-],blocks_used,blocks_dropped,variance[unit^2]\n";
    for (std::size_t k = 0; k < r.outputs.size(); ++k)
      for (std::size_t i = 0; i < d; ++i) {
        const uq::SobolIndices& x = r.sobol->outputs[k];
        const uq::Interval none{NAN, NAN}, a = x.S1ci.empty() ? none : x.S1ci[i], b = x.STci.empty() ? none : x.STci[i];
        c << r.outputs[k].metric << "," << csvField(r.outputs[k].caseName) << "," << r.outputs[k].unit << ","
          << s.variables[i].path << "," << exactNumber(x.S1[i]) << "," << exactNumber(a.lo) << "," << exactNumber(a.hi)
          << "," << exactNumber(x.ST[i]) << "," << exactNumber(b.lo) << "," << exactNumber(b.hi) << ","
          << x.blocks - x.dropped.size() << "," << x.dropped.size() << "," << exactNumber(x.variance) << "\n";
      }
  } else {
    throw std::invalid_argument("indicesCsv: no " + method + " results");
  }
  return c.str();
}

std::string convergenceCsv(const Study& s, const SensitivityResult& r) {
  if (!r.sobol) throw std::invalid_argument("convergenceCsv: no Sobol results");
  std::ostringstream c;
  c << "metric,case,variable,N,runs,S1[-],ST[-]\n";
  const std::size_t d = s.variables.size();
  for (std::size_t k = 0; k < r.outputs.size(); ++k)
    for (std::size_t i = 0; i < d; ++i)
      for (std::size_t n = 0; n < r.sobol->convergenceN.size(); ++n) {
        const uq::SobolIndices& x = r.sobol->convergence[n][k];
        c << r.outputs[k].metric << "," << csvField(r.outputs[k].caseName) << "," << s.variables[i].path << ","
          << r.sobol->convergenceN[n] << "," << r.sobol->convergenceN[n] * (d + 2) << "," << exactNumber(x.S1[i]) << ","
          << exactNumber(x.ST[i]) << "\n";
      }
  return c.str();
}

}  // namespace lg::optim
