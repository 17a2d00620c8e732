// The observer of a drop run, templated on the scalar: with double it measures a drop test (refined
// peaks per strut and tyre, compression integrals, rebound, energy balance, and for a recorded case its
// time histories); with ceres::Jet the same figures carry their derivatives with respect to the design
// parameters seeded in the model.
//
// Derivatives of the figures. Every extremum is located on the dense output at a time t* found on
// values (Brent's search where the channel's rate turns from + to -); the figure is the channel at t*,
// so by the envelope rule its derivative is the channel's partial derivative there (the rate is 0).
// The time of the peak load itself moves: dt*/dp = -(dP'/dp)(t*) / P''(t*) (implicit function rule on
// the rate P' = 0), applied to t_peak. Integrals over the compression end where their integrand
// (P_y h', P_a s') vanishes, so their end's motion adds nothing. An event inside a step moves the step's
// end: its time carries the derivative of the event (the integrator's Newton correction), and the
// figures taken there follow it.
//
// What makes a derivative one-sided is recorded for the gradient report (sim/drop/gradient.hpp): the
// local maxima of P_y (two humps of nearly equal height: the maximum can jump between them), the
// bottoming margin, and the intervals where a strut sticks (|s'| within the friction band, where the
// regularised friction decides).
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "sim/core/brent.hpp"
#include "sim/drop/case.hpp"
#include "sim/drop/channels.hpp"
#include "sim/drop/figures.hpp"
#include "sim/drop/peak_refiner.hpp"
#include "sim/engine/engine.hpp"

