// Model<S>: what the scene declares, built once by the parser and never changed by a run.
// The engine's free functions take (model, state, work) like MuJoCo's mj_step(m, d).
#pragma once

#include <string>
#include <vector>

#include "sim/constraints/constraint.hpp"
#include "sim/forces/force_element.hpp"

namespace lg {

enum class MultiplierSolver { Direct, GaussSeidel };
enum class IntegratorKind { SemiImplicitEuler, RK4, DormandPrince, Ros2, Ros34pw2 };
// The linearly implicit (Rosenbrock-W) integrators: they need the force elements' damping terms.
inline bool isRosenbrock(IntegratorKind k) { return k == IntegratorKind::Ros2 || k == IntegratorKind::Ros34pw2; }
// The fixed-step integrators (semi-implicit Euler, RK4).
inline bool isFixedStep(IntegratorKind k) { return k == IntegratorKind::SemiImplicitEuler || k == IntegratorKind::RK4; }
enum class Stabilization { Projection, Baumgarte, None };

struct Settings {
  MultiplierSolver solver = MultiplierSolver::Direct;
  IntegratorKind integrator = IntegratorKind::DormandPrince;
  Stabilization stabilization = Stabilization::Projection;
  double rtol = 1e-6;                 // [-] relative tolerance (adaptive)
  double atol = 1e-8;                 // [m, m/s, rad/s] absolute tolerance (adaptive)
  double step = 1e-4;                 // [s] fixed step; first trial step of the adaptive pair
  double maxStep = 1e-2;              // [s] largest adaptive step
  long maxSteps = 5'000'000;          // a run stops with a failure status beyond this
  double projectionTolerance = 1e-9;  // [m] project positions when |C| exceeds this (and J V likewise, [m/s])
  double baumgarteAlpha = 10.0;       // [1/s] 2 alpha dC/dt
  double baumgarteBeta = 10.0;        // [1/s] beta^2 C
  int gaussSeidelIterations = 10000;  // Gauss-Seidel sweeps at most (large mass ratios converge slowly)
  double gaussSeidelTolerance = 1e-9;   // [-] relative residual of the multipliers' equations
  double contactTolerance = 1e-7;     // [m] a stop within this is touching
  double eventTolerance = 1e-12;      // [s] width of the bracket of a located event
  bool profile = false;               // time each stage of the step
  double accuracy = 0;                // [-] the relative accuracy these settings were chosen for (applyAccuracy), 0: none
  // [-] > 0: a dopri5 run that finds itself stiff (Hairer's test: h |lambda| at its stability bound on 15
  // steps with fewer than 6 between them that are not) goes on with ros34pw2 at this rtol (atol rtol / 100),
  // from the step that showed it (sim/engine/integration/stiffness.hpp). 0: dopri5 to the end.
  double stiffSwitchRtol = 0;
  bool eliminateGroundJoints = true;  // a body's prismatic or fixed joint to the ground restricts its
                                      // mobility instead of adding rows (exact; see Model::finalize)
  // [-] a planar model's plane normal n (unit; zero: the model moves in space). Every free body then moves
  // in the plane: it translates perpendicular to n and rotates about n (Mobility kPlanar), the rows a
  // planar motion satisfies by itself are not solved (impliedPlanarRows), and an out-of-plane component
  // of a force is carried by the plane.
  Vec3<double> planeNormal = Vec3<double>::Zero();
  bool planar() const { return planeNormal.squaredNorm() > 0; }
};

template <class S> struct Model {
  std::vector<Body<S>> bodies;
  std::vector<Constraint<S>> constraints;
  std::vector<ForceElement<S>> forces;
  Settings settings;

  // Derived once by finalize(): the row table and the sizes of the state.
  std::vector<RowInfo> rowInfo;   // one per scalar constraint row, then the force elements' friction locks
  std::vector<int> rowOffset;     // first row of each constraint
  std::vector<int> lockRow;       // per force element: its friction-lock row, or -1
  std::vector<int> bearingForces;  // the force elements with joint friction from bearing reactions (engine: bearingFriction)
  std::vector<signed char> mobility;    // per body: kFree, kTranslation / kImmobile by an eliminated ground joint, kPlanar
  std::vector<Vec3<S>> mobilityAxis;    // per body: the world axis of a kTranslation body, the plane normal of a kPlanar one
  std::vector<int> dissipationOffset, eventOffset, outputOffset, dampingOffset;  // per force element
  int nRows = 0, nDissipation = 0, nForceEvents = 0, nOutputs = 0, nDamping = 0;
  int nErrorChannels = 0;         // the first dissipation channels, error-controlled like x and V
  std::vector<char> inputChannel; // per dissipation channel: it holds work put in (booked negative), not dissipation
  std::vector<std::string> outputNames;  // "<element>.<channel>"

  int nBodies() const { return static_cast<int>(bodies.size()); }
  int nx() const { return 7 * nBodies(); }
  int nv() const { return 6 * nBodies(); }
  int ny() const { return nx() + nv() + nDissipation; }
  int nErr() const { return nx() + nv() + nErrorChannels; }  // the error-controlled part of y

  // The layout of everything the engine indexes, after the parser (or cast) filled the model: the
  // bodies' mobility, the constraint and friction-lock rows, the force elements' channels.
  void finalize() {
    rowInfo.clear();
    rowOffset.clear();
    const std::vector<char> eliminated = restrictMobility();
    layoutRows(eliminated);
    layoutForceChannels();
  }

 private:
  // Which constraints are eliminated into a body's mobility (1 each) rather than enforced by rows.
  std::vector<char> restrictMobility() {
    // A prismatic joint between a body and the ground lets the body translate along a fixed world axis
    // only, a fixed joint not move at all: the body's inverse mass restricted to that subspace
    // (BodyKin::invMassTimes) is the exact Schur complement of the joint's rows, which are then not
    // built (rowOffset -1). One such joint per body; a second one keeps its rows.
    mobility.assign(bodies.size(), kFree);
    mobilityAxis.assign(bodies.size(), Vec3<S>::Zero());
    std::vector<char> eliminated(constraints.size(), 0);
    // A joint with bearing friction keeps its rows: the friction reads their multipliers.
    std::vector<char> keep(constraints.size(), 0);
    for (const auto& f : forces)
      if (const auto* bf = std::get_if<BearingFriction<S>>(&f.type); bf && bf->joint >= 0) keep[bf->joint] = 1;
    for (int c = 0; settings.eliminateGroundJoints && c < static_cast<int>(constraints.size()); ++c) {
      if (keep[c]) continue;
      if (const auto* p = std::get_if<Prismatic<S>>(&constraints[c].type)) {
        const int b = p->bj == kGround ? p->bi : (p->bi == kGround ? p->bj : kGround);
        if (b == kGround || mobility[b] != kFree) continue;
        Vec3<S> a = p->bj == kGround ? Vec3<S>(p->n_a.cross(p->n_b)) : Vec3<S>(p->rho_i2 - p->rho_i1);
        mobility[b] = kTranslation;
        mobilityAxis[b] = a / a.norm();
        eliminated[c] = 1;
      } else if (const auto* f = std::get_if<Fixed<S>>(&constraints[c].type)) {
        const int b = f->bj == kGround ? f->bi : (f->bi == kGround ? f->bj : kGround);
        if (b == kGround || mobility[b] != kFree) continue;
        mobility[b] = kImmobile;
        eliminated[c] = 1;
      }
    }
    // A planar model: every body not restricted above moves in the plane (BodyKin::invMassTimes).
    if (settings.planar())
      for (size_t b = 0; b < bodies.size(); ++b)
        if (mobility[b] == kFree) {
          mobility[b] = kPlanar;
          mobilityAxis[b] = settings.planeNormal.template cast<S>();
        }
    return eliminated;
  }
  // The rows: each constraint's (none for an eliminated one: rowOffset -1), then the friction locks'.
  void layoutRows(const std::vector<char>& eliminated) {
    for (int c = 0; c < static_cast<int>(constraints.size()); ++c) {
      if (eliminated[c]) {
        rowOffset.push_back(-1);
        continue;
      }
      rowOffset.push_back(static_cast<int>(rowInfo.size()));
      for (int k = 0; k < constraints[c].rows(); ++k)
        rowInfo.push_back({constraints[c].bodyI(), constraints[c].bodyJ(), constraints[c].unilateral(), c});
    }
    // A force element with exact Coulomb friction (stick/slip) owns one row: the lock that holds its
    // rate at zero while it sticks (enforced only then; see sim/forces/friction_lock.hpp).
    lockRow.assign(forces.size(), -1);
    for (int f = 0; f < static_cast<int>(forces.size()); ++f) {
      const FrictionLockInfo li = forces[f].frictionLock();
      forces[f].setLockRow(li.present ? static_cast<int>(rowInfo.size()) : -1);
      if (!li.present) continue;
      lockRow[f] = static_cast<int>(rowInfo.size());
      RowInfo ri;
      ri.bi = li.bi;
      ri.bj = li.bj;
      ri.force = f;
      rowInfo.push_back(ri);
    }
    nRows = static_cast<int>(rowInfo.size());
    bearingForces.clear();
    for (int f = 0; f < static_cast<int>(forces.size()); ++f)
      if (auto* bf = std::get_if<BearingFriction<S>>(&forces[f].type)) {
        bf->jointRow = bf->joint >= 0 ? rowOffset[bf->joint] : -1;
        bf->lockRow = bf->strut >= 0 ? lockRow[bf->strut] : -1;  // joined to the strut's lock (exact friction)
        bearingForces.push_back(f);
      }
  }
  // The force elements' dissipation, event, output and damping channels.
  void layoutForceChannels() {
    dissipationOffset.clear();
    eventOffset.clear();
    outputOffset.clear();
    dampingOffset.clear();
    outputNames.clear();
    nDissipation = nForceEvents = nOutputs = nDamping = nErrorChannels = 0;
    // The error-controlled dissipation channels come first in z (the integrators control y up to
    // nx + nv + nErrorChannels), the others after them, each element's channels together.
    dissipationOffset.assign(forces.size(), 0);
    for (size_t f = 0; f < forces.size(); ++f)
      if (forces[f].dissipationErrorControlled()) {
        dissipationOffset[f] = nErrorChannels;
        nErrorChannels += forces[f].dissipationChannels();
      }
    nDissipation = nErrorChannels;
    for (size_t f = 0; f < forces.size(); ++f)
      if (!forces[f].dissipationErrorControlled()) {
        dissipationOffset[f] = nDissipation;
        nDissipation += forces[f].dissipationChannels();
      }
    inputChannel.assign(nDissipation, 0);
    for (size_t f = 0; f < forces.size(); ++f)
      for (int k = forces[f].dissipationChannels() - forces[f].inputChannels(); k < forces[f].dissipationChannels(); ++k)
        inputChannel[dissipationOffset[f] + k] = 1;
    for (const auto& f : forces) {
      dampingOffset.push_back(nDamping);
      nDamping += f.dampingTerms();
      eventOffset.push_back(nForceEvents);
      outputOffset.push_back(nOutputs);
      nForceEvents += f.eventCount();
      for (const auto& n : f.outputNames()) outputNames.push_back(f.name + "." + n);
      nOutputs += static_cast<int>(f.outputNames().size());
    }
  }

 public:
  template <class T> Model<T> cast() const {
    Model<T> m;
    for (const auto& b : bodies) m.bodies.push_back(b.template cast<T>());
    for (const auto& c : constraints) m.constraints.push_back(c.template cast<T>());
    for (const auto& f : forces) m.forces.push_back(f.template cast<T>());
    m.settings = settings;
    m.finalize();
    return m;
  }

  int bodyIndex(const std::string& name) const {
    for (int b = 0; b < nBodies(); ++b)
      if (bodies[b].name == name) return b;
    return name == "ground" ? kGround : -2;
  }
  int forceIndex(const std::string& name) const {
    for (int f = 0; f < static_cast<int>(forces.size()); ++f)
      if (forces[f].name == name) return f;
    return -1;
  }
  int constraintIndex(const std::string& name) const {
    for (int c = 0; c < static_cast<int>(constraints.size()); ++c)
      if (constraints[c].name == name) return c;
    return -1;
  }
};

}  // namespace lg
