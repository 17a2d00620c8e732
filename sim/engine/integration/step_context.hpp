// The state of a run that the step functions share (StepContext), its status (RunStatus), and the
// pieces every method uses: failing with a reason, refreshing f and the event functions, stabilising
// an accepted state, and the verdict on a trial step.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "sim/engine/engine.hpp"
#include "sim/engine/integration/dense_output.hpp"
#include "sim/engine/integration/event_functions.hpp"
#include "sim/engine/integration/stiffness.hpp"

namespace lg {

struct RunStatus {
  bool ok = true;
  std::string message;
  long steps = 0, rejected = 0, events = 0, projections = 0;
  double maxPositionViolation = 0;  // [m] largest |C| seen at the end of a step (before projection)
  double maxVelocityViolation = 0;  // [m/s]
  double stiffFrom = std::numeric_limits<double>::quiet_NaN();  // [s] where a dopri5 run found itself stiff and
                                                                // went on with ros34pw2 to the end; NaN: never
  int handBacks = 0;                // hand-overs to ros34pw2 that cost more than dopri5 and were handed back
};

// A run that stops making progress ends at once with a failed status saying why, instead of spending
// its step limit (minutes): kEvents events (stops, friction modes, force switches) within a thousandth
// of the run's length (modes that alternate at one instant: stick and slip both inconsistent, a contact
// made and let go), or an adaptive run's kSteps steps within a millionth of it (a step size that
// collapsed). A drop takes some ten events and a few thousand steps in all. stalled() is called before
// each step with the run's counts so far; "" while it progresses.
struct ProgressWatch {
  static constexpr long kEvents = 2000, kSteps = 20000;
  double t0;         // [s] where the counts were last taken
  long events0 = 0, steps0 = 0;
  std::string stalled(double t, double tEnd, long events, long steps, bool adaptive) {
    const double span = std::max(tEnd, 1e-3);
    if (events - events0 >= kEvents) {
      if (t - t0 < 1e-3 * span)
        return "no progress: " + std::to_string(events - events0) + " events within " + shortNumber(t - t0) +
               " s (contact or friction modes alternating: the mode problem has no consistent solution here)";
      t0 = t, events0 = events, steps0 = steps;
    }
    if (steps - steps0 >= kSteps) {
      if (adaptive && t - t0 < 1e-6 * span)
        return "no progress: " + std::to_string(steps - steps0) + " steps within " + shortNumber(t - t0) +
               " s (the step size collapsed)";
      t0 = t, events0 = events, steps0 = steps;
    }
    return {};
  }
  static std::string shortNumber(double x) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.3g", x);
    return buf;
  }
};

// What every step function works on: the model, the state it advances, the workspace, the dense output
// of the last accepted step and the step-size controller's memory.
template <class S> struct StepContext {
  const Model<S>& m;
  State<S>& s;
  Workspace<S>& w;
  DenseOutput<S> dense;
  double errOld = 1e-4;  // error of the last accepted step (PI control)
  double rtol = 0, atol = 0;  // the adaptive steps' tolerances: the settings', or after a switch to ros34pw2 its own
  StiffnessTest stiffness;    // dopri5's test of h |lambda| against its stability bound
  StiffHandOver handOver;     // and the cost of acting on it
  bool touchdown = false;     // the event just handled was a touchdown (events.hpp: endOnEvent)
};

template <class S> RunStatus& fail(StepContext<S>& c, RunStatus& st, const std::string& why) {
  st.ok = false;
  st.message = why + " at t = " + std::to_string(value(c.s.t)) + " s";
  return st;
}

template <class S> bool allFinite(const VecX<S>& v) {
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!isFinite(v[i])) return false;
  return true;
}

template <class S> void forceOutputs(StepContext<S>& c) {
  const Kins<S> K = c.w.kins();
  for (size_t f = 0; f < c.m.forces.size(); ++f)
    std::visit([&](const auto& e) { e.outputs(K, c.w.outputs.data() + c.m.outputOffset[f]); }, c.m.forces[f].type);
}

