// State<S>: what changes during a run. Workspace<S>: every buffer the step needs, sized once.
#pragma once

#include <array>
#include <chrono>
#include <vector>

#include "sim/constraints/row.hpp"
#include "sim/model/model.hpp"

namespace lg {

// y = [ x (per body: r (3), q (4)) ; V (per body: v (3), omega (3)) ; z (dissipated energy per channel) ]
template <class S> struct State {
  S t = S(0);                // [s]
  VecX<S> y;                 // see above; r [m], q [-], v [m/s], omega [rad/s], z [J]
  VecX<S> lambda;            // multipliers of every row (last solve; warm start of Gauss-Seidel)
  std::vector<char> active;  // per row: 1 if it is enforced (bilateral rows always; stops in contact;
                             // friction locks while stuck)
  std::vector<signed char> slip;  // per friction-lock row: slip direction +1 / -1, 0 if not slipping
  S impactLoss = S(0);       // [J] kinetic energy removed by plastic impacts

  explicit State(const Model<S>& m = Model<S>())
      : y(VecX<S>::Zero(m.ny())), lambda(VecX<S>::Zero(m.nRows)), active(m.nRows, 1), slip(m.nRows, 0) {
    for (int b = 0; b < m.nBodies(); ++b) y[7 * b + 3] = S(1);
    for (int k = 0; k < m.nRows; ++k) active[k] = (m.rowInfo[k].unilateral || m.rowInfo[k].friction()) ? 0 : 1;
  }

  // Accessors for body b of a model with N bodies.
  static Eigen::Index rIndex(int b) { return 7 * b; }
  static Eigen::Index qIndex(int b) { return 7 * b + 3; }
  static Eigen::Index vIndex(int N, int b) { return 7 * N + 6 * b; }
  static Eigen::Index wIndex(int N, int b) { return 7 * N + 6 * b + 3; }
};

enum Stage { kKinematics, kForces, kRows, kMultipliers, kIntegrate, kStabilise, kEvents, kStageCount };
inline const char* stageName(int s) {
  static const char* names[] = {"kinematics", "forces", "constraint rows", "multipliers", "integrate", "stabilise",
                                "events"};
  return names[s];
}

struct StageTimer {
  std::array<double, kStageCount> seconds{};
  std::array<long, kStageCount> calls{};
};

// One term of J M^-1 J^T: A[target] += J_k(side) . W_l(side), target being the flat index of the
// entry in the solver's storage (see assembleA). The sides are those of the term's group in pairs.
struct PairTerm {
  int target;  // flat index into the envelope of A
  int j, w;    // byte offsets of row k's J block (Ji or Jj) in the rows and of row l's W block in Wi or Wj
};

// One update of the supernodal factor: L[dst] -= L[a .. a + width) . L[b .. b + width) (flat indices).
struct FactorUpdate {
  int dst, a, b;
};

// The structure of the direct factor for one row list (analyseA, assembleA): kept for the few lists a
// run switches between (contact and friction modes), so that a switch back costs a copy, not an analysis.
struct FactorStructure {
  std::vector<int> list, order, pos, below, belowStart, envFirst, envStart, superStart, rowAt, superRows, superRowAt,
      superRowStart, updateStart;
  std::vector<FactorUpdate> updates;
  std::vector<PairTerm> pairs;
  std::array<int, 5> pairGroup{};
};

// What the last multiplier solve reports.
struct SolveReport {
  int iterations = 0;       // Gauss-Seidel sweeps (0 for the direct solve)
  double residual = 0.0;    // largest |A lambda - b| after the solve
  bool ok = true;
};

// A flag set for a scope and restored at its end (or earlier, by restore()): the workspace's
// needDampingResponse while events are located, the drop observer's need for the locks' reactions.
struct ScopedFlag {
  bool& flag;
  const bool saved;
  ScopedFlag(bool& f, bool on) : flag(f), saved(f) { f = on; }
  ~ScopedFlag() { flag = saved; }
  ScopedFlag(const ScopedFlag&) = delete;
  ScopedFlag& operator=(const ScopedFlag&) = delete;
  void restore() { flag = saved; }
};

template <class S> struct Workspace {
  std::vector<BodyKin<S>> kin;       // N bodies + ground
  std::vector<Vec6<S>> wrench;       // (f, tau - w x I w) per body
  std::vector<Vec6<S>> aFree;        // M^-1 (f, tau) per body
  std::vector<Row<S>> rows;          // every row at the current configuration (but the implied ones)
  std::vector<char> implied;         // per row: satisfied by the bodies' mobility (impliedPlanarRows), not
                                     // written by constraintRows (never in a solve, projection or event)
  std::vector<Vec6<S>> Wi, Wj;       // M^-1 J^T per row, body i and body j parts
  std::vector<int> list;             // the rows in the current solve
  MatX<S> A;                         // J M^-1 J^T over 'list'
  VecX<S> b, lam, work;              // right-hand side, multipliers, scratch
  VecX<S> rowLambda;                 // per row: the multipliers of the last solve (0 where not enforced)
  std::vector<signed char> slip;     // per row: the friction modes of the run's state (State::slip), read by
                                     // the force elements through Kins (set by setFrictionModes)
  VecX<S> dissipation;               // dissipation rate per channel [W]
  VecX<S> forceEvents;               // force-element event functions
  VecX<S> outputs;                   // named outputs of the force elements
  VecX<S> ydot;                      // derivative of y
  std::vector<VecX<S>> stages;       // integrator stages k1..k7
  VecX<S> y0, y1, yerr, ytmp;        // integrator scratch
  VecX<S> yStiff;                    // dopri5: its 6th stage's argument y*, for the stiffness test
  Eigen::VectorXd errTerm;           // the scaled error of each component of a trial step
  VecX<S> g0, g1, g2, gtmp;          // event functions at step start / end / trials
  VecX<S> gRate0, gRate1;            // a free stop's dC/dt = J V at step start / end (interior dips)
  VecX<S> fTmp, lamTmp;              // scratch for event location
  std::vector<char> candidate;       // per row: touching stop considered by a contact solve
  std::vector<int> pairList;         // the row list the pair terms were built for
  std::vector<DampingTerm<S>> damping, damping0;  // velocity stiffness of the force elements (ros2, ros34pw2)
  bool needDampingResponse = false;  // evaluate() also computes U (set by the Rosenbrock integrators)
  MatX<S> U, U0;                     // M_c^-1 G^T per damping term (constrained response), nv x nDamping
  std::vector<Vec6<S>> zb;           // per-body scratch
  VecX<S> bearingB0, bearingF, bearingFNext;  // bearing friction: the friction-free right-hand side, F_f per element (and the next iterate)
  VecX<S> dampRhs, dampMu, smallT;   // scratch of the response and of the W solve
  MatX<S> smallM;                    // (I + G U C), nDamping x nDamping
  std::vector<int> termsInW;         // the terms of the W solve (those with a coefficient not exactly 0)
  int termsInWCount = 0;             // how many (prepareVelocityW, once per trial step)
  std::vector<int> smallPivot;       // the pivot rows of smallM's elimination
  VecX<S> coefInW, stiffInW;         // per term in W: gamma h (c + gamma h k); per term: gamma h k
  std::vector<PairTerm> pairs;       // terms of J M^-1 J^T for that list, grouped by the sides (i/j)
  std::array<int, 5> pairGroup{};    // of the two rows: terms [pairGroup[g], pairGroup[g+1]) have sides (g/2, g%2)
  std::vector<int> order, pos;       // elimination order of the factor (order[t]: list index; pos: inverse)
  std::vector<char> adjacency, eliminated;  // analyseA's scratch: the coupling of two rows (n x n), eliminated rows
  std::vector<int> degree;           // and each row's number of uneliminated neighbours
  std::vector<int> below, belowStart;  // symbolic factor: the positions t' > t with L(t', t) != 0
  std::vector<int> envFirst, envStart;  // envelope of the direct factor: row t holds L(t, envFirst[t]..t) from L[envStart[t]]
  VecX<S> L, invDiag;                // the packed envelope (A, then its factor), 1 / L(t, t)
  std::vector<int> superStart;       // supernodes: runs of columns [superStart[K], superStart[K+1]) sharing their structure
  std::vector<int> rowAt;            // flat index of L(i, first column of i's supernode)
  std::vector<int> superRows, superRowAt, superRowStart;  // the rows below each supernode, flat index of L(r, c0)
  std::vector<FactorUpdate> updates;  // the updates of each supernode, [updateStart[K], updateStart[K+1])
  std::vector<int> updateStart;
  std::array<FactorStructure, 4> structureCache;  // recently analysed row lists (filled at mode switches)
  int structureNext = 0;                           // the cache entry to overwrite next
  VecX<S> permTmp;                   // a right-hand side in elimination order
  MatX<S> lcpA, lcpAs;               // the contact LCP (mode switches): A over 'list', its block of the rows in
  VecX<S> lcpB, lcpLam, lcpX, lcpGap;  // its right-hand side, multipliers, the block's solution, A lambda - b
  std::vector<char> lcpIn;           // per list entry: in the active set
  std::vector<int> lcpIdx;           // the list entries in it
  SolveReport report;
  StageTimer timer;
  long rhsEvaluations = 0;

  explicit Workspace(const Model<S>& m) {
    const int N = m.nBodies(), R = m.nRows;
    kin.assign(N + 1, BodyKin<S>::ground());
    for (int b = 0; b < N; ++b) {
      kin[b].mobility = m.mobility[b];
      kin[b].axis = m.mobilityAxis[b];
      if (m.mobility[b] == kPlanar) kin[b].planeAxis = BodyKin<S>::coordinateAxis(m.mobilityAxis[b]);
    }
    wrench.assign(N, Vec6<S>::Zero());
    aFree.assign(N, Vec6<S>::Zero());
    rows.assign(R, Row<S>{S(0), S(0), Vec6<S>::Zero(), Vec6<S>::Zero()});
    implied.assign(R, 0);
    Wi.assign(R, Vec6<S>::Zero());
    Wj.assign(R, Vec6<S>::Zero());
    list.reserve(R);
    A = MatX<S>::Zero(R, R);
    b = lam = work = VecX<S>::Zero(R);
    rowLambda = VecX<S>::Zero(R);
    slip.assign(R, 0);
    dissipation = VecX<S>::Zero(m.nDissipation);
    forceEvents = VecX<S>::Zero(m.nForceEvents);
    outputs = VecX<S>::Zero(m.nOutputs);
    ydot = y0 = y1 = yerr = ytmp = yStiff = VecX<S>::Zero(m.ny());
    errTerm = Eigen::VectorXd::Zero(m.ny());
    stages.assign(7, VecX<S>::Zero(m.ny()));
    g0 = g1 = g2 = gtmp = VecX<S>::Zero(R + m.nForceEvents);
    gRate0 = gRate1 = VecX<S>::Zero(R);
    fTmp = VecX<S>::Zero(m.ny());
    lamTmp = VecX<S>::Zero(R);
    candidate.assign(R, 0);
    pairList.reserve(R);
    damping.assign(m.nDamping, DampingTerm<S>{});
    termsInW.assign(m.nDamping, 0);
    smallPivot.assign(m.nDamping, 0);
    coefInW = stiffInW = VecX<S>::Zero(m.nDamping);
    damping0 = damping;
    U = U0 = MatX<S>::Zero(m.nv(), m.nDamping);
    zb.assign(N, Vec6<S>::Zero());
    bearingB0 = VecX<S>::Zero(R);
    bearingF = bearingFNext = VecX<S>::Zero(static_cast<Eigen::Index>(m.bearingForces.size()));
    dampRhs = dampMu = VecX<S>::Zero(R);
    smallT = VecX<S>::Zero(m.nDamping);
    smallM = MatX<S>::Zero(m.nDamping, m.nDamping);
    pairs.reserve(static_cast<size_t>(2 * R * (R + 1)));
    order.reserve(R);
    pos.reserve(R);
    adjacency.assign(static_cast<size_t>(R) * R, 0);
    eliminated.assign(R, 0);
    degree.assign(R, 0);
    below.reserve(static_cast<size_t>(R * R));
    belowStart.reserve(R + 1);
    permTmp = VecX<S>::Zero(R);
    lcpA = lcpAs = MatX<S>::Zero(R, R);
    lcpB = lcpLam = lcpX = lcpGap = VecX<S>::Zero(R);
    lcpIn.assign(R, 0);
    lcpIdx.reserve(R);
    envFirst.reserve(R);
    envStart.reserve(R + 1);
    envStart.assign(1, 0);  // the structure of an empty row list (analyseA rebuilds it when the list changes)
    L = VecX<S>::Zero(R * (R + 1) / 2);
    invDiag = VecX<S>::Zero(R);
    superStart.reserve(R + 1);
    superStart.assign(1, 0);
    rowAt.reserve(R);
    superRows.reserve(static_cast<size_t>(R * R));
    superRowAt.reserve(static_cast<size_t>(R * R));
    superRowStart.reserve(R + 1);
    updates.reserve(static_cast<size_t>(R * (R + 1) / 2 * R));
    updateStart.reserve(R + 1);
  }
  Kins<S> kins() const { return {kin.data(), static_cast<int>(kin.size()) - 1, slip.data(), rowLambda.data()}; }
};

// Times a stage when the model asks for profiling; costs one branch otherwise.
class ScopedStage {
 public:
  ScopedStage(StageTimer& t, Stage s, bool on) : t_(t), s_(s), on_(on) {
    if (on_) start_ = std::chrono::steady_clock::now();
  }
  ~ScopedStage() {
    if (!on_) return;
    t_.seconds[s_] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    ++t_.calls[s_];
  }

 private:
  StageTimer& t_;
  Stage s_;
  bool on_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace lg
