// Physical consistency of a scene (scene_check.hpp).
#include "sim/scene/check.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "sim/engine/engine.hpp"

namespace lg {
namespace {

std::string num(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

bool samePair(int a1, const Vec3<double>& p1, int a2, const Vec3<double>& p2, int b1, const Vec3<double>& q1, int b2,
              const Vec3<double>& q2) {
  auto same = [](const Vec3<double>& a, const Vec3<double>& b) { return (a - b).norm() <= 1e-9; };
  return (a1 == b1 && a2 == b2 && same(p1, q1) && same(p2, q2)) || (a1 == b2 && a2 == b1 && same(p1, q2) && same(p2, q1));
}

// The checks, each returning the first problem of its kind.
class Checker {
 public:
  explicit Checker(Scene& sc) : sc_(sc), m_(sc.model), w_(sc.model) { kinematics(m_, sc.initial.y, w_); }

  std::optional<SceneProblem> run() {
    for (int b = 0; b < m_.nBodies(); ++b)
      if (!(m_.bodies[b].mass > 0)) return problem("body", b, "mass", "value " + num(m_.bodies[b].mass) + " must be > 0");
    for (size_t k = 0; k < sc_.roles.stops.size(); ++k)
      if (auto p = stop(static_cast<int>(k))) return p;
    for (size_t k = 0; k < sc_.roles.pads.size(); ++k)
      if (auto p = pad(static_cast<int>(k))) return p;
    sc_.roles.strokeLimits.assign(sc_.roles.struts.size(), std::numeric_limits<double>::quiet_NaN());
    sc_.roles.bottomingStops.assign(sc_.roles.struts.size(), -1);
    for (size_t f = 0; f < m_.forces.size(); ++f) {
      std::optional<SceneProblem> p;
      if (const auto* s = std::get_if<ShockAbsorber<double>>(&m_.forces[f].type)) p = strut(static_cast<int>(f), *s);
      else if (const auto* t = std::get_if<Tyre<double>>(&m_.forces[f].type)) p = tyre(static_cast<int>(f), *t);
      else if (const auto* d = std::get_if<SpringDamper<double>>(&m_.forces[f].type)) p = springDamper(static_cast<int>(f), *d);
      else if (const auto* b = std::get_if<Bushing<double>>(&m_.forces[f].type)) p = bushing(static_cast<int>(f), *b);
      else if (const auto* bf = std::get_if<BearingFriction<double>>(&m_.forces[f].type); bf && !(bf->mu >= 0))
        p = problem("force", static_cast<int>(f), "mu", "value " + num(bf->mu) + " must be >= 0");
      if (p) return p;
    }
    for (size_t f = 0; f < m_.forces.size(); ++f)  // (after the struts: their S_max)
      if (const auto* bf = std::get_if<BearingFriction<double>>(&m_.forces[f].type))
        if (auto p = bearingsApart(static_cast<int>(f), *bf)) return p;
    for (size_t c = 0; c < sc_.cases.size(); ++c) {
      const DropCase& d = sc_.cases[c];
      const int i = static_cast<int>(c);
      if (const std::string rule = sinkSpeedRule(touchdownSpeed(d, sc_.gravity)); !rule.empty())
        return problem("case", i, d.dropHeight > 0 ? "drop_height" : "sink_speed",
                       d.dropHeight > 0 ? "the touchdown speed sqrt(sink_speed^2 + 2 g (1 - lift_ratio) drop_height): " + rule : rule);
      if (const std::string rule = liftRatioRule(d.liftRatio); !rule.empty()) return problem("case", i, "lift_ratio", rule);
      if (!(d.duration > 0)) return problem("case", i, "duration", "value " + num(d.duration) + " must be > 0");
    }
    return std::nullopt;
  }

 private:
  static std::optional<SceneProblem> problem(const std::string& array, int index, const std::string& key,
                                             const std::string& rule) {
    return SceneProblem{array, index, key, rule};
  }
  std::optional<SceneProblem> positive(int f, const std::string& key, double v) const {
    if (!(v > 0)) return problem("force", f, key, "value " + num(v) + " must be > 0");
    return std::nullopt;
  }

  // A "no nearer" (bottoming) stop on the same two points as a "no farther" (extension) stop must be
  // shorter than it, or the two leave no stroke between them.
  std::optional<SceneProblem> stop(int k) const {
    const int entry = sc_.roles.stopEntry[k];
    const auto& A = std::get<DistanceStop<double>>(m_.constraints[sc_.roles.stops[k]].type);
    if (!(A.L > 0)) return problem("stop", entry, A.noFarther ? "max_distance" : "min_distance", "value " + num(A.L) + " must be > 0");
    if (A.noFarther) return std::nullopt;
    auto longer = [&](double L, const std::string& name) {
      return problem("stop", entry, "min_distance", "value " + num(A.L) + " m must be shorter than the max_distance " + num(L) +
                                                        " m of stop '" + name + "' on the same points");
    };
    for (int ci : sc_.roles.stops) {
      const auto& B = std::get<DistanceStop<double>>(m_.constraints[ci].type);
      if (B.noFarther && samePair(A.bi, A.rho_i, A.bj, A.rho_j, B.bi, B.rho_i, B.bj, B.rho_j) && !(A.L < B.L))
        return longer(B.L, m_.constraints[ci].name);
    }
    for (int f : sc_.roles.pads) {
      const auto& B = std::get<StopPad<double>>(m_.forces[f].type);
      if (samePair(A.bi, A.rho_i, A.bj, A.rho_j, B.bi, B.rho_i, B.bj, B.rho_j) && !(A.L < B.L)) return longer(B.L, m_.forces[f].name);
    }
    return std::nullopt;
  }
  // An elastic extension stop (a design may move its values).
  std::optional<SceneProblem> pad(int k) const {
    const int entry = sc_.roles.padEntry[k];
    const auto& P = std::get<StopPad<double>>(m_.forces[sc_.roles.pads[k]].type);
    if (!(P.L > 0)) return problem("stop", entry, "max_distance", "value " + num(P.L) + " must be > 0");
    if (!(P.k > 0)) return problem("stop", entry, "stiffness", "value " + num(P.k) + " must be > 0");
    if (!(P.c >= 0)) return problem("stop", entry, "damping", "value " + num(P.c) + " must be >= 0");
    return std::nullopt;
  }

  std::optional<SceneProblem> strut(int f, const ShockAbsorber<double>& s) {
    for (const auto& [key, v] : {std::pair<const char*, double>{"D", s.D}, {"p01", s.p01}, {"Omega0", s.Omega0},
                                 {"rho", s.rho}, {"xi1", s.xi1}})
      if (auto p = positive(f, key, v)) return p;
    if (!s.f1Table)
      if (auto p = positive(f, "f1", s.f1)) return p;
    for (size_t k = 0; k < s.f1Values.size(); ++k)  // a design may move the metering pin's samples
      if (auto p = positive(f, "f1_table[" + std::to_string(k) + "]", s.f1Values[k])) return p;
    if (!(s.D2 >= s.D)) return problem("force", f, "D2", "bore " + num(s.D2) + " must be >= rod diameter D = " + num(s.D));
    if (!(s.n >= 1)) return problem("force", f, "n", "polytropic exponent " + num(s.n) + " must be >= 1 (1: isothermal)");
    if (!(s.mu >= 0)) return problem("force", f, "mu", "value " + num(s.mu) + " must be >= 0");
    if (!(s.pAtm >= 0 && s.pAtm < s.p01))
      return problem("force", f, "p_atm", "value " + num(s.pAtm) + " must be >= 0 and < p01 = " + num(s.p01) +
                                             " (the gas must push the rod out)");
    if (s.twoStage) {  // a design may move the second chamber's values
      if (!(s.p02 > s.p01))
        return problem("force", f, "p02", "value " + num(s.p02) + " must be > p01 = " + num(s.p01) +
                                              " (the second stage engages when p_1 reaches it)");
      if (auto p = positive(f, "Omega02", s.Omega02)) return p;
      if (!(s.n2 >= 1)) return problem("force", f, "n2", "polytropic exponent " + num(s.n2) + " must be >= 1 (1: isothermal)");
    }
    if (s.ownF1e && !s.f1eTable)
      if (auto p = positive(f, "f1_extension", s.f1e)) return p;
    if (s.ownXi1e)
      if (auto p = positive(f, "xi1_extension", s.xi1e)) return p;
    if (s.ownF2e)
      if (auto p = positive(f, "f2_extension", s.f2e)) return p;
    if (s.ownXi2e)
      if (auto p = positive(f, "xi2_extension", s.xi2e)) return p;
    if (s.declaresReboundOrifice()) {
      if (auto p = positive(f, "f2", s.f2)) return p;
      if (auto p = positive(f, "xi2", s.xi2)) return p;
      if (!(s.D2 > s.D)) return problem("force", f, "D2", "a rebound orifice f2 needs an annular chamber: D2 > D");
    }
    // Fully extended at touchdown.
    const Vec3<double> B = w_.kin[s.bi].point(s.rho_i), C = w_.kin[s.bj].point(s.rho_j);
    const double dist = (B - C).norm();
    if (std::abs(s.L0 - dist) > 1e-6)
      return problem("force", f, "L0", "value " + num(s.L0) + " m differs from the distance of rod_point and cylinder_point at touchdown, " +
                                           num(dist) + " m: the strut starts fully extended (s = 0); leave L0 out or correct the points");
    // The stroke it can reach: its bottoming stop's S_max, else the stroke that would exhaust the gas
    // (or L0). The gas must outlast the bottoming stroke, and a table cover the reach.
    const double F = M_PI * s.D * s.D / 4;
    const double gas = s.twoStage ? s.Omega0 + s.Omega02 : s.Omega0;  // the gas volume the rod can take
    double reach = std::min(s.L0, gas / F);
    int k = -1;
    for (size_t j = 0; j < sc_.roles.stops.size(); ++j) {
      const auto& st = std::get<DistanceStop<double>>(m_.constraints[sc_.roles.stops[j]].type);
      if (!st.noFarther && samePair(st.bi, st.rho_i, st.bj, st.rho_j, s.bi, s.rho_i, s.bj, s.rho_j)) k = static_cast<int>(j);
    }
    const size_t index = std::find(sc_.roles.struts.begin(), sc_.roles.struts.end(), f) - sc_.roles.struts.begin();
    if (k >= 0) {
      const int ci = sc_.roles.stops[k];
      const auto& st = std::get<DistanceStop<double>>(m_.constraints[ci].type);
      const double S = s.L0 - st.L;
      if (!(S > 0))
        return problem("force", f, "L0", "the bottoming stop '" + m_.constraints[ci].name + "' (min_distance " + num(st.L) +
                                             " m) is not shorter than the extended strut, L0 = " + num(s.L0) + " m");
      if (!(gas > F * S))
        return problem("force", f, "Omega0", std::string(s.twoStage ? "gas volume Omega0 + Omega02 = " : "gas volume ") + num(gas) +
                                             " m^3 must be larger than the volume swept at the "
                                             "bottoming stroke, F S_max = " + num(F * S) + " m^3 (F = pi D^2/4 = " + num(F) +
                                             " m^2, S_max = " + num(S) + " m at stop '" + m_.constraints[ci].name + "')");
      reach = std::min(reach, S);
      if (index < sc_.roles.struts.size()) {
        sc_.roles.strokeLimits[index] = S;
        sc_.roles.bottomingStops[index] = ci;
      }
    }
    for (const auto& [table, key] : {std::pair{s.f1Table.get(), "f1_table"}, std::pair{s.f1eTable.get(), "f1_extension_table"}})
      if (table && table->xMax() > 100 * reach)
        return problem("force", f, key, "the table's strokes reach " + num(table->xMax()) + " m, " + num(table->xMax() / reach) +
                                            " times the stroke the strut can reach, " + num(reach) +
                                            " m: its stroke column in mm? (strokes in m)");
    if (s.f1Table && s.f1Table->xMax() < reach - 1e-12)
      return problem("force", f, "f1_table", "table ends at stroke " + num(s.f1Table->xMax()) + " m but the strut can reach " +
                                                 num(reach) + " m");
    if (s.f1eTable && s.f1eTable->xMax() < reach - 1e-12)
      return problem("force", f, "f1_extension_table", "table ends at stroke " + num(s.f1eTable->xMax()) +
                                                           " m but the strut can reach " + num(reach) + " m");
    for (size_t k = 0; k < s.f1eValues.size(); ++k)  // a design may move the extension table's samples
      if (auto p = positive(f, "f1_extension_table[" + std::to_string(k) + "]", s.f1eValues[k])) return p;
    return std::nullopt;
  }

  // Bearing friction's lever rule divides by the bearings' distance along the axis: on the strut of the
  // same rod and cylinder, it must keep its sign from s = 0 to S_max (the rod's bearing and the
  // cylinder's gland move apart as a strut compresses; bearings that meet within the stroke cannot be).
  std::optional<SceneProblem> bearingsApart(int f, const BearingFriction<double>& b) const {
    for (size_t k = 0; k < sc_.roles.struts.size(); ++k) {
      const auto& a = std::get<ShockAbsorber<double>>(m_.forces[sc_.roles.struts[k]].type);
      const double S = k < sc_.roles.strokeLimits.size() ? sc_.roles.strokeLimits[k] : std::nan("");
      if (a.bi != b.bi || a.bj != b.bj || !std::isfinite(S)) continue;
      const Vec3<double> B = w_.kin[a.bi].point(a.rho_i), C = w_.kin[a.bj].point(a.rho_j);
      const Vec3<double> u = (C - B).normalized();  // the rod's motion relative to the cylinder, per unit stroke
      const Mat3<double>& R = w_.kin[b.bj].R;
      const Vec3<double> e = (R * b.n_a).cross(R * b.n_b);
      const double z0 = e.dot(w_.kin[b.bi].point(b.rho_l) - w_.kin[b.bj].point(b.rho_u)), zS = z0 + S * e.dot(u);
      if (!(z0 * zS > 0))
        return problem("force", f, "lower_bearing", "the bearings meet within the stroke: their distance along the axis goes "
                                                    "from " + num(std::abs(z0)) + " m at s = 0 to " + num(zS * (z0 < 0 ? -1 : 1)) +
                                                    " m at S_max = " + num(S) + " m (the rod's bearing and the cylinder's "
                                                    "gland move apart as the strut compresses)");
    }
    return std::nullopt;
  }

  std::optional<SceneProblem> tyre(int f, const Tyre<double>& t) const {
    for (const auto& [key, v] : {std::pair<const char*, double>{"radius", t.radius}, {"delta_max", t.deltaMax}})
      if (auto p = positive(f, key, v)) return p;
    if (!(t.deltaMax < t.radius))
      return problem("force", f, "delta_max", "value " + num(t.deltaMax) + " m is not below the tyre's radius " + num(t.radius) +
                                                  " m: a deflection limit in mm?");
    if (t.law == TyreLaw::Table && t.curve->xMax() > 100 * t.deltaMax)
      return problem("force", f, "load_table", "the table's deflections reach " + num(t.curve->xMax()) + " m, " +
                                                   num(t.curve->xMax() / t.deltaMax) + " times delta_max = " + num(t.deltaMax) +
                                                   " m: its deflection column in mm? (the header reads deflection[m])");
    if (t.law != TyreLaw::Table)
      if (auto p = positive(f, "K", t.K)) return p;
    if (!(t.alpha >= 0)) return problem("force", f, "alpha", "value " + num(t.alpha) + " must be >= 0");
    if (t.law == TyreLaw::Power && !(t.exponent >= 1))
      return problem("force", f, "exponent", "value " + num(t.exponent) + " must be >= 1 (a tyre stiffens as it deflects)");
    if (t.law == TyreLaw::Table && t.curve->xMax() < t.deltaMax - 1e-12)
      return problem("force", f, "load_table", "table ends at deflection " + num(t.curve->xMax()) + " m, before delta_max = " +
                                                    num(t.deltaMax) + " m: it must cover the tyre's allowed deflection");
    if (t.damped && t.dampingLaw == TyreDampingLaw::Stiffness) {  // (a design may move them)
      if (auto p = positive(f, "damping_ratio", t.dampingRatio)) return p;
      if (auto p = positive(f, "damping_mass", t.dampingMass)) return p;
    } else if (t.damped) {
      if (!(t.c >= 0)) return problem("force", f, "c", "value " + num(t.c) + " must be >= 0");
      if (!(t.dampingExponent >= 0))
        return problem("force", f, "damping_exponent", "value " + num(t.dampingExponent) + " must be >= 0");
    }
    if (t.longitudinal) {
      if (!(t.muX > 0 && t.muX <= 1.5))
        return problem("force", f, "mu_x", "value " + num(t.muX) + " must be > 0 and <= 1.5 (a tyre's friction coefficient)");
      if (!(t.slipRatio > 0 && t.slipRatio < 1))
        return problem("force", f, "slip_ratio", "value " + num(t.slipRatio) + " must be > 0 and < 1 (a slip ratio)");
    }
    const double clearance = t.normal.dot(w_.kin[t.body].point(t.rho)) - t.groundHeight;  // wheel centre above the ground
    if (t.radius - clearance > 1e-6)
      return problem("force", f, "radius", "the tyre is pressed " + num(t.radius - clearance) + " m into the ground at touchdown (radius " +
                                               num(t.radius) + " m, wheel centre " + num(clearance) +
                                               " m above the ground): at t = 0 it must just touch the ground or clear it");
    return std::nullopt;
  }

  std::optional<SceneProblem> springDamper(int f, const SpringDamper<double>& d) const {
    for (const auto& [key, v] : {std::pair<const char*, double>{"k", d.k}, {"c", d.c}, {"L0", d.L0}})
      if (!(v >= 0)) return problem("force", f, key, "value " + num(v) + " must be >= 0");
    return std::nullopt;
  }

  std::optional<SceneProblem> bushing(int f, const Bushing<double>& b) const {
    static const char* kKeys[12] = {"k_x", "k_y", "k_z", "c_x", "c_y", "c_z", "k_rx", "k_ry", "k_rz", "c_rx", "c_ry", "c_rz"};
    const Vec3<double>* comp[4] = {&b.kt, &b.ct, &b.kr, &b.cr};
    for (int k = 0; k < 12; ++k)
      if (!((*comp[k / 3])[k % 3] >= 0)) return problem("force", f, kKeys[k], "value " + num((*comp[k / 3])[k % 3]) + " must be >= 0");
    return std::nullopt;
  }

  Scene& sc_;
  const Model<double>& m_;
  Workspace<double> w_;
};

}  // namespace

std::string sinkSpeedRule(double v) {
  if (!(v > 0))
    return "value " + num(v) + " must be > 0 [m/s]: a drop starts moving (the efficiency and the energy balance are "
                               "measured against the initial kinetic energy)";
  if (v > kMaxSinkSpeed)
    return "value " + num(v) + " m/s is above 10 m/s, no landing's sink speed (the rules' drops are 1.83 .. 3.66 m/s): "
                               "a speed in mm/s or ft/s?";
  return "";
}

std::string liftRatioRule(double v) {
  if (!(v >= 0)) return "value " + num(v) + " must be >= 0";
  if (v > kMaxLiftRatio)
    return "value " + num(v) + " is above 1.5: the lift ratio L is the wing's lift over the weight (the rules' drops use "
                               "L <= 1)";
  return "";
}

std::optional<SceneProblem> checkScene(Scene& scene) { return Checker(scene).run(); }

std::optional<std::string> envelopeProblem(const Scene& scene) {
  const Envelope& env = scene.envelope;
  if (!env.declared) return std::nullopt;
  std::vector<double> limits(scene.model.forces.size(), std::numeric_limits<double>::quiet_NaN());
  for (size_t k = 0; k < scene.roles.struts.size() && k < scene.roles.strokeLimits.size(); ++k)
    limits[static_cast<size_t>(scene.roles.struts[k])] = scene.roles.strokeLimits[k];
  std::vector<EnvelopeCorner> points = env.corners();
  if (!(env.point == env.nominal())) points.push_back({"the scene's point", env.point});
  for (const auto& c : points)
    if (auto why = envelopePointProblem(env, scene.model, limits, c)) return why;
  return std::nullopt;
}

std::string describe(const Scene& scene, const SceneProblem& p) {
  std::string element = p.array + "[" + std::to_string(p.index) + "]";
  const Model<double>& m = scene.model;
  if (p.array == "body" && p.index < m.nBodies()) element = m.bodies[p.index].name;
  else if (p.array == "force" && p.index < static_cast<int>(m.forces.size())) element = m.forces[p.index].name;
  else if (p.array == "stop") {
    for (size_t k = 0; k < scene.roles.stopEntry.size(); ++k)
      if (scene.roles.stopEntry[k] == p.index) element = m.constraints[scene.roles.stops[k]].name;
    for (size_t k = 0; k < scene.roles.padEntry.size(); ++k)
      if (scene.roles.padEntry[k] == p.index) element = m.forces[scene.roles.pads[k]].name;
  }
  else if (p.array == "case" && p.index < static_cast<int>(scene.cases.size())) element = scene.cases[p.index].name;
  return element + "." + p.key + ": " + p.rule;
}

}  // namespace lg
