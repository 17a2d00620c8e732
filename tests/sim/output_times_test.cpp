// Rows at listed output times (CaseOptions::outputTimes, sim/drop/case.hpp): a measurement's samples
// taken on the integrator's dense output, the run itself unchanged.
#include "scene_support.hpp"  // sim headers, then Catch (see there)

#include <algorithm>
#include <cstdio>

namespace {

const lg::Scene& seedScene() {
  static const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  return sc;
}

lg::CaseResult runWith(const lg::CaseOptions& opt) {
  return lg::runCase(seedScene(), lgtest::findCase(seedScene(), "limit"), opt);
}

}  // namespace

TEST_CASE("output times: rows at exactly the listed times, the run unchanged", "[drop_test][output]") {
  lg::CaseOptions plain;
  const lg::CaseResult ref = runWith(plain);
  REQUIRE(ref.metrics.ok);

  // Irregular times (a rig's jittery clock), not starting at 0, through touchdown, the peak and rebound.
  lg::CaseOptions listed;
  listed.record = true;
  for (double t = 0.00037; t < 0.8; t += 0.0031 + 0.0007 * std::sin(1e3 * t)) listed.outputTimes.push_back(t);
  listed.outputTimes.push_back(0.8);
  const lg::CaseResult r = runWith(listed);
  REQUIRE(r.metrics.ok);
  REQUIRE(r.samples.size() == listed.outputTimes.size());
  for (size_t k = 0; k < r.samples.size(); ++k) CHECK(r.samples[k].t == listed.outputTimes[k]);
  // the same run: steps and metrics bit for bit
  CHECK(r.metrics.steps == ref.metrics.steps);
  CHECK(r.metrics.rhs_evaluations == ref.metrics.rhs_evaluations);
  CHECK(r.metrics.peak_load_N == ref.metrics.peak_load_N);
  CHECK(r.metrics.stroke_max_m == ref.metrics.stroke_max_m);
  CHECK(r.metrics.energy_balance_error == ref.metrics.energy_balance_error);
}

TEST_CASE("output times: the rows of a uniform list are those of outputInterval, bit for bit", "[drop_test][output]") {
  lg::CaseOptions uniform;
  uniform.record = true;
  uniform.outputInterval = 0.002;
  lg::CaseOptions listed;
  listed.record = true;
  for (long k = 0; k <= 400; ++k) listed.outputTimes.push_back(static_cast<double>(k) * 0.002);
  const lg::CaseResult a = runWith(uniform), b = runWith(listed);
  REQUIRE(a.samples.size() == 401);
  REQUIRE(b.samples.size() == 401);
  for (size_t k = 0; k < a.samples.size(); ++k) {
    CHECK(a.samples[k].t == b.samples[k].t);
    CHECK(a.samples[k].values == b.samples[k].values);
  }
  // Without t = 0 in the list there is no row at t = 0.
  listed.outputTimes.erase(listed.outputTimes.begin());
  const lg::CaseResult c = runWith(listed);
  REQUIRE(c.samples.size() == 400);
  CHECK(c.samples[0].t == 0.002);
  CHECK(c.samples[0].values == a.samples[1].values);
}

TEST_CASE("output times: rows at step ends equal the step rows to the dense output's round-off",
          "[drop_test][output]") {
  lg::CaseOptions steps;
  steps.record = true;
  const lg::CaseResult a = runWith(steps);
  REQUIRE(a.samples.size() > 100);
  lg::CaseOptions listed;
  listed.record = true;
  std::vector<size_t> picked;
  // A step that ends on an event (a stop engaging or letting go, a strut sticking or breaking away) has
  // a row after the jump (plastic impact, projection, the new mode's forces), while the dense output
  // gives the left limit there: such rows are not compared.
  const int sdot = a.column("s_dot"), fExt = a.column("F_extension"), fBot = a.column("F_bottoming");
  REQUIRE(std::min({sdot, fExt, fBot}) >= 0);
  auto mode = [&](size_t k) {
    const auto& v = a.samples[k].values;
    return (v[fExt] != 0) + 2 * (v[fBot] != 0) + 4 * (std::abs(v[sdot]) < 1e-9);
  };
  int skipped = 0;
  for (size_t k = 1; k < a.samples.size(); k += 7) {
    if (mode(k) != mode(k - 1)) {
      ++skipped;
      continue;
    }
    picked.push_back(k);
    listed.outputTimes.push_back(a.samples[k].t);
  }
  CHECK(skipped <= 3);
  const lg::CaseResult b = runWith(listed);
  REQUIRE(b.samples.size() == picked.size());
  // Each column against its largest magnitude: the dense output at a step's end is the step's end state
  // up to round-off (and up to a projection onto the constraints there, below its tolerance).
  const int h = a.column("h"), Py = a.column("P_y"), s = a.column("s"), pa = a.column("P_a");
  double worst = 0;
  for (int c : {h, Py, s, pa}) {
    double big = 0;
    for (const auto& x : a.samples) big = std::max(big, std::abs(x.values[c]));
    for (size_t i = 0; i < picked.size(); ++i)
      worst = std::max(worst, std::abs(b.samples[i].values[c] - a.samples[picked[i]].values[c]) / big);
  }
  std::printf("output times at step ends: worst difference %.3g of the column's largest value\n", worst);
  CHECK(worst < 1e-9);
}

