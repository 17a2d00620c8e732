// Certification matrix: generation of the cases, their limits and verdicts (certification.hpp).
#include "sim/drop/certification.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace lg {
namespace {

constexpr double kFtToM = 0.3048;          // [m/ft]
constexpr double kKgM2ToLbFt2 = 0.204816;  // [lb/ft^2 per kg/m^2] (certification.md)

std::string num(double v, int digits = 4) {
  std::ostringstream o;
  o.precision(digits);
  o << v;
  return o.str();
}

CertCase makeCase(const std::string& name, CertKind kind, double V, double L, double W, double duration,
                  const std::string& rule) {
  CertCase c;
  c.name = name;
  c.kind = kind;
  c.sinkSpeed = V;
  c.liftRatio = L;
  c.mass = W;
  c.duration = duration;
  c.rule = rule;
  return c;
}

}  // namespace

bool certBasisFromName(const std::string& name, CertBasis& basis) {
  static const std::pair<const char*, CertBasis> table[] = {{"part25", CertBasis::Part25}, {"cs25", CertBasis::CS25},
                                                            {"part23", CertBasis::Part23}, {"cs23", CertBasis::CS23},
                                                            {"custom", CertBasis::Custom}};
  for (const auto& [n, b] : table)
    if (name == n) {
      basis = b;
      return true;
    }
  return false;
}
std::string certBasisNames() { return "\"part25\", \"cs25\", \"part23\", \"cs23\", \"custom\""; }

const char* certKindName(CertKind k) { return k == CertKind::Limit ? "limit" : "reserve"; }

const CertCase* Certification::findCase(const std::string& name) const {
  for (const auto& c : cases)
    if (c.name == name) return &c;
  return nullptr;
}

double part23SinkSpeed(double wingLoading) {
  const double ws = wingLoading * kKgM2ToLbFt2;  // [lb/ft^2]
  const double V = std::clamp(4.4 * std::pow(ws, 0.25), 7.0, 10.0);  // [ft/s]
  return V * kFtToM;
}

std::vector<CertCase> basisCases(const Certification& c) {
  std::vector<CertCase> cases;
  if (c.basis == CertBasis::Custom) return cases;
  if (c.part23()) {
    const double V = part23SinkSpeed(c.wingLoading);
    const std::string ws = num(c.wingLoading * kKgM2ToLbFt2, 4) + " lb/ft^2";
    cases.push_back(makeCase("cert-limit", CertKind::Limit, V, c.liftRatio, c.landingMass, c.duration,
                               "limit drop: V = 4.4 (W/S)^(1/4) ft/s clamped to 7..10 ft/s, W/S = " + ws + " -> " +
                                   num(V / kFtToM, 4) + " ft/s; design landing weight"));
    cases.push_back(makeCase("cert-reserve", CertKind::Reserve, 1.2 * V, c.reserveLiftRatio, c.landingMass, c.duration,
                               "reserve energy: 1.2 x the limit sink speed (drop height 1.44 h)"));
  } else {
    const bool cs = c.basis == CertBasis::CS25;
    cases.push_back(makeCase("cert-limit-landing", CertKind::Limit, 3.05, c.liftRatio, c.landingMass, c.duration,
                               "limit drop at the design landing weight, 3.05 m/s (10 ft/s)"));
    cases.push_back(makeCase("cert-limit-takeoff", CertKind::Limit, 1.83, c.liftRatio, c.takeoffMass, c.duration,
                               "limit drop at the design takeoff weight, 1.83 m/s (6 ft/s)"));
    cases.push_back(makeCase("cert-reserve", CertKind::Reserve, cs ? 3.7 : 3.66, c.reserveLiftRatio, c.landingMass,
                               c.duration,
                               cs ? "reserve energy at the design landing weight, 3.7 m/s (CS-25)"
                                  : "reserve energy at the design landing weight, 3.66 m/s (12 ft/s)"));
  }
  for (auto& cc : cases) cc.forwardSpeed = c.forwardSpeed;
  return cases;
}

