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
#include "sim/engine.hpp"
#include "sim/io/toml_reader.hpp"

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

// Reads a two-column CSV table (header "stroke,area" or any two names) through fast-cpp-csv-parser.
std::shared_ptr<const Table1D> readTable(const std::string& path, const TomlReader& r, const std::string& key) {
  std::vector<double> x, y;
  try {
    io::CSVReader<2, io::trim_chars<' ', '\t'>, io::no_quote_escape<','>, io::throw_on_overflow, io::single_and_empty_line_comment<'#'>> in(path);
    in.read_header(io::ignore_no_column, "stroke", "area");
    double a, b;
    while (in.read_row(a, b)) {
      x.push_back(a);
      y.push_back(b);
    }
  } catch (const std::exception& e) {
    r.fail(key, "cannot read table '" + path + "': " + e.what());
  }
  if (x.size() < 4) r.fail(key, "table '" + path + "' needs at least 4 rows of (stroke, area)");
  const double dx = (x.back() - x.front()) / double(x.size() - 1);
  if (!(dx > 0)) r.fail(key, "table '" + path + "': stroke must increase");
  for (size_t i = 0; i < x.size(); ++i) {
    if (std::abs(x[i] - (x.front() + dx * double(i))) > 1e-9 * std::max(1.0, std::abs(x.back())))
      r.fail(key, "table '" + path + "': stroke must be uniformly spaced (row " + std::to_string(i + 2) + ")");
    if (!(y[i] > 0)) r.fail(key, "table '" + path + "': area " + fmt(y[i]) + " at row " + std::to_string(i + 2) + " must be > 0");
  }
  return std::make_shared<Table1D>(std::move(x), std::move(y), path);
}

}  // namespace

