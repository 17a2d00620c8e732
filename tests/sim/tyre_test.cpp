// The tyre element (sim/forces/tyre.hpp): method.md's law, never pulling, stored energy consistent
// with the force, and the contact event function; the options of a tyre from data (a load table, the
// power law, damping) against closed forms and a reduced model, their derivatives, and their bad input.
#include <array>

#include "reference/reduced_common.hpp"
#include "sim/core/jet.hpp"
#include "sim/forces/tyre.hpp"
#include "tests/sim/bad_input_support.hpp"
#include "tests/sim/engine_support.hpp"

#include <catch2/catch.hpp>  // after the sim headers (see scene_support.hpp)

namespace {

struct OneBody {
  std::array<lg::BodyKin<double>, 2> k{lg::BodyKin<double>::ground(), lg::BodyKin<double>::ground()};
  explicit OneBody(double y) {
    k[0].r = lg::Vec3<double>(0.1, y, -0.2);
    k[0].R = Eigen::AngleAxisd(0.7, lg::Vec3<double>(0, 0, 1)).toRotationMatrix();  // a spinning wheel
  }
  lg::Kins<double> kins() const { return {k.data(), 1}; }
};

lg::Tyre<double> seedTyre() {
  lg::Tyre<double> t;
  t.body = 0;
  t.rho.setZero();
  t.normal = lg::Vec3<double>(0, 1, 0);
  t.groundHeight = 0;
  t.radius = 0.30;
  t.K = 8.0e5;
  t.deltaMax = 0.10;
  t.alpha = 0.5;
  return t;
}

}  // namespace

TEST_CASE("tyre force follows method.md and never pulls", "[tyre]") {
  const lg::Tyre<double> t = seedTyre();
  const ref::TyreLaw law{8.0e5, 0.10, 0.5};
  for (double delta : {-0.05, -1e-9, 0.0, 1e-9, 0.01, 0.05, 0.1, 0.13}) {
    const OneBody b(0.30 - delta);
    INFO("delta = " << delta);
    CHECK(t.deflection(b.kins()) == Approx(delta).margin(1e-15));
    const double P = t.load(delta);
    CHECK(P >= 0.0);
    if (delta <= 0) CHECK(P == 0.0);
    else CHECK(P == Approx(8.0e5 * delta * (1 + 0.5 * (delta / 0.1) * (delta / 0.1))).epsilon(1e-14));
    CHECK(P == Approx(law.force(delta)).epsilon(1e-14));
    // Stored energy: its derivative along delta is the force.
    const double h = 1e-7;
    if (std::abs(delta) > 2 * h) {
      const double dE = (t.stored(OneBody(0.30 - delta - h).kins()) - t.stored(OneBody(0.30 - delta + h).kins())) / (2 * h);
      CHECK(dE == Approx(P).epsilon(1e-6).margin(1e-6));
    }
    // Event function: the deflection (contact starts / ends where it crosses 0).
    double g = 1;
    t.events(b.kins(), &g);
    CHECK(g == Approx(delta).margin(1e-15));
    // Outputs: delta, P_t and their rates, with the wheel moving down at 1.3 m/s (and spinning): delta'
    // = 1.3 m/s, P_t' = dP_t/ddelta delta' (against a central difference of the load law; 0 off the ground).
    OneBody moving(0.30 - delta);
    moving.k[0].v = lg::Vec3<double>(0.4, -1.3, 0.0);
    moving.k[0].w = lg::Vec3<double>(0.0, 0.0, 9.0);
    double out[4];
    REQUIRE(t.outputNames().size() == 4);
    t.outputs(moving.kins(), out);
    CHECK(out[0] == t.deflection(moving.kins()));
    CHECK(out[1] == t.load(out[0]));
    CHECK(out[2] == Approx(1.3).epsilon(1e-14));
    const double rate = delta > 2 * h ? (t.load(delta + h) - t.load(delta - h)) / (2 * h) * 1.3 : 0.0;
    if (delta <= 0) CHECK(out[3] == 0.0);
    else if (delta > 2 * h) CHECK(out[3] == Approx(rate).epsilon(1e-7));
  }
}

TEST_CASE("tyre force acts along the ground normal at the wheel centre", "[tyre]") {
  const lg::Tyre<double> t = seedTyre();
  const OneBody b(0.25);
  std::array<lg::Vec6<double>, 1> w{lg::Vec6<double>::Zero()};
  t.apply(b.kins(), lg::Wrenches<double>{w.data()}, nullptr);
  CHECK(w[0][0] == 0.0);
  CHECK(w[0][1] == Approx(t.load(0.05)));
  CHECK(w[0][2] == 0.0);
  CHECK(w[0].tail<3>().norm() == 0.0);  // through the centre: no moment on the wheel
}

// ---- the options of a tyre from data: load laws, damping (sim/forces/tyre.hpp) ------------------------

namespace {

// A wheel on a vertical guide (no gravity) meeting the ground at 2 m/s: a mass on the tyre alone.
const char* kBounce = R"(
[solver]
integrator = "dopri5"
rtol = 1e-11
atol = 1e-13

[[body]]
name = "wheel"
mass = 50.0
inertia = [1.0, 1.0, 1.0]
position = [0.0, 0.3, 0.0]

[[joint]]
name = "guide"
type = "prismatic"
body1 = "wheel"
body2 = "ground"
point = [0.0, 0.3, 0.0]
axis = [0.0, 1.0, 0.0]

[[force]]
name = "tyre"
type = "tyre"
body = "wheel"
radius = 0.3
K = 2.0e5
delta_max = 0.1
alpha = 0.0
c = 1500.0
)";

constexpr double kM = 50.0, kK = 2.0e5, kC = 1500.0, kV0 = 2.0;

// The bounce in closed form (linear spring, viscous damping, no gravity): x = (v0/wd) e^(-z w0 t) sin(wd t)
// while k x + c x' > 0; the tyre lets go where k x + c x' = 0, tan(wd t) = -c wd / (k - c z w0), and the
// wheel leaves at v_out = -x'(t_s). Dissipated: m (v0^2 - v_out^2) / 2.
struct BounceClosedForm {
  double tSep, vOut, dissipated;
  BounceClosedForm(double m, double k, double c, double v0) {
    const double w0 = std::sqrt(k / m), z = c / (2 * m * w0), wd = w0 * std::sqrt(1 - z * z);
    tSep = (M_PI - std::atan(c * wd / (k - c * z * w0))) / wd;
    vOut = -v0 * std::exp(-z * w0 * tSep) * (std::cos(wd * tSep) - z * w0 / wd * std::sin(wd * tSep));
    dissipated = m * (v0 * v0 - vOut * vOut) / 2;
  }
};

