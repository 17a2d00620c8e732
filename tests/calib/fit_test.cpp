// The calibration fit (calib/fit.hpp) on synthetic measurements of the seed gear whose true parameters
// are known: noise-free data recovered to round-off, noisy data within the reported uncertainty,
// parameters the data cannot separate reported as such, and the central-difference Jacobian against
// independent derivatives. Run calib_tests -s to see the achieved numbers.
#include "calib_support.hpp"  // project headers, then Catch

#include <cmath>
#include <cstdio>

#include "calib/report.hpp"
#include "calib/residuals.hpp"
#include "sim/drop/run.hpp"

using namespace calibtest;
using lg::calib::FitResult;

namespace {

const std::vector<lg::ParameterOverride> kTruth{{"strut.f1", 7.7e-5}, {"strut.p01", 2.85e6}, {"tyre.K", 8.8e5}};
const std::vector<std::pair<std::string, double>> kTrueValues{
    {"strut.f1", 7.7e-5}, {"strut.p01", 2.85e6}, {"tyre.K", 8.8e5}, {"drop.t_shift", 0.0123}};

// f1, p01 and K fitted from the scene's values (7e-5, 3e6, 8e5), and the touchdown in [0, 0.03] s.
std::string threeParameters() {
  return parameter("strut.f1", 3e-5, 1.6e-4) + parameter("strut.p01", 2e6, 4e6) + parameter("tyre.K", 5e5, 1.2e6);
}

FitResult fitLimitDrop(const TempDir& dir, double noise, std::uint64_t seed, const std::string& parameters) {
  writeFile(dir / "drop.csv", limitCsv(kTruth, 0.0123, noise, seed));
  writeFile(dir / "c.cfg", calibText("drop.csv",
                                     noise > 0 ? "sigma = { P_y = 500.0, s = 2e-4, h = 2e-4 }\nt_shift = \"fit\"\nt_shift_range = [0.0, 0.03]"
                                               : "weights = { P_y = 1e-3, s = 1e3, h = 1e3 }\nt_shift = \"fit\"\nt_shift_range = [0.0, 0.03]",
                                     parameters));
  const lg::calib::Calibration c = lg::calib::loadCalibration(dir / "c.cfg");
  lg::calib::FitOptions o;
  o.threads = 2;
  return lg::calib::runFit(c, o);
}

}  // namespace

TEST_CASE("calibrate: noise-free data give back the true parameters to 1e-11", "[calib][fit]") {
  TempDir dir("exact");
  const FitResult r = fitLimitDrop(dir, 0, 1, threeParameters());
  REQUIRE(r.ident.identifiable);
  CHECK(r.converged);
  double worst = 0;
  for (const auto& [name, truth] : kTrueValues) {
    const double v = r.value[unknown(r, name)];
    const double err = name == "drop.t_shift" ? std::abs(v - truth) / 0.3 : std::abs(v - truth) / truth;
    std::printf("noise-free: %-14s fitted %.12g, true %.12g, relative error %.2g\n", name.c_str(), v, truth, err);
    worst = std::max(worst, err);
  }
  CHECK(worst < 1e-11);  // t_shift relative to the record's 0.3 s (achieved 3e-13)
  CHECK(r.s2 < 1e-12);  // residuals of the weights' unit (1 kN, 1 mm): none left
}

