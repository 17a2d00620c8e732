// The scene parser's [[force]] rows (sim/io/scene_builder.hpp): one function per element type
// (gravity, lift, constant, shock_absorber, tyre, spring_damper, bushing, bearing_friction), the larger
// ones in named parts (a strut's orifices, gas chambers and check valve; a tyre's load law and
// longitudinal friction), each reading its keys in the order that decides which error comes first;
// then what needs all of them: |g| and up, each lift element's direction, and the airframe.
#include <cmath>
#include <filesystem>
#include <utility>
#include <variant>

#include "sim/io/scene.hpp"
#include "sim/io/scene_builder.hpp"

namespace lg::detail {

void SceneBuilder::readForces() {
  forceTables = tablesOf(doc, "force", file);
  for (size_t i = 0; i < forceTables.size(); ++i) readForce(i);
}

void SceneBuilder::readForce(size_t i) {
  TomlReader r(*forceTables[i], file, "force[" + std::to_string(i) + "]");
  const std::string type = r.string("type");
  ForceElement<double> f;
  f.name = r.has("name") ? uniqueName(r) : type;
  if (type == "gravity") readGravity(r, f);
  else if (type == "lift") readLift(r, f);
  else if (type == "constant") readConstant(r, f);
  else if (type == "shock_absorber") readShockAbsorber(r, f);
  else if (type == "tyre") readTyre(r, f);
  else if (type == "spring_damper") readSpringDamper(r, f);
  else if (type == "bushing") readBushing(r, f);
  else if (type == "bearing_friction") readBearingFriction(r, f);
  else
    r.fail("type", "value '" + type + "' must be one of gravity, lift, constant, shock_absorber, tyre, spring_damper, bushing, "
                   "bearing_friction");
  m.forces.push_back(f);
}

void SceneBuilder::readGravity(const TomlReader& r, ForceElement<double>& f) {
  r.allowOnly({"name", "type", "g"});
  if (hasGravity) r.fail("type", "gravity is declared twice");
  g = r.vec3("g", Vec3<double>(0, -9.80665, 0));
  if (!(g.norm() > 0)) r.fail("g", "must be non-zero (leave gravity out for none)");
  f.type = Gravity<double>{g};
  hasGravity = true;
}

// Its direction is read in finishLifts, once the gravity element is known.
void SceneBuilder::readLift(const TomlReader& r, ForceElement<double>& f) {
  r.allowOnly({"name", "type", "body", "ratio", "direction"});
  const int b = bodyRef(r, "body", false);
  f.isLift = true;
  f.liftRatio = r.nonNegative("ratio", 1.0);
  ConstantForce<double> cf{b, Vec3<double>::Zero()};
  f.type = cf;
  sc.roles.lifts.push_back(static_cast<int>(m.forces.size()));
}

void SceneBuilder::readConstant(const TomlReader& r, ForceElement<double>& f) {
  r.allowOnly({"name", "type", "body", "force"});
  f.type = ConstantForce<double>{bodyRef(r, "body", false), r.vec3("force")};
}

void SceneBuilder::readShockAbsorber(const TomlReader& r, ForceElement<double>& f) {
  r.allowOnly({"name", "type", "rod", "cylinder", "rod_point", "cylinder_point", "L0", "D", "D2", "p01", "Omega0",
               "n", "rho", "f1", "f1_table", "f2", "xi1", "xi2", "mu", "p_atm", "friction", "friction_velocity",
               "f1_extension", "f1_extension_table", "xi1_extension", "f2_extension", "xi2_extension", "p02",
               "Omega02", "n2", "f2_direction"});
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
  if (!(s.n >= 1)) r.fail("n", "polytropic exponent " + fmt(s.n) + " must be >= 1 (1: isothermal)");
  s.rho = r.positive("rho");
  s.xi1 = r.positive("xi1");
  readStrutOrifices(r, s);
  s.mu = r.nonNegative("mu", 0.0);
  s.pAtm = r.nonNegative("p_atm", 0.0);
  if (!(s.pAtm < s.p01)) r.fail("p_atm", "value " + fmt(s.pAtm) + " must be < p01 = " + fmt(s.p01) + " (the gas must push the rod out)");
  readStrutGas(r, s);
  const std::string law = r.string("friction", "regularised");
  if (law != "coulomb" && law != "regularised")
    r.fail("friction", "value '" + law + "' must be \"coulomb\" (exact stick/slip) or \"regularised\"");
  s.coulomb = law == "coulomb";
  if (s.coulomb && r.has("friction_velocity"))
    r.fail("friction_velocity", "applies to friction = \"regularised\" only (this strut's friction is \"coulomb\")");
  s.frictionVelocity = r.positive("friction_velocity", 1e-3);
  readStrutCheckValve(r, s);
  f.type = s;
  sc.roles.struts.push_back(static_cast<int>(m.forces.size()));
}

// The metering orifice (a constant area f1, or a table of the area over the stroke) and the rebound
// orifice f2.
void SceneBuilder::readStrutOrifices(const TomlReader& r, ShockAbsorber<double>& s) {
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
  if (r.has("f2_direction")) {  // the rebound orifice by direction (a one-way orifice)
    if (!r.has("f2")) r.fail("f2_direction", "names the direction of the rebound orifice f2: give f2 (and xi2)");
    const std::string d = r.string("f2_direction");
    if (d == "both") s.f2Direction = 0;
    else if (d == "compression") s.f2Direction = 1;
    else if (d == "extension") s.f2Direction = -1;
    else r.fail("f2_direction", "value '" + d + "' must be \"both\", \"compression\" or \"extension\"");
  }
}

// Two-stage gas spring: a second chamber behind a floating piston (p02 and Omega02; n2 defaults to n).
void SceneBuilder::readStrutGas(const TomlReader& r, ShockAbsorber<double>& s) {
  s.twoStage = r.has("p02") || r.has("Omega02") || r.has("n2");
  if (s.twoStage) {
    if (!r.has("p02")) r.fail(r.has("Omega02") ? "Omega02" : "n2", "a second gas chamber needs both p02 and Omega02");
    if (!r.has("Omega02")) r.fail("p02", "a second gas chamber needs both p02 and Omega02");
    s.p02 = r.positive("p02");
    if (!(s.p02 > s.p01)) r.fail("p02", "value " + fmt(s.p02) + " must be > p01 = " + fmt(s.p01) + " (the second stage engages when p_1 reaches it)");
    s.Omega02 = r.positive("Omega02");
    s.n2 = r.positive("n2", s.n);
    if (!(s.n2 >= 1)) r.fail("n2", "polytropic exponent " + fmt(s.n2) + " must be >= 1 (1: isothermal)");
  }
}

// Orifices by direction (a check valve): the extension's area and loss coefficient of each orifice,
// each defaulting to its compression one's.
void SceneBuilder::readStrutCheckValve(const TomlReader& r, ShockAbsorber<double>& s) {
  for (const char* k : {"f1_extension", "f1_extension_table", "xi1_extension", "f2_extension", "xi2_extension"})
    s.checkValve = s.checkValve || r.has(k);
  if (!s.checkValve) return;
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

void SceneBuilder::readTyre(const TomlReader& r, ForceElement<double>& f) {
  r.allowOnly({"name", "type", "body", "point", "radius", "K", "delta_max", "alpha", "ground_normal", "ground_height",
               "law", "exponent", "load_table", "c", "damping_exponent", "damping_law", "damping_ratio", "damping_mass",
               "damping_direction", "mu_x", "slip_ratio", "forward"});
  Tyre<double> t;
  t.body = bodyRef(r, "body", false);
  const Vec3<double> centre = r.vec3("point", poses[t.body].r);
  t.rho = toBody(t.body, centre);
  t.normal = r.unitVec3("ground_normal", Vec3<double>(0, 1, 0));
  t.groundHeight = r.number("ground_height", 0.0);
  t.radius = r.positive("radius");
  readTyreLaw(r, t);
  readTyreDamping(r, t);
  readTyreLongitudinal(r, t);
  f.type = t;
  sc.roles.tyres.push_back(static_cast<int>(m.forces.size()));
}

// The damping: its coefficient's law (power: c, damping_exponent; stiffness: damping_ratio, damping_mass)
// and its direction; a key of the other law is named, never ignored.
void SceneBuilder::readTyreDamping(const TomlReader& r, Tyre<double>& t) {
  const std::string law = r.string("damping_law", "power");
  if (law != "power" && law != "stiffness")
    r.fail("damping_law", "value '" + law + "' must be \"power\" (c (delta/delta_max)^q) or \"stiffness\" (2 zeta sqrt(k_t m))");
  if (law == "stiffness") {
    for (const char* key : {"c", "damping_exponent"})
      if (r.has(key)) r.fail(key, "not a parameter of damping_law = \"stiffness\" (it uses damping_ratio, damping_mass)");
    t.damped = true;
    t.dampingLaw = TyreDampingLaw::Stiffness;
    t.dampingRatio = r.positive("damping_ratio");
    t.dampingMass = r.positive("damping_mass");
  } else {
    for (const char* key : {"damping_ratio", "damping_mass"})
      if (r.has(key)) r.fail(key, "a parameter of damping_law = \"stiffness\" (this tyre's damping law is \"power\")");
    t.damped = r.has("c");
    if (!t.damped && r.has("damping_exponent")) r.fail("damping_exponent", "needs the damping coefficient c");
    t.c = r.nonNegative("c", 0.0);
    t.dampingExponent = r.nonNegative("damping_exponent", 0.0);
  }
  const std::string dir = r.string("damping_direction", "both");
  if (dir != "both" && dir != "compression")
    r.fail("damping_direction", "value '" + dir + "' must be \"both\" or \"compression\" (the damping acts while the tyre compresses only)");
  if (r.has("damping_direction") && !t.damped)
    r.fail("damping_direction", "needs a damping law (c, or damping_law = \"stiffness\")");
  t.compressionOnly = dir == "compression";
}

// The load law and the keys it takes (a key of another law is named, never ignored).
void SceneBuilder::readTyreLaw(const TomlReader& r, Tyre<double>& t) {
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
}

// Longitudinal friction (mu_x, with its slip ratio and forward direction): the ground moves aft under
// the tyre at a case's forward speed.
void SceneBuilder::readTyreLongitudinal(const TomlReader& r, Tyre<double>& t) {
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
}

void SceneBuilder::readSpringDamper(const TomlReader& r, ForceElement<double>& f) {
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
}

void SceneBuilder::readBushing(const TomlReader& r, ForceElement<double>& f) {
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
}

void SceneBuilder::readBearingFriction(const TomlReader& r, ForceElement<double>& f) {
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
}

// |g| and up from the gravity element; each lift element's unit direction (up unless declared), which
// a case scales.
void SceneBuilder::finishLifts() {
  if (hasGravity) {
    sc.gravity = g.norm();
    sc.up = -g / g.norm();
  }
  for (int li : sc.roles.lifts) {
    TomlReader r(*forceTables[li], file, "force[" + std::to_string(li) + "]");
    if (!hasGravity) r.fail("type", "a lift element needs a gravity element (lift = ratio * G * g)");
    const Vec3<double> dir = r.unitVec3("direction", sc.up);
    std::get<ConstantForce<double>>(m.forces[li].type).force = dir;  // unit direction until a case scales it
  }
}

// Bearing friction on the slide of a Coulomb strut (the same rod and cylinder) shares that strut's
// friction lock (bearing_friction.hpp): the strut's points must lie on the joint's axis (then the lock's
// rate is the slide's, up to the sign c recorded here).
// The elastic stops, after every [[force]] row.
void SceneBuilder::finishStops() {
  for (const auto& [f, entry] : pads) {
    sc.roles.pads.push_back(static_cast<int>(m.forces.size()));
    sc.roles.padEntry.push_back(entry);
    m.forces.push_back(f);
  }
}

void SceneBuilder::finishBearings() {
  for (size_t f = 0; f < m.forces.size(); ++f) {
    auto* b = std::get_if<BearingFriction<double>>(&m.forces[f].type);
    if (!b) continue;
    for (size_t g = 0; g < m.forces.size(); ++g) {
      const auto* s = std::get_if<ShockAbsorber<double>>(&m.forces[g].type);
      if (!s || !s->coulomb || !((s->bi == b->bi && s->bj == b->bj) || (s->bi == b->bj && s->bj == b->bi))) continue;
      auto at = [&](int body, const Vec3<double>& rho) { return body < 0 ? rho : Vec3<double>(poses[body].r + poses[body].R * rho); };
      const Vec3<double> e = (b->bj < 0 ? Mat3<double>::Identity() : poses[b->bj].R) * b->n_a.cross(b->n_b);
      const Vec3<double> p0 = at(b->bi, b->rho_1), B = at(s->bi, s->rho_i), C = at(s->bj, s->rho_j);
      TomlReader r(*forceTables[f], file, "force[" + std::to_string(f) + "]");
      for (const Vec3<double>& p : {B, C}) {
        const Vec3<double> d = p - p0;
        const double off = (d - e * e.dot(d)).norm();
        if (off > 1e-6)
          r.fail("joint", "the Coulomb strut '" + m.forces[g].name + "' on this slide has a point " + fmt(off) +
                              " m off the joint's axis (tolerance 1e-6 m): its friction and the bearings' share one "
                              "friction lock, which needs the strut along the slide");
      }
      if (r.has("friction_velocity"))
        r.fail("friction_velocity", "applies to bearing friction alone (on this slide it shares the exact Coulomb friction "
                                    "of strut '" + m.forces[g].name + "')");
      // sdot_lock = -e_s.(u_B - u_C), e_s = (B - C)/|B - C|; the rod moving along e at sdot: u_B - u_C = +-sdot e.
      const double c = -(B - C).normalized().dot(e) * (s->bi == b->bi ? 1.0 : -1.0);
      b->strut = static_cast<int>(g);
      b->slideSign = c > 0 ? 1 : -1;
      break;
    }
  }
}

// The airframe: declared, else the body of the first lift element.
void SceneBuilder::findAirframe() {
  if (!airframe.empty()) {
    if (m.bodyIndex(airframe) < 0) {
      TomlReader r(*doc["scene"].as_table(), file, "scene");
      r.fail("airframe", "'" + airframe + "' is not a body of this scene");
    }
    sc.roles.airframe = airframe;
  } else if (!sc.roles.lifts.empty()) {
    sc.roles.airframe = m.bodies[std::get<ConstantForce<double>>(m.forces[sc.roles.lifts[0]].type).body].name;
  }
}

}  // namespace lg::detail