// The bounce with the engine: the wheel's final upward speed and the tyre's dissipated energy (its
// damping channel), for a scene and a model of it (any scalar).
template <class S> struct BounceRun {
  S vOut, dissipated;
  double energyError;
};
template <class S> BounceRun<S> bounce(const lg::Scene& sc, const lg::Model<S>& m, double T = 0.2) {
  lg::State<S> s(m);
  s.y = sc.initial.y.template cast<S>();
  s.active = sc.initial.active;
  const int N = m.nBodies();
  s.y[7 * N + 1] = S(-kV0);
  lg::Workspace<S> w(m);
  lg::kinematics(m, s.y, w);
  const double E0 = lg::value(lg::energy(m, s, w).total());
  REQUIRE(lg::simulate(m, s, w, T).ok);
  lg::kinematics(m, s.y, w);
  const double E1 = lg::value(lg::energy(m, s, w).total());
  return {s.y[7 * N + 1], s.y[m.nx() + m.nv()], std::abs(E1 - E0) / (0.5 * kM * kV0 * kV0)};
}

// P_s, its slope and its integral of the polynomial law of method.md.
double polyLoad(double d) { return 8.0e5 * d * (1 + 0.5 * (d / 0.1) * (d / 0.1)); }
double polyEnergy(double d) { return 8.0e5 * (d * d / 2 + 0.5 * d * d * d * d / (4 * 0.01)); }

// The seed gear with its tyre's table sampled from the polynomial law: 'rows' rows over [0, 0.15] m.
std::string writePolynomialCurve(const lgtest::TempDir& dir, int rows) {
  std::string csv = "deflection,load\n";
  char line[80];
  for (int i = 0; i < rows; ++i) {
    const double d = 0.15 * i / (rows - 1);
    std::snprintf(line, sizeof line, "%.17g,%.17g\n", d, polyLoad(d));
    csv += line;
  }
  const std::string path = dir / "poly_tyre.csv";
  lgtest::writeFile(path, csv);
  return path;
}

}  // namespace

// A table sampled from the polynomial law (a cubic) reproduces it to round-off: the curve's slopes are
// exact for cubics (curve_table.hpp). At 31 rows (every 5 mm up to 0.15 m) the load, the slope and the
// stored energy match the law to 1e-12 of their local values (measured 1.2e-15, 2.4e-14 and 8.8e-16). On a curve that is no
// polynomial, P = K d_m (e^(d/d_m) - 1), the error (as a fraction of the largest load) is fourth order:
// from 16 to 31 rows it falls by 12 or more (measured 15.0: 4.7e-6 to 3.1e-7; relative to the local
// load near 0 it is third order, the one-sided end slope's). The seed gear dropped on the table: every
// metric of the limit and free-drop cases within 1e-12 of the polynomial tyre's (measured 5.2e-14), the
// energy balance closed as with the polynomial (below 1e-6).
TEST_CASE("tyre table: sampled from the polynomial law, it reproduces it", "[tyre][table]") {
  lgtest::TempDir dir("tyre_table");
  {
    const std::string path = writePolynomialCurve(dir, 31);
    toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
    auto& t = lgtest::element(doc, "force", "tyre");
    t.erase("K");
    t.erase("alpha");
    t.insert_or_assign("law", "table");
    t.insert_or_assign("load_table", path);
    const lg::Scene sc = lgtest::build(doc);
    lg::Tyre<double> tyre = std::get<lg::Tyre<double>>(sc.model.forces[sc.roles.tyres.at(0)].type);
    REQUIRE(tyre.law == lg::TyreLaw::Table);
    REQUIRE(tyre.radius == 0.30);
    tyre.body = 0;  // on OneBody's wheel
    tyre.rho.setZero();
    double eLoad = 0, eSlope = 0, eEnergy = 0;
    for (int i = 1; i <= 3000; ++i) {
      const double d = 0.15 * i / 3000;
      eLoad = std::max(eLoad, std::abs(tyre.load(d) - polyLoad(d)) / polyLoad(d));
      const double slope = 8.0e5 * (1 + 1.5 * (d / 0.1) * (d / 0.1));
      eSlope = std::max(eSlope, std::abs(tyre.stiffness(d) - slope) / slope);
      const OneBody b(0.30 - d);
      const double dd = tyre.deflection(b.kins());  // d up to the rounding of 0.30 - d
      eEnergy = std::max(eEnergy, std::abs(tyre.stored(b.kins()) - polyEnergy(dd)) / polyEnergy(dd));
    }
    lgtest::report("tyre table of 31 rows: load %.2e, slope %.2e, energy %.2e", eLoad, eSlope, eEnergy);
    CHECK(eLoad < 1e-12);
    CHECK(eSlope < 1e-12);
    CHECK(eEnergy < 1e-12);
  }
  // Fourth order on a smooth curve that is no polynomial.
  {
    auto P = [](double d) { return 8.0e5 * 0.1 * (std::exp(d / 0.1) - 1); };
    auto worst = [&](int rows) {
      std::vector<double> x, y;
      for (int i = 0; i < rows; ++i) {
        x.push_back(0.15 * i / (rows - 1));
        y.push_back(P(x.back()));
      }
      const lg::CurveTable curve(x, y, "exp");
      double e = 0;
      for (int i = 1; i <= 3000; ++i) {
        const double d = 0.15 * i / 3000;
        e = std::max(e, std::abs(curve(d) - P(d)) / P(0.15));
      }
      return e;
    };
    const double coarse = worst(16), fine = worst(31);
    lgtest::report("exponential curve: 16 rows %.2e, 31 rows %.2e, ratio %.1f", coarse, fine, coarse / fine);
    CHECK(coarse > 12 * fine);
  }
  // Beyond the last row it continues linearly with its end slope.
  {
    const std::string path = writePolynomialCurve(dir, 61);
    std::vector<double> x, y;
    for (int i = 0; i < 61; ++i) {
      x.push_back(0.15 * i / 60);
      y.push_back(polyLoad(x.back()));
    }
    const lg::CurveTable curve(x, y, path);
    const double s = curve.slope(0.15);
    CHECK(curve(0.16) == Approx(curve(0.15) + 0.01 * s).epsilon(1e-14));
    CHECK(curve.integral(0.16) == Approx(curve.integral(0.15) + 0.01 * curve(0.15) + 0.5 * 0.01 * 0.01 * s).epsilon(1e-14));
  }
  // The seed gear on the sampled table against the polynomial tyre.
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  const lg::Scene poly = lgtest::build(doc);
  auto& t = lgtest::element(doc, "force", "tyre");
  t.erase("K");
  t.erase("alpha");
  t.insert_or_assign("law", "table");
  t.insert_or_assign("load_table", writePolynomialCurve(dir, 61));
  const lg::Scene table = lgtest::build(doc);
  for (const char* name : {"limit", "free-drop"}) {
    const auto a = lg::runCase(poly, lgtest::findCase(poly, name)).metrics;
    const auto b = lg::runCase(table, lgtest::findCase(table, name)).metrics;
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    const double worst = lgtest::largestMetricDifference(b, a);
    lgtest::report("tyre table vs polynomial, %s: largest relative difference %.2e, energy balance %.2e", name, worst,
                   b.energy_balance_error);
    CHECK(worst < 1e-12);
    CHECK(b.energy_balance_error < 1e-6);
  }
}