TEST_CASE("calibrate: noisy data are recovered within 3 standard deviations, s^2 near 1", "[calib][fit]") {
  TempDir dir("noisy");
  const FitResult r = fitLimitDrop(dir, 1, 7, threeParameters());
  REQUIRE(r.ident.identifiable);
  REQUIRE(r.covariance);
  CHECK(r.converged);
  for (const auto& [name, truth] : kTrueValues) {
    const std::size_t i = unknown(r, name);
    const double z = (r.value[i] - truth) / r.sd[i];
    std::printf("noisy: %-14s fitted %.8g +- %.3g (95 %% [%.8g, %.8g]), true %.8g: %.2f sd\n", name.c_str(), r.value[i], r.sd[i],
                r.lo[i], r.hi[i], truth, z);
    CHECK(std::abs(z) < 3);
    CHECK(r.lo[i] < r.value[i]);
    CHECK(r.hi[i] > r.value[i]);
    CHECK(r.hi[i] - r.value[i] == Approx(r.t * r.sd[i]).epsilon(1e-12));
  }
  // sigma is the noise the data were made with: the residual variance estimated from the fit is 1 within
  // its own scatter, sqrt(2 / dof) = 0.026.
  std::printf("noisy: s^2 = %.4f with %zu degrees of freedom, t = %.4f\n", r.s2, r.dof, r.t);
  CHECK(std::abs(r.s2 - 1) < 3 * std::sqrt(2.0 / static_cast<double>(r.dof)));
  // Student's t(0.975, dof) by its series in 1/dof around the normal quantile z (Abramowitz & Stegun 26.7.5).
  const double z = 1.959963984540054, nu = static_cast<double>(r.dof);
  const double t = z + (z * z * z + z) / (4 * nu) + (5 * std::pow(z, 5) + 16 * z * z * z + 3 * z) / (96 * nu * nu);
  CHECK(r.t == Approx(t).epsilon(1e-7));
  // A correlation matrix: unit diagonal, symmetric, within [-1, 1].
  for (Eigen::Index i = 0; i < r.corr.rows(); ++i) {
    CHECK(r.corr(i, i) == Approx(1).epsilon(1e-12));
    for (Eigen::Index k = 0; k < r.corr.cols(); ++k) {
      CHECK(r.corr(i, k) == Approx(r.corr(k, i)).epsilon(1e-9));
      CHECK(std::abs(r.corr(i, k)) <= 1 + 1e-12);
    }
  }
  // The fitted histories sit on the data: the residuals' RMS is the noise.
  CHECK(r.measurements[0].statsAfter[0].rms == Approx(500).epsilon(0.06));  // P_y [N]
}

TEST_CASE("calibrate: a robust loss keeps spikes in the data from biasing the fit", "[calib][fit]") {
  // Every 15th load sample from 0.03 s to 0.25 s carries a +20 kN spike (40 sigma). Least squares is
  // pulled off the fit of the same data without spikes; a Cauchy loss at 3 (residuals in sigma) is not.
  const std::string clean = limitCsv(kTruth, 0.0123, 1, 5);
  std::istringstream in(clean);
  std::string spiked, line;
  for (int row = -1; std::getline(in, line); ++row) {
    if (row >= 60 && row <= 500 && row % 15 == 0) {
      const auto a = line.find(','), b = line.find(',', a + 1);
      line = line.substr(0, a + 1) + std::to_string(std::stod(line.substr(a + 1, b - a - 1)) + 2e4) + line.substr(b);
    }
    spiked += line + "\n";
  }
  auto fit = [&](const std::string& csv, const std::string& fitTable) {
    TempDir dir("robust");
    writeFile(dir / "drop.csv", csv);
    writeFile(dir / "c.cfg", calibText("drop.csv", "sigma = { P_y = 500.0, s = 2e-4, h = 2e-4 }\nt_shift = \"fit\"\nt_shift_range = [0.0, 0.03]",
                                       threeParameters() + fitTable));
    lg::calib::FitOptions o;
    o.threads = 2;
    return lg::calib::runFit(lg::calib::loadCalibration(dir / "c.cfg"), o);
  };
  const FitResult reference = fit(clean, ""), plain = fit(spiked, ""), robust = fit(spiked, "[fit]\nloss = \"cauchy\"\nloss_scale = 3.0\n");
  REQUIRE(robust.covariance);
  double worstPlain = 0, worstRobust = 0;
  for (std::size_t i = 0; i < reference.names.size(); ++i) {
    // Against the clean fit, in its standard deviations.
    const double zp = (plain.value[i] - reference.value[i]) / reference.sd[i];
    const double zr = (robust.value[i] - reference.value[i]) / reference.sd[i];
    std::printf("spikes: %-14s least squares %+.2f sd, Cauchy %+.2f sd off the fit without spikes; sd %.3g / %.3g\n",
                reference.names[i].c_str(), zp, zr, robust.sd[i], reference.sd[i]);
    worstPlain = std::max(worstPlain, std::abs(zp));
    worstRobust = std::max(worstRobust, std::abs(zr));
    // The robust fit's uncertainty is the clean data's (its s^2 is estimated robustly), not inflated.
    CHECK(robust.sd[i] == Approx(reference.sd[i]).epsilon(0.1));
  }
  std::printf("spikes: s^2 least squares %.3g, Cauchy %.3g, without spikes %.3g\n", plain.s2, robust.s2, reference.s2);
  CHECK(worstPlain > 3);
  CHECK(worstRobust < 0.5);
  CHECK(std::abs(robust.s2 - 1) < 0.1);
}

