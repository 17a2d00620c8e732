// Scene parser: TOML -> Model<double>, initial state, drop cases. Validates everything at the edge.

// A false positive of GCC in inlined library code: fast-cpp-csv-parser's bounded file-name copy.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wstringop-truncation"
#endif
#include "sim/io/scene.hpp"

#include <csv.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>

#include "sim/accuracy.hpp"
#include "sim/certification.hpp"
#include "sim/engine.hpp"
#include "sim/io/toml_reader.hpp"
#include "sim/scene_check.hpp"

namespace lg {

bool integratorFromName(const std::string& name, IntegratorKind& kind) {
  static const std::pair<const char*, IntegratorKind> table[] = {{"dopri5", IntegratorKind::DormandPrince},
                                                                 {"ros34pw2", IntegratorKind::Ros34pw2},
                                                                 {"ros2", IntegratorKind::Ros2},
                                                                 {"rk4", IntegratorKind::RK4},
                                                                 {"euler", IntegratorKind::SemiImplicitEuler}};
  for (const auto& [n, k] : table)
    if (name == n) {
      kind = k;
      return true;
    }
  return false;
}
std::string integratorNames() { return "\"dopri5\", \"ros34pw2\", \"ros2\", \"rk4\", \"euler\""; }

namespace {

struct Pose {
  Vec3<double> r = Vec3<double>::Zero();
  Mat3<double> R = Mat3<double>::Identity();
};

// Reads the two columns 'cx', 'cy' of a CSV table with a header through fast-cpp-csv-parser.
void readColumns(const std::string& path, const TomlReader& r, const std::string& key, const char* cx, const char* cy,
                 std::vector<double>& x, std::vector<double>& y) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec))
    r.fail(key, "cannot read table '" + path + "': " + (std::filesystem::exists(path, ec) ? "not a regular file" : "no such file"));
  try {
    io::CSVReader<2, io::trim_chars<' ', '\t'>, io::no_quote_escape<','>, io::throw_on_overflow, io::single_and_empty_line_comment<'#'>> in(path);
    in.read_header(io::ignore_no_column, cx, cy);
    double a, b;
    while (in.read_row(a, b)) {
      x.push_back(a);
      y.push_back(b);
    }
  } catch (const std::exception& e) {
    r.fail(key, "cannot read table '" + path + "': " + e.what());
  }
}

// A path of the scene relative to its folder.
std::string scenePath(const TomlReader& r, const std::string& key, const std::string& baseDir) {
  std::filesystem::path tp(r.string(key));
  if (tp.is_relative()) tp = std::filesystem::path(baseDir) / tp;
  return tp.string();
}

// A table's samples checked: at least 4, stroke increasing and uniformly spaced, every area > 0.
std::shared_ptr<const Table1D> checkedTable(std::vector<double> x, std::vector<double> y, const std::string& source,
                                            const TomlReader& r, const std::string& key, int firstRow) {
  if (x.size() < 4) r.fail(key, "table '" + source + "' needs at least 4 rows of (stroke, area)");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  if (!(dx > 0)) r.fail(key, "table '" + source + "': stroke must increase");
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      r.fail(key, "table '" + source + "': stroke must be uniformly spaced (row " + std::to_string(i + firstRow) + ")");
    if (!(y[i] > 0))
      r.fail(key, "table '" + source + "': area " + fmt(y[i]) + " at row " + std::to_string(i + firstRow) + " must be > 0");
  }
  return std::make_shared<Table1D>(std::move(x), std::move(y), source);
}

// Reads a two-column CSV table (header "stroke,area" or any two names) through fast-cpp-csv-parser.
std::shared_ptr<const Table1D> readTable(const std::string& path, const TomlReader& r, const std::string& key) {
  std::vector<double> x, y;
  readColumns(path, r, key, "stroke", "area", x, y);
  return checkedTable(std::move(x), std::move(y), path, r, key, 2);
}

// An inline table: { stroke = [...] [m], area = [...] [m^2] } (what best.toml and calibrated.toml write
// when a table's samples are design parameters).
std::shared_ptr<const Table1D> inlineTable(const toml::table& t, const TomlReader& r, const std::string& key) {
  for (auto&& [k, v] : t)
    if (k.str() != "stroke" && k.str() != "area")
      r.fail(key + "." + std::string(k.str()), "unknown key (an inline table has stroke = [...] and area = [...])");
  std::vector<double> col[2];
  const char* names[2] = {"stroke", "area"};
  for (int c = 0; c < 2; ++c) {
    const toml::array* a = t[names[c]].as_array();
    if (!a) r.fail(key + "." + names[c], "must be an array of numbers");
    for (const auto& e : *a) col[c].push_back(r.toNumber(e, key + "." + names[c]));
  }
  if (col[0].size() != col[1].size())
    r.fail(key, "stroke has " + std::to_string(col[0].size()) + " samples and area " + std::to_string(col[1].size()) +
                    ": they must pair up");
  return checkedTable(std::move(col[0]), std::move(col[1]), "inline", r, key, 1);
}

// A tyre's load-deflection curve: CSV "deflection,load" [m, N], uniformly spaced from deflection 0 with
// load 0, the load rising.
std::shared_ptr<const CurveTable> readCurve(const std::string& path, const TomlReader& r, const std::string& key) {
  std::vector<double> x, y;
  readColumns(path, r, key, "deflection", "load", x, y);
  if (x.size() < 4) r.fail(key, "table '" + path + "' needs at least 4 rows of (deflection, load)");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  if (!(dx > 0)) r.fail(key, "table '" + path + "': deflection must increase");
  if (x.front() != 0.0 || y.front() != 0.0)
    r.fail(key, "table '" + path + "': the first row must be deflection 0 with load 0 (got " + fmt(x.front()) + ", " +
                    fmt(y.front()) + "): the tyre touches the ground unloaded");
  for (size_t i = 0; i < x.size(); ++i) {
    if (!std::isfinite(x[i]) || !std::isfinite(y[i]))
      r.fail(key, "table '" + path + "': row " + std::to_string(i + 2) + " must hold finite numbers");
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      r.fail(key, "table '" + path + "': deflection must be uniformly spaced (row " + std::to_string(i + 2) + ")");
    if (i > 0 && !(y[i] > y[i - 1]))
      r.fail(key, "table '" + path + "': load " + fmt(y[i]) + " N at row " + std::to_string(i + 2) +
                      " must be larger than the row before's " + fmt(y[i - 1]) + " N (a tyre's load rises with its deflection)");
  }
  return std::make_shared<CurveTable>(std::move(x), std::move(y), path);
}