// The power law P_s = K delta_max (delta/delta_max)^m of tyre handbooks: the load, its slope and its
// stored energy against the closed forms (to round-off, 1e-14), the stored energy's derivative in
// delta is the load (central differences, 1e-7).
TEST_CASE("tyre power law: load, slope and energy in closed form", "[tyre][power]") {
  lg::Tyre<double> t = seedTyre();
  t.law = lg::TyreLaw::Power;
  t.exponent = 1.35;
  for (double d : {1e-4, 0.01, 0.05, 0.1, 0.12}) {
    INFO("delta = " << d);
    const double P = 8.0e5 * 0.1 * std::pow(d / 0.1, 1.35);
    CHECK(t.load(d) == Approx(P).epsilon(1e-14));
    CHECK(t.stiffness(d) == Approx(8.0e5 * 1.35 * std::pow(d / 0.1, 0.35)).epsilon(1e-14));
    const OneBody b(0.30 - d);
    const double dd = t.deflection(b.kins());  // d up to the rounding of 0.30 - d
    CHECK(t.stored(b.kins()) == Approx(8.0e5 * 0.01 * std::pow(dd / 0.1, 2.35) / 2.35).epsilon(1e-14));
    const double h = 1e-7;
    const double dE = (t.stored(OneBody(0.30 - d - h).kins()) - t.stored(OneBody(0.30 - d + h).kins())) / (2 * h);
    CHECK(dE == Approx(P).epsilon(1e-7));
  }
  CHECK(t.load(-0.01) == 0.0);
  CHECK(t.load(0.0) == 0.0);
}

// The damped tyre (viscous, q = 0) on a 50 kg wheel meeting the ground at 2 m/s without gravity: the
// closed form of the damped oscillator up to where the tyre would pull (located as an event). The wheel
// leaves at v_out to 1e-9 relative (measured 4e-14 at rtol 1e-11), the tyre's dissipation channel holds
// m (v0^2 - v_out^2)/2 to 1e-9 (measured 3.2e-10), and kinetic + stored + dissipated stays its initial
// value to 1e-9 of the initial kinetic energy (measured 2.3e-10). The balance's error is the channel's:
// a quadrature of c delta'^2 whose local error the step control holds at rtol |D| (1e-11 of 73 J), so
// it falls with rtol (4e-8, 5e-9, 2.3e-10, 7e-11, 1e-12 at rtol 1e-9 ... 1e-13).
TEST_CASE("tyre damping: a bounce against the closed form, energy booked as dissipated", "[tyre][damping]") {
  const lg::Scene sc = lgtest::inlineScene(kBounce);
  REQUIRE(sc.model.nDissipation == 1);
  REQUIRE(sc.model.nForceEvents == 2);
  const BounceClosedForm cf(kM, kK, kC, kV0);
  const auto run = bounce(sc, sc.model);
  lgtest::report("damped bounce: v_out %.15f (closed form %.15f, rel. %.1e), dissipated %.12f J (closed form %.12f J, "
                 "rel. %.1e), energy balance %.1e",
                 run.vOut, cf.vOut, lgtest::relDiff(run.vOut, cf.vOut), run.dissipated, cf.dissipated,
                 lgtest::relDiff(run.dissipated, cf.dissipated), run.energyError);
  CHECK(cf.vOut > 0.5);  // a real bounce, well damped: not the undamped 2 m/s, not stuck
  CHECK(cf.vOut < 1.8);
  CHECK(lgtest::relDiff(run.vOut, cf.vOut) < 1e-9);
  CHECK(lgtest::relDiff(run.dissipated, cf.dissipated) < 1e-9);
  CHECK(run.energyError < 1e-9);
}

// Damping in compression only (damping_direction = "compression"), on the same bounce: while the tyre
// compresses, the damped oscillator, until x' = 0 at t_1, tan(w_d t_1) = w_d / (z w_0), at x_max =
// (v0/w_d) e^(-z w_0 t_1) sin(w_d t_1); then the undamped spring from rest, which returns the wheel at
// v_out = w_0 x_max (no clamp: P_d >= 0). The largest deflection is an event (the damping's kink). And the
// stiffness-following law (damping_law = "stiffness", c_d = 2 zeta sqrt(k_t m)) on this linear tyre is the
// viscous c = 2 zeta sqrt(K m): with zeta, m chosen for c = 1500 N s/m it gives the two closed forms, each
// direction. Rebound speeds to 1e-9 (measured 1e-14 .. 4e-14), energy balance to 1e-9 (measured 2e-10).
namespace {
std::string exact(double x) {
  char buf[40];
  std::snprintf(buf, sizeof buf, "%.17g", x);
  return buf;
}
}  // namespace

TEST_CASE("tyre damping: compression only and the stiffness-following law against closed forms", "[tyre][damping]") {
  const double w0 = std::sqrt(kK / kM), z = kC / (2 * kM * w0), wd = w0 * std::sqrt(1 - z * z);
  const double t1 = std::atan(wd / (z * w0)) / wd;
  const double xMax = kV0 / wd * std::exp(-z * w0 * t1) * std::sin(wd * t1), vCompression = w0 * xMax;
  const double vBoth = BounceClosedForm(kM, kK, kC, kV0).vOut;
  const double zeta = kC / (2 * std::sqrt(kK * kM));
  const std::string power = "c = 1500.0\n", stiffness = "damping_law = \"stiffness\"\ndamping_ratio = " +
                                                          exact(zeta) + "\ndamping_mass = 50.0\n";
  struct Variant {
    const char* what;
    std::string keys;
    double vOut;
    int events;
  };
  for (const Variant& v : {Variant{"power, compression", power + "damping_direction = \"compression\"\n", vCompression, 3},
                           Variant{"stiffness, both", stiffness, vBoth, 2},
                           Variant{"stiffness, compression", stiffness + "damping_direction = \"compression\"\n", vCompression, 3}}) {
    INFO(v.what);
    const lg::Scene sc = lgtest::inlineScene(lgtest::replacedText(kBounce, "c = 1500.0\n", v.keys));
    REQUIRE(sc.model.nForceEvents == v.events);
    const auto run = bounce(sc, sc.model);
    lgtest::report("bounce, %s: v_out %.15f (closed form %.15f, rel. %.1e), energy balance %.1e", v.what, run.vOut, v.vOut,
                   lgtest::relDiff(run.vOut, v.vOut), run.energyError);
    CHECK(lgtest::relDiff(run.vOut, v.vOut) < 1e-9);
    CHECK(run.energyError < 1e-9);
  }
  CHECK(vCompression > vBoth + 0.1);  // (the two directions differ: the recovery is not damped)
}