TEST_CASE("calibrate: an orifice area fitted with its loss coefficient is reported as not identifiable", "[calib][fit]") {
  TempDir dir("xi1");
  const FitResult r =
      fitLimitDrop(dir, 1, 3, parameter("strut.f1", 3e-5, 1.6e-4) + parameter("strut.xi1", 0.5, 4) + parameter("strut.p01", 2e6, 4e6) +
                                  parameter("tyre.K", 5e5, 1.2e6));
  std::printf("f1 with xi1: %s\n", r.ident.message.c_str());

  CHECK_FALSE(r.ident.identifiable);
  REQUIRE(r.ident.involved.size() == 2);
  CHECK(r.names[r.ident.involved[0]] == "strut.f1");
  CHECK(r.names[r.ident.involved[1]] == "strut.xi1");
  CHECK(r.ident.message.find("strut.f1 and strut.xi1") != std::string::npos);
  // The null direction: xi1 / f1^2 unchanged, i.e. +1 % of xi1 with +0.5 % of f1.
  CHECK(r.ident.message.find("+0.5 % strut.f1 with +1 % strut.xi1") != std::string::npos);
  CHECK(r.ident.rcond < 1e-6);
  CHECK_FALSE(r.covariance);
  CHECK(std::isnan(r.sd[0]));
  // What the data do determine, xi1 / f1^2, is the truth's (1.6 / 7.7e-5^2) within the noise.
  const double q = r.value[1] / (r.value[0] * r.value[0]), qTrue = 1.6 / (7.7e-5 * 7.7e-5);
  std::printf("f1 with xi1: xi1/f1^2 = %.6g, true %.6g\n", q, qTrue);
  CHECK(q == Approx(qTrue).epsilon(2e-3));
}

TEST_CASE("calibrate: the two orifices of the seed gear's strut are not identifiable together", "[calib][fit]") {
  // Both orifices act in both directions in this model: the drop sees xi1 F^3/f1^2 + xi2 F2^3/f2^2 only.
  // The exact Jacobian finds the columns proportional to round-off; the central differences to their own
  // error, not to round-off: the test of the Jacobian's error (a second Jacobian with twice the steps)
  // names them.
  for (const bool exact : {true, false}) {
    TempDir dir(exact ? "f2x" : "f2c");
    const FitResult r = fitLimitDrop(dir, 1, 3,
                                     parameter("strut.f1", 3e-5, 1.6e-4) + parameter("strut.f2", 2e-5, 1e-4) +
                                         parameter("strut.p01", 2e6, 4e6) + parameter("tyre.K", 5e5, 1.2e6) +
                                         (exact ? "" : "[fit]\njacobian = \"central\"\n"));
    std::printf("f1 with f2 (%s): smallest singular value %.3g of the largest, limit %.3g\n", exact ? "exact" : "central",
                r.ident.rcond, r.ident.limit);
    CHECK_FALSE(r.ident.identifiable);
    REQUIRE(r.ident.involved.size() == 2);
    CHECK(r.names[r.ident.involved[0]] == "strut.f1");
    CHECK(r.names[r.ident.involved[1]] == "strut.f2");
    if (exact) CHECK(r.ident.rcond < 1e-13);  // round-off: the columns are proportional
    if (exact) CHECK(r.ident.limit == 1e-6);  // the threshold alone: an exact Jacobian has no error to add
  }
}

