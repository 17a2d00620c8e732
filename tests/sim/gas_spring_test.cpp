// The two-stage gas spring of the shock absorber (sim/forces/gas_spring.hpp): a second chamber behind a
// floating piston, engaging when p_1 reaches its precharge. Its pressures against an independent reduced
// model (the two-chamber equilibrium by bisection on the volume split), its stored energy against the
// quadrature of its force, the engagement stroke against the closed form and located as an event in a
// drop, the energy balance of the nose gear's drops, the damping term and Jet derivatives against central
// differences, bad input, and the single stage unchanged to the bit.
#include "sim/core/jet.hpp"
#include "tests/sim/bad_input_support.hpp"
#include "tests/sim/engine_support.hpp"

#include <catch2/catch.hpp>  // after the sim headers (see scene_support.hpp)

#include <cmath>

namespace {

// The independent reduced model: two polytropic chambers, the second behind a free piston on its stop.
// Total gas volume V_t = Omega_0 + Omega_02 - s F. On the stop (V_2 = Omega_02) while p_1(V_t - Omega_02)
// <= p_02; else the piston floats, p_1(V_1) = p_2(V_t - V_1), found by bisection on V_1 in
// [V_t - Omega_02, V_t] (p_1 - p_2 falls from > 0 to -inf there).
struct TwoChamber {
  double p01, V01, n1, p02, V02, n2, F;
  struct At {
    double p1, p2, V1, V2;
  };
  At at(double s) const {
    const double Vt = V01 + V02 - s * F;
    auto p1 = [&](double V1) { return p01 * std::pow(V01 / V1, n1); };
    auto p2 = [&](double V2) { return p02 * std::pow(V02 / V2, n2); };
    if (p1(Vt - V02) <= p02) return {p1(Vt - V02), p02, Vt - V02, V02};
    double lo = Vt - V02, hi = Vt;
    for (int it = 0; it < 2000; ++it) {
      const double mid = 0.5 * (lo + hi);
      if (!(mid > lo && mid < hi)) break;
      (p1(mid) - p2(Vt - mid) > 0 ? lo : hi) = mid;
    }
    const double V1 = 0.5 * (lo + hi);
    return {p1(V1), p2(Vt - V1), V1, Vt - V1};
  }
  // Work of the gas from the precharge to the state at s (each chamber's polytropic integral).
  double energy(double s) const {
    const At a = at(s);
    return p01 * V01 / (n1 - 1) * (std::pow(V01 / a.V1, n1 - 1) - 1) + p02 * V02 / (n2 - 1) * (std::pow(V02 / a.V2, n2 - 1) - 1);
  }
};

const lg::ShockAbsorber<double>& strutOf(const lg::Scene& sc) {
  return std::get<lg::ShockAbsorber<double>>(sc.model.forces[sc.roles.struts.at(0)].type);
}

TwoChamber reducedOf(const lg::ShockAbsorber<double>& sa) {
  return {sa.p01, sa.Omega0, sa.n, sa.p02, sa.Omega02, sa.n2, M_PI * sa.D * sa.D / 4};
}

// The nose gear's strut (vertical: the rod and wheel moved up by ds compress it by ds, moving at sdot):
// its outputs (s, s', p_1, P_a, P_gas, P_friction, P_orifice1, P_orifice2, p_2), its stored energy and
// optionally its damping term, for any scalar model. 'dsSeed' >= 0 seeds the stroke as that derivative.
template <class S> struct StrutAt {
  std::vector<S> out;
  S stored;
  S bound;
};
template <class S> StrutAt<S> strutAt(const lg::Scene& sc, const lg::Model<S>& m, double ds, double sdot,
                                      lg::DampingTerm<S>* term = nullptr, int dsSeed = -1) {
  lg::VecX<S> y = sc.initial.y.template cast<S>();
  const int N = m.nBodies();
  for (const char* b : {"rod", "wheel"}) {
    const int i = m.bodyIndex(b);
    S d(ds);
    if constexpr (!std::is_same_v<S, double>)
      if (dsSeed >= 0) d.v[dsSeed] = 1.0;
    y[7 * i + 1] += d;
    y[7 * N + 6 * i + 1] = S(sdot);
  }
  lg::Workspace<S> w(m);
  lg::kinematics(m, y, w);
  const auto& sa = std::get<lg::ShockAbsorber<S>>(m.forces[sc.roles.struts.at(0)].type);
  StrutAt<S> r;
  r.out.resize(sa.outputNames().size());
  sa.outputs(w.kins(), r.out.data());
  r.stored = sa.stored(w.kins());
  r.bound = sa.frictionBound(w.kins());
  if (term) sa.damping(w.kins(), term);
  return r;
}

lg::Scene noseGear() { return lg::loadScene(lgtest::sourcePath("data/nose_gear.toml")); }

}  // namespace

