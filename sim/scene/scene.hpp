// A scene as data: the model and its initial state, the drop cases, the roles the drop-test reports
// read (airframe, struts, tyres, stops), gravity, the certification matrix and the servicing envelope.
// The readers of sim/io/ fill it (sim/io/scene.hpp); the drop layer (drop tests, checks, parameters,
// servicing) reads it and never a file. It still carries the document it was read from (doc, text) for
// the written scenes and the text-level overrides, until those change the data alone.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "sim/scene/envelope.hpp"
#include "sim/model/state.hpp"

namespace lg {

struct Certification;  // sim/drop/certification.hpp

// A named drop test: every body starts with velocity (0, -sinkSpeed, 0) along -gravity, no rotation, at
// the scene's positions (touchdown) or, from a height, dropHeight above them.
struct DropCase {
  std::string name;
  double sinkSpeed = 0;    // [m/s] V_y0: at touchdown, or (dropHeight > 0) at the release
  double dropHeight = 0;   // [m] h_d: the release this far above the touchdown positions (the gear hanging on
                           // its extension stop); touchdown at sqrt(V_y0^2 + 2 g (1 - L) h_d) (touchdownSpeed)
  double liftRatio = 0;    // [-] L: lift P_H = L G g on the lift elements
  double duration = 0.8;   // [s]
  double forwardSpeed = 0; // [m/s] V_x: the ground moves aft at V_x under the tyres that declare mu_x
  std::map<std::string, double> masses;  // [kg] body name -> mass, overriding the scene for this case
  // The point of the scene's [envelope] the case runs at (a corner of certify or a robust study); none:
  // the scene's own point (Envelope::point).
  std::optional<EnvelopeCorner> corner;
};

// The speed at touchdown of a drop from the height h [m] released at v0 [m/s] with lift ratio L: the gear
// moves as one body until its tyre touches (a rigid extension stop), accelerated by g (1 - L) (the lift
// acts from the release on): sqrt(v0^2 + 2 g (1 - L) h); v0 itself when h = 0. NaN when a drop from a
// height never reaches the ground (v0^2 + 2 g (1 - L) h <= 0).
template <class S> S touchdownSpeed(const S& v0, const S& L, double h, double g) {
  using std::sqrt;
  if (h == 0) return v0;
  const S v2 = v0 * v0 + S(2 * g * h) * (S(1) - L);
  return v2 > S(0) ? S(sqrt(v2)) : S(std::numeric_limits<double>::quiet_NaN());
}
inline double touchdownSpeed(const DropCase& c, double g) { return touchdownSpeed(c.sinkSpeed, c.liftRatio, c.dropHeight, g); }
// The time of that fall [s]: h over the mean of the release and touchdown speeds.
inline double fallTime(const DropCase& c, double g) {
  return c.dropHeight > 0 ? 2 * c.dropHeight / (c.sinkSpeed + touchdownSpeed(c, g)) : 0.0;
}

// What a scene declares for the drop-test reports.
struct GearRoles {
  std::string airframe;                 // body whose vertical displacement is h
  std::vector<int> tyres, struts;       // force element indices
  std::vector<int> stops;               // constraint indices of the rigid (unilateral) stops
  std::vector<int> pads;                // force indices of the elastic extension stops (StopPad)
  std::vector<int> stopEntry, padEntry; // per rigid stop, per pad: its row of the file's [[stop]] array
  std::vector<int> lifts;               // force element indices of lift elements
  std::vector<double> strokeLimits;     // per strut: S_max [m], the stroke at its bottoming stop (a
                                        // "min_distance" stop on the strut's own two points); NaN if none
  std::vector<int> bottomingStops;      // per strut: that stop's constraint index, -1 if none
};

struct Scene {
  std::string file;          // path as given (for messages)
  std::string name;
  toml::table doc;           // the parsed document (design studies edit it and rebuild)
  std::string text;          // the file's text as read: a written scene keeps it (sim/io/toml_rewrite.hpp)
  Model<double> model;
  State<double> initial;     // positions at t = 0 (velocities set per case)
  std::vector<DropCase> cases;
  GearRoles roles;
  double gravity = 9.80665;  // [m/s^2] |g|
  Vec3<double> up{0, 1, 0};  // -g / |g|
  std::shared_ptr<const Certification> certification;  // the [certification] table, if declared
  Envelope envelope;         // the [envelope] table (sim/scene/envelope.hpp); declared = false without one
};

// The envelope point a case of the scene runs at: its corner's, else the scene's own.
inline const EnvelopePoint<double>& casePoint(const Scene& scene, const DropCase& c) {
  return c.corner ? c.corner->at : scene.envelope.point;
}

}  // namespace lg