// The joints' rows must be independent at touchdown: a joint whose row is a combination of earlier
// rows over-constrains the mechanism (its multipliers have no unique solution and every case would
// fail). Names the joint and the joints it repeats.
void checkRedundantJoints(const Model<double>& m, const Workspace<double>& w, const std::string& file,
                          const std::vector<int>& constraintLine) {
  const int N = m.nBodies();
  std::vector<int> kept;                  // independent rows so far
  std::vector<Eigen::VectorXd> basis;     // their orthonormalised directions
  auto rowVector = [&](int k) {
    Eigen::VectorXd v = Eigen::VectorXd::Zero(6 * N);
    const RowInfo& ri = m.rowInfo[k];
    if (ri.bi >= 0) v.segment<6>(6 * ri.bi) += w.rows[k].Ji;
    if (ri.bj >= 0) v.segment<6>(6 * ri.bj) += w.rows[k].Jj;
    return v;
  };
  for (int k = 0; k < m.nRows; ++k) {
    if (m.rowInfo[k].unilateral) continue;
    const Eigen::VectorXd v = rowVector(k);
    Eigen::VectorXd r = v;
    for (int pass = 0; pass < 2; ++pass)  // Gram-Schmidt, twice for round-off
      for (const auto& b : basis) r -= b.dot(r) * b;
    if (r.norm() > 1e-8 * std::max(1.0, v.norm())) {
      basis.push_back(r / r.norm());
      kept.push_back(k);
      continue;
    }
    // Which earlier joints it repeats: the least-squares combination of the kept rows.
    Eigen::MatrixXd A(6 * N, static_cast<Eigen::Index>(kept.size()));
    for (size_t i = 0; i < kept.size(); ++i) A.col(static_cast<Eigen::Index>(i)) = rowVector(kept[i]);
    const Eigen::VectorXd c = A.colPivHouseholderQr().solve(v);
    std::set<std::string> others;
    for (size_t i = 0; i < kept.size(); ++i)
      if (std::abs(c[static_cast<Eigen::Index>(i)]) > 1e-6) others.insert("'" + m.constraints[m.rowInfo[kept[i]].constraint].name + "'");
    std::string list;
    for (const auto& o : others) list += (list.empty() ? "" : ", ") + o;
    const int ci = m.rowInfo[k].constraint;
    throw InputError(file, constraintLine[ci], "joint." + m.constraints[ci].name,
                     "this joint over-constrains the mechanism: its row " + std::to_string(k - m.rowOffset[ci]) +
                         " repeats what joint" + (others.size() > 1 ? "s " + list + " already hold" : " " + list + " already holds") +
                         " (remove it, or use a joint that removes fewer degrees of freedom)");
  }
}

}  // namespace

