// Reading scene files (TOML) into a Scene (sim/scene/scene.hpp): bodies, joints, stops, force elements,
// solver settings and drop cases. The parser validates at the edge: every error names the file, line,
// key, value and rule, and the caller exits with status 2 before writing anything. See docs/scene.md.
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

#include "sim/core/input_error.hpp"
#include "sim/scene/scene.hpp"

namespace lg {

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
// sim/scene/check.hpp). Throws InputError naming file, line and key (sim/io/scene_envelope.cpp).
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
