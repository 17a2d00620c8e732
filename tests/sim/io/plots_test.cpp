// The case figure's data (sim/io/plots.cpp): the strut's work diagram keeps its return stroke down to full
// extension where Coulomb friction holds the strut at its turn (s stands still there to round-off, which
// once cut the return); the reserve drop's figure draws the ultimate load, not the limit load.
#include "../scene_support.hpp"  // sim headers, then Catch (see there)

#include "sim/drop/certification.hpp"
#include "sim/io/compliance.hpp"
#include "sim/io/plots.hpp"

namespace {

// A scene's case run with its histories and drawn (data and script, no gnuplot) into dir as 'stem'.
lg::CaseResult drawCase(const lg::Scene& sc, const std::string& name, const lgtest::TempDir& dir, const std::string& stem) {
  lg::CaseOptions opt;
  opt.record = true;
  lg::CaseResult r = lg::runCase(sc, lgtest::findCase(sc, name), opt);
  REQUIRE(r.metrics.ok);
  lg::CaseFigure f;
  f.title = name;
  f.run = &r;
  f.limits = lg::sceneLimits(sc);
  f.drawElementsOf(sc);
  REQUIRE(lg::drawCaseFigure(f, dir.path.string(), stem, false, nullptr));
  return r;
}

}  // namespace

TEST_CASE("plots: the seed limit drop's strut work diagram returns to full extension", "[plots]") {
  const lgtest::TempDir dir("plots");
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  const lg::CaseResult r = drawCase(sc, "limit", dir, "limit");
  std::istringstream in(lgtest::readFile(dir / "limit.dat"));
  int returnRows = 0;
  double lowest = 1, turn = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream l(line);
    double t, h, Py, s, Pa, delta;
    int gear, strut;
    l >> t >> h >> Py >> s >> Pa >> delta >> gear >> strut;
    if (strut == 0) turn = std::max(turn, s);
    if (strut == 1) {
      ++returnRows;
      lowest = std::min(lowest, s);
    }
  }
  CHECK(turn == Approx(r.metrics.stroke_max_m).epsilon(1e-3));
  CHECK(returnRows > 50);
  CHECK(lowest < 1e-6);  // down to full extension
  // the reserve drop's figure: the ultimate load drawn, the limit load (no limit of it) not
  const lg::Certification& c = *sc.certification;
  lg::CaseVerdict v;
  v.role = "certification";
  v.cert = *c.findCase("cert-reserve");
  const lg::PlotLimits l = lg::compliancePlotLimits(sc, c, v);
  CHECK(std::isnan(l.loadLimit));
  CHECK(l.loadUltimate == Approx(1.5 * 2.5 * 4050 * 9.80665).epsilon(1e-14));
  v.cert = *c.findCase("cert-limit-landing");
  CHECK(lg::compliancePlotLimits(sc, c, v).loadLimit == Approx(2.5 * 4050 * 9.80665).epsilon(1e-14));
}

TEST_CASE("plots: a spin-up drop's figure has its drag panel with spin-up and spring-back marked", "[plots][tyre]") {
  const lgtest::TempDir dir("plots_drag");
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/main_gear.toml"));
  const lg::CaseResult r = drawCase(sc, "limit-spinup", dir, "spinup");
  const std::string gp = lgtest::readFile(dir / "spinup.gp");
  CHECK(gp.find("set multiplot layout 4,2") != std::string::npos);
  CHECK(gp.find("drag load P_x(t): wheel spin-up and spring-back") != std::string::npos);
  char mark[80];
  std::snprintf(mark, sizeof mark, "title 'spin-up %.0f N'", std::round(r.metrics.drag_peak_N));
  CHECK(gp.find(mark) != std::string::npos);
  CHECK(gp.find("title 'spring-back ") != std::string::npos);
}