// Pressures and gas force from s = 0 to the bottoming stroke (S_max = 0.30 m, 601 strokes and the two
// sides of s*) against the reduced model: 1e-14 relative (measured 2.7e-15; the reduced model's
// bisection is exact to the last bits of V_1, and p carries n of its relative error). p_2 = p_02 before
// engagement, p_1 = p_2 after; the Coulomb friction's bound mu (p - p_atm) F uses the common pressure.
TEST_CASE("two-stage gas spring: pressures and force over the stroke against a reduced model", "[shock_absorber][gas_spring]") {
  const lg::Scene sc = noseGear();
  const auto& sa = strutOf(sc);
  REQUIRE(sa.twoStage);
  REQUIRE(sa.outputNames().back() == "p_2");
  const TwoChamber ref = reducedOf(sa);
  const double F = ref.F, sStar = sa.gasSpring().engagementStroke(F);
  std::vector<double> strokes;
  for (int k = 0; k <= 600; ++k) strokes.push_back(0.30 * k / 600);
  for (double d : {-1e-9, -1e-12, 1e-12, 1e-9}) strokes.push_back(sStar + d);
  double worst = 0;
  int engaged = 0;
  for (double s : strokes) {
    const auto o = strutAt(sc, sc.model, s, 0.0).out;
    const TwoChamber::At a = ref.at(o[0]);  // at the element's own stroke (s to round-off)
    INFO("s = " << s);
    REQUIRE(std::abs(o[0] - s) < 1e-15);
    const double e = std::max({lgtest::relDiff(o[2], a.p1), lgtest::relDiff(o[8], a.p2), lgtest::relDiff(o[4], a.p1 * F)});
    worst = std::max(worst, e);
    CHECK(e < 1e-14);
    if (o[0] > sStar) {
      ++engaged;
      CHECK(o[2] == o[8]);
    } else {
      CHECK(o[8] == sa.p02);
    }
    const auto b = strutAt(sc, sc.model, s, 0.0).bound;
    CHECK(lgtest::relDiff(b, sa.mu * a.p1 * F) < 1e-14);
  }
  lgtest::report("two-stage gas spring vs reduced model: %d strokes (%d engaged), worst rel. error %.1e", int(strokes.size()),
                 engaged, worst);
  CHECK(engaged > 100);
}