DropCase certDropCase(const Scene& scene, const Certification& c, const CertCase& cc) {
  DropCase d;
  d.name = cc.name;
  d.sinkSpeed = cc.sinkSpeed;
  d.liftRatio = cc.liftRatio;
  d.duration = cc.duration;
  d.forwardSpeed = cc.forwardSpeed;
  double rest = 0;
  for (const auto& b : scene.model.bodies)
    if (b.name != c.massBody) rest += b.mass;
  d.masses[c.massBody] = cc.mass - rest;
  return d;
}

std::vector<Limit> checkLimits(const Certification* c, const Scene& scene) {
  std::vector<Limit> out;
  bool anyStop = false;
  for (double S : scene.roles.strokeLimits) anyStop = anyStop || std::isfinite(S);
  const double margin = c ? c->strokeMargin : 0.0;
  if (anyStop)
    out.push_back({"stroke_margin", false, margin,
                   margin > 0 ? "stroke margin to the bottoming stop >= " + num(margin) + " m" : "no bottoming"});
  if (!scene.roles.tyres.empty()) {
    if (c && c->tyreLimit > 0) out.push_back({"tyre_deflection", true, c->tyreLimit, "tyre deflection limit"});
    else out.push_back({"tyre_margin", false, 0.0, "tyre deflection within delta_max"});
  }
  return out;
}

std::vector<Limit> caseLimits(const Certification& c, const CertCase& cc, const Scene& scene) {
  std::vector<Limit> out;
  const double ngLim = c.limitGroundFactor();
  if (cc.kind == CertKind::Limit) {
    if (c.part23()) out.push_back({"inertia_load_factor", true, c.limitLoadFactor, "design limit load factor n (n_g + L)"});
    else out.push_back({"load_factor", true, ngLim, "design limit load factor n_g"});
  } else {
    out.push_back({"load_factor", true, c.ultimateFactor * ngLim,
                   "ultimate ground load factor (" + num(c.ultimateFactor) + " x n_g,lim = " + num(ngLim) + ")"});
  }
  for (const Limit& l : checkLimits(&c, scene)) out.push_back(l);
  return out;
}

CaseVerdict assessCase(const std::string& role, const CertCase& cc, const CaseMetrics& m, const std::vector<Limit>& limits) {
  CaseVerdict v;
  v.name = m.name;
  v.role = role;
  v.cert = cc;
  v.metrics = m;
  if (!m.ok) v.reasons.push_back("simulation failed: " + m.message);
  for (const Limit& l : limits) {
    LimitResult lr;
    lr.limit = l;
    lr.value = metricValue(m, l.metric);
    lr.pass = m.ok && (l.upper ? lr.value <= l.bound : lr.value >= l.bound);
    if (m.ok && !lr.pass) {
      const MetricInfo* info = findMetric(l.metric);
      const std::string unit = info && std::string(info->unit) != "-" ? std::string(" ") + info->unit : "";
      v.reasons.push_back(l.metric + " " + num(lr.value, 5) + (l.upper ? " > " : " < ") + num(l.bound, 5) + unit + " (" +
                          l.rule + ")");
    }
    v.limits.push_back(lr);
  }
  if (m.ok && m.bottomed) v.reasons.push_back("bottomed: the strut reached its bottoming stop");
  if (m.ok && !m.compression_ended)
    v.reasons.push_back("the compression did not end within " + num(cc.duration) + " s: the energy was not absorbed in the run");
  v.pass = v.reasons.empty();
  return v;
}

std::vector<UnitItem> unitItems(const Certification& c) {
  std::vector<UnitItem> out;
  if (c.part23()) {
    out.push_back({"design inertia load factor n", c.limitLoadFactor, 2.67, c.limitLoadFactor >= 2.67,
                   "Part 23 (23.473): n >= 2.67 at the design maximum weight"});
    out.push_back({"design ground load factor n_g = n - L", c.limitGroundFactor(), 2.0, c.limitGroundFactor() >= 2.0,
                   "Part 23 (23.473): n_g >= 2.0 at the design maximum weight"});
  }
  return out;
}