Scene buildScene(const toml::table& doc, const std::string& file, const std::string& baseDir) {
  Scene sc;
  sc.file = file;
  sc.doc = doc;
  Model<double>& m = sc.model;
  {
    const std::set<std::string> top{"scene", "solver", "body", "joint", "stop", "force", "case", "certification"};
    for (const auto& [k, v] : doc)
      if (!top.count(std::string(k.str())))
        throw InputError(file, static_cast<int>(v.source().begin.line), std::string(k.str()),
                         "unknown top-level key (allowed: scene, solver, body, joint, stop, force, case, certification)");
  }
  // [scene]
  std::string airframe;
  if (const toml::table* t = tableOf(doc, "scene", file)) {
    TomlReader r(*t, file, "scene");
    r.allowOnly({"name", "airframe", "description"});
    sc.name = r.name("name", "scene");
    airframe = r.string("airframe", "");
  }
  // [solver]
  if (const toml::table* t = tableOf(doc, "solver", file)) {
    TomlReader r(*t, file, "solver");
    r.allowOnly({"multipliers", "integrator", "stabilization", "rtol", "atol", "step", "max_step", "max_steps",
                 "projection_tolerance", "baumgarte_alpha", "baumgarte_beta", "gauss_seidel_iterations",
                 "gauss_seidel_tolerance", "contact_tolerance", "event_tolerance", "accuracy"});
    Settings& s = m.settings;
    const std::string mult = r.string("multipliers", "direct");
    if (mult == "direct") s.solver = MultiplierSolver::Direct;
    else if (mult == "gauss-seidel") s.solver = MultiplierSolver::GaussSeidel;
    else r.fail("multipliers", "value '" + mult + "' must be \"direct\" or \"gauss-seidel\"");
    const std::string integ = r.string("integrator", "dopri5");
    if (!integratorFromName(integ, s.integrator))
      r.fail("integrator", "value '" + integ + "' must be one of " + integratorNames());
    const std::string stab = r.string("stabilization", "projection");
    if (stab == "projection") s.stabilization = Stabilization::Projection;
    else if (stab == "baumgarte") s.stabilization = Stabilization::Baumgarte;
    else if (stab == "none") s.stabilization = Stabilization::None;
    else r.fail("stabilization", "value '" + stab + "' must be \"projection\", \"baumgarte\" or \"none\"");
    s.rtol = r.positive("rtol", s.rtol);
    s.atol = r.positive("atol", s.atol);
    s.step = r.positive("step", s.step);
    s.maxStep = r.positive("max_step", s.maxStep);
    s.maxSteps = static_cast<long>(r.count("max_steps", s.maxSteps, 1, 1000000000000LL));
    s.projectionTolerance = r.positive("projection_tolerance", s.projectionTolerance);
    s.baumgarteAlpha = r.nonNegative("baumgarte_alpha", s.baumgarteAlpha);
    s.baumgarteBeta = r.nonNegative("baumgarte_beta", s.baumgarteBeta);
    s.gaussSeidelIterations = static_cast<int>(r.count("gauss_seidel_iterations", s.gaussSeidelIterations, 1, 1000000000));
    s.gaussSeidelTolerance = r.positive("gauss_seidel_tolerance", s.gaussSeidelTolerance);
    s.contactTolerance = r.positive("contact_tolerance", s.contactTolerance);
    s.eventTolerance = r.positive("event_tolerance", s.eventTolerance);
    if (r.has("accuracy")) {  // the relative accuracy of the metrics: chooses integrator and tolerances
      const double a = r.positive("accuracy");
      if (const std::string rule = accuracyRule(a); !rule.empty()) r.fail("accuracy", "value " + fmt(a) + " " + rule);
      for (const char* k : {"integrator", "rtol", "atol", "max_step"})
        if (r.has(k)) r.fail(k, std::string("accuracy chooses integrator, rtol, atol and max_step: give either accuracy or ") + k);
      applyAccuracy(s, a);
    }
  }
  // [[body]]
  std::vector<Pose> poses;
  std::set<std::string> names;
  auto uniqueName = [&](const TomlReader& r) {
    const std::string n = r.name("name");
    if (n == "ground") r.fail("name", "'ground' is reserved for the fixed frame");
    if (!names.insert(n).second) r.fail("name", "'" + n + "' is already used by another element");
    return n;
  };
  const auto bodies = tablesOf(doc, "body", file);
  if (bodies.empty()) throw InputError(file, 0, "body", "a scene needs at least one [[body]]");
  for (size_t i = 0; i < bodies.size(); ++i) {
    TomlReader r(*bodies[i], file, "body[" + std::to_string(i) + "]");
    r.allowOnly({"name", "mass", "inertia", "position", "x_axis", "z_axis", "quaternion"});
    Body<double> b;
    b.name = uniqueName(r);
    b.mass = r.positive("mass");
    b.inertia = r.vec3("inertia");
    for (int k = 0; k < 3; ++k)
      if (!(b.inertia[k] > 0)) r.fail("inertia", "principal moments must be > 0 (got " + fmt(b.inertia[k]) + ")");
    Pose p;
    p.r = r.vec3("position");
    if (r.has("quaternion")) {
      if (r.has("x_axis") || r.has("z_axis")) r.fail("quaternion", "give either quaternion or x_axis/z_axis, not both");
      const toml::array* a = (*bodies[i])["quaternion"].as_array();
      if (!a || a->size() != 4) r.fail("quaternion", "must be 4 numbers [w, a, b, c]");
      Vec4<double> q;
      for (int k = 0; k < 4; ++k) q[k] = r.toNumber(*a->get(k), "quaternion");
      if (std::abs(q.norm() - 1) > 1e-6) r.fail("quaternion", "must be a unit quaternion (|q| = " + fmt(q.norm()) + ")");
      p.R = rotation<double>(q.normalized());
    } else {
      const Vec3<double> ex = r.unitVec3("x_axis", Vec3<double>(1, 0, 0));
      const Vec3<double> ez = r.unitVec3("z_axis", Vec3<double>(0, 0, 1));
      if (std::abs(ex.dot(ez)) > 1e-6) r.fail("z_axis", "must be perpendicular to x_axis");
      p.R = rotation<double>(quaternionFromAxes(ex, ez));
    }
    m.bodies.push_back(b);
    poses.push_back(p);
  }
  auto bodyRef = [&](const TomlReader& r, const std::string& key, bool groundOk = true) {
    const std::string n = r.string(key);
    const int b = m.bodyIndex(n);
    if (b == kGround && groundOk) return b;
    if (b < 0) r.fail(key, "'" + n + "' is not a body of this scene" + std::string(groundOk ? " (nor \"ground\")" : ""));
    return b;
  };
  auto toBody = [&](int b, const Vec3<double>& p) -> Vec3<double> {
    if (b < 0) return p;
    return poses[b].R.transpose() * (p - poses[b].r);
  };
  auto dirToBody = [&](int b, const Vec3<double>& d) -> Vec3<double> {
    return b < 0 ? d : Vec3<double>(poses[b].R.transpose() * d);
  };
  // [[joint]]
  std::vector<int> constraintLine;
  const auto joints = tablesOf(doc, "joint", file);
  for (size_t i = 0; i < joints.size(); ++i) {
    const toml::table* t = joints[i];
    TomlReader r(*t, file, "joint[" + std::to_string(i) + "]");
    const std::string type = r.string("type");
    // The keys of each type, checked before any is read (a misspelt key is named as unknown).
    if (type == "spherical" || type == "fixed") r.allowOnly({"name", "type", "body1", "body2", "point"});
    else if (type == "revolute" || type == "sliding" || type == "prismatic")
      r.allowOnly({"name", "type", "body1", "body2", "point", "axis"});
    else if (type == "point_on_plane") r.allowOnly({"name", "type", "body1", "body2", "point", "plane_point", "normal"});
    else r.fail("type", "value '" + type + "' must be one of spherical, revolute, sliding, prismatic, fixed, point_on_plane");
    Constraint<double> c;
    c.name = r.has("name") ? uniqueName(r) : "joint" + std::to_string(i);
    const int bi = bodyRef(r, "body1"), bj = bodyRef(r, "body2");
    if (bi == bj) r.fail("body2", "a joint needs two different bodies");
    if (bi < 0) r.fail("body1", "body1 must be a body; put the ground as body2");
    if (type == "spherical") {
      const Vec3<double> p = r.vec3("point");
      c.type = Spherical<double>{bi, bj, toBody(bi, p), toBody(bj, p)};
    } else if (type == "revolute") {
      const Vec3<double> p = r.vec3("point"), e = r.unitVec3("axis");
      Vec3<double> t1, t2;
      orthonormalBasis(e, t1, t2);
      c.type = Revolute<double>{bi, bj, toBody(bi, p), toBody(bj, p), toBody(bi, p + e), dirToBody(bj, t1), dirToBody(bj, t2)};
    } else if (type == "sliding" || type == "prismatic") {
      const Vec3<double> p = r.vec3("point"), e = r.unitVec3("axis");
      Vec3<double> t1, t2;
      orthonormalBasis(e, t1, t2);
      if (type == "sliding")
        c.type = Sliding<double>{bi, bj, toBody(bi, p), toBody(bi, p + e), toBody(bj, p), dirToBody(bj, t1), dirToBody(bj, t2)};
      else
        c.type = Prismatic<double>{bi, bj, toBody(bi, p), toBody(bi, p + e), toBody(bi, p + t1), toBody(bj, p),
                                   dirToBody(bj, t1), dirToBody(bj, t2)};
    } else if (type == "fixed") {
      const Vec3<double> p = r.vec3("point");
      c.type = Fixed<double>{bi, bj, toBody(bi, p), toBody(bj, p), toBody(bi, p + Vec3<double>(1, 0, 0)),
                             toBody(bi, p + Vec3<double>(0, 1, 0)), dirToBody(bj, Vec3<double>(0, 1, 0)),
                             dirToBody(bj, Vec3<double>(0, 0, 1))};
    } else if (type == "point_on_plane") {
      const Vec3<double> p = r.vec3("point"), n = r.unitVec3("normal");
      c.type = PointOnPlane<double>{bi, bj, toBody(bi, p), toBody(bj, r.vec3("plane_point", p)), dirToBody(bj, n)};
    } else {
      r.fail("type", "value '" + type + "' must be one of spherical, revolute, sliding, prismatic, fixed, point_on_plane");
    }
    m.constraints.push_back(c);
    constraintLine.push_back(r.line());
  }
  // [[stop]]
  const auto stops = tablesOf(doc, "stop", file);
  for (size_t i = 0; i < stops.size(); ++i) {
    TomlReader r(*stops[i], file, "stop[" + std::to_string(i) + "]");
    r.allowOnly({"name", "body1", "point1", "body2", "point2", "max_distance", "min_distance"});
    Constraint<double> c;
    c.name = uniqueName(r);
    const int bi = bodyRef(r, "body1"), bj = bodyRef(r, "body2");
    if (bi == bj) r.fail("body2", "a stop needs two different bodies");
    const bool hasMax = r.has("max_distance"), hasMin = r.has("min_distance");
    if (hasMax == hasMin) r.fail(hasMax ? "min_distance" : "max_distance", "give exactly one of max_distance, min_distance");
    const double L = hasMax ? r.positive("max_distance") : r.positive("min_distance");
    c.type = DistanceStop<double>{bi, bj, toBody(bi, r.vec3("point1")), toBody(bj, r.vec3("point2")), L, hasMax};
    sc.roles.stops.push_back(static_cast<int>(m.constraints.size()));
    m.constraints.push_back(c);
    constraintLine.push_back(r.line());
  }
  // [[force]]
  const auto forcesT = tablesOf(doc, "force", file);
  Vec3<double> g = Vec3<double>::Zero();
  bool hasGravity = false;
  for (size_t i = 0; i < forcesT.size(); ++i) {
    TomlReader r(*forcesT[i], file, "force[" + std::to_string(i) + "]");
    const std::string type = r.string("type");
    ForceElement<double> f;
    f.name = r.has("name") ? uniqueName(r) : type;
    if (type == "gravity") {
      r.allowOnly({"name", "type", "g"});
      if (hasGravity) r.fail("type", "gravity is declared twice");
      g = r.vec3("g", Vec3<double>(0, -9.80665, 0));
      if (!(g.norm() > 0)) r.fail("g", "must be non-zero (leave gravity out for none)");
      f.type = Gravity<double>{g};
      hasGravity = true;
    } else if (type == "lift") {
      r.allowOnly({"name", "type", "body", "ratio", "direction"});
      const int b = bodyRef(r, "body", false);
      f.isLift = true;
      f.liftRatio = r.nonNegative("ratio", 1.0);
      ConstantForce<double> cf{b, Vec3<double>::Zero()};
      f.type = cf;
      sc.roles.lifts.push_back(static_cast<int>(m.forces.size()));
    } else if (type == "constant") {
      r.allowOnly({"name", "type", "body", "force"});
      f.type = ConstantForce<double>{bodyRef(r, "body", false), r.vec3("force")};
    } else if (type == "shock_absorber") {
      r.allowOnly({"name", "type", "rod", "cylinder", "rod_point", "cylinder_point", "L0", "D", "D2", "p01", "Omega0",
                   "n", "rho", "f1", "f1_table", "f2", "xi1", "xi2", "mu", "p_atm", "friction", "friction_velocity",
                   "f1_extension", "f1_extension_table", "xi1_extension", "f2_extension", "xi2_extension", "p02",
                   "Omega02", "n2"});
      ShockAbsorber<double> s;
      s.bi = bodyRef(r, "rod");
      s.bj = bodyRef(r, "cylinder");
      if (s.bi == s.bj) r.fail("cylinder", "rod and cylinder must be different bodies");
      const Vec3<double> B = r.vec3("rod_point"), C = r.vec3("cylinder_point");
      s.rho_i = toBody(s.bi, B);
      s.rho_j = toBody(s.bj, C);
      s.L0 = r.positive("L0", (B - C).norm());
      s.D = r.positive("D");
      s.D2 = r.positive("D2", s.D);
      if (!(s.D2 >= s.D)) r.fail("D2", "bore " + fmt(s.D2) + " must be >= rod diameter D = " + fmt(s.D));
      s.p01 = r.positive("p01");
      s.Omega0 = r.positive("Omega0");
      s.n = r.positive("n");
      if (!(s.n > 1)) r.fail("n", "polytropic exponent " + fmt(s.n) + " must be > 1");
      s.rho = r.positive("rho");
      s.xi1 = r.positive("xi1");
      if (r.has("f1") == r.has("f1_table")) r.fail("f1", "give exactly one of f1 (constant area) and f1_table (CSV file or inline table)");
      s.f1 = r.has("f1") ? r.positive("f1") : 0.0;
      if (r.has("f1_table")) {
        if (const toml::table* inl = r.get("f1_table")->as_table()) {
          s.f1Table = inlineTable(*inl, r, "f1_table");
        } else {
          std::filesystem::path tp(r.string("f1_table"));
          if (tp.is_relative()) tp = std::filesystem::path(baseDir) / tp;
          s.f1Table = readTable(tp.string(), r, "f1_table");
        }
        s.f1Values = s.f1Table->ys();
        if (s.f1Table->xMin() > 0) r.fail("f1_table", "table must start at stroke <= 0");
      }
      s.f2 = r.has("f2") ? r.positive("f2") : 0.0;
      s.reboundOrifice = r.has("f2");
      if (r.has("f2") && s.D2 <= s.D) r.fail("D2", "a rebound orifice f2 needs an annular chamber: D2 > D");
      s.xi2 = r.has("f2") ? r.positive("xi2") : (r.has("xi2") ? r.positive("xi2") : 0.0);
      s.mu = r.nonNegative("mu", 0.0);
      s.pAtm = r.nonNegative("p_atm", 0.0);
      if (!(s.pAtm < s.p01)) r.fail("p_atm", "value " + fmt(s.pAtm) + " must be < p01 = " + fmt(s.p01) + " (the gas must push the rod out)");
      // Two-stage gas spring: a second chamber behind a floating piston (p02 and Omega02; n2 defaults to n).
      s.twoStage = r.has("p02") || r.has("Omega02") || r.has("n2");
      if (s.twoStage) {
        if (!r.has("p02")) r.fail(r.has("Omega02") ? "Omega02" : "n2", "a second gas chamber needs both p02 and Omega02");
        if (!r.has("Omega02")) r.fail("p02", "a second gas chamber needs both p02 and Omega02");
        s.p02 = r.positive("p02");
        if (!(s.p02 > s.p01)) r.fail("p02", "value " + fmt(s.p02) + " must be > p01 = " + fmt(s.p01) + " (the second stage engages when p_1 reaches it)");
        s.Omega02 = r.positive("Omega02");
        s.n2 = r.positive("n2", s.n);
        if (!(s.n2 > 1)) r.fail("n2", "polytropic exponent " + fmt(s.n2) + " must be > 1");
      }
      const std::string law = r.string("friction", "regularised");
      if (law != "coulomb" && law != "regularised")
        r.fail("friction", "value '" + law + "' must be \"coulomb\" (exact stick/slip) or \"regularised\"");
      s.coulomb = law == "coulomb";
      if (s.coulomb && r.has("friction_velocity"))
        r.fail("friction_velocity", "applies to friction = \"regularised\" only (this strut's friction is \"coulomb\")");
      s.frictionVelocity = r.positive("friction_velocity", 1e-3);
      // Orifices by direction (a check valve): the extension's area and loss coefficient of each orifice,
      // each defaulting to its compression one's.
      for (const char* k : {"f1_extension", "f1_extension_table", "xi1_extension", "f2_extension", "xi2_extension"})
        s.checkValve = s.checkValve || r.has(k);
      if (s.checkValve) {
        if (r.has("f1_extension") && r.has("f1_extension_table"))
          r.fail("f1_extension", "give at most one of f1_extension (constant area) and f1_extension_table");
        s.ownF1e = r.has("f1_extension") || r.has("f1_extension_table");
        if (r.has("f1_extension")) s.f1e = r.positive("f1_extension");
        if (r.has("f1_extension_table")) {
          if (const toml::table* inl = r.get("f1_extension_table")->as_table()) {
            s.f1eTable = inlineTable(*inl, r, "f1_extension_table");
          } else {
            s.f1eTable = readTable(scenePath(r, "f1_extension_table", baseDir), r, "f1_extension_table");
          }
          if (s.f1eTable->xMin() > 0) r.fail("f1_extension_table", "table must start at stroke <= 0");
          s.f1eValues = s.f1eTable->ys();
        }
        s.ownXi1e = r.has("xi1_extension");
        if (s.ownXi1e) s.xi1e = r.positive("xi1_extension");
        for (const char* k : {"f2_extension", "xi2_extension"})
          if (r.has(k) && !s.reboundOrifice) r.fail(k, "needs the rebound orifice f2");
        s.ownF2e = r.has("f2_extension");
        if (s.ownF2e) s.f2e = r.positive("f2_extension");
        s.ownXi2e = r.has("xi2_extension");
        if (s.ownXi2e) s.xi2e = r.positive("xi2_extension");
      }
      f.type = s;
      sc.roles.struts.push_back(static_cast<int>(m.forces.size()));
    } else if (type == "tyre") {
      r.allowOnly({"name", "type", "body", "point", "radius", "K", "delta_max", "alpha", "ground_normal", "ground_height",
                   "law", "exponent", "load_table", "c", "damping_exponent", "mu_x", "slip_ratio", "forward"});
      Tyre<double> t;
      t.body = bodyRef(r, "body", false);
      const Vec3<double> centre = r.vec3("point", poses[t.body].r);
      t.rho = toBody(t.body, centre);
      t.normal = r.unitVec3("ground_normal", Vec3<double>(0, 1, 0));
      t.groundHeight = r.number("ground_height", 0.0);
      t.radius = r.positive("radius");
      // The load law and the keys it takes (a key of another law is named, never ignored).
      const std::string law = r.string("law", "polynomial");
      auto notFor = [&](const char* key, const char* uses) {
        if (r.has(key)) r.fail(key, "not a parameter of law = \"" + law + "\" (it uses " + uses + ")");
      };
      if (law == "polynomial") {
        t.law = TyreLaw::Polynomial;
        notFor("exponent", "K, delta_max, alpha");
        notFor("load_table", "K, delta_max, alpha");
      } else if (law == "power") {
        t.law = TyreLaw::Power;
        notFor("alpha", "K, delta_max, exponent");
        notFor("load_table", "K, delta_max, exponent");
      } else if (law == "table") {
        t.law = TyreLaw::Table;
        notFor("K", "load_table, delta_max");
        notFor("alpha", "load_table, delta_max");
        notFor("exponent", "load_table, delta_max");
      } else {
        r.fail("law", "value '" + law + "' must be \"polynomial\", \"power\" or \"table\"");
      }
      t.K = t.law == TyreLaw::Table ? 0.0 : r.positive("K");
      t.deltaMax = r.positive("delta_max");
      t.alpha = r.nonNegative("alpha", 0.0);
      if (t.law == TyreLaw::Power) {
        t.exponent = r.positive("exponent");
        if (!(t.exponent >= 1)) r.fail("exponent", "value " + fmt(t.exponent) + " must be >= 1 (a tyre stiffens as it deflects)");
      }
      if (t.law == TyreLaw::Table) {
        t.curve = readCurve(scenePath(r, "load_table", baseDir), r, "load_table");
        if (t.curve->xMax() < t.deltaMax - 1e-12)
          r.fail("load_table", "table ends at deflection " + fmt(t.curve->xMax()) + " m, before delta_max = " + fmt(t.deltaMax) +
                                   " m: it must cover the tyre's allowed deflection");
      }
      t.damped = r.has("c");
      if (!t.damped && r.has("damping_exponent")) r.fail("damping_exponent", "needs the damping coefficient c");
      t.c = r.nonNegative("c", 0.0);
      t.dampingExponent = r.nonNegative("damping_exponent", 0.0);
      t.longitudinal = r.has("mu_x");
      if (!t.longitudinal)
        for (const char* k : {"slip_ratio", "forward"})
          if (r.has(k)) r.fail(k, "needs the longitudinal friction coefficient mu_x");
      if (t.longitudinal) {
        t.muX = r.positive("mu_x");
        if (!(t.muX <= 1.5)) r.fail("mu_x", "value " + fmt(t.muX) + " must be <= 1.5 (a tyre's friction coefficient)");
        t.slipRatio = r.positive("slip_ratio", 0.05);
        if (!(t.slipRatio < 1)) r.fail("slip_ratio", "value " + fmt(t.slipRatio) + " must be < 1 (a slip ratio)");
        t.forward = r.unitVec3("forward", Vec3<double>(1, 0, 0));
        if (std::abs(t.forward.dot(t.normal)) > 1e-9)
          r.fail("forward", "must lie in the ground plane (perpendicular to ground_normal)");
      }
      f.type = t;
      sc.roles.tyres.push_back(static_cast<int>(m.forces.size()));
    } else if (type == "spring_damper") {
      r.allowOnly({"name", "type", "body1", "point1", "body2", "point2", "k", "c", "L0"});
      SpringDamper<double> s;
      s.bi = bodyRef(r, "body1");
      s.bj = bodyRef(r, "body2");
      const Vec3<double> p1 = r.vec3("point1"), p2 = r.vec3("point2");
      s.rho_i = toBody(s.bi, p1);
      s.rho_j = toBody(s.bj, p2);
      s.k = r.nonNegative("k", 0.0);
      s.c = r.nonNegative("c", 0.0);
      s.L0 = r.nonNegative("L0", (p2 - p1).norm());
      f.type = s;
    } else if (type == "bushing") {
      static const char* kKeys[12] = {"k_x", "k_y", "k_z", "c_x", "c_y", "c_z", "k_rx", "k_ry", "k_rz", "c_rx", "c_ry", "c_rz"};
      r.allowOnly({"name", "type", "body1", "body2", "point", "point2", "x_axis", "z_axis", "k_x", "k_y", "k_z", "c_x", "c_y",
                   "c_z", "k_rx", "k_ry", "k_rz", "c_rx", "c_ry", "c_rz"});
      Bushing<double> s;
      s.bi = bodyRef(r, "body1");
      s.bj = bodyRef(r, "body2");
      if (s.bi == s.bj) r.fail("body2", "a bushing needs two different bodies");
      const Vec3<double> p1 = r.vec3("point"), p2 = r.vec3("point2", p1);
      const Vec3<double> ex = r.unitVec3("x_axis", Vec3<double>(1, 0, 0));
      const Vec3<double> ez = r.unitVec3("z_axis", Vec3<double>(0, 0, 1));
      if (std::abs(ex.dot(ez)) > 1e-6) r.fail("z_axis", "must be perpendicular to x_axis");
      const Mat3<double> Q = rotation<double>(quaternionFromAxes(ex, ez));  // the bushing's axes in the scene
      s.rho_i = toBody(s.bi, p1);
      s.rho_j = toBody(s.bj, p2);
      s.A_i = s.bi < 0 ? Q : Mat3<double>(poses[s.bi].R.transpose() * Q);
      s.A_j = s.bj < 0 ? Q : Mat3<double>(poses[s.bj].R.transpose() * Q);
      Vec3<double>* comp[4] = {&s.kt, &s.ct, &s.kr, &s.cr};
      bool any = false;
      for (int k = 0; k < 12; ++k) {
        (*comp[k / 3])[k % 3] = r.nonNegative(kKeys[k], 0.0);
        any = any || (*comp[k / 3])[k % 3] > 0;
      }
      if (!any) r.fail("k_x", "a bushing needs at least one stiffness or damping > 0 (k_x .. k_rz, c_x .. c_rz)");
      f.type = s;
    } else if (type == "bearing_friction") {
      r.allowOnly({"name", "type", "joint", "mu", "upper_bearing", "lower_bearing", "friction_velocity"});
      BearingFriction<double> e;
      const std::string jn = r.string("joint");
      e.joint = m.constraintIndex(jn);
      if (e.joint < 0) r.fail("joint", "'" + jn + "' is not a joint of this scene");
      Vec3<double> rhoJ;
      if (const auto* sl = std::get_if<Sliding<double>>(&m.constraints[e.joint].type)) {
        e.rows = 4;
        e.bi = sl->bi, e.bj = sl->bj, e.rho_1 = sl->rho_i1, e.rho_2 = sl->rho_i2, e.n_a = sl->n_a, e.n_b = sl->n_b;
        rhoJ = sl->rho_j;
      } else if (const auto* pr = std::get_if<Prismatic<double>>(&m.constraints[e.joint].type)) {
        e.rows = 5;
        e.bi = pr->bi, e.bj = pr->bj, e.rho_1 = pr->rho_i1, e.rho_2 = pr->rho_i2, e.n_a = pr->n_a, e.n_b = pr->n_b;
        rhoJ = pr->rho_j;
      } else {
        r.fail("joint", "'" + jn + "' must be a sliding or prismatic joint (bearing friction acts along a slide)");
      }
      // The joint's axis in the scene (the cylinder's, body 2), and the bearings on it.
      const Pose pc = e.bj < 0 ? Pose{} : poses[e.bj];
      const Vec3<double> axis = pc.R * e.n_a.cross(e.n_b), p0 = pc.r + pc.R * rhoJ;
      const Vec3<double> pu = r.vec3("upper_bearing"), pl = r.vec3("lower_bearing");
      for (const auto& [key, p] : {std::pair<const char*, Vec3<double>>{"upper_bearing", pu}, {"lower_bearing", pl}}) {
        const Vec3<double> d = p - p0;
        const double off = (d - axis * axis.dot(d)).norm();
        if (off > 1e-6) r.fail(key, "the point is " + fmt(off) + " m off the axis of joint '" + jn + "' (tolerance 1e-6 m)");
      }
      if (!(std::abs(axis.dot(pl - pu)) > 1e-3))
        r.fail("lower_bearing", "must be at least 1e-3 m from upper_bearing along the joint's axis (the lever rule divides by it)");
      e.rho_u = toBody(e.bj, pu);
      e.rho_l = toBody(e.bi, pl);
      e.mu = r.number("mu");
      if (!(e.mu >= 0)) r.fail("mu", "value " + fmt(e.mu) + " must be >= 0");
      e.frictionVelocity = r.positive("friction_velocity", 1e-3);
      f.type = e;
    } else {
      r.fail("type", "value '" + type + "' must be one of gravity, lift, constant, shock_absorber, tyre, spring_damper, bushing, "
                     "bearing_friction");
    }
    m.forces.push_back(f);
  }
  if (hasGravity) {
    sc.gravity = g.norm();
    sc.up = -g / g.norm();
  }
  for (int li : sc.roles.lifts) {
    TomlReader r(*forcesT[li], file, "force[" + std::to_string(li) + "]");
    if (!hasGravity) r.fail("type", "a lift element needs a gravity element (lift = ratio * G * g)");
    const Vec3<double> dir = r.unitVec3("direction", sc.up);
    std::get<ConstantForce<double>>(m.forces[li].type).force = dir;  // unit direction until a case scales it
  }
  // airframe: declared, else the body of the first lift element
  if (!airframe.empty()) {
    if (m.bodyIndex(airframe) < 0) {
      TomlReader r(*doc["scene"].as_table(), file, "scene");
      r.fail("airframe", "'" + airframe + "' is not a body of this scene");
    }
    sc.roles.airframe = airframe;
  } else if (!sc.roles.lifts.empty()) {
    sc.roles.airframe = m.bodies[std::get<ConstantForce<double>>(m.forces[sc.roles.lifts[0]].type).body].name;
  }
  m.finalize();
  // Initial state: positions from the bodies; every joint must hold there.
  sc.initial = State<double>(m);
  for (int b = 0; b < m.nBodies(); ++b) {
    sc.initial.y.segment<3>(7 * b) = poses[b].r;
    sc.initial.y.segment<4>(7 * b + 3) = quaternionFromAxes(poses[b].R.col(0), poses[b].R.col(2));
  }
  {
    Workspace<double> w(m);
    kinematics(m, sc.initial.y, w);
    constraintRows(m, w);
    for (int k = 0; k < m.nRows; ++k) {
      const RowInfo& ri = m.rowInfo[k];
      const double C = w.rows[k].C;
      const double scale = std::max(1e-12, w.rows[k].Ji.head<3>().norm());
      const bool bad = ri.unilateral ? (C / scale < -1e-6) : (std::abs(C) / scale > 1e-6);
      if (bad) {
        const bool isStop = ri.unilateral;
        const auto& c = m.constraints[ri.constraint];
        throw InputError(file, constraintLine[ri.constraint], (isStop ? "stop." : "joint.") + c.name,
                         std::string("the initial positions violate this ") + (isStop ? "stop" : "joint") + " by " +
                             fmt(std::abs(C) / scale) + " m (tolerance 1e-6 m): check its points against the bodies");
      }
    }
    checkRedundantJoints(m, w, file, constraintLine);
  }
  // [[case]]
  const auto cases = tablesOf(doc, "case", file);
  std::set<std::string> caseNames;
  for (size_t i = 0; i < cases.size(); ++i) {
    TomlReader r(*cases[i], file, "case[" + std::to_string(i) + "]");
    r.allowOnly({"name", "sink_speed", "lift_ratio", "duration", "masses", "forward_speed"});
    DropCase c;
    c.name = r.name("name");
    if (!caseNames.insert(c.name).second) r.fail("name", "case '" + c.name + "' is defined twice");
    c.sinkSpeed = r.number("sink_speed");
    c.liftRatio = r.nonNegative("lift_ratio", 0.0);
    c.duration = r.positive("duration", 0.8);
    if (c.liftRatio > 0 && sc.roles.lifts.empty()) r.fail("lift_ratio", "the scene declares no lift element");
    c.forwardSpeed = r.nonNegative("forward_speed", 0.0);
    if (r.has("forward_speed")) {
      bool friction = false;
      for (int f : sc.roles.tyres) friction = friction || std::get<Tyre<double>>(m.forces[f].type).longitudinal;
      if (!friction) r.fail("forward_speed", "no tyre of this scene declares the longitudinal friction coefficient mu_x");
    }
    if (const toml::node* mn = cases[i]->get("masses")) {
      const toml::table* mt = mn->as_table();
      if (!mt) r.fail("masses", "must be a table of body = mass");
      TomlReader mr(*mt, file, r.full("masses"));
      for (const auto& [k, v] : *mt) {
        const std::string body(k.str());
        if (m.bodyIndex(body) < 0) mr.fail(body, "'" + body + "' is not a body of this scene");
        c.masses[body] = mr.positive(body);
      }
    }
    sc.cases.push_back(c);
  }
  // Physical consistency (sim/scene_check.hpp), named at the key's line; then the matrix, which needs
  // each strut's S_max.
  if (const auto p = checkScene(sc)) {
    const auto rows = tablesOf(doc, p->array, file);
    const int line = p->index >= 0 && p->index < static_cast<int>(rows.size())
                         ? TomlReader(*rows[p->index], file, "").lineOf(p->key)
                         : 0;
    throw InputError(file, line, p->array + "[" + std::to_string(p->index) + "]." + p->key, p->rule);
  }
  // [certification]: the drop-test matrix of the rules (sim/certification.hpp).
  if (const toml::table* t = tableOf(doc, "certification", file))
    sc.certification = std::make_shared<const Certification>(parseCertification(*t, file, sc));
  return sc;
}

