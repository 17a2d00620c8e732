// Time integration of the index-1 equations with contact modes, events and stabilisation.
//
//   semi-implicit Euler   V += h dV/dt(x, V);  x += h dx/dt(x, V_new)              (fixed step)
//   RK4                   classical 4th order                                       (fixed step)
//   Dormand-Prince 5(4)   embedded pair, error control, FSAL, 4th-order dense output (adaptive)
//   ROS2, ROS34PW2        linearly implicit Rosenbrock-W methods of order 2 and 3 with embedded
//                         error estimates (adaptive): the strut's velocity stiffness is implicit
//
// Between events the mode (which stops are enforced) is fixed and the right-hand side is smooth. An
// event is: a free stop reaching contact (C crosses 0), an enforced stop whose multiplier would pull
// (lambda crosses 0), a force element's switching function (the tyre's deflection crosses 0). The
// adaptive pair locates the earliest event on its dense output (Illinois regula falsi, to
// eventTolerance) and ends the step on it; the fixed-step methods handle events at the step's end.
// Contact mode changes and plastic impacts are done by resolveContacts (engine.hpp).
// Stabilisation: projection (engine.hpp, project) whenever the violation exceeds projectionTolerance,
// or Baumgarte terms inside the multiplier right-hand side, or none.
//
// The pieces, one file each in sim/engine/integration/: dense_output, event_functions, tableaus, step_context
// (what the methods share), events (handling them inside a step), dopri5, rosenbrock, fixed_step.
#pragma once

#include <limits>
#include <string>
#include <type_traits>

#include "sim/engine/integration/dopri5.hpp"
#include "sim/engine/integration/fixed_step.hpp"
#include "sim/engine/integration/rosenbrock.hpp"

