// The scene parser's steps for everything but the force elements (sim/io/scene_builder.hpp): the
// builder's helpers (unique names, body references, scene points and directions in a body's axes),
// the [scene] and [solver] tables, the [[body]] rows with their initial poses, the [[joint]] rows (the
// keys of each type, then its geometry in the bodies' axes), the [[stop]] rows and the [[case]] rows.
// Each reads its keys in a fixed order: that order decides which error a file with several gets first.
#include <cmath>

#include "sim/drop/accuracy.hpp"
#include "sim/io/scene.hpp"
#include "sim/io/scene_builder.hpp"
#include "sim/io/drop_case.hpp"

namespace lg::detail {

std::string SceneBuilder::uniqueName(const TomlReader& r) {
  const std::string n = r.name("name");
  if (n == "ground") r.fail("name", "'ground' is reserved for the fixed frame");
  if (!names.insert(n).second) r.fail("name", "'" + n + "' is already used by another element");
  return n;
}

int SceneBuilder::bodyRef(const TomlReader& r, const std::string& key, bool groundOk) const {
  const std::string n = r.string(key);
  const int b = m.bodyIndex(n);
  if (b == kGround && groundOk) return b;
  if (b < 0) r.fail(key, "'" + n + "' is not a body of this scene" + std::string(groundOk ? " (nor \"ground\")" : ""));
  return b;
}

Vec3<double> SceneBuilder::toBody(int b, const Vec3<double>& p) const {
  if (b < 0) return p;
  return poses[b].R.transpose() * (p - poses[b].r);
}

Vec3<double> SceneBuilder::dirToBody(int b, const Vec3<double>& d) const {
  return b < 0 ? d : Vec3<double>(poses[b].R.transpose() * d);
}

// [scene]
void SceneBuilder::readSceneTable() {
  if (const toml::table* t = tableOf(doc, "scene", file)) {
    TomlReader r(*t, file, "scene");
    r.allowOnly({"name", "airframe", "description", "plane_normal"});
    sc.name = r.name("name", "scene");
    airframe = r.string("airframe", "");
    if (r.has("plane_normal")) {  // a planar model (Settings::planeNormal; checked in readInitialState)
      m.settings.planeNormal = r.unitVec3("plane_normal");
      planeLine = r.lineOf("plane_normal");
    }
  }
}

// [solver]
void SceneBuilder::readSolver() {
  const toml::table* t = tableOf(doc, "solver", file);
  if (!t) return;
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
  if (r.has("rtol") && !(s.rtol < 1)) r.fail("rtol", "value " + fmt(s.rtol) + " must be < 1 (a relative tolerance)");
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
void SceneBuilder::readBodies() {
  const auto bodies = tablesOf(doc, "body", file);
  if (bodies.empty()) throw InputError(file, 0, "body", "a scene needs at least one [[body]]");
  for (size_t i = 0; i < bodies.size(); ++i) readBody(*bodies[i], i);
}

void SceneBuilder::readBody(const toml::table& t, size_t i) {
  TomlReader r(t, file, "body[" + std::to_string(i) + "]");
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
    const toml::array* a = t["quaternion"].as_array();
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

// [[joint]]
void SceneBuilder::readJoints() {
  const auto joints = tablesOf(doc, "joint", file);
  for (size_t i = 0; i < joints.size(); ++i) readJoint(*joints[i], i);
}

void SceneBuilder::readJoint(const toml::table& t, size_t i) {
  TomlReader r(t, file, "joint[" + std::to_string(i) + "]");
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

// [[stop]]: rigid (a unilateral constraint row), or elastic with `stiffness` (a penalty pad, StopPad:
// a force element, added by finishStops after the [[force]] rows).
void SceneBuilder::readStops() {
  const auto stops = tablesOf(doc, "stop", file);
  for (size_t i = 0; i < stops.size(); ++i) {
    TomlReader r(*stops[i], file, "stop[" + std::to_string(i) + "]");
    r.allowOnly({"name", "body1", "point1", "body2", "point2", "max_distance", "min_distance", "stiffness", "damping"});
    const std::string name = uniqueName(r);
    const int bi = bodyRef(r, "body1"), bj = bodyRef(r, "body2");
    if (bi == bj) r.fail("body2", "a stop needs two different bodies");
    const bool hasMax = r.has("max_distance"), hasMin = r.has("min_distance");
    if (hasMax == hasMin) r.fail(hasMax ? "min_distance" : "max_distance", "give exactly one of max_distance, min_distance");
    const double L = hasMax ? r.positive("max_distance") : r.positive("min_distance");
    const Vec3<double> p1 = r.vec3("point1"), p2 = r.vec3("point2");  // (scene axes, at t = 0)
    const Vec3<double> rho_i = toBody(bi, p1), rho_j = toBody(bj, p2);
    if (r.has("damping") && !r.has("stiffness")) r.fail("damping", "a rigid stop has no damping: give stiffness too (an elastic stop)");
    if (r.has("stiffness")) {
      if (!hasMax) r.fail("stiffness", "an elastic stop is an extension stop: give max_distance (a bottoming stop stays rigid)");
      ForceElement<double> f;
      f.name = name;
      StopPad<double> p{bi, bj, rho_i, rho_j, L, r.positive("stiffness")};
      p.damped = r.has("damping");
      p.c = r.nonNegative("damping", 0.0);
      if ((p2 - p1).norm() - L > 1e-6)
        r.fail("max_distance", "the initial positions press this stop by " + fmt((p2 - p1).norm() - L) +
                                   " m (tolerance 1e-6 m): the scene's positions are the unloaded ones; check its points");
      f.type = p;
      pads.push_back({f, static_cast<int>(i)});
      continue;
    }
    Constraint<double> c;
    c.name = name;
    c.type = DistanceStop<double>{bi, bj, rho_i, rho_j, L, hasMax};
    sc.roles.stops.push_back(static_cast<int>(m.constraints.size()));
    sc.roles.stopEntry.push_back(static_cast<int>(i));
    m.constraints.push_back(c);
    constraintLine.push_back(r.line());
  }
}

// [[case]]
void SceneBuilder::readCases() {
  const auto cases = tablesOf(doc, "case", file);
  std::set<std::string> caseNames;
  for (size_t i = 0; i < cases.size(); ++i) readCase(*cases[i], i, caseNames);
}

void SceneBuilder::readCase(const toml::table& t, size_t i, std::set<std::string>& caseNames) {
  TomlReader r(t, file, "case[" + std::to_string(i) + "]");
  r.allowOnly({"name", "sink_speed", "lift_ratio", "duration", "masses", "forward_speed", "drop_height"});
  DropCase c;
  c.name = r.name("name");
  if (!caseNames.insert(c.name).second) r.fail("name", "case '" + c.name + "' is defined twice");
  readDropCase(r, sc, c, true);  // (sim/io/drop_case.hpp: the same keys and rules as a study's and a calibration's)
  sc.cases.push_back(c);
}

}  // namespace lg::detail