std::vector<WorstCorner> worstCorners(const std::vector<CaseVerdict>& at, const std::vector<EnvelopeCorner>& corners) {
  std::vector<WorstCorner> out;
  if (at.empty()) return out;
  for (size_t l = 0; l < at.front().limits.size(); ++l) {
    WorstCorner w;
    w.limit = at.front().limits[l].limit;
    w.pass = true;
    bool first = true;
    for (size_t k = 0; k < at.size(); ++k) {
      const LimitResult& r = at[k].limits[l];
      const double margin = !at[k].metrics.ok ? std::nan("") : r.limit.upper ? r.limit.bound - r.value : r.value - r.limit.bound;
      w.pass = w.pass && r.pass;
      // The least margin; a failed run is the worst of all (the first one found).
      const bool worse = first || (std::isnan(margin) && !std::isnan(w.margin)) || (!std::isnan(w.margin) && margin < w.margin);
      if (worse) {
        w.corner = corners[k].name;
        w.value = r.value;
        w.margin = margin;
        first = false;
      }
    }
    out.push_back(w);
  }
  return out;
}

Compliance assessCompliance(const Scene& scene, const Certification& c, int threads, const CaseOptions& opt,
                            std::vector<CaseResult>* runs, bool envelope) {
  Compliance out;
  out.scene = scene.file;
  out.sceneRun = &scene;
  out.spec = &c;
  out.unit = unitItems(c);
  std::vector<DropCase> base;
  for (const auto& cc : c.cases) base.push_back(certDropCase(scene, c, cc));
  for (const auto& sc : scene.cases) base.push_back(sc);
  const bool over = envelope && scene.envelope.declared;
  if (over) {
    out.envelope = &scene.envelope;
    out.corners = scene.envelope.corners();
  }
  // The runs: every case at every point (point-major: the nominal point's block first).
  std::vector<DropCase> cases;
  const size_t points = over ? out.corners.size() : 1;
  for (size_t k = 0; k < points; ++k)
    for (DropCase d : base) {
      if (over) {
        d.corner = out.corners[k];
        if (k > 0) d.name += "@" + out.corners[k].name;
      }
      cases.push_back(d);
    }
  std::vector<CaseResult> res = runCases(scene, cases, threads, opt);
  out.drops = static_cast<long>(res.size());
  for (const auto& r : res) out.rhsEvaluations += r.metrics.rhs_evaluations;
  const size_t nm = c.cases.size(), ns = scene.cases.size();
  const std::vector<Limit> checks = checkLimits(&c, scene);
  auto verdictOf = [&](size_t k, size_t i) {
    CaseMetrics m = res[k * base.size() + i].metrics;
    m.name = base[i].name;
    if (i < nm) return assessCase("certification", c.cases[i], m, caseLimits(c, c.cases[i], scene));
    const DropCase& d = scene.cases[i - nm];
    CertCase cc = makeCase(d.name, CertKind::Limit, touchdownSpeed(d, scene.gravity), d.liftRatio, caseMass(scene, d), d.duration,
                           "the scene's own case (a check)");
    cc.forwardSpeed = d.forwardSpeed;
    return assessCase("check", cc, m, checks);
  };
  for (size_t i = 0; i < nm; ++i) out.cases.push_back(verdictOf(0, i));
  for (size_t i = 0; i < ns; ++i) out.checks.push_back(verdictOf(0, nm + i));
  out.pass = true;
  for (const auto& u : out.unit) out.pass = out.pass && u.pass;
  for (const auto& v : out.cases) out.pass = out.pass && v.pass;
  out.nominalPass = out.pass;
  out.checksPass = true;
  for (const auto& v : out.checks) out.checksPass = out.checksPass && v.pass;
  if (over) {
    for (size_t i = 0; i < nm + ns; ++i) {
      EnvelopeVerdict ev;
      ev.name = base[i].name;
      ev.role = i < nm ? "certification" : "check";
      for (size_t k = 0; k < points; ++k) ev.at.push_back(verdictOf(k, i));
      ev.worst = worstCorners(ev.at, out.corners);
      for (const auto& v : ev.at) ev.failing += v.pass ? 0 : 1;
      ev.pass = ev.failing == 0;
      if (i < nm) out.pass = out.pass && ev.pass;
      else out.checksPass = out.checksPass && ev.pass;
      (i < nm ? out.envelopeCases : out.envelopeChecks).push_back(std::move(ev));
    }
  }
  res.resize(base.size());  // the nominal point's
  if (runs) *runs = std::move(res);
  return out;
}

}  // namespace lg
