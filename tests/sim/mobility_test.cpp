// A body's prismatic or fixed joint to the ground, eliminated into the body's mobility (Model::finalize,
// BodyKin::invMassTimes) instead of being enforced by its rows: the same motion, with fewer rows.
#include "tests/sim/engine_support.hpp"  // sim headers, then Catch (see there)
#include "tests/sim/bad_input_support.hpp"
#include "tests/sim/scene_support.hpp"

TEST_CASE("a guide to the ground eliminated into the body's mobility gives the motion of its rows",
          "[engine][mobility]") {
  for (const char* file : {"data/seed_gear.toml", "data/telescopic_gear.toml"}) {
    toml::table doc = lgtest::shippedDoc(file);
    doc["solver"].as_table()->insert_or_assign("rtol", 1e-9);
    doc["solver"].as_table()->insert_or_assign("atol", 1e-11);
    const lg::Scene eliminated = lgtest::build(doc);
    lg::Scene rows = eliminated;
    rows.model.settings.eliminateGroundJoints = false;
    rows.model.finalize();
    rows.initial = lg::State<double>(rows.model);
    rows.initial.y = eliminated.initial.y;
    INFO(file);
    CHECK(rows.model.nRows == eliminated.model.nRows + 5);  // the rig's prismatic joint
    const auto a = lg::runCase(eliminated, lgtest::findCase(eliminated, "limit")).metrics;
    const auto b = lg::runCase(rows, lgtest::findCase(rows, "limit")).metrics;
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    const double worst = lgtest::largestMetricDifference(a, b);
    lgtest::report("%s: eliminated rig (%d rows) against its rows (%d rows): largest relative difference %.1e",
                   file, eliminated.model.nRows, rows.model.nRows, worst);
    // Measured 3e-11 (seed gear), 0 (telescopic gear): the two runs differ by round-off from the start (other
    // rows, other sums), which moves the located stick/slip events by about 1e-12 s.
    CHECK(worst < 1e-10);
    CHECK(a.energy_balance_error < 1e-6);
  }
}

// A planar model ([scene] plane_normal; Mobility kPlanar, impliedPlanarRows): every body translates in the
// plane and rotates about its normal, and the joints' rows that such motions satisfy by themselves are not
// solved. The 3-D run of the same scene is the reference: its motion stays in the plane up to round-off
// and the loose steps' drift (out of the plane, which a planar model cannot drift into).
namespace {
lg::Scene spatial(const lg::Scene& planar) {  // (the same scene, its model rebuilt in space)
  lg::Scene s = planar;
  s.model.settings.planeNormal.setZero();
  s.model.finalize();
  s.initial = lg::State<double>(s.model);  // every joint row in the mode
  s.initial.y = planar.initial.y;
  return s;
}
int solvedBilateralRows(const lg::Scene& sc) {
  const lg::DropCase& c = lgtest::findCase(sc, "limit");
  const lg::Model<double> m = lg::caseModel(sc, c);
  lg::State<double> s = lg::caseState(sc, m, c);
  lg::Workspace<double> w(m);
  lg::impliedPlanarRows(m, s, w);
  int n = 0;
  for (int k = 0; k < m.nRows; ++k) n += !m.rowInfo[k].unilateral && !m.rowInfo[k].friction() && s.active[k];
  return n;
}
}  // namespace

TEST_CASE("a planar model moves as its scene in space does, with half the joints' rows", "[engine][mobility][planar]") {
  struct Shipped {
    const char* file;
    int spatialRows, planarRows;  // bilateral rows solved
  };
  // seed gear: revolute d, g (5 rows each -> 2), spherical a, b (3 -> 2), sliding v (4 -> 2).
  for (const Shipped& f : {Shipped{"data/seed_gear.toml", 20, 10}, Shipped{"data/telescopic_gear.toml", 0, 0}}) {
    toml::table doc = lgtest::shippedDoc(f.file);  // (planar as shipped)
    doc["solver"].as_table()->insert_or_assign("rtol", 1e-10);
    doc["solver"].as_table()->insert_or_assign("atol", 1e-12);
    const lg::Scene planar = lgtest::build(doc);
    REQUIRE(planar.model.settings.planar());
    const lg::Scene space = spatial(planar);
    INFO(f.file);
    const int rowsSpace = solvedBilateralRows(space), rowsPlane = solvedBilateralRows(planar);
    if (f.spatialRows > 0) {
      CHECK(rowsSpace == f.spatialRows);
      CHECK(rowsPlane == f.planarRows);
    } else {
      CHECK(rowsPlane < rowsSpace);
    }
    const auto a = lg::runCase(planar, lgtest::findCase(planar, "limit")).metrics;
    const auto b = lg::runCase(space, lgtest::findCase(space, "limit")).metrics;
    REQUIRE(a.ok);
    REQUIRE(b.ok);
    const double worst = lgtest::largestMetricDifference(a, b);
    lgtest::report("%s: planar (%d bilateral rows solved) against spatial (%d): largest relative difference %.1e, "
                   "%ld against %ld evaluations",
                   f.file, rowsPlane, rowsSpace, worst, a.rhs_evaluations, b.rhs_evaluations);
    // Measured 2.9e-12 (seed gear: 10 of 20 joint rows solved), 2.8e-15 (telescopic gear: 7 of 16).
    CHECK(worst < 1e-11);
    CHECK(a.energy_balance_error < 1e-6);
  }
}