Scene buildScene(const toml::table& doc, const std::string& file, const std::string& baseDir) {
  Scene sc;
  sc.file = file;
  sc.doc = doc;
  Model<double>& m = sc.model;
  {
    const std::set<std::string> top{"scene", "solver", "body", "joint", "stop", "force", "case"};
    for (const auto& [k, v] : doc)
      if (!top.count(std::string(k.str())))
        throw InputError(file, static_cast<int>(v.source().begin.line), std::string(k.str()),
                         "unknown top-level key (allowed: scene, solver, body, joint, stop, force, case)");
  }
  // [scene]
  std::string airframe;
  if (const toml::table* t = doc["scene"].as_table()) {
    TomlReader r(*t, file, "scene");
    r.allowOnly({"name", "airframe", "description"});
    sc.name = r.string("name", "scene");
    airframe = r.string("airframe", "");
  } else if (doc.contains("scene")) {
    throw InputError(file, 0, "scene", "must be a table [scene]");
  }
  // [solver]
  if (const toml::table* t = doc["solver"].as_table()) {
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
    s.maxSteps = static_cast<long>(r.positive("max_steps", double(s.maxSteps)));
    s.projectionTolerance = r.positive("projection_tolerance", s.projectionTolerance);
    s.baumgarteAlpha = r.nonNegative("baumgarte_alpha", s.baumgarteAlpha);
    s.baumgarteBeta = r.nonNegative("baumgarte_beta", s.baumgarteBeta);
    s.gaussSeidelIterations = static_cast<int>(r.positive("gauss_seidel_iterations", s.gaussSeidelIterations));
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
    const std::string n = r.string("name");
    if (n.empty() || n == "ground") r.fail("name", "'" + n + "' is reserved or empty");
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
      for (int k = 0; k < 4; ++k) {
        auto v = a->get(k)->value<double>();
        if (!v) r.fail("quaternion", "must be 4 numbers [w, a, b, c]");
        q[k] = *v;
      }
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
    Constraint<double> c;
    c.name = r.has("name") ? uniqueName(r) : "joint" + std::to_string(i);
    const int bi = bodyRef(r, "body1"), bj = bodyRef(r, "body2");
    if (bi == bj) r.fail("body2", "a joint needs two different bodies");
    if (bi < 0) r.fail("body1", "body1 must be a body; put the ground as body2");
    if (type == "spherical") {
      r.allowOnly({"name", "type", "body1", "body2", "point"});
      const Vec3<double> p = r.vec3("point");
      c.type = Spherical<double>{bi, bj, toBody(bi, p), toBody(bj, p)};
    } else if (type == "revolute") {
      r.allowOnly({"name", "type", "body1", "body2", "point", "axis"});
      const Vec3<double> p = r.vec3("point"), e = r.unitVec3("axis");
      Vec3<double> t1, t2;
      orthonormalBasis(e, t1, t2);
      c.type = Revolute<double>{bi, bj, toBody(bi, p), toBody(bj, p), toBody(bi, p + e), dirToBody(bj, t1), dirToBody(bj, t2)};
    } else if (type == "sliding" || type == "prismatic") {
      r.allowOnly({"name", "type", "body1", "body2", "point", "axis"});
      const Vec3<double> p = r.vec3("point"), e = r.unitVec3("axis");
      Vec3<double> t1, t2;
      orthonormalBasis(e, t1, t2);
      if (type == "sliding")
        c.type = Sliding<double>{bi, bj, toBody(bi, p), toBody(bi, p + e), toBody(bj, p), dirToBody(bj, t1), dirToBody(bj, t2)};
      else
        c.type = Prismatic<double>{bi, bj, toBody(bi, p), toBody(bi, p + e), toBody(bi, p + t1), toBody(bj, p),
                                   dirToBody(bj, t1), dirToBody(bj, t2)};
    } else if (type == "fixed") {
      r.allowOnly({"name", "type", "body1", "body2", "point"});
      const Vec3<double> p = r.vec3("point");
      c.type = Fixed<double>{bi, bj, toBody(bi, p), toBody(bj, p), toBody(bi, p + Vec3<double>(1, 0, 0)),
                             toBody(bi, p + Vec3<double>(0, 1, 0)), dirToBody(bj, Vec3<double>(0, 1, 0)),
                             dirToBody(bj, Vec3<double>(0, 0, 1))};
    } else if (type == "point_on_plane") {
      r.allowOnly({"name", "type", "body1", "body2", "point", "plane_point", "normal"});
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
                   "n", "rho", "f1", "f1_table", "f2", "xi1", "xi2", "mu", "p_atm", "friction", "friction_velocity"});
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
      if (r.has("f1") == r.has("f1_table")) r.fail("f1", "give exactly one of f1 (constant area) and f1_table (CSV file)");
      s.f1 = r.has("f1") ? r.positive("f1") : 0.0;
      if (r.has("f1_table")) {
        std::filesystem::path tp(r.string("f1_table"));
        if (tp.is_relative()) tp = std::filesystem::path(baseDir) / tp;
        s.f1Table = readTable(tp.string(), r, "f1_table");
        if (s.f1Table->xMin() > 0) r.fail("f1_table", "table must start at stroke <= 0");
      }
      s.f2 = r.has("f2") ? r.positive("f2") : 0.0;
      if (r.has("f2") && s.D2 <= s.D) r.fail("D2", "a rebound orifice f2 needs an annular chamber: D2 > D");
      s.xi2 = r.has("f2") ? r.positive("xi2") : (r.has("xi2") ? r.positive("xi2") : 0.0);
      s.mu = r.nonNegative("mu", 0.0);
      s.pAtm = r.nonNegative("p_atm", 0.0);
      if (!(s.pAtm < s.p01)) r.fail("p_atm", "value " + fmt(s.pAtm) + " must be < p01 = " + fmt(s.p01) + " (the gas must push the rod out)");
      const std::string law = r.string("friction", "regularised");
      if (law != "coulomb" && law != "regularised")
        r.fail("friction", "value '" + law + "' must be \"coulomb\" (exact stick/slip) or \"regularised\"");
      s.coulomb = law == "coulomb";
      if (s.coulomb && r.has("friction_velocity"))
        r.fail("friction_velocity", "applies to friction = \"regularised\" only (this strut's friction is \"coulomb\")");
      s.frictionVelocity = r.positive("friction_velocity", 1e-3);
      if (s.f1Table) {
        // The table must cover every stroke the strut can reach: up to a "no nearer" stop between the
        // same bodies if there is one, else up to the stroke that would exhaust the gas volume.
        double reach = std::min(s.L0, s.Omega0 / (M_PI * s.D * s.D / 4));
        for (const auto& c : m.constraints)
          if (const auto* st = std::get_if<DistanceStop<double>>(&c.type))
            if (!st->noFarther && ((st->bi == s.bi && st->bj == s.bj) || (st->bi == s.bj && st->bj == s.bi)))
              reach = std::min(reach, s.L0 - st->L);
        if (s.f1Table->xMax() < reach - 1e-12)
          r.fail("f1_table", "table ends at stroke " + fmt(s.f1Table->xMax()) + " m but the strut can reach " + fmt(reach) + " m");
      }
      f.type = s;
      sc.roles.struts.push_back(static_cast<int>(m.forces.size()));
    } else if (type == "tyre") {
      r.allowOnly({"name", "type", "body", "point", "radius", "K", "delta_max", "alpha", "ground_normal", "ground_height"});
      Tyre<double> t;
      t.body = bodyRef(r, "body", false);
      t.rho = toBody(t.body, r.vec3("point", poses[t.body].r));
      t.normal = r.unitVec3("ground_normal", Vec3<double>(0, 1, 0));
      t.groundHeight = r.number("ground_height", 0.0);
      t.radius = r.positive("radius");
      t.K = r.positive("K");
      t.deltaMax = r.positive("delta_max");
      t.alpha = r.nonNegative("alpha", 0.0);
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
    } else {
      r.fail("type", "value '" + type + "' must be one of gravity, lift, constant, shock_absorber, tyre, spring_damper");
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
  }
  // [[case]]
  const auto cases = tablesOf(doc, "case", file);
  std::set<std::string> caseNames;
  for (size_t i = 0; i < cases.size(); ++i) {
    TomlReader r(*cases[i], file, "case[" + std::to_string(i) + "]");
    r.allowOnly({"name", "sink_speed", "lift_ratio", "duration", "masses"});
    DropCase c;
    c.name = r.string("name");
    if (!caseNames.insert(c.name).second) r.fail("name", "case '" + c.name + "' is defined twice");
    c.sinkSpeed = r.nonNegative("sink_speed", 0.0);
    c.liftRatio = r.nonNegative("lift_ratio", 0.0);
    c.duration = r.positive("duration", 0.8);
    if (c.liftRatio > 0 && sc.roles.lifts.empty()) r.fail("lift_ratio", "the scene declares no lift element");
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
  return sc;
}