// The time the first tyre in the air that falls toward the ground takes to touch it, on the parabola of
// its present gap, rate and acceleration: delta + delta' tau + delta'' tau^2 / 2 = 0 (the outputs and
// w.ydot at the step's start; delta'' = -n . a_p, a_p the wheel point's acceleration); infinity when none
// does. An adaptive step ends no later: a step across the touchdown integrates the impact's first
// instants with the flight's stages, and its dense output, on which the contact is located, then
// misplaces the state there (a drop from a height, the bounce of a free drop). The flight under gravity
// and lift is that parabola, so the step ends on the touchdown to round-off. (On the rate alone,
// -delta/delta', the gear falling faster crossed within the last step by up to ~1e-4 s, and the drop's
// energy balance took an error of 1e-5 from the dense output across the kink there.)
template <class S> double touchdownHorizon(const StepContext<S>& c) {
  double horizon = std::numeric_limits<double>::infinity();
  const int N = c.m.nBodies();
  for (size_t f = 0; f < c.m.forces.size(); ++f) {
    const auto* tyre = std::get_if<Tyre<S>>(&c.m.forces[f].type);
    if (!tyre) continue;
    const S* out = c.w.outputs.data() + c.m.outputOffset[f];  // delta, P_t, delta', ...
    const double delta = value(out[0]), rate = value(out[2]);
    if (!(delta < 0) || tyre->body < 0) continue;
    const BodyKin<S>& K = c.w.kin[tyre->body];
    const Vec3<double> arm = (K.R * tyre->rho).unaryExpr([](const S& x) { return value(x); });
    const Vec3<double> om = K.w.unaryExpr([](const S& x) { return value(x); });
    Vec6<double> a;
    for (int i = 0; i < 6; ++i) a[i] = value(c.w.ydot[7 * N + 6 * tyre->body + i]);
    const Vec3<double> ap = a.head<3>() + a.tail<3>().cross(arm) + om.cross(om.cross(arm));
    const double acc = -tyre->normal.unaryExpr([](const S& x) { return value(x); }).dot(ap);
    const double disc = rate * rate - 2 * acc * delta;  // (delta < 0)
    if (!(disc >= 0)) continue;
    const double den = rate + std::sqrt(disc);
    if (den > 0) horizon = std::min(horizon, -2 * delta / den);
  }
  return horizon;
}

// f at the current state into w.ydot (always the derivative at s.y), event functions into g0.
template <class S> bool refresh(StepContext<S>& c) {
  const bool ok = evaluate(c.m, c.s.y, c.s.active, c.s.lambda, c.w, c.w.ydot);
  eventFunctions(c.m, c.s, c.s.lambda, c.w, c.w.g0);
  freeStopRates(c.m, c.s, c.w, c.w.gRate0);
  forceOutputs(c);
  return ok && allFinite(c.w.ydot);
}

template <class S> bool failNonFinite(StepContext<S>& c, RunStatus& st) {
  fail(c, st, "non-finite state (a force or multiplier overflowed)");
  return false;
}

// The stabilisation of an accepted state (the rows in the workspace must be current at s.y): records
// the violation, then projects onto the constraint manifold if it exceeds the tolerance, or else only
// renormalises the quaternions. 'normalised': the caller made the quaternions of unit length before it
// computed the rows, so the projection starts from those rows (project's rowsCurrent). Returns false if
// the projection fails; 'projected' says if it ran.
template <class S> bool stabilise(StepContext<S>& c, RunStatus& st, bool& projected, bool normalised = false) {
  const Settings& cfg = c.m.settings;
  double pos, vel;
  violation(c.m, c.s.active, c.w, pos, vel);
  st.maxPositionViolation = std::max(st.maxPositionViolation, pos);
  st.maxVelocityViolation = std::max(st.maxVelocityViolation, vel);
  projected = cfg.stabilization == Stabilization::Projection &&
              (pos > cfg.projectionTolerance || vel > cfg.projectionTolerance);
  if (!projected) {
    if (!normalised) normalizeQuaternions(c.m, c.s.y);
    return true;
  }
  ++st.projections;
  return project(c.m, c.s, c.w, /*factorNearby=*/true, normalised);  // the step's last evaluation factored A nearby
}

// After an accepted step or event whose end was evaluated: stabilise if needed, then refresh f and g.
template <class S> bool afterStep(StepContext<S>& c, RunStatus& st) {
  bool projected = false;
  if (!stabilise(c, st, projected)) return false;
  return projected ? refresh(c) : true;
}

// The verdict on a trial step of an adaptive method with error norm err (1 = the tolerance): a
// non-finite trial is retried at a quarter of the step, one over the tolerance at the size its error
// suggests (0.9 err^-expo, at least a fifth); a step that underflows fails the run.
enum class Trial { Accept, Retry, Fail };
// What became of an accepted trial (a method's accept stage): the step is done, it is tried again
// smaller (a friction slip that reversed unseen inside it), or the run failed (the reason in its status).
enum class Accepted { Done, Retry, Failed };
template <class S> Trial judge(StepContext<S>& c, bool ok, double err, double expo, double& h, RunStatus& st) {
  if (!ok || !allFinite(c.w.y1) || !std::isfinite(err)) {
    if (h < 1e-12) {
      failNonFinite(c, st);
      return Trial::Fail;
    }
    h *= 0.25;
    ++st.rejected;
    return Trial::Retry;
  }
  if (err <= 1.0) return Trial::Accept;
  h *= std::max(0.2, 0.9 * std::pow(err, -expo));
  ++st.rejected;
  if (h < 1e-14) {
    fail(c, st, "step size underflow");
    return Trial::Fail;
  }
  return Trial::Retry;
}

}  // namespace lg
