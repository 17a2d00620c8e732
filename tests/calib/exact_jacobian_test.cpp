// The exact Jacobian of a calibration's residuals (calib/exact_jacobian.hpp): against central
// differences of the same residuals at a tight tolerance (every column: model parameters, a scene case's
// sink speed that also moves the free fall before touchdown, and t_shift), against identities of the
// model that hold exactly (an orifice area and its loss coefficient enter only as xi1 / f1^2), and its
// t_shift column against the model's own stroke rate. Run calib_tests -s to see the achieved numbers.
#include "calib_support.hpp"  // project headers, then Catch

#include <cmath>
#include <cstdio>

#include "calib/exact_jacobian.hpp"
#include "calib/residuals.hpp"
#include "sim/drop/run.hpp"

using namespace calibtest;

namespace {

const std::vector<lg::ParameterOverride> kTruth{{"strut.f1", 7.7e-5}, {"strut.p01", 2.85e6}, {"tyre.K", 8.8e5}};

// Column j of J against column j of R, relative to the column's norm.
double columnError(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / a.norm(); }

}  // namespace

TEST_CASE("exact Jacobian: every column against central differences at a tight tolerance", "[calib][jacobian]") {
  // The scene's limit case (so that its sink speed is a parameter of the drop), samples from 12.3 ms
  // before touchdown (the free fall: h's columns carry t_s and the shift's -(V + (1 - L) g t_s)).
  TempDir dir("exact_vs_central");
  writeFile(dir / "drop.csv", limitCsv(kTruth, 0.0123, 0, 1));
  writeFile(dir / "c.cfg", "scene = \"" + sourcePath("data/seed_gear.toml") +
                               "\"\n[solver]\nintegrator = \"dopri5\"\nrtol = 1e-10\natol = 1e-12\n"
                               "[[measurement]]\nfile = \"drop.csv\"\ncase = \"limit\"\n"
                               "columns = { t = \"time_s\", P_y = \"Fz_N\", s = \"stroke_m\", h = \"travel_m\" }\n"
                               "weights = { P_y = 1e-3, s = 1e3, h = 1e3 }\nt_shift = \"fit\"\nt_shift_range = [0.0, 0.03]\n" +
                               parameter("strut.f1", 3e-5, 1.6e-4) + parameter("strut.p01", 2e6, 4e6) +
                               parameter("tyre.K", 5e5, 1.2e6) + parameter("limit.sink_speed", 2.5, 3.5));
  const lg::calib::Calibration c = lg::calib::loadCalibration(dir / "c.cfg");
  lg::calib::Point p = lg::calib::initialPoint(c);
  p.shift[0] = 0.0123;
  std::vector<lg::calib::MeasurementEval> exact, central;
  lg::calib::ExactDerivatives(c, 2).evaluate(p, true, exact);
  lg::calib::CentralDifferences(c, 2).evaluate(p, true, central);
  REQUIRE(exact[0].ok);
  REQUIRE(central[0].ok);
  CHECK(exact[0].r == central[0].r);  // the residuals: the same double run, bit for bit
  double worst = 0;
  for (Eigen::Index j = 0; j < exact[0].J.cols(); ++j) {
    const double e = columnError(exact[0].J.col(j), central[0].J.col(j));
    std::printf("exact Jacobian: %-18s column within %.2g of the central differences\n", c.parameters[j].path.c_str(), e);
    CHECK(e < 1e-6);
    worst = std::max(worst, e);
  }
  const double es = columnError(exact[0].Jshift, central[0].Jshift);
  std::printf("exact Jacobian: t_shift            column within %.2g of the central differences\n", es);
  CHECK(es < 1e-6);
  // Before touchdown (the first 24 samples of each channel): h's sink-speed column is w t_s, its shift
  // column -w (V + (1 - L) g t_s), exactly.
  const lg::calib::Measurement& m = c.measurements[0];
  const std::size_t n = m.t.size();
  std::size_t hChannel = 0;
  for (std::size_t k = 0; k < m.channels.size(); ++k)
    if (m.channels[k].name == "h") hChannel = k;
  const double g = c.scene.gravity, L = m.dropCase.liftRatio, V = m.dropCase.sinkSpeed;
  int before = 0;
  for (std::size_t i = 0; i < n && m.t[i] - p.shift[0] <= 0; ++i, ++before) {
    const double ts = m.t[i] - p.shift[0];
    const Eigen::Index row = static_cast<Eigen::Index>(hChannel * n + i);
    CHECK(exact[0].J(row, 3) == Approx(1e3 * ts).margin(1e-12));  // the touchdown row's own dh/dV is 0
    CHECK(exact[0].Jshift[row] == Approx(-1e3 * (V + (1 - L) * g * ts)).epsilon(1e-14));
  }
  CHECK(before == 25);
  std::printf("exact Jacobian: %d samples before touchdown with the free fall's closed-form columns\n", before);
}

TEST_CASE("exact Jacobian: an area and its loss coefficient, and the t_shift column against the stroke rate",
          "[calib][jacobian]") {
  TempDir dir("exact_identities");
  writeFile(dir / "drop.csv", limitCsv(kTruth, 0.0123, 0, 1));
  writeFile(dir / "c.cfg", calibText("drop.csv", "weights = { P_y = 1e-3, s = 1e3, h = 1e3 }\nt_shift = \"fit\"\nt_shift_range = [0.0, 0.03]",
                                     parameter("strut.f1", 3e-5, 1.6e-4) + parameter("strut.xi1", 0.5, 4)));
  const lg::calib::Calibration c = lg::calib::loadCalibration(dir / "c.cfg");
  lg::calib::Point p = lg::calib::initialPoint(c);
  p.shift[0] = 0.0123;
  std::vector<lg::calib::MeasurementEval> e;
  lg::calib::ExactDerivatives(c, 1).evaluate(p, true, e);
  REQUIRE(e[0].ok);
  // (1) xi1 and f1 enter only as xi1 / f1^2: f1 dr/df1 = -2 xi1 dr/dxi1 for the run as computed, to
  // round-off (central differences reach 2e-6 here).
  const Eigen::VectorXd a = e[0].J.col(0) * p.x[0], b = -2 * e[0].J.col(1) * p.x[1];
  const double pair = (a - b).norm() / a.norm();
  std::printf("exact Jacobian: f1 dr/df1 against -2 xi1 dr/dxi1: %.3g of its norm\n", pair);
  CHECK(pair < 1e-13);
  // (2) The stroke's t_shift column is -w ds/dt along the dense output; the strut's s_dot output is the
  // model's velocity: they differ by the interpolant's error only.
  const lg::calib::Measurement& m = c.measurements[0];
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
    const double model = -1e3 * run.samples[i - before].values[static_cast<std::size_t>(sdot)];
    worst = std::max(worst, std::abs(e[0].Jshift[static_cast<Eigen::Index>(2 * n + i)] - model));
    big = std::max(big, std::abs(model));
  }
  std::printf("exact Jacobian: dr/dt_shift of the stroke against -w s_dot: %.3g of its largest\n", worst / big);
  CHECK(worst / big < 5e-6);
  for (std::size_t i = 0; i < before; ++i) CHECK(e[0].Jshift[static_cast<Eigen::Index>(2 * n + i)] == 0);
}
