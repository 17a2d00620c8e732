// The one reader of a drop case's keys (sim/io/drop_case.hpp).
#include "sim/io/drop_case.hpp"

#include <cmath>

#include "sim/scene/check.hpp"

namespace lg {

namespace {
const char* const kKeys[] = {"sink_speed", "drop_height", "lift_ratio", "duration", "forward_speed", "masses"};

bool hasGravity(const Scene& scene) {
  for (const auto& f : scene.model.forces)
    if (std::holds_alternative<Gravity<double>>(f.type)) return true;
  return false;
}

}  // namespace

bool declaresSpinUp(const Scene& scene) {
  for (int f : scene.roles.tyres)
    if (std::get<Tyre<double>>(scene.model.forces[f].type).longitudinal) return true;
  return false;
}

std::string dropCaseKey(const TomlReader& r) {
  for (const char* k : kKeys)
    if (r.has(k)) return k;
  return "";
}

void readDropCase(const TomlReader& r, const Scene& scene, DropCase& c, bool fresh) {
  const bool height = r.has("drop_height");
  if (height) c.dropHeight = r.nonNegative("drop_height", 0.0);
  if (r.has("sink_speed")) c.sinkSpeed = height ? r.nonNegative("sink_speed", 0.0) : r.number("sink_speed");
  else if (fresh && !height) c.sinkSpeed = r.number("sink_speed");  // (missing required number)
  if (r.has("lift_ratio")) {
    c.liftRatio = r.nonNegative("lift_ratio", 0.0);
    if (const std::string rule = liftRatioRule(c.liftRatio); !rule.empty()) r.fail("lift_ratio", rule);
  }
  if (c.liftRatio > 0 && scene.roles.lifts.empty()) r.fail("lift_ratio", "the scene declares no lift element");
  if (c.dropHeight > 0 && !hasGravity(scene)) r.fail("drop_height", "a drop from a height needs a gravity element");
  if (c.dropHeight > 0 && !(touchdownSpeed(c, scene.gravity) > 0))
    r.fail("drop_height", "the gear never reaches the ground: with lift_ratio " + fmt(c.liftRatio) +
                              " >= 1 it does not fall, so a drop from a height needs sink_speed > 0");
  if (r.has("sink_speed") || height)
    if (const std::string rule = sinkSpeedRule(touchdownSpeed(c, scene.gravity)); !rule.empty())
      r.fail(c.dropHeight > 0 ? "drop_height" : "sink_speed",
             c.dropHeight > 0 ? "the touchdown speed sqrt(sink_speed^2 + 2 g (1 - lift_ratio) drop_height): " + rule : rule);
  // (default: 0.8 s after the touchdown of a rigid gear, for a new drop)
  const double fall = c.dropHeight > 0 ? fallTime(c, scene.gravity) : 0.0;
  c.duration = r.duration("duration", fresh || height ? 0.8 + fall : c.duration);
  if (r.has("forward_speed")) {
    c.forwardSpeed = r.nonNegative("forward_speed", 0.0);
    if (!declaresSpinUp(scene)) r.fail("forward_speed", "no tyre of this scene declares the longitudinal friction coefficient mu_x");
    if (c.forwardSpeed > kMaxForwardSpeed)
      r.fail("forward_speed", "value " + fmt(c.forwardSpeed) + " m/s is not a landing speed (at most 150 m/s)");
  }
  r.masses("masses", scene.model, c.masses);
}

}  // namespace lg