Scene parseScene(const std::string& text, const std::string& file, const std::string& baseDir) {
  return buildScene(parseToml(text, file), file, baseDir);
}

Scene loadScene(const std::string& path) {
  const std::string text = readText(path, "scene file");
  std::string base = std::filesystem::path(path).parent_path().string();
  if (base.empty()) base = ".";
  return parseScene(text, path, base);
}

// ---- parameters by path ----------------------------------------------------------------------------
namespace {
toml::table* findElement(toml::table& doc, const std::string& name) {
  for (const char* arr : {"body", "joint", "stop", "force", "case"}) {
    toml::array* a = doc[arr].as_array();
    if (!a) continue;
    for (auto& e : *a) {
      toml::table* t = e.as_table();
      if (!t) continue;
      const toml::node* n = t->get("name");
      if (n && n->value<std::string>() && *n->value<std::string>() == name) return t;
      // unnamed force elements are known by their type
      if (!n && std::string(arr) == "force" && t->get("type") && t->get("type")->value<std::string>() &&
          *t->get("type")->value<std::string>() == name)
        return t;
    }
  }
  return nullptr;
}
void splitPath(const std::string& path, std::string& element, std::string& key, const std::string& where) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    throw InputError(where, 0, path, "parameter path must read <element>.<key>, e.g. strut.f1");
  element = path.substr(0, dot);
  key = path.substr(dot + 1);
}
}  // namespace