// Stored energy against the gas force's integral (composite 5-point Gauss-Legendre, 400 panels, split at
// s*: the force's slope jumps there) from 0 to strokes across the whole stroke: 2e-14 of the energy
// (measured 5.4e-15), and against the reduced model's polytropic work at its own volumes (2e-14; measured
// 4.7e-15).
TEST_CASE("two-stage gas spring: stored energy is the integral of its force", "[shock_absorber][gas_spring][energy]") {
  const lg::Scene sc = noseGear();
  const auto& sa = strutOf(sc);
  const TwoChamber ref = reducedOf(sa);
  const double sStar = sa.gasSpring().engagementStroke(ref.F);
  static const double x[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  static const double wg[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665, 0.2369268850561891};
  auto integral = [&](double a, double b) {
    double sum = 0;
    const int panels = 400;
    const double h = (b - a) / panels;
    for (int p = 0; p < panels; ++p)
      for (int q = 0; q < 5; ++q) sum += 0.5 * h * wg[q] * sa.gasSpring().pressure(a + h * (p + 0.5 + 0.5 * x[q]), ref.F) * ref.F;
    return sum;
  };
  double worstQ = 0, worstR = 0;
  for (double s : {0.05, 0.15, sStar, 0.24, 0.27, 0.30}) {
    const double E = strutAt(sc, sc.model, s, 0.0).stored;
    const double Q = s <= sStar ? integral(0, s) : integral(0, sStar) + integral(sStar, s);
    INFO("s = " << s << ", E = " << E << " J, quadrature " << Q << " J");
    worstQ = std::max(worstQ, lgtest::relDiff(E, Q));
    worstR = std::max(worstR, lgtest::relDiff(E, ref.energy(s)));
    CHECK(lgtest::relDiff(E, Q) < 2e-14);
    CHECK(lgtest::relDiff(E, ref.energy(s)) < 2e-14);
  }
  lgtest::report("two-stage stored energy: vs quadrature %.1e, vs reduced model %.1e", worstQ, worstR);
}

// The engagement stroke s* = (Omega_0/F)(1 - (p_01/p_02)^(1/n)) against the closed form (1e-15), p_1 = p_02
// there (2e-15); in the nose gear's limit drop the integrator stops on it: a step ends within 1e-11 m of
// s* on the way in and on the way out (the event's bracket is 1e-12 s at |s'| < 3 m/s; measured 2.8e-17 m),
// p_2 leaves p_02 only beyond it, and the energy balance closes in every case as the other scenes' do
// (1e-6; measured 4.0e-7 at most). The second stage softens the end of the stroke: the limit drop's peak
// load falls and its stroke grows against the same strut with one chamber (measured: 58618 N against
// 69838 N, 0.2370 m against 0.2269 m; README "Two-stage gas spring").
TEST_CASE("two-stage gas spring: engagement located in a drop, energy balance closed", "[shock_absorber][gas_spring][events]") {
  const lg::Scene sc = noseGear();
  const auto& sa = strutOf(sc);
  const double F = M_PI * sa.D * sa.D / 4;
  const double closed = sa.Omega0 / F * (1 - std::pow(sa.p01 / sa.p02, 1 / sa.n));
  const double sStar = sa.gasSpring().engagementStroke(F);
  CHECK(lgtest::relDiff(sStar, closed) < 1e-15);
  CHECK(lgtest::relDiff(sa.gasSpring().pressure(sStar, F), sa.p02) < 2e-15);
  CHECK(sc.model.nForceEvents == 2);  // the tyre's contact and the strut's engagement
  lg::CaseOptions opt;
  opt.record = true;
  const lg::CaseResult r = lg::runCase(sc, lgtest::findCase(sc, "limit"), opt);
  REQUIRE(r.metrics.ok);
  const int cs = r.column("s"), cp = r.column("p_2");
  REQUIRE(cs >= 0);
  REQUIRE(cp >= 0);
  double nearest = 1, sMax = 0;
  int crossings = 0;
  for (size_t k = 0; k < r.samples.size(); ++k) {
    const double s = r.samples[k].values[cs];
    sMax = std::max(sMax, s);
    nearest = std::min(nearest, std::abs(s - sStar));
    if (std::abs(s - sStar) < 1e-11) ++crossings;
    if (s < sStar - 1e-11) CHECK(r.samples[k].values[cp] == sa.p02);
    if (s > sStar + 1e-11) CHECK(r.samples[k].values[cp] > sa.p02);
  }
  REQUIRE(sMax > sStar);
  CHECK(crossings >= 2);  // in and out
  // The same strut with one chamber.
  toml::table doc = lgtest::shippedDoc("data/nose_gear.toml");
  for (const char* k : {"p02", "Omega02", "n2"}) lgtest::element(doc, "force", "strut").erase(k);
  const lg::Scene one = lgtest::build(doc);
  const lg::CaseMetrics m1 = lg::runCase(one, lgtest::findCase(one, "limit")).metrics;
  REQUIRE(m1.ok);
  lgtest::report("nose gear limit: s* %.6f m, nearest step end %.1e m (%d), peak %.0f N (one chamber %.0f N, %+.1f %%), "
                 "stroke %.4f m (one chamber %.4f m), E_bal %.1e",
                 sStar, nearest, crossings, r.metrics.peak_load_N, m1.peak_load_N,
                 100 * (m1.peak_load_N - r.metrics.peak_load_N) / r.metrics.peak_load_N, r.metrics.stroke_max_m, m1.stroke_max_m,
                 r.metrics.energy_balance_error);
  CHECK(r.metrics.peak_load_N < m1.peak_load_N);
  CHECK(r.metrics.stroke_max_m > m1.stroke_max_m);
  double worstBalance = 0;
  for (const auto& res : lg::runCases(sc, sc.cases, 2)) {
    INFO(res.metrics.name << ": " << res.metrics.message);
    REQUIRE(res.metrics.ok);
    worstBalance = std::max(worstBalance, res.metrics.energy_balance_error);
    CHECK(res.metrics.energy_balance_error < 1e-6);
    CHECK(!res.metrics.bottomed);
  }
  lgtest::report("nose gear: energy balance %.1e at most over its cases", worstBalance);
}

// Derivatives at strokes before and after engagement. The damping term c = dP_a/ds' with regularised
// friction (whose bound carries the common pressure) against central differences (1e-8; measured
// 7.4e-10); Jet derivatives of the gas force and the stored energy in p02, Omega02, n2 (relative to the
// value over the parameter) and the stroke against central differences at relative steps 1e-6 (1e-8;
// measured 1.9e-9 worst); before engagement the second chamber's derivatives are exactly 0; dP_gas/ds
// against the closed-form stiffness p F^2 / (V_1/n + V_2/n_2) after engagement, n p F^2 / V_1 before
// (2e-14; measured 2.9e-15), and the damping term's k = that (1 + mu sign(s')) (2e-14; measured 1.8e-15).
TEST_CASE("two-stage gas spring: damping term and Jet derivatives against central differences", "[shock_absorber][gas_spring][jet]") {
  toml::table doc = lgtest::shippedDoc("data/nose_gear.toml");
  lgtest::element(doc, "force", "strut").insert_or_assign("friction", "regularised");
  const lg::Scene sc = lgtest::build(doc);
  const auto& sa = strutOf(sc);
  const TwoChamber ref = reducedOf(sa);
  const double F = ref.F, sStar = sa.gasSpring().engagementStroke(F);
  using J = ceres::Jet<double, 4>;
  lg::Model<J> mj = sc.model.cast<J>();
  auto& sj = std::get<lg::ShockAbsorber<J>>(mj.forces[sc.roles.struts.at(0)].type);
  REQUIRE(sj.parameter("p02") == &sj.p02);
  REQUIRE(sj.parameter("Omega02") == &sj.Omega02);
  REQUIRE(sj.parameter("n2") == &sj.n2);
  sj.p02.v[0] = 1.0;
  sj.Omega02.v[1] = 1.0;
  sj.n2.v[2] = 1.0;
  double worstC = 0, worstJ = 0, worstK = 0, worstTermK = 0;
  for (double s : {0.12, sStar - 1e-4, sStar + 1e-4, 0.25, 0.29}) {
    // Closed-form stiffness of the gas force at the reduced model's volumes.
    const TwoChamber::At r = ref.at(s);
    const double k = s > sStar ? r.p1 * F * F / (r.V1 / sa.n + r.V2 / sa.n2) : sa.n * r.p1 * F * F / r.V1;
    for (double v : {1.2, -0.4}) {
      INFO("s = " << s << ", s' = " << v);
      lg::DampingTerm<double> dt;
      strutAt(sc, sc.model, s, v, &dt);
      const double h = 1e-6 * std::abs(v);
      const double fd = (strutAt(sc, sc.model, s, v + h).out[3] - strutAt(sc, sc.model, s, v - h).out[3]) / (2 * h);
      worstC = std::max(worstC, lgtest::relDiff(dt.c, fd));
      CHECK(lgtest::relDiff(dt.c, fd) < 1e-8);
      // The term's position stiffness: the gas force's and the friction's that it loads (mu times the
      // regularised sign); the metering pin's share through the orifice is not in it.
      const double kTerm = k * (1.0 + sa.mu * lg::smoothSign(v, sa.frictionVelocity));
      worstTermK = std::max(worstTermK, lgtest::relDiff(dt.k, kTerm));
      CHECK(lgtest::relDiff(dt.k, kTerm) < 2e-14);
    }
    const StrutAt<J> a = strutAt<J>(sc, mj, s, 0.0, nullptr, 3);
    auto central = [&](auto set, double step) {
      lg::Model<double> mp = sc.model, mm = sc.model;
      set(std::get<lg::ShockAbsorber<double>>(mp.forces[sc.roles.struts.at(0)].type), step);
      set(std::get<lg::ShockAbsorber<double>>(mm.forces[sc.roles.struts.at(0)].type), -step);
      const auto p = strutAt(sc, mp, s, 0.0), m = strutAt(sc, mm, s, 0.0);
      return std::pair{(p.out[4] - m.out[4]) / (2 * step), (p.stored - m.stored) / (2 * step)};
    };
    const auto dP02 = central([](lg::ShockAbsorber<double>& x, double d) { x.p02 += d; }, 1e-6 * sa.p02);
    const auto dO02 = central([](lg::ShockAbsorber<double>& x, double d) { x.Omega02 += d; }, 1e-6 * sa.Omega02);
    const auto dN2 = central([](lg::ShockAbsorber<double>& x, double d) { x.n2 += d; }, 1e-6);
    const double hs = 1e-7;
    const double dS = (strutAt(sc, sc.model, s + hs, 0.0).out[4] - strutAt(sc, sc.model, s - hs, 0.0).out[4]) / (2 * hs);
    const J P = a.out[4], E = a.stored;
    INFO("s = " << s);
    if (s < sStar) {
      for (int k = 0; k < 3; ++k) {
        CHECK(P.v[k] == 0.0);
        CHECK(E.v[k] == 0.0);
      }
    } else {
      const std::pair<double, double> d[3] = {dP02, dO02, dN2};
      for (int k = 0; k < 3; ++k) {
        const double scaleP = std::abs(P.a) / (k == 0 ? sa.p02 : k == 1 ? sa.Omega02 : 1.0);
        const double scaleE = std::abs(E.a) / (k == 0 ? sa.p02 : k == 1 ? sa.Omega02 : 1.0);
        const double eP = std::abs(P.v[k] - d[k].first) / scaleP, eE = std::abs(E.v[k] - d[k].second) / scaleE;
        worstJ = std::max({worstJ, eP, eE});
        CHECK(eP < 1e-8);
        CHECK(eE < 1e-8);
      }
    }
    const double eS = lgtest::relDiff(P.v[3], dS);
    worstJ = std::max(worstJ, eS);
    CHECK(eS < 1e-8);
    worstK = std::max(worstK, lgtest::relDiff(P.v[3], k));
    CHECK(lgtest::relDiff(P.v[3], k) < 2e-14);
  }
  lgtest::report("two-stage derivatives: damping term %.1e, Jet vs central differences %.1e (scaled), stiffness vs closed "
                 "form %.1e, the term's stiffness %.1e",
                 worstC, worstJ, worstK, worstTermK);
}

// A single-stage strut is the one it was: the seed gear with a second chamber that never engages
// (p02 = 1 GPa: s* beyond the bottoming stroke) gives every metric of every case bit for bit (the law
// before engagement is the single stage's expression, and an event function that never changes sign
// changes no step).
TEST_CASE("two-stage gas spring: a second stage that never engages leaves the seed gear's runs to the bit", "[shock_absorber][gas_spring]") {
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  REQUIRE(!strutOf(seed).twoStage);
  REQUIRE(seed.model.nForceEvents == 1);  // the tyre's contact only
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  auto& st = lgtest::element(doc, "force", "strut");
  st.insert_or_assign("p02", 1.0e9);
  st.insert_or_assign("Omega02", 1.0e-3);
  const lg::Scene two = lgtest::build(doc);
  REQUIRE(strutOf(two).twoStage);
  REQUIRE(strutOf(two).gasSpring().engagementStroke(M_PI * 0.01 / 4) > 0.16);
  const auto a = lg::runCases(seed, seed.cases, 2), b = lg::runCases(two, two.cases, 2);
  for (size_t i = 0; i < a.size(); ++i) {
    INFO(a[i].metrics.name);
    REQUIRE(b[i].metrics.ok);
    CHECK(a[i].metrics.peak_load_N == b[i].metrics.peak_load_N);
    CHECK(a[i].metrics.t_peak_s == b[i].metrics.t_peak_s);
    CHECK(a[i].metrics.stroke_max_m == b[i].metrics.stroke_max_m);
    CHECK(a[i].metrics.rebound_velocity_mps == b[i].metrics.rebound_velocity_mps);
    CHECK(a[i].metrics.energy_dissipated_J == b[i].metrics.energy_dissipated_J);
    CHECK(a[i].metrics.energy_balance_error == b[i].metrics.energy_balance_error);
    CHECK(a[i].metrics.steps == b[i].metrics.steps);
  }
}

TEST_CASE("two-stage gas spring: bad input names file, line, key and rule, exit status 2", "[shock_absorber][gas_spring][input]") {
  lgtest::TempDir dir("gas_spring_bad");
  const std::string nose = lgtest::readFile(lgtest::sourcePath("data/nose_gear.toml"));
  auto with = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(nose, from, to); };
  const std::string noP02 = with("p02 = 7.0e6", "");
  lgtest::checkBadInputs(
      {
          {"second precharge below the first", with("p02 = 7.0e6", "p02 = 1.8e6"), "p02 = 1.8e6", "force[2].p02",
           "value 1800000 must be > p01 = 1800000"},
          {"negative second precharge", with("p02 = 7.0e6", "p02 = -7.0e6"), "p02 = -7.0e6", "force[2].p02", "value -7000000 must be > 0"},
          {"zero second volume", with("Omega02 = 1.0e-3", "Omega02 = 0.0"), "Omega02 = 0.0", "force[2].Omega02", "value 0 must be > 0"},
          {"second exponent below 1", with("n2 = 1.35", "n2 = 0.9"), "n2 = 0.9", "force[2].n2", "polytropic exponent 0.9 must be >= 1"},
          {"second volume without its precharge", noP02, "Omega02 = 1.0e-3", "force[2].Omega02",
           "a second gas chamber needs both p02 and Omega02"},
          {"precharge without its volume", with("Omega02 = 1.0e-3", ""), "p02 = 7.0e6", "force[2].p02",
           "a second gas chamber needs both p02 and Omega02"},
          {"both chambers too small for the bottoming stroke", lgtest::replacedText(with("Omega02 = 1.0e-3", "Omega02 = 1.0e-5"),
                                                                                    "Omega0 = 1.95e-3", "Omega0 = 1.8e-3"),
           "Omega0 = 1.8e-3", "force[2].Omega0", "gas volume Omega0 + Omega02 = 0.00181 m^3 must be larger than the volume swept"},
      },
      dir);
}