// Deflection-dependent damping, P_d = c (delta/delta_max)^q delta' with q = 1, against an independent
// reduced model written here: m x'' = -max(k x + c (x/delta_max) x', 0) by RK4 at 2e-7 s until x returns
// to 0 (the clamp's kink costs RK4 its order in one step: error ~ h^2). Rebound speed within 1e-8
// (measured 3.5e-10), dissipation within 1e-8 (measured 5.6e-10), balance within 2e-9 (measured 6.3e-10:
// the dissipation channel's quadrature at rtol 1e-11, as above).
TEST_CASE("tyre damping growing with the deflection against a reduced model", "[tyre][damping]") {
  toml::table doc = toml::parse(kBounce);
  lgtest::element(doc, "force", "tyre").insert_or_assign("damping_exponent", 1.0);
  lgtest::element(doc, "force", "tyre").insert_or_assign("c", 6000.0);
  const lg::Scene sc = lg::buildScene(doc, "inline.toml");
  const auto run = bounce(sc, sc.model);
  // reduced model
  auto acc = [](double x, double v) { return x <= 0 ? 0.0 : -std::max(kK * x + 6000.0 * (x / 0.1) * v, 0.0) / kM; };
  double x = 0, v = kV0;
  const double h = 2e-7;
  for (int i = 0; i < 10000000; ++i) {
    const double k1x = v, k1v = acc(x, v);
    const double k2x = v + h / 2 * k1v, k2v = acc(x + h / 2 * k1x, v + h / 2 * k1v);
    const double k3x = v + h / 2 * k2v, k3v = acc(x + h / 2 * k2x, v + h / 2 * k2v);
    const double k4x = v + h * k3v, k4v = acc(x + h * k3x, v + h * k3v);
    x += h / 6 * (k1x + 2 * k2x + 2 * k3x + k4x);
    v += h / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
    if (x < 0 && v < 0) break;
  }
  const double vOut = -v, diss = kM * (kV0 * kV0 - vOut * vOut) / 2;
  lgtest::report("q = 1 bounce: v_out %.12f (reduced %.12f, rel. %.1e), dissipated %.9f J (reduced %.9f, rel. %.1e), "
                 "balance %.1e",
                 run.vOut, vOut, lgtest::relDiff(run.vOut, vOut), run.dissipated, diss, lgtest::relDiff(run.dissipated, diss),
                 run.energyError);
  CHECK(vOut > 0.5);
  CHECK(vOut < 1.9);
  CHECK(lgtest::relDiff(run.vOut, vOut) < 1e-8);
  CHECK(lgtest::relDiff(run.dissipated, diss) < 1e-8);
  CHECK(run.energyError < 2e-9);
}

// Jet derivatives through the damped bounce against central differences of the closed form's. In contact,
// before any event (t = 10 ms), the wheel's speed: d/dc and d/dK to 1e-10 relative (measured 1.4e-11, 1.3e-11). Through
// the clamp's event, d v_out / dc and d v_out / dK to 2e-8 (measured 1.2e-9 and 8.3e-9): the engine moves the
// state to the event time's derivative along f at the event (it took the dense output's slope before, which
// the step that straddles the kink of the tyre's force fits to both sides of it: 1.5e-6 and 1.1e-5).
TEST_CASE("tyre damping: Jet derivatives of the bounce against the closed form's", "[tyre][damping][jet]") {
  using J = ceres::Jet<double, 2>;
  const lg::Scene sc = lgtest::inlineScene(kBounce);
  lg::Model<J> mj = sc.model.cast<J>();
  auto& tj = std::get<lg::Tyre<J>>(mj.forces[mj.forceIndex("tyre")].type);
  tj.c.v[0] = 1.0;
  tj.K.v[1] = 1.0;
  const auto run = bounce(sc, mj);
  const double hc = 1e-5 * kC, hk = 1e-5 * kK;
  const double dc = (BounceClosedForm(kM, kK, kC + hc, kV0).vOut - BounceClosedForm(kM, kK, kC - hc, kV0).vOut) / (2 * hc);
  const double dk = (BounceClosedForm(kM, kK + hk, kC, kV0).vOut - BounceClosedForm(kM, kK - hk, kC, kV0).vOut) / (2 * hk);
  lgtest::report("bounce Jet: dv/dc %.10e (closed form %.10e, rel. %.1e), dv/dK %.10e (%.10e, rel. %.1e)", run.vOut.v[0], dc,
                 lgtest::relDiff(run.vOut.v[0], dc), run.vOut.v[1], dk, lgtest::relDiff(run.vOut.v[1], dk));
  REQUIRE(std::abs(dc) > 1e-5);
  CHECK(lgtest::relDiff(run.vOut.v[0], dc) < 2e-8);
  CHECK(lgtest::relDiff(run.vOut.v[1], dk) < 2e-8);
  // In contact, before the clamp: v_y(t) = -x'(t) of the damped oscillator.
  auto vIn = [](double k, double c, double t) {
    const double w0 = std::sqrt(k / kM), z = c / (2 * kM * w0), wd = w0 * std::sqrt(1 - z * z);
    return -kV0 * std::exp(-z * w0 * t) * (std::cos(wd * t) - z * w0 / wd * std::sin(wd * t));
  };
  const auto in = bounce(sc, mj, 0.01);
  const double ic = (vIn(kK, kC + hc, 0.01) - vIn(kK, kC - hc, 0.01)) / (2 * hc);
  const double ik = (vIn(kK + hk, kC, 0.01) - vIn(kK - hk, kC, 0.01)) / (2 * hk);
  lgtest::report("in contact at 10 ms: dv/dc %.10e (closed form %.10e, rel. %.1e), dv/dK %.10e (%.10e, rel. %.1e)",
                 in.vOut.v[0], ic, lgtest::relDiff(in.vOut.v[0], ic), in.vOut.v[1], ik, lgtest::relDiff(in.vOut.v[1], ik));
  CHECK(lgtest::relDiff(in.vOut.v[0], ic) < 1e-10);
  CHECK(lgtest::relDiff(in.vOut.v[1], ik) < 1e-10);
}

