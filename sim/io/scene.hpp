// Scene files (TOML): bodies, joints, stops, force elements, solver settings and drop cases.
// The parser validates at the edge: every error names the file, line, key, value and rule, and the
// caller exits with status 2 before writing anything. See docs/scene.md.
#pragma once

#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "sim/model/state.hpp"
#include "sim/envelope.hpp"
#include "sim/input_error.hpp"

namespace lg {

struct Certification;  // sim/certification.hpp

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
  Envelope envelope;         // the [envelope] table (sim/envelope.hpp); declared = false without one
};

// The envelope point a case of the scene runs at: its corner's, else the scene's own.
inline const EnvelopePoint<double>& casePoint(const Scene& scene, const DropCase& c) {
  return c.corner ? c.corner->at : scene.envelope.point;
}

// The integrators by their scene-file names ("dopri5", "ros34pw2", "ros2", "rk4", "euler"); false if
// the name is none of them. integratorNames() lists them for messages.
bool integratorFromName(const std::string& name, IntegratorKind& kind);
std::string integratorNames();
std::vector<std::string> integratorList();  // the same names, as a list

// Parses a scene file; throws InputError.
Scene loadScene(const std::string& path);
// Parses scene text; 'file' names it in messages; 'baseDir' resolves relative table paths.
Scene parseScene(const std::string& text, const std::string& file, const std::string& baseDir = ".");
// Builds a scene from an already parsed document (used by design studies after editing 'doc').
Scene buildScene(const toml::table& doc, const std::string& file, const std::string& baseDir = ".");
// Parses and validates an [envelope] table for 'scene' (its struts, tyres and S_max known): every key's
// rule, and the nominal point, the scene's point and every corner run (no strut locks: envelopeProblem,
// sim/scene_check.hpp). Throws InputError naming file, line and key (sim/io/scene_envelope.cpp).
Envelope parseEnvelope(const toml::table& t, const std::string& file, const Scene& scene);

// Design-parameter paths "<element>.<key>" (e.g. "strut.f1", "tyre.K", "airframe.mass"): the element
// is a body, joint, stop or force element named in the scene, or "case.<name>" for a drop case.
// Throws InputError naming 'where' if the path does not name a numeric scalar of the scene.
// A table's sample is "<element>.<key>[k]" (k from 0: "strut.f1_table[3]", the area of the metering
// pin's fourth sample [m^2]); the document must hold that table inline (see inlineTables).
double getParameter(const toml::table& doc, const std::string& path, const std::string& where = "");
void setParameter(toml::table& doc, const std::string& path, double value, const std::string& where = "");
// Whether a path names a table's sample ("strut.f1_table[3]").
bool tableSample(const std::string& path);
// Replaces each table file that one of 'paths' samples by the table inline, { stroke = [...], area =
// [...] } with the scene's values, so that setParameter can write its samples (best.toml,
// calibrated.toml, --set); other keys and tables are left as they are.
void inlineTables(toml::table& doc, const Scene& scene, const std::vector<std::string>& paths);

// Writes the document back as TOML.
std::string toTomlString(const toml::table& doc);

}  // namespace lg