// The implied rows are not even written (w.implied, ImpliedRows): every constraint type leaves them as
// they were, and writes its other rows with the bits of a full write.
TEST_CASE("a planar model's implied rows are left unwritten, its other rows are written as in full",
          "[engine][mobility][planar]") {
  for (const char* file : {"data/seed_gear.toml", "data/telescopic_gear.toml"}) {
    INFO(file);
    const lg::Scene sc = lgtest::build(lgtest::shippedDoc(file));
    const lg::DropCase& c = lgtest::findCase(sc, "limit");
    const lg::Model<double> m = lg::caseModel(sc, c);
    lg::State<double> s = lg::caseState(sc, m, c);
    lg::Workspace<double> masked(m), full(m);
    lg::impliedPlanarRows(m, s, masked);
    int implied = 0;  // (out of the mode already in the scene's initial state, or now)
    for (int k = 0; k < m.nRows; ++k) implied += !m.rowInfo[k].unilateral && !m.rowInfo[k].friction() && !s.active[k];
    REQUIRE(implied > 0);
    // a moved, turning state: the rows then differ from the initial ones in every entry
    for (int b = 0; b < m.nBodies(); ++b) s.y.segment<6>(m.nx() + 6 * b) << 0.3 * b, -1.2, 0.0, 0.0, 0.0, 2.0 - b;
    s.y[1] -= 0.01;
    const double sentinel = 12345.0;
    for (auto& row : masked.rows) row = {sentinel, sentinel, lg::Vec6<double>::Constant(sentinel), lg::Vec6<double>::Constant(sentinel)};
    lg::kinematics(m, s.y, masked);
    lg::kinematics(m, s.y, full);
    lg::constraintRows(m, masked);
    lg::constraintRows(m, full);
    int marked = 0, untouched = 0, same = 0;
    for (int k = 0; k < m.nRows; ++k) {
      const lg::Row<double>& a = masked.rows[k];
      const lg::Row<double>& b = full.rows[k];
      if (masked.implied[k]) {
        ++marked;
        CHECK(!s.active[k]);
        untouched += a.C == sentinel && a.gamma == sentinel && (a.Ji.array() == sentinel).all() && (a.Jj.array() == sentinel).all();
      } else {
        same += a.C == b.C && a.gamma == b.gamma && a.Ji == b.Ji && a.Jj == b.Jj;
      }
    }
    lgtest::report("%s: %d of %d rows implied and left unwritten", file, marked, m.nRows);
    CHECK(marked == implied);
    CHECK(untouched == marked);
    CHECK(same == m.nRows - marked);
  }
}

TEST_CASE("a planar model: bad input names file, line, key and rule, exit status 2", "[mobility][planar][input]") {
  lgtest::TempDir dir("planar_bad");
  const std::string normal = "plane_normal = [0.0, 0.0, 1.0]";
  const std::string good = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));  // (planar as shipped)
  auto with = [&](const std::string& from, const std::string& to) { return lgtest::replacedText(good, from, to); };
  lgtest::checkBadInputs(
      {
          {"zero normal", with(normal, "plane_normal = [0.0, 0.0, 0.0]"), "plane_normal", "scene.plane_normal",
           "direction must be a non-zero vector"},
          {"not a principal axis of the lever", with(normal, "plane_normal = [1.0, 0.0, 0.0]"), "plane_normal",
           "scene.plane_normal", "must be a principal axis of body 'lever'"},
          {"tilted plane", with(normal, "plane_normal = [0.0, 0.1, 1.0]"), "plane_normal", "scene.plane_normal",
           "must be a principal axis of body 'wheel'"},
      },
      dir);
}