namespace {
// "f1_table[3]" -> ("f1_table", 3); any other key -> (key, -1).
std::pair<std::string, long> indexedKey(const std::string& key) {
  const auto open = key.find('[');
  if (open == std::string::npos || open == 0 || key.back() != ']') return {key, -1};
  const std::string digits = key.substr(open + 1, key.size() - open - 2);
  if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) return {key, -1};
  return {key.substr(0, open), std::stol(digits)};
}
// The node of a parameter: a number, or the area sample of an inline table.
toml::node* parameterNode(toml::table& doc, const std::string& path, const std::string& where) {
  std::string element, key;
  splitPath(path, element, key, where);
  toml::table* t = findElement(doc, element);
  if (!t) throw InputError(where, 0, path, "no body, joint, stop, force or case named '" + element + "' in the scene");
  const auto [base, k] = indexedKey(key);
  toml::node* n = t->get(base);
  if (!n) throw InputError(where, 0, path, "element '" + element + "' has no key '" + base + "' in the scene");
  if (k < 0) return n;
  if (n->is_string())
    throw InputError(where, 0, path, "'" + element + "." + base + "' is a table file: inline it first (inlineTables)");
  toml::array* area = n->is_table() ? (*n->as_table())["area"].as_array() : nullptr;
  if (!area || k >= static_cast<long>(area->size()))
    throw InputError(where, 0, path, "'" + element + "." + base + "' has no sample " + std::to_string(k));
  return area->get(static_cast<size_t>(k));
}
}  // namespace