// The element's derivatives: the damping terms the Rosenbrock-W integrators take (c = dP/d(rate) along
// G) against central differences of the force in the velocity, and the Jet derivatives of the force and
// the stored energy in K, c, the exponents and the state against central differences (1e-7 relative).
TEST_CASE("tyre: damping term and Jet derivatives of force and energy", "[tyre][jet]") {
  using J = ceres::Jet<double, 4>;
  for (const lg::TyreLaw law : {lg::TyreLaw::Polynomial, lg::TyreLaw::Power}) {
    lg::Tyre<double> t = seedTyre();
    t.law = law;
    t.exponent = 1.3;
    t.damped = true;
    t.c = 2500.0;
    t.dampingExponent = 0.5;
    // The force on the wheel along the normal at deflection d and rate v, and the stored energy.
    auto force = [&](const lg::Tyre<double>& tt, double d, double v) {
      OneBody b(0.30 - d);
      b.k[0].v = lg::Vec3<double>(0.0, -v, 0.0);
      std::array<lg::Vec6<double>, 1> w{lg::Vec6<double>::Zero()};
      double diss[1];
      tt.apply(b.kins(), lg::Wrenches<double>{w.data()}, diss);
      return w[0][1];
    };
    for (double d : {0.02, 0.07})
      for (double v : {1.5, -0.3}) {
        INFO("law " << int(law) << ", delta " << d << ", rate " << v);
        OneBody b(0.30 - d);
        b.k[0].v = lg::Vec3<double>(0.0, -v, 0.0);
        lg::DampingTerm<double> dt[1];
        REQUIRE(t.dampingTerms() == 1);
        t.damping(b.kins(), dt);
        const double h = 1e-6;
        const double fd = (force(t, d, v + h) - force(t, d, v - h)) / (2 * h);
        CHECK(dt[0].c == Approx(fd).epsilon(1e-7));
        CHECK(dt[0].Gi.head<3>().dot(b.k[0].v) == Approx(v).epsilon(1e-14));  // G V = delta'
        // k = dP/ddelta (the carcass's stiffness; the damping's share through delta is left to the W-method)
        const double fdK = (t.load(d + h) - t.load(d - h)) / (2 * h);
        CHECK(dt[0].k == Approx(fdK).epsilon(1e-7));
        // Jet: force and energy in K, c, q, and the deflection.
        lg::Tyre<J> tj = t.cast<J>();
        tj.K.v[0] = 1.0;
        tj.c.v[1] = 1.0;
        tj.dampingExponent.v[2] = 1.0;
        std::array<lg::BodyKin<J>, 2> kj{lg::BodyKin<J>::ground(), lg::BodyKin<J>::ground()};
        kj[0].r = lg::Vec3<J>(J(0.1), J(0.30 - d, 3), J(-0.2));
        kj[0].R = b.k[0].R.cast<J>();
        kj[0].v = lg::Vec3<J>(J(0.0), J(-v), J(0.0));
        std::array<lg::Vec6<J>, 1> wj{lg::Vec6<J>::Zero()};
        J dj[1];
        tj.apply(lg::Kins<J>{kj.data(), 1}, lg::Wrenches<J>{wj.data()}, dj);
        const J E = tj.stored(lg::Kins<J>{kj.data(), 1});
        auto fdParam = [&](auto set, double step) {
          lg::Tyre<double> a = t, bb = t;
          set(a, step);
          set(bb, -step);
          return std::pair{(force(a, d, v) - force(bb, d, v)) / (2 * step),
                           (a.stored(OneBody(0.30 - d).kins()) - bb.stored(OneBody(0.30 - d).kins())) / (2 * step)};
        };
        const auto dK = fdParam([](lg::Tyre<double>& x, double s) { x.K += s; }, 1.0);
        const auto dC = fdParam([](lg::Tyre<double>& x, double s) { x.c += s; }, 1e-3);
        const auto dQ = fdParam([](lg::Tyre<double>& x, double s) { x.dampingExponent += s; }, 1e-6);
        const double dDelta = (force(t, d - 1e-8, v) - force(t, d + 1e-8, v)) / 2e-8;  // y = 0.3 - delta
        CHECK(wj[0][1].v[0] == Approx(dK.first).epsilon(1e-7));
        CHECK(wj[0][1].v[1] == Approx(dC.first).epsilon(1e-7));
        CHECK(wj[0][1].v[2] == Approx(dQ.first).epsilon(1e-7));
        CHECK(wj[0][1].v[3] == Approx(dDelta).epsilon(1e-6));
        CHECK(E.v[0] == Approx(dK.second).epsilon(1e-7));
        CHECK(E.a == Approx(t.stored(OneBody(0.30 - d).kins())).epsilon(1e-15));
      }
  }
}

// Every option in a drop: the seed gear with a damped table tyre closes its energy balance in all five
// cases (below 1e-6, as the seed gear does; measured 2.9e-7 at most). (The whole run's dissipated energy
// is no measure of the tyre's damping: the strut's friction leaves each run at another rest state.)
TEST_CASE("tyre from data in the seed gear: energy balance closed in every case", "[tyre][energy]") {
  lgtest::TempDir dir("tyre_energy");
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  auto& t = lgtest::element(doc, "force", "tyre");
  t.erase("K");
  t.erase("alpha");
  t.insert_or_assign("law", "table");
  t.insert_or_assign("load_table", writePolynomialCurve(dir, 61));
  t.insert_or_assign("c", 3000.0);
  t.insert_or_assign("damping_exponent", 0.5);
  const lg::Scene sc = lgtest::build(doc);
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  CHECK(sc.model.nDissipation == seed.model.nDissipation + 1);  // the tyre's damping channel
  const auto results = lg::runCases(sc, sc.cases, 2);
  for (const auto& r : results) {
    const auto& m = r.metrics;
    INFO(m.name << ": " << m.message);
    REQUIRE(m.ok);
    lgtest::report("damped table tyre %-9s peak %.1f N, E_bal %.2e, dissipated %.1f J", m.name.c_str(), m.peak_load_N,
                   m.energy_balance_error, m.energy_dissipated_J);
    CHECK(m.energy_balance_error < 1e-6);
    const auto plain = lg::runCase(seed, lgtest::findCase(seed, m.name)).metrics;
    lgtest::report("   undamped polynomial tyre: peak %.1f N, dissipated %.1f J, rebound %.3f m/s (damped %.3f m/s)",
                   plain.peak_load_N, plain.energy_dissipated_J, plain.rebound_velocity_mps, m.rebound_velocity_mps);
  }
}

