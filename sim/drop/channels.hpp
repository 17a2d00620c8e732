// The channels the drop observer (sim/drop/observer.hpp) reads of a run at one time, in any scalar:
// the gear's vertical load P_y [N] and its rate [N/s], the airframe's travel h [m] and h' [m/s], the drag
// load P_x [N]; per strut its stroke s [m], s' [m/s] and force P_a [N]; per tyre its deflection delta
// [m], delta' [m/s], load P_t [N], P_t' [N/s] and drag P_x [N] (0 without a longitudinal force).
#pragma once

#include <cstddef>
#include <vector>

namespace lg {

template <class S> struct DropChannels {
  S t = S(0), Py = S(0), PyDot = S(0), h = S(0), hdot = S(0), Px = S(0);
  std::vector<S> s, sdot, Pa;        // per strut
  std::vector<S> delta, ddelta, Pt, dPt, px;  // per tyre (px: P_x, 0 without a longitudinal force)
  DropChannels(size_t struts = 0, size_t tyres = 0)
      : s(struts), sdot(struts), Pa(struts), delta(tyres), ddelta(tyres), Pt(tyres), dPt(tyres), px(tyres) {}
};

}  // namespace lg
