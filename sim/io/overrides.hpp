// Parameter overrides and case matrices from the command line (simulate, optimize): "--set
// PATH=VALUE" in the study variables' path syntax, and "--sink-speeds 1.5:0.25:3.5 --lift-ratios
// 0.667,1" expanded to every combination. Each is validated like the file it stands for: a bad one is
// an InputError naming "command line", the flag and the rule.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "sim/io/scene.hpp"

namespace lg {

struct ParameterOverride {
  std::string path;  // "<element>.<key>", e.g. "strut.f1"
  double value = 0;  // in the parameter's SI unit
};

// "strut.f1=8e-5" -> {strut.f1, 8e-5}; throws InputError("command line", "--set", ...).
ParameterOverride parseOverride(const std::string& text);
// Applies overrides to a scene document (each path must name a numeric scalar of the scene), then
// rebuilds the scene: its own rules apply to the new values.
Scene applyOverrides(const Scene& scene, const std::vector<ParameterOverride>& sets);

// Prepares a scene document for writing into 'outDir' (best.toml, calibrated.toml): relative table
// paths ("*_table" keys), which resolve against the scene's folder 'sceneDir', are rewritten to resolve
// from outDir (absolute where no relative path leads there).
void relocateTablePaths(toml::table& doc, const std::string& sceneDir, const std::string& outDir);

// The [solver] table 't' of a study or calibration file (integrator, rtol, atol = rtol/100 unless given,
// step; or accuracy, which chooses integrator and tolerances; absent: nothing) applied to the scene's
// settings by the one rule of solver overrides (applySolverOverrides, sim/drop/accuracy.hpp), and the same
// keys written into the scene document's [solver], so that the written scenes (best.toml,
// calibrated.toml) run with those settings too. Errors name 'file'.
void applySolverTable(const toml::table* t, const std::string& file, Scene& scene);

// The text of a written scene holding 'doc': the scene file's own text 'source' with only the changed
// values replaced (sim/io/toml_rewrite.hpp), so that a diff against the scene shows the change alone;
// where that cannot reproduce 'doc' exactly, the document written whole, after a comment saying why.
std::string writtenSceneText(const std::string& source, const std::string& file, const toml::table& doc);

// A list of numbers "a,b,c" or a range "start:step:stop" (stop included when the steps land on it
// within 1e-9 of a step); every value must satisfy 'positive' (> 0) or be >= 0. 'flag' names it in errors.
std::vector<double> parseValueList(const std::string& text, const std::string& flag, bool positive);

// The drop cases of every (sink speed, lift ratio) pair, named "V<speed>_L<ratio>" (e.g. V2.5_L0.667),
// each running 'duration' seconds with the scene's masses.
std::vector<DropCase> caseMatrix(const std::vector<double>& sinkSpeeds, const std::vector<double>& liftRatios,
                                 double duration);

}  // namespace lg