TEST_CASE("tyre options: bad input names file, line, key and rule, exit status 2", "[tyre][input]") {
  lgtest::TempDir dir("tyre_bad");
  lgtest::writeFile(dir / "falling.csv", "deflection,load\n0.0,0.0\n0.05,4e4\n0.1,3e4\n0.15,9e4\n");  // (table with K)
  lgtest::writeFile(dir / "short.csv", "deflection,load\n0.0,0.0\n0.02,1e4\n0.04,2e4\n0.06,3e4\n");
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string tyre = "K = 8.0e5                      # [N/m]\n";
  REQUIRE(seed.find(tyre) != std::string::npos);
  auto with = [&](const std::string& extra) { return lgtest::replacedText(seed, tyre, tyre + extra); };
  auto table = [&](const std::string& csv) {
    return lgtest::replacedText(lgtest::replacedText(seed, tyre, "law = \"table\"\nload_table = \"" + csv + "\"\n"),
                                "alpha = 0.5\n", "");
  };
  lgtest::checkBadInputs(
      {
          {"unknown law", with("law = \"cubic\"\n"), "law = \"cubic\"", "force[3].law",
           "value 'cubic' must be \"polynomial\", \"power\" or \"table\""},
          {"power law without its exponent", lgtest::replacedText(with("law = \"power\"\n"), "alpha = 0.5\n", ""), "[[force]]\nname = \"tyre\"", "force[3].exponent",
           "missing"},
          {"power law with alpha", with("law = \"power\"\nexponent = 1.3\n"), "alpha = 0.5", "force[3].alpha",
           "not a parameter of law = \"power\""},
          {"power law exponent below 1", lgtest::replacedText(with("law = \"power\"\nexponent = 0.8\n"), "alpha = 0.5\n", ""),
           "exponent = 0.8", "force[3].exponent", "value 0.8 must be >= 1"},
          {"table with K", lgtest::replacedText(with("law = \"table\"\nload_table = \"falling.csv\"\n"), "alpha = 0.5\n", ""),
           "K = 8.0e5", "force[3].K", "not a parameter of law = \"table\""},
          {"table short of delta_max", table("short.csv"), "load_table", "force[3].load_table",
           "table ends at deflection 0.06 m, before delta_max = 0.1 m"},
          {"missing table", table("no_such.csv"), "load_table", "force[3].load_table", "no such file"},
          {"negative damping", with("c = -10.0\n"), "c = -10.0", "force[3].c", "value -10 must be >= 0"},
          {"damping exponent without damping", with("damping_exponent = 1.0\n"), "damping_exponent = 1.0",
           "force[3].damping_exponent", "needs the damping coefficient c"},
          {"unknown damping law", with("c = 10.0\ndamping_law = \"hydraulic\"\n"), "damping_law", "force[3].damping_law",
           "value 'hydraulic' must be \"power\" (c (delta/delta_max)^q) or \"stiffness\" (2 zeta sqrt(k_t m))"},
          {"stiffness law with c", with("c = 10.0\ndamping_law = \"stiffness\"\n"), "c = 10.0", "force[3].c",
           "not a parameter of damping_law = \"stiffness\" (it uses damping_ratio, damping_mass)"},
          {"stiffness law without its mass", with("damping_law = \"stiffness\"\ndamping_ratio = 0.1\n"),
           "[[force]]\nname = \"tyre\"", "force[3].damping_mass", "missing"},
          {"zero damping ratio", with("damping_law = \"stiffness\"\ndamping_ratio = 0.0\ndamping_mass = 100.0\n"),
           "damping_ratio = 0.0", "force[3].damping_ratio", "must be > 0"},
          {"damping ratio under the power law", with("c = 10.0\ndamping_ratio = 0.1\n"), "damping_ratio = 0.1",
           "force[3].damping_ratio", "a parameter of damping_law = \"stiffness\" (this tyre's damping law is \"power\")"},
          {"unknown damping direction", with("c = 10.0\ndamping_direction = \"rebound\"\n"), "damping_direction",
           "force[3].damping_direction", "value 'rebound' must be \"both\" or \"compression\""},
          {"damping direction without damping", with("damping_direction = \"compression\"\n"), "damping_direction",
           "force[3].damping_direction", "needs a damping law (c, or damping_law = \"stiffness\")"},
          {"friction coefficient too large", with("mu_x = 2.0\n"), "mu_x = 2.0", "force[3].mu_x", "value 2 must be <= 1.5"},
          {"slip ratio without friction", with("slip_ratio = 0.1\n"), "slip_ratio = 0.1", "force[3].slip_ratio",
           "needs the longitudinal friction coefficient mu_x"},
          {"forward off the ground plane", with("mu_x = 0.8\nforward = [1.0, 1.0, 0.0]\n"), "forward = [1.0, 1.0", "force[3].forward",
           "must lie in the ground plane"},
          {"forward speed without a tyre with friction",
           lgtest::replacedText(seed, "sink_speed = 2.0\n", "sink_speed = 2.0\nforward_speed = 60.0\n"), "forward_speed = 60.0",
           "case[0].forward_speed", "no tyre of this scene declares the longitudinal friction coefficient mu_x"},
          {"negative forward speed",
           lgtest::replacedText(with("mu_x = 0.8\n"), "sink_speed = 2.0\n", "sink_speed = 2.0\nforward_speed = -60.0\n"),
           "forward_speed = -60.0", "case[0].forward_speed", "value -60 must be >= 0"},
      },
      dir);
}

// ---- wheel spin-up: the longitudinal force (sim/forces/tyre.hpp) -----------------------------------

namespace {

// A free wheel on its axle (revolute to the ground, no gravity), pressed 20 mm into a belt that moves
// aft at V: the tyre's load P = K delta stays constant and only the wheel's spin moves.
const char* kBelt = R"(
[solver]
integrator = "dopri5"
rtol = 1e-11
atol = 1e-13

[[body]]
name = "wheel"
mass = 20.0
inertia = [0.5, 0.5, 0.8]
position = [0.0, 0.3, 0.0]

[[joint]]
name = "axle"
type = "revolute"
body1 = "wheel"
body2 = "ground"
point = [0.0, 0.3, 0.0]
axis = [0.0, 0.0, 1.0]

[[force]]
name = "tyre"
type = "tyre"
body = "wheel"
radius = 0.3
K = 2.0e5
delta_max = 0.1
alpha = 0.0
mu_x = 0.8
)";

constexpr double kIz = 0.8, kBeltV = 10.0, kMu = 0.8, kPress = 0.02, kKb = 2.0e5;

// The spin-up in closed form. The slip v_s = omega_z h + V (h: the axle's height over the belt) obeys
// I v_s' = -h^2 mu P v_s / sqrt(v_s^2 + eps^2), i.e. v_s' = -a v_s / S with a = mu P h^2 / I, S =
// sqrt(v_s^2 + eps^2), whose solution is F(v_s(t)) = F(V) - a t with F(v) = S - eps ln((eps + S) / v).
// Whatever the slip law, once the wheel rolls (v_s -> 0): the impulse of the drag is I V / h^2, the
// belt's work on the tyre V times it, and half of that is lost in the slip (the other half is the
// wheel's kinetic energy I omega^2 / 2).
struct SpinUp {
  double P = kKb * kPress, h = 0.3 - kPress, eps = 0.05 * kBeltV, a = kMu * P * h * h / kIz;
  double F(double v) const {
    const double S = std::sqrt(v * v + eps * eps);
    return S - eps * std::log((eps + S) / v);
  }
  double timeTo(double v) const { return (F(kBeltV) - F(v)) / a; }
  // d v_s / d a at fixed t, where v_s(t) = v.
  double dvda(double v, double t) const { return -t * v / std::sqrt(v * v + eps * eps); }
};

// The belt scene's model with the belt raised into the tyre and moving at V (any scalar).
template <class S> lg::Model<S> beltModel(const lg::Scene& sc) {
  lg::Model<S> m = sc.model.template cast<S>();
  auto& t = std::get<lg::Tyre<S>>(m.forces[m.forceIndex("tyre")].type);
  t.groundHeight = S(kPress);
  t.groundSpeed = S(kBeltV);
  return m;
}

