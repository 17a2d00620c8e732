// Scene parser: TOML -> Model<double>, initial state, drop cases. Validates everything at the edge.
// buildScene runs the steps of a SceneBuilder (sim/io/scene_builder.hpp) in order: the top-level keys,
// [scene], [solver], bodies, joints, stops, force elements (sim/io/scene_elements.cpp,
// sim/io/scene_forces.cpp), then checks the initial positions against the joints and stops, reads the
// cases, applies the scene's physical rules (sim/scene/check.hpp) and reads [certification]. The table
// readers are in sim/io/scene_tables.cpp, the parameter paths in sim/io/scene_parameters.cpp.
#include "sim/io/scene.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>

#include "sim/io/certification.hpp"
#include "sim/engine/engine.hpp"
#include "sim/io/scene_builder.hpp"
#include "sim/io/toml_reader.hpp"
#include "sim/scene/check.hpp"

namespace lg {

namespace {
// The integrators by name: the one list behind the lookup, the names and the messages.
constexpr std::pair<const char*, IntegratorKind> kIntegratorNames[] = {{"dopri5", IntegratorKind::DormandPrince},
                                                                       {"ros34pw2", IntegratorKind::Ros34pw2},
                                                                       {"ros2", IntegratorKind::Ros2},
                                                                       {"rk4", IntegratorKind::RK4},
                                                                       {"euler", IntegratorKind::SemiImplicitEuler}};
}  // namespace

bool integratorFromName(const std::string& name, IntegratorKind& kind) {
  for (const auto& [n, k] : kIntegratorNames)
    if (name == n) {
      kind = k;
      return true;
    }
  return false;
}
std::vector<std::string> integratorList() {
  std::vector<std::string> out;
  for (const auto& [n, k] : kIntegratorNames) out.push_back(n);
  return out;
}
std::string integratorNames() {
  std::string out;
  for (const auto& n : integratorList()) out += (out.empty() ? "\"" : ", \"") + n + "\"";
  return out;
}

namespace {

using detail::SceneBuilder;

void checkTopLevelKeys(const toml::table& doc, const std::string& file) {
  const std::set<std::string> top{"scene", "solver", "body", "joint", "stop", "force", "case", "certification", "envelope"};
  for (const auto& [k, v] : doc)
    if (!top.count(std::string(k.str())))
      throw InputError(file, static_cast<int>(v.source().begin.line), std::string(k.str()),
                       "unknown top-level key (allowed: scene, solver, body, joint, stop, force, case, certification, envelope)");
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

// A planar model (Settings::planeNormal): its plane motions must be those of the scene. The normal n must
// be a principal axis of every planar body's inertia (else rotating about n would tilt it), a guided
// body's axis and the drop direction (against gravity) must lie in the plane, and no bearing friction.
void checkPlanar(const SceneBuilder& b) {
  const Model<double>& m = b.m;
  if (!m.settings.planar()) return;
  const Vec3<double> n = m.settings.planeNormal;
  auto fail = [&](const std::string& why) { throw InputError(b.file, b.planeLine, "scene.plane_normal", why); };
  for (int k = 0; k < m.nBodies(); ++k) {
    const Vec3<double> u = b.poses[k].R.transpose() * n;
    if (m.mobility[k] == kPlanar && u.cwiseAbs().maxCoeff() < 1 - 1e-9)
      fail("the plane's normal must be a principal axis of body '" + m.bodies[k].name +
           "' (its inertia axes at t = 0); a planar model rotates each body about it");
    if (m.mobility[k] == kTranslation && std::abs(m.mobilityAxis[k].dot(n)) > 1e-9)
      fail("body '" + m.bodies[k].name + "' is guided along an axis that leaves the plane");
  }
  if (std::abs(b.sc.up.dot(n)) > 1e-9) fail("the drop direction (against gravity) must lie in the plane");
  if (!m.bearingForces.empty())  // (it reads every row of its joint, some of which a planar model does not solve)
    fail("a planar model cannot hold bearing friction ('" + m.forces[m.bearingForces[0]].name +
         "' reads its joint's reactions out of the plane too): remove plane_normal");
}

// Initial state: positions from the bodies; every joint must hold there, and no joint may repeat
// another.
void readInitialState(SceneBuilder& b) {
  const Model<double>& m = b.m;
  Scene& sc = b.sc;
  sc.initial = State<double>(m);
  for (int k = 0; k < m.nBodies(); ++k) {
    sc.initial.y.segment<3>(7 * k) = b.poses[k].r;
    sc.initial.y.segment<4>(7 * k + 3) = quaternionFromAxes(b.poses[k].R.col(0), b.poses[k].R.col(2));
  }
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
      throw InputError(b.file, b.constraintLine[ri.constraint], (isStop ? "stop." : "joint.") + c.name,
                       std::string("the initial positions violate this ") + (isStop ? "stop" : "joint") + " by " +
                           fmt(std::abs(C) / scale) + " m (tolerance 1e-6 m): check its points against the bodies");
    }
  }
  checkRedundantJoints(m, w, b.file, b.constraintLine);
  checkPlanar(b);
  impliedPlanarRows(m, sc.initial, w);  // (a planar model: the rows out of its mode from the start)
}

// Physical consistency (sim/scene/check.hpp, which also derives each strut's S_max), named at the
// key's line.
void checkPhysics(Scene& sc, const toml::table& doc, const std::string& file) {
  if (const auto p = checkScene(sc)) {
    const auto rows = tablesOf(doc, p->array, file);
    const int line = p->index >= 0 && p->index < static_cast<int>(rows.size())
                         ? TomlReader(*rows[p->index], file, "").lineOf(p->key)
                         : 0;
    throw InputError(file, line, p->array + "[" + std::to_string(p->index) + "]." + p->key, p->rule);
  }
}

}  // namespace

Scene buildScene(const toml::table& doc, const std::string& file, const std::string& baseDir) {
  Scene sc;
  sc.file = file;
  sc.doc = doc;
  checkTopLevelKeys(doc, file);
  SceneBuilder b(sc, doc, file, baseDir);
  b.readSceneTable();
  b.readSolver();
  b.readBodies();
  b.readJoints();
  b.readStops();
  b.readForces();
  b.finishLifts();
  b.finishBearings();
  b.finishStops();
  b.findAirframe();
  sc.model.finalize();
  readInitialState(b);
  b.readCases();
  // The rules, then the matrix, which needs each strut's S_max.
  checkPhysics(sc, doc, file);
  // [envelope]: the servicing and temperature envelope (sim/scene/envelope.hpp), checked at every corner.
  if (const toml::table* t = tableOf(doc, "envelope", file)) sc.envelope = parseEnvelope(*t, file, sc);
  // [certification]: the drop-test matrix of the rules (sim/drop/certification.hpp).
  if (const toml::table* t = tableOf(doc, "certification", file))
    sc.certification = std::make_shared<const Certification>(parseCertification(*t, file, sc));
  return sc;
}

Scene parseScene(const std::string& text, const std::string& file, const std::string& baseDir) {
  Scene sc = buildScene(parseToml(text, file), file, baseDir);
  sc.text = text;
  return sc;
}

Scene loadScene(const std::string& path) {
  const std::string text = readText(path, "scene file");
  std::string base = std::filesystem::path(path).parent_path().string();
  if (base.empty()) base = ".";
  return parseScene(text, path, base);
}

}  // namespace lg