namespace {
// The key of the statement a TOML syntax error at 'line' (1-based) belongs to: the left-hand side of
// the nearest assignment at or above it (a multi-line array continues its first line's statement), or
// the header on the error line itself; "" if none. toml++ reports where it noticed the error only.
std::string syntaxErrorKey(const std::string& text, int line) {
  std::vector<std::string> lines;
  {
    std::istringstream in(text);
    for (std::string l; std::getline(in, l);) lines.push_back(l);
  }
  auto content = [&](int i) {  // line i without its comment, trimmed
    std::string l = lines[i].substr(0, lines[i].find('#'));
    const auto a = l.find_first_not_of(" \t\r"), b = l.find_last_not_of(" \t\r");
    return a == std::string::npos ? std::string() : l.substr(a, b - a + 1);
  };
  auto openBracket = [](const std::string& l) { return std::count(l.begin(), l.end(), '[') > std::count(l.begin(), l.end(), ']'); };
  for (int i = std::min(line, static_cast<int>(lines.size())) - 1; i >= 0; --i) {
    const std::string l = content(i);
    if (l.empty()) continue;
    if (l[0] == '[') {
      if (i != line - 1) return "";
      int j = i - 1;
      while (j >= 0 && content(j).empty()) --j;
      if (j >= 0 && openBracket(content(j))) continue;  // a value above is still open
      return l;
    }
    const auto eq = l.find('=');
    if (eq != std::string::npos) {
      std::string k = l.substr(0, eq);
      k.erase(k.find_last_not_of(" \t") + 1);
      return k;
    }
  }
  return "";
}
}  // namespace

Scene parseScene(const std::string& text, const std::string& file, const std::string& baseDir) {
  toml::table doc;
  try {
    doc = toml::parse(text, file);
  } catch (const toml::parse_error& e) {
    const int line = static_cast<int>(e.source().begin.line);
    throw InputError(file, line, syntaxErrorKey(text, line), "TOML syntax: " + std::string(e.description()));
  }
  return buildScene(doc, file, baseDir);
}

Scene loadScene(const std::string& path) {
  const std::string text = readText(path);
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

double getParameter(const toml::table& doc, const std::string& path, const std::string& where) {
  std::string element, key;
  splitPath(path, element, key, where);
  toml::table* t = findElement(const_cast<toml::table&>(doc), element);
  if (!t) throw InputError(where, 0, path, "no body, joint, stop, force or case named '" + element + "' in the scene");
  const toml::node* n = t->get(key);
  if (!n) throw InputError(where, 0, path, "element '" + element + "' has no key '" + key + "' in the scene");
  if (auto v = n->value<double>()) return *v;
  throw InputError(where, 0, path, "'" + path + "' is not a number in the scene");
}

void setParameter(toml::table& doc, const std::string& path, double value, const std::string& where) {
  (void)getParameter(doc, path, where);
  std::string element, key;
  splitPath(path, element, key, where);
  toml::table* t = findElement(doc, element);
  t->insert_or_assign(key, value);
}

std::string toTomlString(const toml::table& doc) {
  std::ostringstream o;
  o << doc << "\n";
  return o.str();
}

}  // namespace lg