struct BeltState {
  double vSlip, kinetic, slip, groundWork, energyError;
};
// Runs the belt model from rest to each time in 'ts' (increasing); the slip velocity (any scalar) and,
// for doubles, the energies at each.
template <class S> std::vector<S> beltRun(const lg::Scene& sc, const lg::Model<S>& m, const std::vector<double>& ts,
                                          std::vector<BeltState>* energies = nullptr) {
  lg::State<S> s(m);
  s.y = sc.initial.y.template cast<S>();
  s.active = sc.initial.active;
  lg::Workspace<S> w(m);
  lg::kinematics(m, s.y, w);
  const double E0 = lg::value(lg::energy(m, s, w).total());
  const auto& tyre = std::get<lg::Tyre<S>>(m.forces[m.forceIndex("tyre")].type);
  const int ch = m.nx() + m.nv() + m.dissipationOffset[m.forceIndex("tyre")];
  std::vector<S> out;
  for (double t : ts) {
    REQUIRE(lg::simulate(m, s, w, t).ok);
    REQUIRE(std::abs(lg::value(s.t) - t) < 1e-12);
    lg::kinematics(m, s.y, w);
    out.push_back(tyre.contact(w.kins()).vSlip);
    if (energies) {
      const auto e = lg::energy(m, s, w);
      energies->push_back({lg::value(out.back()), lg::value(e.kinetic), lg::value(s.y[ch]), -lg::value(s.y[ch + 1]),
                           std::abs(lg::value(e.total()) - E0)});
    }
  }
  return out;
}

}  // namespace

// Spin-up of a free wheel on a moving belt (V = 10 m/s, P = 4 kN, mu_x = 0.8, eps = 0.5 m/s) against
// the closed form: the slip velocity at the times the closed form gives for v_s = 5 m/s (mid spin-up)
// and 0.05 m/s (deep in the regularisation's tail) to 1e-10 of V (measured 3.8e-13, 3.3e-12); after
// 0.3 s (rolling): the drag's impulse (the belt's work / V) I V / h^2 = 102.04 N s to 1e-12 relative
// (measured 1.7e-15), the slip's dissipation I V^2 / (2 h^2) = 510.2 J to 1e-11 (measured 1.8e-13) and
// the wheel's kinetic energy to 1e-12 (measured 1.1e-16): half of the belt's work lost, as for Coulomb
// friction; the energy balance (kinetic + slip - belt's work) to 1e-11 of the belt's work (measured 9e-14).
TEST_CASE("tyre spin-up: a free wheel on a moving belt against the closed form", "[tyre][spinup]") {
  const lg::Scene sc = lgtest::inlineScene(kBelt);
  REQUIRE(sc.model.nDissipation == 2);  // slip, belt's work
  REQUIRE(sc.model.nForceEvents == 1);
  const lg::Model<double> m = beltModel<double>(sc);
  const SpinUp cf;
  const double t1 = cf.timeTo(5.0), t2 = cf.timeTo(0.05);
  REQUIRE(t1 > 0.005);
  REQUIRE(t2 < 0.1);
  std::vector<BeltState> e;
  const auto v = beltRun(sc, m, {t1, t2, 0.3}, &e);
  const double J = e[2].groundWork / kBeltV, Jcf = kIz * kBeltV / (cf.h * cf.h);
  const double D = kIz * kBeltV * kBeltV / (2 * cf.h * cf.h);
  lgtest::report("spin-up: v_s(%.6f s) = %.12f (5, err %.1e of V), v_s(%.6f s) = %.12f (0.05, err %.1e of V); after 0.3 s: "
                 "v_s %.2e, impulse %.10f N s (%.10f, rel. %.1e), slip %.9f J (%.9f, rel. %.1e), kinetic %.9f J (rel. %.1e), "
                 "balance %.1e",
                 t1, v[0], std::abs(v[0] - 5.0) / kBeltV, t2, v[1], std::abs(v[1] - 0.05) / kBeltV, v[2], J, Jcf,
                 lgtest::relDiff(J, Jcf), e[2].slip, D, lgtest::relDiff(e[2].slip, D), e[2].kinetic,
                 lgtest::relDiff(e[2].kinetic, D), e[2].energyError / e[2].groundWork);
  CHECK(std::abs(v[0] - 5.0) / kBeltV < 1e-10);
  CHECK(std::abs(v[1] - 0.05) / kBeltV < 1e-10);
  CHECK(std::abs(v[2]) < 1e-10 * kBeltV);
  CHECK(lgtest::relDiff(J, Jcf) < 1e-12);
  CHECK(lgtest::relDiff(e[2].slip, D) < 1e-11);
  CHECK(lgtest::relDiff(e[2].kinetic, D) < 1e-12);
  CHECK(e[2].energyError / e[2].groundWork < 1e-11);
}

// Jet derivatives through the spin-up: d v_s / d mu_x and d v_s / dK at mid spin-up against the closed
// form's (d v_s / da = -t v_s / S, a = mu_x K delta h^2 / I), to 1e-10 relative (measured 7.7e-12).
TEST_CASE("tyre spin-up: Jet derivatives against the closed form", "[tyre][spinup][jet]") {
  using J = ceres::Jet<double, 2>;
  const lg::Scene sc = lgtest::inlineScene(kBelt);
  lg::Model<J> mj = beltModel<J>(sc);
  auto& tj = std::get<lg::Tyre<J>>(mj.forces[mj.forceIndex("tyre")].type);
  tj.muX.v[0] = 1.0;
  tj.K.v[1] = 1.0;
  const SpinUp cf;
  const double t1 = cf.timeTo(5.0);
  const J v = beltRun(sc, mj, {t1})[0];
  const double dv = cf.dvda(5.0, t1);
  const double dmu = dv * cf.P * cf.h * cf.h / kIz, dK = dv * kMu * kPress * cf.h * cf.h / kIz;
  lgtest::report("spin-up Jet: dv/dmu %.10e (closed form %.10e, rel. %.1e), dv/dK %.10e (%.10e, rel. %.1e)", v.v[0], dmu,
                 lgtest::relDiff(v.v[0], dmu), v.v[1], dK, lgtest::relDiff(v.v[1], dK));
  CHECK(lgtest::relDiff(v.v[0], dmu) < 1e-10);
  CHECK(lgtest::relDiff(v.v[1], dK) < 1e-10);
}