double getParameter(const toml::table& doc, const std::string& path, const std::string& where) {
  const toml::node* n = parameterNode(const_cast<toml::table&>(doc), path, where);
  if (auto v = n->value<double>()) return *v;
  throw InputError(where, 0, path, "'" + path + "' is not a number in the scene");
}

void setParameter(toml::table& doc, const std::string& path, double value, const std::string& where) {
  (void)getParameter(doc, path, where);
  std::string element, key;
  splitPath(path, element, key, where);
  const auto [base, k] = indexedKey(key);
  if (k >= 0) {
    *parameterNode(doc, path, where)->as_floating_point() = value;
    return;
  }
  toml::table* t = findElement(doc, element);
  t->insert_or_assign(key, value);
}

bool tableSample(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot != std::string::npos && indexedKey(path.substr(dot + 1)).second >= 0;
}

void inlineTables(toml::table& doc, const Scene& scene, const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    if (!tableSample(path)) continue;
    const auto dot = path.rfind('.');
    const std::string element = path.substr(0, dot), base = indexedKey(path.substr(dot + 1)).first;
    toml::table* t = findElement(doc, element);
    const int f = scene.model.forceIndex(element);
    if (!t || f < 0 || !t->get(base) || !t->get(base)->is_string()) continue;
    const auto* sa = std::get_if<ShockAbsorber<double>>(&scene.model.forces[static_cast<size_t>(f)].type);
    if (!sa) continue;
    const bool main = base == "f1_table", extension = base == "f1_extension_table";
    const std::shared_ptr<const Table1D>& table = main ? sa->f1Table : sa->f1eTable;
    if (!(main || extension) || !table) continue;
    toml::array stroke, area;
    for (double x : table->xs()) stroke.push_back(x);
    for (double y : main ? sa->f1Values : sa->f1eValues) area.push_back(y);
    toml::table inl{{"stroke", std::move(stroke)}, {"area", std::move(area)}};
    inl.is_inline(true);
    t->insert_or_assign(base, std::move(inl));
  }
}

std::string toTomlString(const toml::table& doc) {
  std::ostringstream o;
  o << doc << "\n";
  return o.str();
}

}  // namespace lg