// n = 1, isothermal: p V constant, the energy p_0 Omega_0 ln(Omega_0 / V) against Simpson quadrature of
// the force over the stroke, one stage and two (both chambers isothermal, engaged), its derivative in n
// the polytropic law's limit; a drop of the seed gear with an isothermal gas closes its energy balance.
TEST_CASE("gas spring: n = 1, the isothermal energy against quadrature", "[gas_spring]") {
  const double p01 = 3e6, Om = 1.3e-3, F = M_PI * 0.1 * 0.1 / 4, one = 1.0, p02 = 7e6, Om2 = 0.4e-3;
  for (bool two : {false, true}) {
    INFO((two ? "two stages" : "one stage"));
    const lg::GasSpring<double> g{p01, Om, one, two, p02, Om2, one};
    const double S = 0.15;
    // Simpson over [0, S] of p F ds (2000 panels; the kink at s* on a node of its own side: tolerance)
    const int n = 2000;
    double sum = 0;
    for (int i = 0; i <= n; ++i) {
      const double s = S * i / n, w = (i == 0 || i == n) ? 1 : (i % 2 ? 4 : 2);
      sum += w * g.pressure(s, F) * F;
    }
    const double quad = sum * (S / n) / 3;
    CHECK(g.stored(S, F) == Approx(quad).epsilon(two ? 1e-7 : 2e-11));  // (Simpson: 7.7e-12 one stage)
    if (!two) CHECK(g.stored(S, F) == Approx(p01 * Om * std::log(Om / (Om - S * F))).epsilon(1e-14));
  }
  // d E / d n at n = 1: the limit of the polytropic law's, p_0 Omega_0 L^2 / 2
  using J = ceres::Jet<double, 1>;
  const J p(p01), O(Om), nJ(1.0, 0), zero(0.0);
  const lg::GasSpring<J> gj{p, O, nJ, false, zero, zero, nJ};
  const double L = std::log(Om / (Om - 0.1 * F));
  CHECK(gj.stored(J(0.1), J(F)).v[0] == Approx(p01 * Om * L * L / 2).epsilon(1e-12));
  // the polytropic law just above n = 1 continues the isothermal value with that slope
  const double h = 1e-5, nUp = 1 + h, zeroD = 0.0;
  const lg::GasSpring<double> up{p01, Om, nUp, false, zeroD, zeroD, nUp};
  CHECK((up.stored(0.1, F) - gj.stored(J(0.1), J(F)).a) / h == Approx(p01 * Om * L * L / 2).epsilon(1e-4));
  // a drop with an isothermal strut closes its energy balance
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  lgtest::element(doc, "force", "strut").insert_or_assign("n", 1.0);
  const lg::Scene sc = lgtest::build(doc);
  const lg::CaseMetrics m = lg::runCase(sc, lgtest::findCase(sc, "limit")).metrics;
  REQUIRE(m.ok);
  CHECK(m.energy_balance_error < 1e-6);
}