// The longitudinal force's damping term (what the Rosenbrock-W integrators take: c_x = dP_x/dv_s along
// G = (t, a_c x t)) against central differences of the force in the wheel's speed, G V = v_s - V to
// round-off, and the Jet derivatives of P_x in mu_x and slip_ratio against central differences (1e-7).
TEST_CASE("tyre spin-up: damping term and Jet derivatives of the drag", "[tyre][spinup][jet]") {
  lg::Tyre<double> t = seedTyre();
  t.longitudinal = true;
  t.muX = 0.8;
  t.groundSpeed = 10.0;
  const double d = 0.03;
  auto drag = [&](const lg::Tyre<double>& tt, double vx, double wz) {
    OneBody b(0.30 - d);
    b.k[0].v = lg::Vec3<double>(vx, 0.0, 0.0);
    b.k[0].w = lg::Vec3<double>(0.0, 0.0, wz);
    std::array<lg::Vec6<double>, 1> w{lg::Vec6<double>::Zero()};
    double diss[2];
    tt.apply(b.kins(), lg::Wrenches<double>{w.data()}, diss);
    return -w[0][0];  // the force on the wheel is -P_x t
  };
  for (double wz : {0.0, -20.0, -35.0, -40.0}) {
    INFO("omega_z " << wz);
    OneBody b(0.30 - d);
    b.k[0].w = lg::Vec3<double>(0.0, 0.0, wz);
    lg::DampingTerm<double> dt[2];  // the vertical term (the carcass's stiffness), then the drag's
    REQUIRE(t.dampingTerms() == 2);
    t.damping(b.kins(), dt);
    const double vs = t.contact(b.kins()).vSlip;
    CHECK(dt[1].Gi.tail<3>().dot(b.k[0].w) == Approx(vs - 10.0).epsilon(1e-14));
    const double h = 1e-5 * std::max(std::abs(vs), 0.5);  // relative to the slip's scale (eps = 0.5 m/s)
    const double fd = (drag(t, h, wz) - drag(t, -h, wz)) / (2 * h);
    CHECK(dt[1].c == Approx(fd).epsilon(1e-7));
    CHECK(dt[1].k == 0.0);
    CHECK(dt[0].c == 0.0);  // undamped
    CHECK(dt[0].k == t.stiffness(t.contact(b.kins()).delta));
    using J = ceres::Jet<double, 2>;
    lg::Tyre<J> tj = t.cast<J>();
    tj.muX.v[0] = 1.0;
    tj.slipRatio.v[1] = 1.0;
    std::array<lg::BodyKin<J>, 2> kj{lg::BodyKin<J>::ground(), lg::BodyKin<J>::ground()};
    kj[0].r = b.k[0].r.cast<J>();
    kj[0].R = b.k[0].R.cast<J>();
    kj[0].w = b.k[0].w.cast<J>();
    const J Px = tj.contact(lg::Kins<J>{kj.data(), 1}).Px;
    auto fdParam = [&](auto set, double step) {
      lg::Tyre<double> a = t, c = t;
      set(a, step);
      set(c, -step);
      return (drag(a, 0, wz) - drag(c, 0, wz)) / (2 * step);
    };
    CHECK(Px.a == Approx(drag(t, 0, wz)).epsilon(1e-15));
    CHECK(Px.v[0] == Approx(fdParam([](lg::Tyre<double>& x, double s) { x.muX += s; }, 1e-6)).epsilon(1e-7));
    CHECK(Px.v[1] == Approx(fdParam([](lg::Tyre<double>& x, double s) { x.slipRatio += s; }, 1e-7)).epsilon(1e-7));
  }
}

// The shipped main gear (data/main_gear.toml: check valve, table tyre, tyre damping, spin-up, fore-aft flexibility) in
// its drop cases: every case within its limits with the energy balance closed below 1e-6 (measured 1.4e-7;
// the ground's work on the tyres in the balance); the drag never above mu_x P_t at any row; the peak
// drag the largest P_x of the histories (refined on the dense output: at least the rows' largest, within
// 1 % of it); spin-up at 60 m/s drags aft, the leg's spring-back then loads it forward (P_x < 0); the
// limit drop without forward speed (not shipped: its nearly Coulomb slip law at eps = 0.05 m/s costs
// ten times the steps) has a drag below 5 % of the spin-up's (the trailing link's rim motion only). The seed gear's histories and summaries have no drag columns (what a scene does not declare
// costs nothing).
TEST_CASE("main gear scene: spin-up and spring-back in the drop cases", "[tyre][spinup][scene]") {
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/main_gear.toml"));
  lg::CaseOptions opt;
  opt.record = true;
  std::vector<lg::DropCase> cases = sc.cases;
  REQUIRE(cases.size() == 2);
  cases.push_back(lgtest::findCase(sc, "limit-spinup"));
  cases.back().name = "limit";
  cases.back().forwardSpeed = 0;
  const auto results = lg::runCases(sc, cases, 2, opt);
  double dragNoSpeed = 0, dragSpinup = 0;
  for (const auto& r : results) {
    const auto& m = r.metrics;
    INFO(m.name << ": " << m.message);
    REQUIRE(m.ok);
    CHECK(m.withinLimits());
    CHECK(m.longitudinal);
    CHECK(m.energy_balance_error < 1e-6);
    CHECK(m.energy_dissipated_J > 0);
    const int px = r.column("P_x"), py = r.column("P_y");
    REQUIRE(px >= 0);
    double rowMax = -1e300, rowMin = 1e300, worstRatio = 0;
    for (const auto& row : r.samples) {
      rowMax = std::max(rowMax, row.values[px]);
      rowMin = std::min(rowMin, row.values[px]);
      if (row.values[py] > 0) worstRatio = std::max(worstRatio, std::abs(row.values[px]) / row.values[py]);
    }
    lgtest::report("main gear %-15s V_x %4.0f m/s: peak P_y %.0f N, drag peak %.1f N at %.4f s (rows' largest %.1f N), "
                   "least P_x %.1f N, |P_x|/P_t <= %.4f, E_bal %.2e, dissipated %.0f J, %ld steps",
                   m.name.c_str(), m.forward_speed_mps, m.peak_load_N, m.drag_peak_N, m.t_drag_peak_s, rowMax, rowMin, worstRatio,
                   m.energy_balance_error, m.energy_dissipated_J, m.steps);
    CHECK(worstRatio <= 0.8 + 1e-12);
    CHECK(m.drag_peak_N >= rowMax);
    CHECK(m.drag_peak_N <= 1.01 * rowMax);
    REQUIRE(m.tyres.size() == 1);
    CHECK(m.tyres[0].drag_max_N == m.drag_peak_N);  // one tyre
    if (m.forward_speed_mps > 0) {
      CHECK(m.drag_peak_N > 0.25 * m.peak_load_N);  // spin-up: a drag of the order of mu_x P_t
      CHECK(rowMin < -0.02 * m.drag_peak_N);        // spring-back
      if (m.name == "limit-spinup") dragSpinup = m.drag_peak_N;
    } else {
      dragNoSpeed = m.drag_peak_N;
    }
  }
  CHECK(dragNoSpeed < 0.05 * dragSpinup);
  // What the seed gear does not declare costs nothing: no drag columns.
  const lg::Scene seed = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  for (const auto& c : lg::historyColumns(seed)) CHECK(c.name != "P_x");
  const auto seedRun = lg::runCase(seed, lgtest::findCase(seed, "limit"));
  CHECK(!seedRun.metrics.longitudinal);
  CHECK(lg::summaryCsv({seedRun}).find("drag") == std::string::npos);
  CHECK(lg::summaryCsv(results).find("drag_peak[N]") != std::string::npos);
}