namespace lg {

// A null observer: every hook does nothing.
struct NoObserver {
  template <class S> void onStart(const Model<S>&, const State<S>&, Workspace<S>&) {}
  template <class S> void onStep(const Model<S>&, const State<S>&, Workspace<S>&, const DenseOutput<S>&) {}
  bool stopRequested() const { return false; }
};

template <class S> class Integrator {
 public:
  Integrator(const Model<S>& m, State<S>& s, Workspace<S>& w) : c_{m, s, w, {}, 1e-4, m.settings.rtol, m.settings.atol, {}, {}} {}

  // Integrates from s.t to tEnd. The observer's onStart runs with the workspace evaluated at the start;
  // onStep after every accepted step with the state at the step's end (kinematics, rows, multipliers and
  // outputs current in the workspace: exactly at s.y for the Rosenbrock steps; dopri5 and the fixed steps
  // evaluated it before renormalising its quaternions, a round-off apart).
  template <class Observer> RunStatus run(double tEnd, Observer& obs) {
    RunStatus st;
    const Settings& cfg = c_.m.settings;
    IntegratorKind kind = cfg.integrator;  // (dopri5 may hand over to ros34pw2: Settings::stiffSwitchRtol)
    c_.w.needDampingResponse = isRosenbrock(kind);
    c_.w.slip = c_.s.slip;
    projectMobility(c_.m, c_.s.y);  // a guided, immobile or planar body's velocity into its subspace
    impliedPlanarRows(c_.m, c_.s, c_.w);  // a planar model's rows that its plane motions satisfy by themselves
    // Initial contact modes (and impacts if a stop starts approaching), then a consistent state.
    if (resolveContacts(c_.m, c_.s, c_.w) < 0) return fail(c_, st, "contact solve failed at the start");
    if (cfg.stabilization != Stabilization::None && !project(c_.m, c_.s, c_.w))
      return fail(c_, st, "projection failed at the start (redundant or inconsistent constraints)");
    if (!refresh(c_)) return fail(c_, st, "multiplier solve failed at the start");
    obs.onStart(c_.m, c_.s, c_.w);
    double h = cfg.step;
    ProgressWatch progress{value(c_.s.t), 0, 0};
    while (value(c_.s.t) < tEnd - 1e-14 * std::max(1.0, tEnd)) {
      if (obs.stopRequested()) return fail(c_, st, "stopped on request");
      if (st.steps >= cfg.maxSteps) return fail(c_, st, "step limit reached (" + std::to_string(cfg.maxSteps) + " steps)");
      if (const std::string why = progress.stalled(value(c_.s.t), tEnd, st.events, st.steps, !isFixedStep(kind)); !why.empty())
        return fail(c_, st, why);
      const double remaining = tEnd - value(c_.s.t);
      if (!isFixedStep(kind)) h = std::min(h, std::max(touchdownHorizon(c_), 1e-8));
      bool ok;
      if (kind == IntegratorKind::DormandPrince) ok = stepDopri(c_, std::min(h, remaining), h, st);
      else if (kind == IntegratorKind::Ros2) ok = stepRosenbrock(c_, RosenbrockTableau::ros2(), std::min(h, remaining), h, st);
      else if (kind == IntegratorKind::Ros34pw2)
        ok = stepRosenbrock(c_, RosenbrockTableau::ros34pw2(), std::min(h, remaining), h, st);
      else ok = stepFixed(c_, std::min(cfg.step, remaining), st);
      if (!ok) return st;
      ++st.steps;
      obs.onStep(c_.m, c_.s, c_.w, c_.dense);
      if (cfg.stiffSwitchRtol > 0 && !stiffHandOver(kind, h, st)) return st;
    }
    // An event whose time depends on the parameters (a stop reached, a strut breaking away) moves every
    // later step by that much: the run ends at tEnd in value but at tEnd + dt_event/dp in derivative.
    // The state at tEnd itself: y(tEnd) = y - dy/dt (t - tEnd), to first order in the derivative part.
    if constexpr (!std::is_same_v<S, double>) {
      const S dt = derivativePart(c_.s.t);
      c_.s.y -= c_.w.ydot * dt;
      c_.s.t -= dt;
    }
    return st;
  }

 private:
  // Settings::stiffSwitchRtol: dopri5 watches its stiffness (StiffnessTest) and, where acting on it looks
  // worth it (StiffHandOver), hands the run over to ros34pw2 at that rtol (atol a hundredth of it), the
  // step size as it was (the Rosenbrock steps grow it); its first step needs the damping terms and their
  // responses at that state: one evaluation. A trial that costs more is handed back to dopri5 at its own
  // tolerances and the step it had. Returns false if the evaluation at the switch fails.
  bool stiffHandOver(IntegratorKind& kind, double& h, RunStatus& st) {
    const double t = value(c_.s.t);
    const long evals = c_.w.rhsEvaluations;
    if (kind == IntegratorKind::DormandPrince) {
      c_.handOver.dopriStep(t, evals);
      if (!c_.stiffness.stiff) return true;
      c_.stiffness = {};  // (the count starts again, whatever is decided)
      if (!c_.handOver.tryStiff(t, evals, h)) return true;
      kind = IntegratorKind::Ros34pw2;
      c_.rtol = c_.m.settings.stiffSwitchRtol;
      c_.atol = c_.rtol * 1e-2;
      st.stiffFrom = t;
      c_.w.needDampingResponse = true;
    } else {
      if (!c_.handOver.rosStep(t, evals)) return true;
      kind = IntegratorKind::DormandPrince;
      c_.rtol = c_.m.settings.rtol;
      c_.atol = c_.m.settings.atol;
      st.stiffFrom = std::numeric_limits<double>::quiet_NaN();
      ++st.handBacks;
      c_.w.needDampingResponse = false;
      h = c_.handOver.hDopri;
    }
    if (!refresh(c_)) return failNonFinite(c_, st);
    return true;
  }

  StepContext<S> c_;
};

// Runs a model from state s to tEnd (free-function form, like mj_step).
template <class S, class Observer> RunStatus simulate(const Model<S>& m, State<S>& s, Workspace<S>& w, double tEnd,
                                                      Observer& obs) {
  Integrator<S> integ(m, s, w);
  return integ.run(tEnd, obs);
}
template <class S> RunStatus simulate(const Model<S>& m, State<S>& s, Workspace<S>& w, double tEnd) {
  NoObserver obs;
  return simulate(m, s, w, tEnd, obs);
}

}  // namespace lg