TEST_CASE("calibrate: the central-difference Jacobian against independent derivatives", "[calib][jacobian]") {
  TempDir dir("jac");
  writeFile(dir / "drop.csv", limitCsv(kTruth, 0.0123, 0, 1));
  writeFile(dir / "c.cfg", calibText("drop.csv", "weights = { P_y = 1e-3, s = 1e3, h = 1e3 }\nt_shift = \"fit\"\nt_shift_range = [0.0, 0.03]",
                                     parameter("strut.f1", 3e-5, 1.6e-4) + parameter("strut.xi1", 0.5, 4)));
  const lg::calib::Calibration c = lg::calib::loadCalibration(dir / "c.cfg");
  lg::calib::Point p = lg::calib::initialPoint(c);
  p.shift[0] = 0.0123;
  std::vector<lg::calib::MeasurementEval> e;
  lg::calib::CentralDifferences(c, 2).evaluate(p, true, e);
  REQUIRE(e[0].ok);
  // (1) xi1 and f1 enter only as xi1 / f1^2: f1 dr/df1 = -2 xi1 dr/dxi1, exactly for the model.
  const Eigen::VectorXd a = e[0].J.col(0) * p.x[0], b = -2 * e[0].J.col(1) * p.x[1];
  const double pair = (a - b).norm() / a.norm();
  std::printf("Jacobian: f1 dr/df1 against -2 xi1 dr/dxi1: %.3g of its norm\n", pair);
  CHECK(pair < 5e-6);
  // (2) The t_shift column of the stroke channel is -w ds/dt at t - t_shift, the model's own stroke rate
  // (the strut's s_dot output on the dense output, a state velocity, not a difference).
  const lg::calib::Measurement& m = c.measurements[0];
  int sChannel = -1;
  for (std::size_t k = 0; k < m.channels.size(); ++k)
    if (m.channels[k].name == "s") sChannel = static_cast<int>(k);
  REQUIRE(sChannel == 2);  // P_y, h, s: the residuals are P_y's, h's, then s's
  lg::CaseOptions opt;
  opt.record = true;
  for (double t : m.t)
    if (t - p.shift[0] > 0) opt.outputTimes.push_back(t - p.shift[0]);
  lg::Scene design;
  REQUIRE_FALSE(lg::calib::designScene(c, p.x, design));
  const lg::CaseResult run = lg::runCase(design, m.dropCase, opt);
  const int sdot = run.column("s_dot");
  const std::size_t n = m.t.size(), before = n - opt.outputTimes.size();
  double worst = 0, big = 0;
  for (std::size_t i = before; i < n; ++i) {
    const double exact = -1e3 * run.samples[i - before].values[static_cast<std::size_t>(sdot)];
    const double fd = e[0].Jshift[static_cast<Eigen::Index>(2 * n + i)];
    worst = std::max(worst, std::abs(fd - exact));
    big = std::max(big, std::abs(exact));
  }
  std::printf("Jacobian: dr/dt_shift of the stroke against -w s_dot: %.3g of its largest\n", worst / big);
  CHECK(worst / big < 1e-5);
  // Before touchdown the stroke does not move: zero columns there.
  for (std::size_t i = 0; i < before; ++i) CHECK(e[0].Jshift[static_cast<Eigen::Index>(2 * n + i)] == 0);
}

TEST_CASE("calibrate: a scene case's own parameter (its sink speed) fitted through the scene, a known t_shift", "[calib][fit]") {
  // The rig dropped at 2.97 m/s where the scene's limit case says 3.05, its clock 4 ms ahead of the
  // touchdown (known): the fit finds the sink speed, and calibrated.toml's limit case carries it.
  TempDir dir("sink");
  lg::calib::SyntheticSpec spec;
  spec.dropCase = seedGear().cases[2];
  REQUIRE(spec.dropCase.name == "limit");
  spec.dropCase.sinkSpeed = 2.97;
  spec.channels = {{"P_y", "Fz_N", 0}, {"s", "stroke_m", 0}};
  spec.end = 0.3;
  spec.touchdown = 0.004;
  writeFile(dir / "drop.csv", lg::calib::syntheticCsv(seedGear(), spec));
  writeFile(dir / "c.cfg", "scene = \"" + sourcePath("data/seed_gear.toml") +
                               "\"\n[[measurement]]\nfile = \"drop.csv\"\ncase = \"limit\"\ncolumns = { t = \"time_s\", P_y = "
                               "\"Fz_N\", s = \"stroke_m\" }\nweights = { P_y = 1e-3, s = 1e3 }\nt_shift = 0.004\n" +
                               parameter("limit.sink_speed", 2.5, 3.5));
  const lg::calib::Calibration c = lg::calib::loadCalibration(dir / "c.cfg");
  lg::calib::FitOptions o;
  o.threads = 2;
  const FitResult r = lg::calib::runFit(c, o);
  REQUIRE(r.ident.identifiable);
  std::printf("sink speed: fitted %.12g m/s, true 2.97, relative error %.2g\n", r.value[0], std::abs(r.value[0] - 2.97) / 2.97);
  CHECK(std::abs(r.value[0] - 2.97) / 2.97 < 1e-6);
  CHECK(r.names.size() == 1);  // a known t_shift is no unknown
  const std::string toml = lg::calib::calibratedToml(c, r, dir / "out");
  const lg::Scene cal = lg::parseScene(toml, "calibrated.toml");  // its header comments included
  CHECK(cal.cases[2].sinkSpeed == r.value[0]);
  CHECK(cal.cases.size() == seedGear().cases.size());  // a scene case: nothing added
}