TEST_CASE("output times: a list that does not increase within [0, duration] is refused", "[drop_test][output]") {
  lg::CaseOptions o;
  o.record = true;
  o.outputTimes = {0.0, 0.2, 0.1};
  CHECK_THROWS_AS(runWith(o), std::invalid_argument);
  o.outputTimes = {0.1, 0.1};
  CHECK_THROWS_AS(runWith(o), std::invalid_argument);
  o.outputTimes = {-0.001, 0.1};
  CHECK_THROWS_AS(runWith(o), std::invalid_argument);
  o.outputTimes = {0.1, 0.9};  // the limit case runs 0.8 s
  CHECK_THROWS_AS(runWith(o), std::invalid_argument);
  o.outputTimes = {0.1, std::numeric_limits<double>::quiet_NaN()};
  CHECK_THROWS_AS(runWith(o), std::invalid_argument);
}

// A row inside a step that ends with an event takes the step's contact mode, not the one the event
// leaves: the extension stop holds the strut (its force > 0) at every row before its release and at none
// after; the bottoming stop carries no force before the impact. (Rows once took the mode after the
// step's event: those of the last step before the release showed F_extension = 0 while the stop held.)
TEST_CASE("output times: a row before an event in the same step has the step's contact mode", "[drop_test][output][events]") {
  auto check = [](const lg::Scene& sc, const lg::DropCase& c, const std::string& column, bool heldFirst) {
    lg::CaseOptions steps;
    steps.record = true;
    const lg::CaseResult per = lg::runCase(sc, c, steps);
    const int col = per.column(column);
    REQUIRE(col >= 0);
    // The event: the first step end where the stop's force switches (released or engaged).
    double te = -1;
    for (size_t k = 1; k < per.samples.size() && te < 0; ++k)
      if ((per.samples[k].values[col] != 0) != heldFirst) te = per.samples[k].t;
    REQUIRE(te > 0);
    lg::CaseOptions dense;
    dense.record = true;
    for (int k = 1; k <= 400; ++k) dense.outputTimes.push_back(te * (k / 400.0) * 1.2);
    const lg::CaseResult r = lg::runCase(sc, c, dense);
    REQUIRE(r.samples.size() == dense.outputTimes.size());
    int before = 0, after = 0;
    for (const auto& row : r.samples) {
      const bool held = row.values[col] != 0;
      if (row.t < te) {
        CHECK(held == heldFirst);
        ++before;
      } else if (row.t > te) {
        CHECK(held != heldFirst);
        ++after;
      }
    }
    CHECK(before > 300);
    CHECK(after > 50);
    std::printf("output times: %s %s at t = %.6f s; %d rows before, %d after, each in its step's mode\n", column.c_str(),
                heldFirst ? "released" : "engaged", te, before, after);
  };
  check(seedScene(), lgtest::findCase(seedScene(), "limit"), "F_extension", true);
  toml::table doc = lgtest::shippedDoc("data/seed_gear.toml");
  lgtest::element(doc, "force", "strut").insert_or_assign("Omega0", 1.6e-3);
  lgtest::element(doc, "force", "strut").insert_or_assign("p01", 1.0e6);
  const lg::Scene bottoming = lgtest::build(doc);
  lg::DropCase c = lgtest::findCase(bottoming, "reserve");
  c.liftRatio = 0;
  check(bottoming, c, "F_bottoming", false);
}