namespace lg {

template <class S> class DropObserver {
 public:
  using Channels = DropChannels<S>;

  // (The peak refiner reads channels through this observer: it stays where it was built.)
  DropObserver(const DropObserver&) = delete;
  DropObserver& operator=(const DropObserver&) = delete;

  // 'record' (double only) receives the time histories when opt.record is set.
  DropObserver(const Scene& sc, const Model<S>& m, const DropCase& c, const S& sinkSpeed, const S& liftRatio,
               const CaseOptions& opt, CaseResult* record)
      : sc_(sc), m_(m), case_(c), V_(touchdownSpeed(sinkSpeed, liftRatio, c.dropHeight, sc.gravity)), L_(liftRatio), opt_(opt),
        rec_(record), wo_(m),
        refiner_([this](const S& t, const DenseOutput<S>& d, Channels& c) { channelsAt(t, d, c); }, sc.roles.struts.size(),
                 sc.roles.tyres.size()) {
    airframe_ = sc.roles.airframe.empty() ? -1 : m.bodyIndex(sc.roles.airframe);
    for (int ci : sc.roles.stops) {
      stopRows_.push_back(m.rowOffset[ci]);
      const auto& st = std::get<DistanceStop<S>>(m.constraints[ci].type);
      if (!st.noFarther) bottomRows_.push_back(m.rowOffset[ci]);
    }
    for (int f : sc.roles.tyres) {
      tyreOut_.push_back(m.outputOffset[f]);
      dampedTyre_.push_back(std::get<Tyre<S>>(m.forces[f].type).damped);
      if (dampedTyre_.back()) rateFromDense_ = true;
      dragTyre_.push_back(std::get<Tyre<S>>(m.forces[f].type).longitudinal);
      if (dragTyre_.back()) drag_ = true;
    }
    for (int k = 0; k < m.nRows; ++k)
      if (m.rowInfo[k].friction()) lockRows_.push_back(k);
    // The elements whose outputs are history columns of their own (historyColumns: bushings, bearing friction).
    for (size_t f = 0; f < m.forces.size(); ++f)
      std::visit(
          [&](const auto& e) {
            if constexpr (requires { e.outputUnit(std::string()); })
              elementOut_.push_back({m.outputOffset[f], static_cast<int>(e.outputNames().size())});
          },
          m.forces[f].type);
    for (int f : sc.roles.struts) {
      strutOut_.push_back(m.outputOffset[f]);
      strutOutputs_.push_back(static_cast<int>(m.forces[f].outputNames().size()));
      const auto& sa = std::get<ShockAbsorber<S>>(m.forces[f].type);
      regularised_.push_back(!sa.coulomb);
      if (!sa.coulomb) epsFriction_ = std::max(epsFriction_, sa.frictionVelocity);
    }
    const size_t ns = strutOut_.size(), nt = tyreOut_.size();
    prev_ = end_ = mid_ = after_ = scratch_ = Channels(ns, nt);
    refiner_.setStep(prev_, mid_, end_);  // (the members: each step's channels are read into them)
    workPa_.assign(ns, S(0));
    workPaAtMax_.assign(ns, S(0));
    F_.struts.resize(ns);
    F_.tyres.resize(nt);
    stickStart_.assign(ns, -1.0);
    strutBottomed_.assign(ns, false);
    moved_.assign(ns, false);
    ytmp_ = VecX<S>::Zero(m.ny());
    ydotTmp_ = VecX<S>::Zero(m.ny());
    lambdaTmp_ = VecX<S>::Zero(m.nRows);
    if (rec_ && opt_.record) rec_->columns = historyColumns(sc);
  }

  void onStart(const Model<S>& m, const State<S>& s, Workspace<S>& w) {
    // (h from the touchdown positions: a drop from a height starts at h = -h_d)
    if (airframe_ >= 0) r0_ = w.kin[airframe_].r - (case_.dropHeight * sc_.up).template cast<S>();
    stepActive_ = s.active;
    stepSlip_ = s.slip;
    wo_.implied = w.implied;  // (the rows the run's mode leaves out: the observer's evaluations skip them too)
    channels(s.t, w, prev_);  // (the run's start is evaluated in w)
    EnergyReport<S> e = energy(m, s, w);
    e0_ = value(e.total());
    ek0_ = value(e.kinetic);
    uExt0_ = externalPotential(w);
    if (recording() && (opt_.outputTimes.empty() || opt_.outputTimes[0] <= 0)) {
      record(value(s.t), w, s.lambda, s.active, w);  // t = 0 in every output mode but a list without it
      nextRow_ = 1;
    }
    F_.peak_load = prev_.Py;
    F_.h_max = prev_.h;
    for (size_t k = 0; k < F_.struts.size(); ++k) {
      F_.struts[k].stroke_max = prev_.s[k];
      F_.struts[k].force_max = prev_.Pa[k];
    }
    for (size_t k = 0; k < F_.tyres.size(); ++k) {
      F_.tyres[k].deflection_max = prev_.delta[k];
      F_.tyres[k].load_max = prev_.Pt[k];
      F_.tyres[k].drag_max = prev_.px[k];
    }
    F_.drag_peak = prev_.Px;
    F_.springback_peak = -prev_.Px;
    F_.drag_at_peak = prev_.Px;
    checkBottom(s);
  }

  // One accepted step [t0, t1] of the run: its channels at the end and the middle, then each group of
  // metrics on the dense output (the load, the tyres, the struts, the airframe's travel and rebound),
  // the time-history rows, and the next step's start.
  void onStep(const Model<S>& m, const State<S>& s, Workspace<S>& w, const DenseOutput<S>& d) {
    const double viol = violation(s.active, w);
    // Compression integrals (Simpson on the dense output) over [t0, t1], and refined extrema. The step's
    // end is taken on the dense output, i.e. before any jump at t1 (a plastic impact or a projection
    // changes the velocities, hence the rates and P_a, but belongs to the next step's start).
    const S t0 = prev_.t, t1 = s.t;
    channelsAt(t1, d, end_);
    channelsAt(S(0.5) * (t0 + t1), d, mid_);
    ReactionsNeeded lazy(reaction_, false);  // from here only what reads P_a solves for the locks' reactions
    if (rateFromDense_) denseRates(t0, t1, d);
    watchLoad(t0, t1, d);
    watchTyres(t0, t1, d);
    watchStruts(t0, t1, d);
    watchTravel(t0, t1, d);
    F_.constraint_violation_max = std::max(F_.constraint_violation_max, viol);
    checkBottom(s);
    if (recording() && denseRows()) recordDense(m, value(t0), value(t1), s, d);
    lazy.restore();
    startNextStep(s, w, d, t1);
  }

 private:
  // The peak vertical load P_y where its rate (the sum of the tyres' P_t') goes from + to -, its time
  // polished, and its humps; the work of P_y along h.
  void watchLoad(const S& t0, const S& t1, const DenseOutput<S>& d) {
    workPy_ += simpson(prev_.Py * prev_.hdot, mid_.Py * mid_.hdot, end_.Py * end_.hdot, t1 - t0);
    double tPy = -1;
    const bool newPeak = refiner_.refine(prev_.PyDot, end_.PyDot, t0, t1, d, [](const Channels& c) { return c.Py; }, F_.peak_load,
                                &F_.t_peak, end_.Py, t1, &tPy, /*everyPeak=*/true);
    if (newPeak) F_.peakCurvature = 0;  // (set again below where the new peak is a smooth interior maximum)
    bool moved = newPeak;
    if (newPeak && tPy >= 0) {
      correctPeakTime(tPy, t0, t1, d);
      refiner_.lastTime = value(F_.t_peak);  // (this hump's time: the peak's own, polished)
    } else if (!newPeak && value(F_.t_peak) == value(t0) && value(prev_.PyDot) > 0 && value(end_.PyDot) < 0) {
      moved = true;
      // The maximum is this step's start: the last step ended rising, and no value inside this one is
      // larger (the top rises above t0 by less than round-off, or by less than the projection between the
      // steps lowered P_y: at rtol 1e-2 the seed gear's limit drop kept its peak 0.3 ms before the top, a
      // t_peak error of 5.1e-3). Polished from t0 on this step's dense output, so that its time (and its
      // derivatives) are the top's, not the step's; the value stays the larger one of the step's end.
      correctPeakTime(value(t0), t0, t1, d, /*fromSearch=*/false);
    }
    if (value(prev_.PyDot) > 0 && value(end_.PyDot) < 0) F_.loadHumps.push_back({refiner_.lastTime, refiner_.lastValue});
    if (drag_ && moved) {  // the drag load at the time of the largest vertical load (spin-up declared)
      const S t = value(F_.t_peak) < value(t0) ? t0 : value(F_.t_peak) > value(t1) ? t1 : F_.t_peak;
      channelsAt(t, d, scratch_);
      F_.drag_at_peak = scratch_.Px;
    }
  }
  // Each tyre's largest deflection, load and drag, and the gear's drag peak.
  void watchTyres(const S& t0, const S& t1, const DenseOutput<S>& d) {
    for (size_t k = 0; k < F_.tyres.size(); ++k) {
      // P_t grows with delta: both peak where delta' goes from + to -.
      auto& T = F_.tyres[k];
      refiner_.refine(prev_.ddelta[k], end_.ddelta[k], t0, t1, d, [k](const Channels& c) { return c.delta[k]; }, T.deflection_max,
             nullptr, end_.delta[k], t1);
      // (a damped tyre's load peaks before its deflection: its own rate)
      refiner_.refine(dampedTyre_[k] ? prev_.dPt[k] : prev_.ddelta[k], dampedTyre_[k] ? end_.dPt[k] : end_.ddelta[k], t0, t1, d,
             [k](const Channels& c) { return c.Pt[k]; }, T.load_max, nullptr, end_.Pt[k], t1);
      // The drag load (no rate channel): searched on the dense output where the step may hold its maximum.
      if (dragTyre_[k])
        refiner_.refineWithoutRate(prev_.px[k], mid_.px[k], end_.px[k], t0, t1, d, [k](const Channels& c) { return c.px[k]; },
                          T.drag_max);
    }
    if (drag_) {
      refiner_.refineWithoutRate(prev_.Px, mid_.Px, end_.Px, t0, t1, d, [](const Channels& c) { return c.Px; }, F_.drag_peak, false,
                        &F_.t_drag_peak);
      refiner_.refineWithoutRate(-prev_.Px, -mid_.Px, -end_.Px, t0, t1, d, [](const Channels& c) { return -c.Px; }, F_.springback_peak,
                        false, &F_.t_springback);
    }
  }
  // Each strut's largest stroke (and its work up to there), its peak force P_a, and the regularised
  // friction's stick watch.
  void watchStruts(const S& t0, const S& t1, const DenseOutput<S>& d) {
    for (size_t k = 0; k < F_.struts.size(); ++k) {
      auto& St = F_.struts[k];
      workPa_[k] += simpson(prev_.Pa[k] * prev_.sdot[k], mid_.Pa[k] * mid_.sdot[k], end_.Pa[k] * end_.sdot[k], t1 - t0);
      double tS = -1;
      if (refiner_.refine(prev_.sdot[k], end_.sdot[k], t0, t1, d, [k](const Channels& c) { return c.s[k]; }, St.stroke_max, nullptr,
                 end_.s[k], t1, &tS)) {
        ReactionsNeeded needed(reaction_, true);
        workPaAtMax_[k] = workPa_[k] - (tS >= 0 ? partialStrut(k, S(tS), t1, d) : S(0));
        F_.tStrokeMax = std::max(F_.tStrokeMax, tS < 0 ? value(t1) : tS);
      }
      // Peak P_a (no rate channel): searched on the dense output where the step may hold it.
      ReactionsNeeded needed(reaction_, true);
      if (refiner_.refineWithoutRate(prev_.Pa[k], mid_.Pa[k], end_.Pa[k], t0, t1, d, [k](const Channels& c) { return c.Pa[k]; },
                            St.force_max))
        F_.tStrutForceMax = value(t1);
      if (regularised_[k]) watchStick(k, value(t1), value(end_.sdot[k]));
    }
  }
  // The airframe's largest travel h (and the gear's work up to there), the end of the compression, and
  // the rebound: the largest upward velocity -h' after it, refined on the dense output where the step's
  // midpoint is above both ends.
  void watchTravel(const S& t0, const S& t1, const DenseOutput<S>& d) {
    double tH = -1;
    if (value(prev_.hdot) > 0 && value(end_.hdot) <= 0) F_.compression_ended = true;
    if (refiner_.refine(prev_.hdot, end_.hdot, t0, t1, d, [](const Channels& c) { return c.h; }, F_.h_max, nullptr, end_.h, t1, &tH)) {
      workPyAtMax_ = workPy_ - (tH >= 0 ? partialGear(S(tH), t1, d) : S(0));
      tHmax_ = tH < 0 ? value(t1) : tH;
      F_.tHMax = tHmax_;
      reboundV_ = S(0);  // a new maximum of h: the rebound starts again from there
    }
    if (value(t1) > tHmax_) {
      const S ta = maxByValue(t0, S(tHmax_));
      const bool whole = value(ta) == value(t0);
      refiner_.refineWithoutRate(whole ? S(-prev_.hdot) : S(-end_.hdot), S(-mid_.hdot), S(-end_.hdot), ta, t1, d,
                        [](const Channels& c) { return S(-c.hdot); }, reboundV_, !whole);
    }
  }
  // The next step's start: the channels after any jump at t1, a kink maximum of P_y at an event, the
  // row at the step's end (one row per step), and the mode the next step runs in.
  void startNextStep(const State<S>& s, const Workspace<S>& w, const DenseOutput<S>& d, const S& t1) {
    const Workspace<S>& endW = stepEnd(s, w, d, after_);  // after any jump at t1: the next step's start
    // Without an event at t1 the next step starts where this one ends, with the same slope f(s.y) (up to
    // the step's projection): the rates at this step's end are also those at the next one's start.
    startRates_ = rateFromDense_ && !d.endsOnEvent;
    if (startRates_) {
      after_.PyDot = end_.PyDot;
      after_.dPt = end_.dPt;
    }
    // A kink maximum of P_y: rising into an event at t1, not rising after it (a stop engaging, a strut
    // locking, the tyre's spin-up ending). A hump like the interior ones, at the event's time.
    if (d.endsOnEvent && value(end_.PyDot) > 0 && !(value(after_.PyDot) > 0))
      F_.loadHumps.push_back({value(t1), std::max(value(end_.Py), value(after_.Py))});
    for (size_t k = 0; k < F_.struts.size(); ++k) F_.struts[k].force_max = maxByValue(F_.struts[k].force_max, after_.Pa[k]);
    if (recording() && !denseRows()) record(value(s.t), endW, s.lambda, s.active, w);
    stepActive_ = s.active;  // after any event at t1: the next step's mode
    stepSlip_ = s.slip;
    std::swap(prev_, after_);
    ++steps_;
  }

 public:
  // Rows of the time histories in the scalar S (with ceres::Jet: their derivatives), at opt.outputTimes or
  // every opt.outputInterval: each row holds the columns of historyColumns(scene). 'timeSlot' >= 0 (Jet
  // only) seeds the row's time in that derivative component, which then holds each column's rate in
  // time along the dense output (d/dt at fixed parameters); the row at t = 0 (before any step) has rate
  // 0 there. A row whose time is an event's is the left limit (before the event's jump). Set before the
  // run; the double run's rows go to the CaseResult as before.
  void recordRows(std::vector<std::vector<S>>* rows, int timeSlot = -1) {
    rows_ = rows;
    timeSlot_ = timeSlot;
  }

  bool stopRequested() const { return opt_.stop && (steps_ % 64 == 0) && opt_.stop(); }

  // [m/s] the largest approach speed s' of a strut onto its bottoming stop when the stop first engaged
  // (-1 if it never did): a speed near 0 is bottoming's onset.
  double bottomingSpeed() const { return bottomSpeed_; }

  // The figures of the run that ended in state s.
  const CaseFigures<S>& finish(const State<S>& s, Workspace<S>& w) {
    kinematics(m_, s.y, w);
    EnergyReport<S> e = energy(m_, s, w);
    const double uExt = externalPotential(w);
    const double input = ek0_ + std::abs(uExt0_ - uExt) + std::abs(value(e.input));  // (+ the ground's work)
    F_.energy_balance_error = std::abs(value(e.total()) - e0_) / std::max(input, 1e-300);
    F_.energy_dissipated = value(e.dissipated);
    F_.energy_absorbed = workPyAtMax_;
    S G = S(0);
    for (const auto& b : m_.bodies) G += b.mass;
    const S g(sc_.gravity);
    F_.mass = G;
    F_.energy_to_absorb = S(0.5) * G * V_ * V_ + (S(1) - L_) * G * g * F_.h_max;
    F_.load_factor = F_.peak_load / (G * g);
    F_.inertia_load_factor = F_.load_factor + L_;
    F_.efficiency = (value(F_.peak_load) > 0 && value(F_.h_max) > 0) ? workPyAtMax_ / (F_.peak_load * F_.h_max) : S(0.0);
    F_.rebound_velocity = reboundV_;
    // Per strut and tyre, then the gear's worst.
    const S nan(std::numeric_limits<double>::quiet_NaN());
    F_.stroke_max = F_.strut_force_max = S(0);
    F_.strut_efficiency = F_.struts.empty() ? S(0.0) : S(std::numeric_limits<double>::infinity());
    F_.stroke_margin = nan;
    for (size_t k = 0; k < F_.struts.size(); ++k) {
      auto& St = F_.struts[k];
      St.stroke_limit = strokeLimit(k);
      if constexpr (!kDouble)  // the stop holds s_max at S_max: its derivative is S_max's, not the drift's
        if (strutBottomed_[k]) St.stroke_max = S(value(St.stroke_max)) + (St.stroke_limit - S(value(St.stroke_limit)));
      St.work = workPaAtMax_[k];
      St.efficiency = (value(St.force_max) > 0 && value(St.stroke_max) > 0) ? St.work / (St.force_max * St.stroke_max) : S(0.0);
      St.stroke_margin = St.stroke_limit - St.stroke_max;  // NaN without a bottoming stop
      F_.stroke_max = maxByValue(F_.stroke_max, St.stroke_max);
      F_.strut_force_max = maxByValue(F_.strut_force_max, St.force_max);
      F_.strut_efficiency = minByValue(F_.strut_efficiency, St.efficiency);
      if (!std::isnan(value(St.stroke_margin)))
        F_.stroke_margin = std::isnan(value(F_.stroke_margin)) ? St.stroke_margin : minByValue(F_.stroke_margin, St.stroke_margin);
      if (stickStart_[k] >= 0) closeStick(k, value(s.t));
    }
    F_.tyre_deflection_max = S(0);
    F_.tyre_margin = nan;
    for (size_t k = 0; k < F_.tyres.size(); ++k) {
      auto& T = F_.tyres[k];
      T.deflection_limit = std::get<Tyre<S>>(m_.forces[sc_.roles.tyres[k]].type).deltaMax;
      T.margin = T.deflection_limit - T.deflection_max;
      F_.tyre_deflection_max = maxByValue(F_.tyre_deflection_max, T.deflection_max);
      F_.tyre_margin = std::isnan(value(F_.tyre_margin)) ? T.margin : minByValue(F_.tyre_margin, T.margin);
    }
    return F_;
  }

 private:
  static constexpr bool kDouble = std::is_same_v<S, double>;
  // Whether channels read on the dense output need the stuck friction locks' reactions (a full evaluation
  // each): set for a scope, restored at its end.
  using ReactionsNeeded = ScopedFlag;
  bool recording() const {
    if constexpr (kDouble) return (rec_ && opt_.record) || rows_;
    else return rows_ != nullptr;
  }
  // S_max of strut k from the model (a design may move L0 or the stop): L0 - L of its bottoming stop.
  S strokeLimit(size_t k) const {
    const int stop = k < sc_.roles.bottomingStops.size() ? sc_.roles.bottomingStops[k] : -1;
    if (stop < 0) return S(std::numeric_limits<double>::quiet_NaN());
    return std::get<ShockAbsorber<S>>(m_.forces[sc_.roles.struts[k]].type).L0 -
           std::get<DistanceStop<S>>(m_.constraints[stop].type).L;
  }

  // Channels at the workspace's current kinematics (outputs must be current).
  void channels(const S& t, const Workspace<S>& w, Channels& c) const {
    c.t = t;
    c.Py = c.PyDot = c.Px = S(0);
    for (size_t k = 0; k < tyreOut_.size(); ++k) {
      const S* o = w.outputs.data() + tyreOut_[k];  // delta, P_t, delta', P_t'
      c.delta[k] = o[0];
      c.Pt[k] = o[1];
      c.ddelta[k] = o[2];
      c.dPt[k] = o[3];
      c.Py += o[1];
      c.PyDot += o[3];
      c.px[k] = dragTyre_[k] ? o[4] : S(0);  // delta, P_t, delta', P_t', P_x, v_s
      c.Px += c.px[k];
    }
    for (size_t k = 0; k < strutOut_.size(); ++k) {
      const S* o = w.outputs.data() + strutOut_[k];  // s, s', p_1, P_a, ...
      c.s[k] = o[0];
      c.sdot[k] = o[1];
      c.Pa[k] = o[3];
    }
    c.h = c.hdot = S(0);
    if (airframe_ >= 0) {
      c.h = sc_.up.template cast<S>().dot(r0_ - w.kin[airframe_].r);
      c.hdot = -sc_.up.template cast<S>().dot(w.kin[airframe_].v);
    }
  }
  void forceOutputs(Workspace<S>& w) const {
    const Kins<S> K = w.kins();
    for (size_t f = 0; f < m_.forces.size(); ++f)
      std::visit([&](const auto& e) { e.outputs(K, w.outputs.data() + m_.outputOffset[f]); }, m_.forces[f].type);
  }
  // Channels at (t, y) on the observer's own workspace (poses and force outputs only: no solve), so that
  // the integrator's workspace is never touched.
  // Channels at state y in a contact and friction mode (active, slip): poses and force outputs, which
  // read each strut's slip direction; with a stuck friction lock a full evaluation, for its reaction
  // (part of P_a), else the locks' reactions are 0; with bearing friction a full evaluation (its outputs
  // read the joint's multipliers).
  // Without reaction_ (a search of a channel other than P_a) the stuck locks' reactions are left at 0:
  // the other channels do not read them, and are the same bits either way.
  void at(const S& t, const VecX<S>& y, const std::vector<char>& active, const std::vector<signed char>& slip,
          Channels& c) {
    wo_.slip = slip;
    bool stuck = !m_.bearingForces.empty();
    for (int r : lockRows_) stuck = stuck || (reaction_ && active[r]);
    if (stuck) {
      evaluate(m_, y, active, lambdaTmp_, wo_, ydotTmp_);
    } else {
      poses(m_, y, wo_);
      for (int r : lockRows_) wo_.rowLambda[r] = S(0);
    }
    forceOutputs(wo_);
    channels(t, wo_, c);
  }
  // The channels at the state s that closes a step, into c; returns the workspace they were read from. The
  // integrator's own where its closing evaluation is at s.y itself (the Rosenbrock steps evaluate after
  // the projection: no second evaluation here); else s.y is evaluated here (dopri5's closing evaluation
  // is its last stage, at y1 before the quaternions' renormalisation; the fixed steps renormalise after
  // theirs: a round-off apart).
  const Workspace<S>& stepEnd(const State<S>& s, const Workspace<S>& w, const DenseOutput<S>& d, Channels& c) {
    if (d.closesAtState) {
      channels(s.t, w, c);
      return w;
    }
    at(s.t, s.y, s.active, s.slip, c);
    return wo_;
  }
  // On the dense output of the step in progress: its mode is the one it started with.
  void channelsAt(const S& t, const DenseOutput<S>& d, Channels& c) {
    d.at(t, ytmp_);
    at(t, ytmp_, stepActive_, stepSlip_, c);
  }

  // A damped tyre's load rate holds c delta'', which its outputs cannot know (no accelerations there): with
  // one, the rates of P_y and of each damped tyre's P_t at the step's ends are one-sided differences on
  // the step's dense output, over 1e-6 of the step (their truncation, P'' tau / 2, and their round-off
  // are far below the rates that matter: only their signs are used, to bracket the peaks). After a step
  // that ended without an event, the rates at the start are the last step's at its end (startRates_).
  void denseRates(const S& t0, const S& t1, const DenseOutput<S>& d) {
    const S tau(1e-6 * (value(t1) - value(t0)));
    if (!startRates_) {
      channelsAt(t0 + tau, d, scratch_);
      prev_.PyDot = (scratch_.Py - prev_.Py) / tau;
      for (size_t k = 0; k < dampedTyre_.size(); ++k)
        if (dampedTyre_[k]) prev_.dPt[k] = (scratch_.Pt[k] - prev_.Pt[k]) / tau;
    }
    channelsAt(t1 - tau, d, scratch_);
    end_.PyDot = (end_.Py - scratch_.Py) / tau;
    for (size_t k = 0; k < dampedTyre_.size(); ++k)
      if (dampedTyre_[k]) end_.dPt[k] = (end_.Pt[k] - scratch_.Pt[k]) / tau;
  }

  // The peak's time, polished: Brent's search locates it on values, to about 1e-9 s (there the values are
  // equal to round-off), which is noise from one design to the next; one Newton step on P' = 0,
  //   t* = t - P'(t) / P''(t),
  // with P' and P'' central differences in time of P_y on the dense output itself (the function whose
  // maximum t* is), places it to the differences' error, smoothly in the design. In a Jet run the same
  // step carries the derivatives dt*/dp = -(dP'/dp) / P''. The difference step dt is 1e-2 of the
  // integration step (the stencil t +- 2 dt inside it; at least 1e-3 of it). With T the peak's time
  // scale (P'' ~ P / T^2) the rate's round-off, eps P / dt, moves t* by about eps T^2 / dt; its
  // truncation, fourth order (P^(5) dt^4 / 30), by about dt^4 / (30 T^3): below 1e-12 s at the loosest
  // steps (the second-order difference's dt^2 / (6 T) was 1e-7 s there, more than the search's own
  // error, so its step had been taken only within ten times the search's tolerance; a double and a Jet
  // run, whose searches end apart where the values are flat to round-off, then took it in one and not
  // in the other: t_peak 1.5e-8 .. 1.6e-7 apart on the nose gear at 6.25e-4 and 3e-4). The step is taken
  // within dt, where the stencil holds the top; a longer one is not (its value; its derivatives are).
  // (At 1e-3 of the step the derivative part of P' carried the integration's error over a smaller dt:
  // dt*/dp of the seed gear was 2e-5 off the differences.)
  // 'fromSearch' false: t is a step's start, not the search's point (P_y there is evaluated; the step is
  // taken whatever its size).
  void correctPeakTime(double t, const S& t0, const S& t1, const DenseOutput<S>& d, bool fromSearch = true) {
    const double h = value(t1) - value(t0);
    const double dt = std::max(1e-3 * h, std::min({1e-2 * h, 0.5 * (t - value(t0)), 0.5 * (value(t1) - t)}));
    channelsAt(S(t + dt), d, scratch_);
    const S up = scratch_.Py;
    channelsAt(S(t - dt), d, scratch_);
    const S down = scratch_.Py;
    channelsAt(S(t + 2 * dt), d, scratch_);
    const S up2 = scratch_.Py;
    channelsAt(S(t - 2 * dt), d, scratch_);
    const S down2 = scratch_.Py;
    S mid;
    if constexpr (kDouble) {
      if (fromSearch) mid = refiner_.lastValue;  // (P_y at t, from the search)
    }
    if (!kDouble || !fromSearch) {
      channelsAt(S(t), d, scratch_);
      mid = scratch_.Py;
    }
    const S rate = (S(8) * (up - down) - (up2 - down2)) / S(12 * dt);                // P' [N/s], fourth order
    const double curvature = (value(up) - 2 * value(mid) + value(down)) / (dt * dt);  // P'' [N/s^2]
    if (!(curvature < 0)) return;
    const S step = rate / S(curvature);
    // From a step's start the top lies ahead, inside the step: P_y falling there already is a kink at t0
    // (an event between the steps), whose time is the event's.
    if (!fromSearch && !(value(step) <= 0 && t - value(step) <= value(t1))) return;
    F_.peakCurvature = curvature;
    F_.t_peak = !fromSearch || std::abs(value(step)) <= dt ? S(t) - step : S(t) - (step - S(value(step)));
  }

  // Friction: a strut sticks while |s'| stays within 10 eps after it has moved; intervals longer than a
  // passage through the band (1e-3 of the run) are recorded.
  void watchStick(size_t k, double t, double sdot) {
    const double band = 10 * epsFriction_;
    if (std::abs(sdot) >= band) {
      moved_[k] = true;
      if (stickStart_[k] >= 0) closeStick(k, t);
    } else if (moved_[k] && stickStart_[k] < 0) {
      stickStart_[k] = t;
    }
  }
  void closeStick(size_t k, double t) {
    if (t - stickStart_[k] > 1e-3 * case_.duration) F_.stickIntervals.push_back({stickStart_[k], t});
    stickStart_[k] = -1;
  }

  // One row of the time histories from a workspace whose poses and force outputs are current, the
  // multipliers, and the workspace holding the constraint rows at that state (the columns of
  // historyColumns, in order): to the CaseResult (double) or to the rows of recordRows.
  void record(double t, const Workspace<S>& wk, const VecX<S>& lambda, const std::vector<char>& active,
              const Workspace<S>& rowsW) {
    std::vector<S> row;
    const S* o = wk.outputs.data();
    S Py = S(0);
    for (int off : tyreOut_) Py += o[off + 1];
    if (!tyreOut_.empty()) row.push_back(Py);
    if (airframe_ >= 0) row.push_back(sc_.up.template cast<S>().dot(r0_ - wk.kin[airframe_].r));
    for (size_t k = 0; k < tyreOut_.size(); ++k) {
      const int off = tyreOut_[k];
      row.push_back(o[off]);
      if (tyreOut_.size() > 1) row.push_back(o[off + 1]);
      if (dragTyre_[k]) row.push_back(o[off + 4]);
    }
    for (size_t k = 0; k < strutOut_.size(); ++k)
      for (int i = 0; i < strutOutputs_[k]; ++i) row.push_back(o[strutOut_[k] + i]);
    for (int r : stopRows_) row.push_back(lambda[r] * rowsW.rows[r].Ji.template head<3>().norm());  // [N]
    for (const auto& [off, n] : elementOut_)
      for (int i = 0; i < n; ++i) row.push_back(o[off + i]);
    row.push_back(S(violation(active, rowsW)));
    if (rows_) rows_->push_back(row);
    if constexpr (kDouble) {
      if (rec_ && opt_.record) rec_->samples.push_back(Sample{t, std::move(row)});
    } else {
      (void)t;
    }
  }
  // Rows on the dense output (outputTimes or outputInterval) rather than one per step.
  bool denseRows() const { return !opt_.outputTimes.empty() || opt_.outputInterval > 0; }
  // The time of output row k: outputTimes[k] (infinity past its end), or k DT.
  double rowTime(long k) const {
    if (opt_.outputTimes.empty()) return static_cast<double>(k) * opt_.outputInterval;
    return k < static_cast<long>(opt_.outputTimes.size()) ? opt_.outputTimes[k] : std::numeric_limits<double>::infinity();
  }
  // Rows at the output times inside (t0, t1], each from the dense output with its multipliers solved
  // on the observer's workspace in the step's contact mode (the one it started with: 's' holds the mode
  // after any event at t1, so a row at t1 is the left limit).
  void recordDense(const Model<S>& m, double t0, double t1, const State<S>& s, const DenseOutput<S>& d) {
    for (;; ++nextRow_) {
      const double t = rowTime(nextRow_);
      if (t > t1 * (1 + 1e-12) || t > case_.duration * (1 + 1e-12)) break;
      if (t <= t0) continue;
      S tr(std::min(t, t1));
      if constexpr (!kDouble)
        if (timeSlot_ >= 0) tr.v[timeSlot_] = 1.0;  // the rates in time along the dense output
      d.at(tr, ytmp_);
      lambdaTmp_ = s.lambda;
      wo_.slip = stepSlip_;
      evaluate(m, ytmp_, stepActive_, lambdaTmp_, wo_, ydotTmp_);
      forceOutputs(wo_);
      record(t, wo_, lambdaTmp_, stepActive_, wo_);
    }
  }
  double violation(const std::vector<char>& active, const Workspace<S>& w) const {
    double v = 0;
    for (int k = 0; k < m_.nRows; ++k) {
      if (!active[k]) continue;
      v = std::max(v, std::abs(value(w.rows[k].C)) / std::max(1e-12, value(w.rows[k].Ji.template head<3>().norm())));
    }
    return v;
  }
  void checkBottom(const State<S>& s) {
    for (int r : bottomRows_)
      if (s.active[r] && !F_.bottomed) {
        F_.bottomed = true;
        for (size_t k = 0; k < end_.sdot.size(); ++k)  // (an arrival at rest may read a round-off below 0)
          bottomSpeed_ = std::max(bottomSpeed_, std::max(0.0, value(end_.sdot[k])));
      }
    for (size_t k = 0; k < strutBottomed_.size(); ++k) {
      const int stop = k < sc_.roles.bottomingStops.size() ? sc_.roles.bottomingStops[k] : -1;
      if (stop >= 0 && s.active[m_.rowOffset[stop]]) strutBottomed_[k] = true;
    }
  }
  double externalPotential(const Workspace<S>& w) const {
    const Kins<S> K = w.kins();
    double U = 0;
    for (const auto& f : m_.forces) {
      if (const auto* g = std::get_if<Gravity<S>>(&f.type)) U += value(g->stored(K));
      if (const auto* c = std::get_if<ConstantForce<S>>(&f.type)) U += value(c->stored(K));
    }
    return U;
  }
  // Simpson's rule for integral(P dx) = integral(P xdot dt) over one step of length h.
  static S simpson(const S& f0, const S& fm, const S& f1, const S& h) { return h / S(6.0) * (f0 + S(4) * fm + f1); }
  // The part of this step's integral after time t (Simpson on [t, t1]).
  S partialGear(const S& t, const S& t1, const DenseOutput<S>& d) {
    Channels& a = scratch_;
    channelsAt(t, d, a);
    const S fa = a.Py * a.hdot;
    channelsAt(S(0.5) * (t + t1), d, a);
    const S fm = a.Py * a.hdot;
    channelsAt(t1, d, a);
    return simpson(fa, fm, a.Py * a.hdot, t1 - t);
  }
  S partialStrut(size_t k, const S& t, const S& t1, const DenseOutput<S>& d) {
    Channels& a = scratch_;
    channelsAt(t, d, a);
    const S fa = a.Pa[k] * a.sdot[k];
    channelsAt(S(0.5) * (t + t1), d, a);
    const S fm = a.Pa[k] * a.sdot[k];
    channelsAt(t1, d, a);
    return simpson(fa, fm, a.Pa[k] * a.sdot[k], t1 - t);
  }
  const Scene& sc_;
  const Model<S>& m_;
  const DropCase& case_;
  const S V_, L_;            // the case's sink speed at touchdown and lift ratio (design parameters, possibly)
  const CaseOptions& opt_;
  CaseResult* rec_;
  Workspace<S> wo_;           // the observer's own: dense-output channels and output rows
  int airframe_ = -1;
  std::vector<int> tyreOut_, strutOut_, strutOutputs_, stopRows_, bottomRows_;
  std::vector<bool> dampedTyre_;  // per tyre: its load rate is taken on the dense output (denseRates)
  bool rateFromDense_ = false;
  bool startRates_ = false;  // prev_'s rates of the damped tyres' loads and of P_y were taken at the last step's end
  std::vector<bool> dragTyre_;    // per tyre: it has a longitudinal force (P_x, its 5th output)
  bool drag_ = false;
  Vec3<S> r0_ = Vec3<S>::Zero();
  VecX<S> ytmp_, ydotTmp_, lambdaTmp_;
  long nextRow_ = 0;          // next dense output row (outputTimes, outputInterval)
  std::vector<std::vector<S>>* rows_ = nullptr;  // recordRows
  std::vector<char> stepActive_;  // the contact mode of the step in progress (rows on the dense output)
  std::vector<signed char> stepSlip_;  // and its friction locks' slip directions
  std::vector<int> lockRows_;          // the friction-lock rows (exact Coulomb struts)
  std::vector<std::pair<int, int>> elementOut_;  // (output offset, count) of the bushings and bearing frictions
  int timeSlot_ = -1;
  bool reaction_ = true;  // see ReactionsNeeded
  Channels prev_, end_, mid_, after_, scratch_;
  PeakRefiner<S> refiner_;  // every running maximum over the steps
  CaseFigures<S> F_;
  double e0_ = 0, ek0_ = 0, uExt0_ = 0;
  S workPy_ = S(0), workPyAtMax_ = S(0), reboundV_ = S(0);
  std::vector<S> workPa_, workPaAtMax_;
  double tHmax_ = 0;
  double epsFriction_ = 0;
  double bottomSpeed_ = -1;
  std::vector<double> stickStart_;
  std::vector<bool> moved_, strutBottomed_;
  std::vector<bool> regularised_;  // per strut: regularised friction (its sticks are watched for the kink notes)
  long steps_ = 0;
};

}  // namespace lg
