// What makes a scene physically consistent, checked on the built model: at load, where the parser names
// the file, line and key, and for every design a study, an override or a calibration makes from data
// (no text parsed again). The rules of a scene's values live here, once.
#pragma once

#include <optional>
#include <string>

#include "sim/scene/scene.hpp"

namespace lg {

// The plausible range of a drop's numbers, where a value outside is a unit mistake or a typing one, not
// a gear: a sink speed above 10 m/s (33 ft/s; the rules ask 1.83 .. 3.66 m/s, "3050" is mm/s), a lift
// ratio above 1.5. The rule in words for a value that breaks one, else empty: the scene's cases, a
// study's and the command line's matrices are held to the same.
constexpr double kMaxSinkSpeed = 10.0;  // [m/s]
constexpr double kMaxLiftRatio = 1.5;   // [-]
std::string sinkSpeedRule(double v);
std::string liftRatioRule(double v);

// A rule a scene's value breaks, located the way the scene file lays it out.
struct SceneProblem {
  std::string array;  // the scene file's array: "body", "stop", "force" or "case"
  int index = -1;     // the entry's position in that array
  std::string key;    // its key, e.g. "Omega0"
  std::string rule;   // the broken rule, for people
};

// Recomputes what derives from the scene's values (each strut's S_max at its bottoming stop) and
// checks every rule: positive and ordered values (D2 >= D, n > 1, p_atm < p01, ...), each strut fully
// extended at touchdown (L0 = |B - C|), a bottoming stop shorter than the extended strut and than the
// extension stop on the same points, a gas volume larger than the volume swept at the bottoming
// stroke, a metering-pin table covering the reachable stroke, no tyre pressed into the ground at
// touchdown, and drop cases with a sink speed > 0. Returns the first problem, if any.
std::optional<SceneProblem> checkScene(Scene& scene);

// Why the scene's [envelope] cannot run: its point or a corner at which a strut's gas volume is gone
// before its bottoming stop (it would lock) or its pre-charge is not above the atmosphere's; nothing
// where it can (or without an envelope). A design that moves the strut is checked again with it.
std::optional<std::string> envelopeProblem(const Scene& scene);

// "strut.Omega0: gas volume ..." for a problem: the element's name and key, as design paths read.
std::string describe(const Scene& scene, const SceneProblem& p);

}  // namespace lg
