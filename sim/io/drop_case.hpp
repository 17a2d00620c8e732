// The one reader of a drop case's keys, wherever a drop is declared: a scene's [[case]], a study's
// [[case]] and a calibration's [[measurement]] read the same keys by the same rules (docs/scene.md).
//
//   sink_speed    [m/s]  V_y0: at touchdown, or at the release of a drop from a height; the touchdown
//                        speed within the sink-speed rule (> 0, at most 10 m/s: sim/scene/check.hpp)
//   drop_height   [m]    h_d >= 0: released this far above the touchdown positions (a gravity element,
//                        and a fall that reaches the ground: L < 1 or sink_speed > 0)
//   lift_ratio    [-]    L within the lift-ratio rule (>= 0, at most 1.5); > 0 only with a lift element
//   duration      [s]    in (0, 60]; default: the case's own, or 0.8 s after a rigid gear's touchdown
//                        for a new case or a new drop height
//   forward_speed [m/s]  V_x in [0, 150]: the ground under the tyres that declare mu_x (spin-up);
//                        > 0 only with such a tyre
//   masses        table  body = mass [kg] (> 0), over the scene's bodies for this case
#pragma once

#include "sim/io/toml_reader.hpp"
#include "sim/scene/scene.hpp"

namespace lg {

// [m/s] The largest forward speed a drop may have (beyond any landing speed): a case's and the
// certification matrix's alike.
constexpr double kMaxForwardSpeed = 150;
// Whether a tyre of the scene declares the longitudinal friction mu_x (wheel spin-up): a forward speed
// needs one.
bool declaresSpinUp(const Scene& scene);

// The first of the keys above that the table sets, in the order above ("" if none): a table that sets
// one declares a drop of its own.
std::string dropCaseKey(const TomlReader& r);

// Reads the keys of the table that are present over 'c' (a scene case it overrides, or a new case:
// 'fresh', which then needs sink_speed unless it gives drop_height) on 'scene' (its bodies, gravity,
// lift elements and tyres built). Throws InputError naming the file, the line, the key and the rule.
void readDropCase(const TomlReader& r, const Scene& scene, DropCase& c, bool fresh);

}  // namespace lg
