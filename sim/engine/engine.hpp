// The engine: the named stages of one evaluation of the equations of motion (method.md),
//
//   M dV/dt = F + J^T lambda,     J dV/dt = -dJ/dt V  (- Baumgarte terms)    for every enforced row,
//
// and the operations around it: contact-mode resolution (which stops are in contact), plastic impacts
// and projection onto the constraint manifold. Free functions f(model, state/y, work), no allocation.
#pragma once

#include <cmath>
#include <limits>

#include "sim/model/state.hpp"
#include "sim/engine/multipliers.hpp"

namespace lg {

// ---- stage: kinematics ---------------------------------------------------------------------------
// Poses and velocities only (r, R, v, w): what an observer of outputs needs, no inertia.
template <class S> void poses(const Model<S>& m, const VecX<S>& y, Workspace<S>& w) {
  const int N = m.nBodies();
  for (int b = 0; b < N; ++b) {
    BodyKin<S>& K = w.kin[b];
    K.r = y.template segment<3>(7 * b);
    K.R = rotation<S>(Vec4<S>(y.template segment<4>(7 * b + 3)));
    K.v = y.template segment<3>(7 * N + 6 * b);
    K.w = y.template segment<3>(7 * N + 6 * b + 3);
  }
}
template <class S> void kinematics(const Model<S>& m, const VecX<S>& y, Workspace<S>& w) {
  ScopedStage timer(w.timer, kKinematics, m.settings.profile);
  poses(m, y, w);
  const int N = m.nBodies();
  for (int b = 0; b < N; ++b) {
    BodyKin<S>& K = w.kin[b];
    const Body<S>& B = m.bodies[b];
    if (K.mobility == kPlanar) {  // the inverse inertia restricted to rotations about n (BodyKin::invMassTimes)
      const Vec3<S> u = K.R.transpose() * K.axis;
      K.IwInv = K.axis * (K.axis.transpose() / B.inertia.dot(u.cwiseProduct(u)));
    } else {
      K.IwInv = K.R * B.inertia.cwiseInverse().asDiagonal() * K.R.transpose();
    }
    K.I0 = B.inertia;
    K.mass = B.mass;
    K.invMass = S(1) / B.mass;
  }
}

// ---- stage: forces -------------------------------------------------------------------------------
// wrench_b = (f_b, tau_b - w_b x I_b w_b); dissipation rates; force-element event functions.
template <class S> void forces(const Model<S>& m, Workspace<S>& w) {
  ScopedStage timer(w.timer, kForces, m.settings.profile);
  const int N = m.nBodies();
  for (int b = 0; b < N; ++b) {
    w.wrench[b].template head<3>().setZero();
    w.wrench[b].template tail<3>() = -w.kin[b].w.cross(w.kin[b].angularMomentum());
  }
  const Kins<S> K = w.kins();
  const Wrenches<S> W{w.wrench.data()};
  for (size_t f = 0; f < m.forces.size(); ++f) {
    S* diss = w.dissipation.data() + m.dissipationOffset[f];
    S* ev = w.forceEvents.data() + m.eventOffset[f];
    std::visit(
        [&](const auto& e) {
          e.apply(K, W, diss);
          e.events(K, ev);
        },
        m.forces[f].type);
  }
  for (int b = 0; b < N; ++b) {
    const BodyKin<S>& K = w.kin[b];
    if (K.mobility == kFree) {
      w.aFree[b].template head<3>() = K.invMass * w.wrench[b].template head<3>();
      w.aFree[b].template tail<3>() = K.IwInv * w.wrench[b].template tail<3>();
    } else {
      w.aFree[b] = K.invMassTimes(w.wrench[b].template head<3>(), w.wrench[b].template tail<3>());
    }
  }
}

// ---- stage: constraint rows ----------------------------------------------------------------------
// Which rows an evaluation writes: all (its event functions follow) or those its solve reads.
enum class RowsFor { Events, Solve };

// Are the rows of unilateral constraint c all free in this mode (never for a bilateral one)?
template <class S> bool freeRows(const Model<S>& m, const std::vector<char>& enforced, int c) {
  for (int k = m.rowOffset[c]; k < m.nRows && m.rowInfo[k].constraint == c; ++k)
    if (!m.rowInfo[k].unilateral || enforced[k]) return false;
  return true;
}

// Every row at the current kinematics: the constraints', then the friction locks of the force elements
// (written whether enforced or not: a slipping lock's J V is the rate its slip event watches). With
// 'enforced' only the rows a solve in that mode reads: a free stop's or a slipping lock's row is left
// as it was (the stages of a step, whose event functions are taken at its end, and the projections).
// The rows the workspace marks implied by the mobility (w.implied) are never written.
template <class S> void constraintRows(const Model<S>& m, Workspace<S>& w, const std::vector<char>* enforced = nullptr) {
  ScopedStage timer(w.timer, kRows, m.settings.profile);
  const Kins<S> K = w.kins();
  for (size_t c = 0; c < m.constraints.size(); ++c) {
    if (m.rowOffset[c] < 0) continue;  // a joint to the ground eliminated into its body's mobility
    if (enforced && freeRows(m, *enforced, static_cast<int>(c))) continue;
    Row<S>* rows = w.rows.data() + m.rowOffset[c];
    const ImpliedRows implied{w.implied.data() + m.rowOffset[c]};
    std::visit([&](const auto& con) { con.write(K[con.bi], K[con.bj], rows, implied); }, m.constraints[c].type);
  }
  for (size_t f = 0; f < m.forces.size(); ++f) {
    if (m.lockRow[f] < 0 || (enforced && !(*enforced)[m.lockRow[f]])) continue;
    Row<S>& row = w.rows[m.lockRow[f]];
    std::visit([&](const auto& e) { if constexpr (requires { e.writeLock(K, row); }) e.writeLock(K, row); },
               m.forces[f].type);
  }
}

// Only the rows of the constraint or force element that owns row k (the same values constraintRows
// writes for them): what an event function of one row needs on the dense output.
template <class S> void ownerRows(const Model<S>& m, Workspace<S>& w, int k) {
  ScopedStage timer(w.timer, kRows, m.settings.profile);
  const Kins<S> K = w.kins();
  const RowInfo& ri = m.rowInfo[k];
  if (ri.friction()) {
    Row<S>& row = w.rows[k];
    std::visit([&](const auto& e) { if constexpr (requires { e.writeLock(K, row); }) e.writeLock(K, row); },
               m.forces[ri.force].type);
    return;
  }
  Row<S>* rows = w.rows.data() + m.rowOffset[ri.constraint];
  const ImpliedRows implied{w.implied.data() + m.rowOffset[ri.constraint]};
  std::visit([&](const auto& con) { con.write(K[con.bi], K[con.bj], rows, implied); }, m.constraints[ri.constraint].type);
}

// J_k V for row k.
template <class S> S rowVelocity(const Model<S>& m, const Workspace<S>& w, int k) {
  const RowInfo& ri = m.rowInfo[k];
  S s(0);
  if (ri.bi >= 0) s += w.rows[k].Ji.template head<3>().dot(w.kin[ri.bi].v) + w.rows[k].Ji.template tail<3>().dot(w.kin[ri.bi].w);
  if (ri.bj >= 0) s += w.rows[k].Jj.template head<3>().dot(w.kin[ri.bj].v) + w.rows[k].Jj.template tail<3>().dot(w.kin[ri.bj].w);
  return s;
}
// J_k a for a per-body 6-vector field a.
template <class S> S rowDot(const Model<S>& m, const Workspace<S>& w, int k, const std::vector<Vec6<S>>& a) {
  const RowInfo& ri = m.rowInfo[k];
  S s(0);
  if (ri.bi >= 0) s += w.rows[k].Ji.dot(a[ri.bi]);
  if (ri.bj >= 0) s += w.rows[k].Jj.dot(a[ri.bj]);
  return s;
}

template <class S> void listActiveRows(const Model<S>& m, const std::vector<char>& active, Workspace<S>& w) {
  w.list.clear();
  for (int k = 0; k < m.nRows; ++k)
    if (active[k]) w.list.push_back(k);
}

// ---- stage: multipliers --------------------------------------------------------------------------
// lambda for the rows enforced in this mode: J M^-1 J^T lambda = -gamma - J a_free (- Baumgarte).
template <class S> bool multipliers(const Model<S>& m, const std::vector<char>& active, VecX<S>& lambdaAll,
                                    Workspace<S>& w) {
  ScopedStage timer(w.timer, kMultipliers, m.settings.profile);
  listActiveRows(m, active, w);
  computeW(m, w);
  assembleA(m, w);
  const bool baumgarte = m.settings.stabilization == Stabilization::Baumgarte;
  const S alpha2(2 * m.settings.baumgarteAlpha), beta2(m.settings.baumgarteBeta * m.settings.baumgarteBeta);
  for (size_t a = 0; a < w.list.size(); ++a) {
    const int k = w.list[a];
    const RowInfo& ri = m.rowInfo[k];
    S Ja = S(0);
    if (ri.bi >= 0) Ja += dot6(w.rows[k].Ji.data(), w.aFree[ri.bi].data());
    if (ri.bj >= 0) Ja += dot6(w.rows[k].Jj.data(), w.aFree[ri.bj].data());
    w.b[a] = -w.rows[k].gamma - Ja;
    if (baumgarte) w.b[a] -= alpha2 * rowVelocity(m, w, k) + beta2 * w.rows[k].C;
    w.lam[a] = lambdaAll[k];  // warm start
  }
  const bool ok = solveEquality(m, w, false);
  for (int k = 0; k < m.nRows; ++k) lambdaAll[k] = S(0);
  for (size_t a = 0; a < w.list.size(); ++a) lambdaAll[w.list[a]] = w.lam[a];
  w.rowLambda = lambdaAll;
  return ok;
}

// ---- stage: joint friction from bearing reactions (sim/forces/bearing_friction.hpp) -------------
// The friction F of each bearing-friction element depends on its joint's multipliers, which depend on
// the friction: the fixed-point iteration F -> lambda -> F from the friction-free multipliers, each step
// one solve on the factor of the multipliers' stage (direct) or a warm-started Gauss-Seidel, until
// |dF| <= 1e-12 (1 + |F|), or until it reaches its round-off floor (|dF| <= 1e-9 (1 + |F|) and no longer
// halving: F is a small difference of large multipliers when the joint's reactions nearly cancel), which
// it does when mu times the joint's lever ratio is below 1 (a contraction). Then the
// friction's accelerations join aFree and its dissipation rates are written. Returns false (the
// evaluation fails) without convergence in 60 iterations. Nothing when no scene declares bearing friction,
// no iteration while none slides (joined to a stuck or held lock: the lock's reaction carries it).
template <class S> bool bearingFriction(const Model<S>& m, VecX<S>& lambdaAll, Workspace<S>& w) {
  if (m.bearingForces.empty()) return true;
  const int n = static_cast<int>(w.list.size()), nb = static_cast<int>(m.bearingForces.size());
  const Kins<S> K = w.kins();
  auto element = [&](int q) -> const BearingFriction<S>& { return std::get<BearingFriction<S>>(m.forces[m.bearingForces[q]].type); };
  bool anySliding = false;
  for (int q = 0; q < nb; ++q) anySliding = anySliding || element(q).sliding(K);
  if (!anySliding) {
    for (int q = 0; q < nb; ++q) w.dissipation[m.dissipationOffset[m.bearingForces[q]]] = S(0);
    return true;
  }
  for (int a = 0; a < n; ++a) w.bearingB0[a] = w.b[a];
  for (int q = 0; q < nb; ++q) w.bearingF[q] = element(q).eval(K, lambdaAll.data() + element(q).jointRow).force;
  bool converged = false;
  double lastChange = std::numeric_limits<double>::infinity();
  for (int it = 0; it < 60 && !converged; ++it) {
    for (auto& z : w.zb) z.setZero();
    for (int q = 0; q < nb; ++q) {
      const BearingFriction<S>& e = element(q);
      const auto r = e.eval(K, lambdaAll.data() + e.jointRow);
      Vec6<S> onRod, onCylinder;
      e.wrench(r, w.bearingF[q], onRod, onCylinder);
      if (e.bi >= 0) w.zb[e.bi] += w.kin[e.bi].invMassTimes(onRod.template head<3>(), onRod.template tail<3>());
      if (e.bj >= 0) w.zb[e.bj] += w.kin[e.bj].invMassTimes(onCylinder.template head<3>(), onCylinder.template tail<3>());
    }
    if (n > 0) {
      for (int a = 0; a < n; ++a) w.b[a] = w.bearingB0[a] - rowDot(m, w, w.list[a], w.zb);
      if (m.settings.solver == MultiplierSolver::Direct) {
        for (int a = 0; a < n; ++a) w.lam[a] = w.b[a];
        solveA(w, w.lam);
      } else if (!solveEquality(m, w, false)) {
        return false;
      }
      for (int a = 0; a < n; ++a) lambdaAll[w.list[a]] = w.lam[a];
    }
    // (once converged, F stays the one lambda was solved with)
    double change = 0;  // the largest |dF| / (1 + |F|)
    for (int q = 0; q < nb; ++q) {
      w.bearingFNext[q] = element(q).eval(K, lambdaAll.data() + element(q).jointRow).force;
      change = std::max(change, std::abs(value(w.bearingFNext[q] - w.bearingF[q])) / (1.0 + std::abs(value(w.bearingF[q]))));
    }
    converged = change <= 1e-12 || (change <= 1e-9 && change >= 0.5 * lastChange);  // (or at the round-off floor)
    lastChange = change;
    if (!converged) w.bearingF = w.bearingFNext;
  }
  if (!converged) return false;
  w.rowLambda = lambdaAll;
  for (int b = 0; b < m.nBodies(); ++b) w.aFree[b] += w.zb[b];
  for (int q = 0; q < nb; ++q) {
    const BearingFriction<S>& e = element(q);
    w.dissipation[m.dissipationOffset[m.bearingForces[q]]] = w.bearingF[q] * e.eval(K, lambdaAll.data() + e.jointRow).sdot;
  }
  return true;
}

// ---- stage: stiffness terms (for the linearly implicit integrators) -----------------------------
// For each term (G, c, k) of the force elements (DampingTerm): u = M_c^-1 G^T, the constrained
// acceleration response to a unit generalised force along G^T:
//   u = M^-1 G^T - M^-1 J^T mu,   J M^-1 J^T mu = J M^-1 G^T   (the enforced rows of this evaluation)
// so that d(dV/dt)/dV ~ -sum c u G and d(dV/dt)/dx ~ -sum k u ds/dx. Reuses the multipliers' factor
// (direct) or iterates on A (GS).
template <class S> void dampingResponse(const Model<S>& m, Workspace<S>& w) {
  const Kins<S> K = w.kins();
  for (size_t f = 0; f < m.forces.size(); ++f)
    std::visit([&](const auto& e) { e.damping(K, w.damping.data() + m.dampingOffset[f]); }, m.forces[f].type);
  const int N = m.nBodies(), n = static_cast<int>(w.list.size());
  for (int e = 0; e < m.nDamping; ++e) {
    const DampingTerm<S>& d = w.damping[e];
    if (exactZero(d.c) && exactZero(d.k)) continue;  // no part of W (a tyre in the air): its column is never read
    for (auto& z : w.zb) z.setZero();
    auto addBody = [&](int b, const Vec6<S>& G) {
      if (b < 0) return;
      w.zb[b] += w.kin[b].invMassTimes(G.template head<3>(), G.template tail<3>());
    };
    addBody(d.bi, d.Gi);
    addBody(d.bj, d.Gj);
    for (int a = 0; a < n; ++a) w.dampRhs[a] = rowDot(m, w, w.list[a], w.zb);
    if (m.settings.solver == MultiplierSolver::Direct) {
      for (int a = 0; a < n; ++a) w.dampMu[a] = w.dampRhs[a];
      solveA(w, w.dampMu);
    } else {  // Gauss-Seidel on the assembled A
      for (int a = 0; a < n; ++a) w.dampMu[a] = S(0);
      for (int it = 0; it < m.settings.gaussSeidelIterations; ++it) {
        double worst = 0;
        for (int a = 0; a < n; ++a) {
          S r = w.dampRhs[a];
          for (int c = 0; c < n; ++c) r -= w.A(a, c) * w.dampMu[c];
          w.dampMu[a] += r / w.A(a, a);
          worst = std::max(worst, std::abs(value(r)));
        }
        if (worst <= 1e-12 * (1.0 + std::abs(value(w.dampRhs.head(n).cwiseAbs().maxCoeff())))) break;
      }
    }
    for (int a = 0; a < n; ++a) {
      const int k = w.list[a];
      const RowInfo& ri = m.rowInfo[k];
      if (ri.bi >= 0) w.zb[ri.bi] -= w.Wi[k] * w.dampMu[a];
      if (ri.bj >= 0) w.zb[ri.bj] -= w.Wj[k] * w.dampMu[a];
    }
    for (int b = 0; b < N; ++b) w.U.col(e).template segment<6>(6 * b) = w.zb[b];
  }
}

// ---- the right-hand side: dy/dt ------------------------------------------------------------------
// Runs kinematics, forces, rows, multipliers; writes ydot (x rates, accelerations, dissipation rates).
template <class S> bool evaluate(const Model<S>& m, const VecX<S>& y, const std::vector<char>& active,
                                 VecX<S>& lambda, Workspace<S>& w, VecX<S>& ydot, RowsFor rowsFor = RowsFor::Events) {
  ++w.rhsEvaluations;
  kinematics(m, y, w);
  forces(m, w);
  constraintRows(m, w, rowsFor == RowsFor::Solve ? &active : nullptr);
  const bool ok = multipliers(m, active, lambda, w) && bearingFriction(m, lambda, w);
  const int N = m.nBodies();
  for (int b = 0; b < N; ++b) {
    Vec6<S> a = w.aFree[b];
    ydot.template segment<3>(7 * b) = w.kin[b].v;
    ydot.template segment<4>(7 * b + 3) = quaternionRate<S>(y.template segment<4>(7 * b + 3), w.kin[b].w);
    ydot.template segment<6>(7 * N + 6 * b) = a;
  }
  for (size_t a = 0; a < w.list.size(); ++a) {
    const int k = w.list[a];
    const RowInfo& ri = m.rowInfo[k];
    if (ri.bi >= 0) ydot.template segment<6>(7 * N + 6 * ri.bi) += w.Wi[k] * w.lam[a];
    if (ri.bj >= 0) ydot.template segment<6>(7 * N + 6 * ri.bj) += w.Wj[k] * w.lam[a];
  }
  ydot.tail(m.nDissipation) = w.dissipation;
  if (w.needDampingResponse && m.nDamping > 0 && ok) dampingResponse(m, w);
  return ok;
}

// ---- energy --------------------------------------------------------------------------------------
template <class S> struct EnergyReport {
  S kinetic = S(0);     // [J]
  S stored = S(0);      // [J] potential of gravity and constant forces, gas, tyre, springs
  S dissipated = S(0);  // [J] orifices, friction, dampers, plastic impacts
  S input = S(0);       // [J] minus the work put in by moving surroundings (the ground under a rolling tyre)
  S total() const { return kinetic + stored + dissipated + input; }
};
// Kinematics must be current (kinematics(m, y, w) for state.y).
template <class S> EnergyReport<S> energy(const Model<S>& m, const State<S>& s, const Workspace<S>& w) {
  EnergyReport<S> e;
  for (int b = 0; b < m.nBodies(); ++b) {
    const BodyKin<S>& K = w.kin[b];
    e.kinetic += S(0.5) * K.mass * K.v.squaredNorm() + S(0.5) * K.w.dot(K.angularMomentum());
  }
  const Kins<S> K = w.kins();
  for (const auto& f : m.forces) e.stored += std::visit([&](const auto& el) { return el.stored(K); }, f.type);
  for (int c = 0; c < m.nDissipation; ++c) (m.inputChannel[c] ? e.input : e.dissipated) += s.y[m.nx() + m.nv() + c];
  e.dissipated += s.impactLoss;
  return e;
}

// ---- applying a correction M^-1 J^T mu ------------------------------------------------------------
// to positions (as a displacement (dr, dtheta) per body) or to velocities.
template <class S> void applyCorrection(const Model<S>& m, Workspace<S>& w, VecX<S>& y, bool toPositions) {
  const int N = m.nBodies();
  for (auto& a : w.aFree) a.setZero();  // reuse as the per-body correction
  for (size_t a = 0; a < w.list.size(); ++a) {
    const int k = w.list[a];
    const RowInfo& ri = m.rowInfo[k];
    if (ri.bi >= 0) w.aFree[ri.bi] += w.Wi[k] * w.lam[a];
    if (ri.bj >= 0) w.aFree[ri.bj] += w.Wj[k] * w.lam[a];
  }
  for (int b = 0; b < N; ++b) {
    if (toPositions) {
      y.template segment<3>(7 * b) += w.aFree[b].template head<3>();
      const Vec4<S> q = y.template segment<4>(7 * b + 3);
      y.template segment<4>(7 * b + 3) = rotateQuaternion<S>(q, w.aFree[b].template tail<3>());
    } else {
      y.template segment<6>(7 * N + 6 * b) += w.aFree[b];
    }
  }
}

// Puts the velocity of every guided, immobile or planar body (Model::finalize) in its subspace: v along
// its axis (the mass-weighted projection: translation only, isotropic mass), no rotation; for a planar
// body with normal n, v without its n part and omega along n.
// Returns whether a velocity changed.
template <class S> bool projectMobility(const Model<S>& m, VecX<S>& y) {
  const int N = m.nBodies();
  bool changed = false;
  for (int b = 0; b < N; ++b) {
    if (m.mobility[b] == kFree) continue;
    const Vec6<S> before = y.template segment<6>(7 * N + 6 * b);
    Vec3<S> v = before.template head<3>(), omega = before.template tail<3>();
    restrictToMobility(m.mobility[b], m.mobilityAxis[b], v, omega);
    y.template segment<3>(7 * N + 6 * b) = v;
    y.template segment<3>(7 * N + 6 * b + 3) = omega;
    for (int i = 0; i < 6; ++i) changed = changed || value(before[i]) != value(y[7 * N + 6 * b + i]);
  }
  return changed;
}

// The rows a planar model's motion satisfies by itself (Settings::planar): a joint's row along the normal
// (a point's out-of-plane offset, a tilt about an in-plane axis) has no part in the bodies' plane motions,
// and a row whose plane part repeats other rows' (a revolute joint's second axis point) adds nothing to
// them. Such a bilateral row is taken out of the mode at the run's start (active 0: never solved,
// projected or reported; its multiplier 0): the rows' plane parts, J P with P each body's motions, at the
// current positions, by Gram-Schmidt in row order; a row whose remainder is below 1e-8 of its own plane
// part (or which has none) is implied. Its constraint then holds to round-off as long as the others do
// (the motion stays in the plane). Unilateral rows and friction locks always stay. The workspace marks
// them (w.implied): constraintRows no longer writes them. Rows and kinematics are left at s.y.
// Allocates (once per run, before the first step).
template <class S> int impliedPlanarRows(const Model<S>& m, State<S>& s, Workspace<S>& w) {
  std::fill(w.implied.begin(), w.implied.end(), 0);
  if (!m.settings.planar()) return 0;
  kinematics(m, s.y, w);
  constraintRows(m, w);
  const int N = m.nBodies();
  auto plain = [](const S* x) { return Vec3<double>(value(x[0]), value(x[1]), value(x[2])); };
  auto planePart = [&](int b, const Vec6<S>& J, Eigen::VectorXd& v) {
    if (b < 0) return;
    Vec3<double> f = plain(J.data()), t = plain(J.data() + 3);
    restrictToMobility(m.mobility[b], plain(m.mobilityAxis[b].data()), f, t);
    v.segment<3>(6 * b) += f;
    v.segment<3>(6 * b + 3) += t;
  };
  std::vector<Eigen::VectorXd> basis;
  int implied = 0;
  for (int k = 0; k < m.nRows; ++k) {
    const RowInfo& ri = m.rowInfo[k];
    if (ri.unilateral || ri.friction() || !s.active[k]) continue;
    Eigen::VectorXd v = Eigen::VectorXd::Zero(6 * N);
    planePart(ri.bi, w.rows[k].Ji, v);
    planePart(ri.bj, w.rows[k].Jj, v);
    const double own = v.norm();
    for (int pass = 0; pass < 2; ++pass)  // (twice, for round-off)
      for (const auto& e : basis) v -= e.dot(v) * e;
    if (own > 0 && v.norm() > 1e-8 * own) {
      basis.push_back(v / v.norm());
      continue;
    }
    s.active[k] = 0;
    s.lambda[k] = S(0);
    ++implied;
  }
  for (int k = 0; k < m.nRows; ++k)  // (found now, or out of the mode in the state given)
    if (!m.rowInfo[k].unilateral && !m.rowInfo[k].friction() && !s.active[k]) w.implied[k] = 1;
  return implied;
}

// Keeps every quaternion of unit length.
template <class S> void normalizeQuaternions(const Model<S>& m, VecX<S>& y) {
  for (int b = 0; b < m.nBodies(); ++b) {
    const Vec4<S> q = y.template segment<4>(7 * b + 3);
    y.template segment<4>(7 * b + 3) = q / q.norm();
  }
}

// Largest |C| and |J V| over the enforced rows (rows must be current).
template <class S> void violation(const Model<S>& m, const std::vector<char>& active, const Workspace<S>& w,
                                  double& position, double& velocity) {
  position = velocity = 0;
  for (int k = 0; k < m.nRows; ++k) {
    if (!active[k]) continue;
    position = std::max(position, std::abs(value(w.rows[k].C)));
    velocity = std::max(velocity, std::abs(value(rowVelocity(m, w, k))));
  }
}

// ---- stage: stabilise ----------------------------------------------------------------------------
// Projection onto the constraint manifold, mass-weighted (the smallest correction in the kinetic-energy
// metric): positions by Gauss-Newton, x += M^-1 J^T mu with J M^-1 J^T mu = -C, then velocities,
// V += M^-1 J^T mu with J M^-1 J^T mu = -J V. Only the enforced rows take part. The corrections are
// tiny (a step's drift), so J M^-1 J^T is factored once, at the first iterate (simplified Newton): each
// further iteration contracts the violation by |I - A A_0^-1| ~ the relative change of A (~1e-6), and
// the velocity projection leaves |J V| at that fraction of its start. Iterates to 1 % of the tolerance.
// With 'factorNearby' the caller says that the workspace holds the factor of J M^-1 J^T (and W) for these
// rows at a nearby state (the step's last evaluation): the Gauss-Newton iteration uses it instead of
// factoring anew (it then contracts by the relative change of A over that distance, ~1e-3 for a stage
// of the step, and takes the same two or three iterations).
// With 'rowsCurrent' the caller says that s.y's quaternions are of unit length and that the workspace
// holds the kinematics and every row at s.y: the first iteration reads them instead of computing them
// again (a step's end, checked for its violation before it is projected).
template <class S> bool project(const Model<S>& m, State<S>& s, Workspace<S>& w, bool factorNearby = false,
                                bool rowsCurrent = false) {
  ScopedStage timer(w.timer, kStabilise, m.settings.profile);
  if (!rowsCurrent) normalizeQuaternions(m, s.y);
  const double tol = m.settings.projectionTolerance;
  bool factored = false;
  if (factorNearby && m.settings.solver == MultiplierSolver::Direct) {
    listActiveRows(m, s.active, w);
    factored = w.pairList == w.list;  // the factor in the workspace is of this row list
  }
  auto factorOnce = [&]() {
    if (factored) return true;
    listActiveRows(m, s.active, w);
    computeW(m, w);
    assembleA(m, w);
    factored = true;
    return factorA(w);
  };
  bool current = false;  // kinematics and rows at the final positions
  for (int it = 0; it < 8; ++it) {
    if (it > 0 || !rowsCurrent) {
      kinematics(m, s.y, w);
      constraintRows(m, w, &s.active);
    }
    double pos, vel;
    violation(m, s.active, w, pos, vel);
    if (pos <= 0.01 * tol) {
      current = true;
      break;
    }
    if (!factorOnce()) return false;
    for (size_t a = 0; a < w.list.size(); ++a) w.lam[a] = -w.rows[w.list[a]].C;
    solveA(w, w.lam);
    applyCorrection(m, w, s.y, true);
  }
  if (projectMobility(m, s.y)) current = false;
  if (!current) {
    kinematics(m, s.y, w);
    constraintRows(m, w, &s.active);
  }
  if (factored) computeW(m, w);     // the correction directions at the final positions
  else if (!factorOnce()) return false;  // (no position iteration: W and the factor are current)
  for (size_t a = 0; a < w.list.size(); ++a) w.lam[a] = -rowVelocity(m, w, w.list[a]);
  solveA(w, w.lam);
  applyCorrection(m, w, s.y, false);
  return true;  // (the workspace's velocities are those before the correction: callers evaluate anew)
}

// ---- stage: events (contact modes) ---------------------------------------------------------------
// Which stops are enforced. Touching stops (|C| <= contactTolerance, or C < 0) are candidates. Those
// approaching (J V < 0) first receive a plastic impact: the impulse P solves the velocity-level mixed
// LCP  J M^-1 J^T P = -J V  (bilateral rows: equality; stops: P >= 0, J V+ >= 0, complementary), and
// the kinetic energy it removes is booked as dissipated. Then the acceleration-level LCP decides
// which candidates stay enforced (lambda > 0) and which separate.
// Returns the number of stops whose mode changed, or -1 on a solver failure.
template <class S> int resolveFriction(const Model<S>& m, State<S>& s, Workspace<S>& w);

template <class S> void setSlip(State<S>& s, Workspace<S>& w, int k, int sigma);
constexpr double kLockRestSpeed = 1e-6;  // [m/s] a friction lock slower than this is at rest

// Sets every slipping friction lock that is at rest to undecided (rows must be current); returns
// whether any was.
template <class S> bool releaseRestingSlips(const Model<S>& m, State<S>& s, Workspace<S>& w) {
  bool any = false;
  for (size_t f = 0; f < m.forces.size(); ++f) {
    const int k = m.lockRow[f];
    if (k < 0 || s.active[k] || s.slip[k] == 0) continue;
    if (std::abs(value(rowVelocity(m, w, k))) > kLockRestSpeed) continue;
    setSlip(s, w, k, 0);
    any = true;
  }
  return any;
}

template <class S> int resolveContacts(const Model<S>& m, State<S>& s, Workspace<S>& w) {
  ScopedStage timer(w.timer, kEvents, m.settings.profile);
  w.slip = s.slip;
  kinematics(m, s.y, w);
  forces(m, w);
  constraintRows(m, w);
  const double ctol = m.settings.contactTolerance;
  bool anyCandidate = false, approaching = false;
  for (int k = 0; k < m.nRows; ++k) {
    w.candidate[k] = 0;
    if (!m.rowInfo[k].unilateral) continue;
    // C is in the stop's own units (m^2 for a distance stop): compare a length.
    const double C = value(w.rows[k].C);
    const double scale = std::max(1e-12, std::sqrt(std::abs(value(w.rows[k].Ji.template head<3>().squaredNorm()))));
    if (C / scale <= ctol || s.active[k]) {
      w.candidate[k] = 1;
      anyCandidate = true;
      if (value(rowVelocity(m, w, k)) < -1e-12) approaching = true;
    }
  }
  if (!anyCandidate) {
    if (releaseRestingSlips(m, s, w)) forces(m, w);
    int changed = 0;
    for (int k = 0; k < m.nRows; ++k)
      if (m.rowInfo[k].unilateral && s.active[k]) { s.active[k] = 0; ++changed; }
    const int fr = resolveFriction(m, s, w);
    return fr < 0 ? -1 : changed + fr;
  }
  // The stops are decided without the friction locks (a stop between the strut's own bodies would
  // repeat a lock's row); resolveFriction then decides the locks given the stops.
  auto buildList = [&]() {
    w.list.clear();
    for (int k = 0; k < m.nRows; ++k)
      if (!m.rowInfo[k].friction() && (m.rowInfo[k].unilateral ? w.candidate[k] : s.active[k])) w.list.push_back(k);
    computeW(m, w);
    assembleA(m, w);
  };
  if (approaching) {  // plastic impact
    EnergyReport<S> before = energy(m, s, w);
    buildList();
    for (size_t a = 0; a < w.list.size(); ++a) w.b[a] = -rowVelocity(m, w, w.list[a]);
    if (!solveLcp(m, w)) return -1;
    applyCorrection(m, w, s.y, false);
    kinematics(m, s.y, w);
    forces(m, w);
    constraintRows(m, w);
    EnergyReport<S> after = energy(m, s, w);
    s.impactLoss += before.kinetic - after.kinetic;
  }
  // A friction lock that slips but is at rest now (an impact stopped its strut) has no direction any
  // more: its friction is off while the stops are decided, so that a stop between the strut's bodies
  // takes the load (the friction is then held), and resolveFriction decides it afresh if no stop does.
  // Left slipping, its full friction could let the stop go (lambda = 0 within the contact band, where
  // a free stop's event no longer watches it) although the strut then moves on into it.
  if (releaseRestingSlips(m, s, w)) forces(m, w);
  buildList();
  for (size_t a = 0; a < w.list.size(); ++a) {
    const int k = w.list[a];
    w.b[a] = -w.rows[k].gamma - rowDot(m, w, k, w.aFree);
  }
  if (!solveLcp(m, w)) return -1;
  int changed = 0;
  for (int k = 0; k < m.nRows; ++k)
    if (m.rowInfo[k].unilateral && !w.candidate[k] && s.active[k]) { s.active[k] = 0; ++changed; }
  // A stop whose multiplier is zero to round-off (relative to the largest of the solve) is not
  // enforced: a strut whose friction just reached its bound leaves its stop with the stop's reaction
  // exactly zero.
  double lamScale = 0;
  for (size_t a = 0; a < w.list.size(); ++a) lamScale = std::max(lamScale, std::abs(value(w.lam[a])));
  for (size_t a = 0; a < w.list.size(); ++a) {
    const int k = w.list[a];
    if (!m.rowInfo[k].unilateral) continue;
    const char on = value(w.lam[a]) > 1e-12 * lamScale ? 1 : 0;
    if (on != s.active[k]) ++changed;
    s.active[k] = on;
    s.lambda[k] = w.lam[a];
  }
  const int fr = resolveFriction(m, s, w);
  return fr < 0 ? -1 : changed + fr;
}

// ---- friction modes (sim/forces/friction_lock.hpp) ------------------------------------------------
// The friction bound F_max of lock row k at the current kinematics.
// With bearing friction joined to the lock (the same slide), its share mu (|N_u| + |N_l|) from the
// multipliers of the last solve is added: one bound for the slide's friction.
template <class S> S frictionBound(const Model<S>& m, const Workspace<S>& w, int k) {
  const Kins<S> K = w.kins();
  S bound = std::visit(
      [&](const auto& e) -> S {
        if constexpr (requires { e.frictionBound(K); }) return e.frictionBound(K);
        else return S(0);
      },
      m.forces[m.rowInfo[k].force].type);
  for (int f : m.bearingForces)
    if (const auto& b = std::get<BearingFriction<S>>(m.forces[f].type); b.lockRow == k) bound += b.lockBound(K);
  return bound;
}

// Is lock row k held by an enforced stop between the same two bodies?
template <class S> bool frictionHeld(const Model<S>& m, const State<S>& s, int k) {
  const RowInfo& f = m.rowInfo[k];
  for (int r = 0; r < m.nRows; ++r) {
    const RowInfo& ri = m.rowInfo[r];
    if (ri.unilateral && s.active[r] && ((ri.bi == f.bi && ri.bj == f.bj) || (ri.bi == f.bj && ri.bj == f.bi)))
      return true;
  }
  return false;
}

// Sets the slip direction of lock row k in the state and in the workspace's copy (what the force
// elements read).
template <class S> void setSlip(State<S>& s, Workspace<S>& w, int k, int sigma) {
  s.slip[k] = static_cast<signed char>(sigma);
  w.slip[k] = static_cast<signed char>(sigma);
}

// Decides the mode of every friction lock that is at rest and undecided (not stuck, not slipping: its
// rate stopped, its stop let go, or the run starts), and holds the locks of struts whose stop is
// enforced. A lock at rest sticks if the acceleration-level problem with it enforced needs
// |lambda| <= F_max, else it slips with sigma = -sgn(lambda). Kinematics, forces and rows must be
// current. Returns the number of locks whose mode changed, or -1 on a solver failure.
template <class S> int resolveFriction(const Model<S>& m, State<S>& s, Workspace<S>& w) {
  int changed = 0;
  for (size_t f = 0; f < m.forces.size(); ++f) {
    const int k = m.lockRow[f];
    if (k < 0) continue;
    if (frictionHeld(m, s, k)) {
      if (s.active[k] || s.slip[k]) ++changed;
      s.active[k] = 0;
      setSlip(s, w, k, 0);
      continue;
    }
    if (s.active[k] || s.slip[k]) continue;  // stuck or slipping: its events decide
    const double rate = value(rowVelocity(m, w, k));
    if (std::abs(rate) > kLockRestSpeed) {  // not at rest after all: it slips the way it moves
      setSlip(s, w, k, rate > 0 ? 1 : -1);
      ++changed;
      continue;
    }
    s.active[k] = 1;  // try to stick
    forces(m, w);                            // (the lock's friction term is off while it is tried)
    if (!multipliers(m, s.active, s.lambda, w)) return -1;
    const S lam = s.lambda[k];
    if (std::abs(value(lam)) <= value(frictionBound(m, w, k))) {
      ++changed;
      continue;
    }
    s.active[k] = 0;
    s.lambda[k] = S(0);
    setSlip(s, w, k, value(lam) > 0 ? -1 : 1);
    ++changed;
  }
  if (changed) forces(m, w);
  return changed;
}

}  // namespace lg
