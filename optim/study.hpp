// Design studies of a gear scene (README.md, "Design studies"): a study file (TOML, ".cfg" or
// ".toml") names a scene, the design variables (scene parameters by path), the drop cases, the
// objective, the constraints and the NLopt algorithm. `optimize` runs it.
//
//   scene = "../data/seed_gear.toml"          # relative to the study file
//   [solver]      integrator = "ros34pw2", rtol = 1e-4, atol, step   # into the scene's [solver]
//   [[variable]]  path = "strut.f1", lower = 4e-5, upper = 1.2e-4, initial = 7e-5, log = true
//   [[case]]      name = "limit"              # a case of the scene ...
//   [[case]]      name = "hard", sink_speed = 3.3, lift_ratio = 1.0, duration = 0.8, weight = 2
//                 [case.masses] airframe = 4200.0   # ... or a new one
//   [objective]   kind = "min_peak_load" | "max_efficiency", aggregate = "max" | "weighted_sum"
//   [constraints] stroke_max = 0.15, stroke_margin = 0.0, tyre_deflection_max = "delta_max" | 0.09,
//                 static_stroke = [0.02, 0.08], no_bottoming = true, rebound_max = 0.05
//   [algorithm]   name = "LN_COBYLA", local = "LN_BOBYQA", maxeval = 200, maxtime = 0, xtol_rel = 1e-4,
//                 ftol_rel = 0, seed = 1, penalty = 100, initial_step = 0
//
// The parser validates at the edge: every error is an lg::InputError naming the study file, the
// line, the key (e.g. "variable[1].upper", zero-based like the scene's) and the rule.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/drop_test.hpp"

namespace lg::optim {

// One design variable: a numeric scene parameter between bounds.
struct Variable {
  std::string path;      // scene parameter path, e.g. "strut.f1" (see lg::getParameter)
  double lower = 0;      // [parameter units] lower bound
  double upper = 0;      // [parameter units] upper bound (> lower)
  double initial = 0;    // [parameter units] start value (default: the scene's value)
  bool log = false;      // optimise log(value) (needs lower > 0)
  int line = 0;          // line of the [[variable]] table in the study file
};

// The optimiser works in scaled coordinates u in [0, 1]^n:
//   linear: x = lower + u (upper - lower),   log: x = lower (upper/lower)^u.
double toPhysical(const Variable& v, double u);
double toScaled(const Variable& v, double x);
std::vector<double> toPhysical(const std::vector<Variable>& vars, const std::vector<double>& u);
std::vector<double> toScaled(const std::vector<Variable>& vars, const std::vector<double>& x);

struct StudyCase {
  DropCase dropCase;        // resolved case (a scene case is re-read from each design's scene)
  bool fromScene = false;   // true: name refers to a case of the scene, no overrides
  double weight = 1;        // [-] weight in aggregate = "weighted_sum"
  int line = 0;
};

enum class ObjectiveKind { MinPeakLoad, MaxEfficiency };
enum class Aggregate { Max, WeightedSum };

// Per-case figure f_i: peak load P_y,max [N] (minimised) or efficiency eta [-] (maximised).
// aggregate "max" takes the worst case (max_i P_i, resp. min_i eta_i); "weighted_sum" sum_i w_i f_i.
struct Objective {
  ObjectiveKind kind = ObjectiveKind::MinPeakLoad;
  Aggregate aggregate = Aggregate::Max;
};

// Constraints g <= 0, evaluated on the worst case (maximum over the cases).
struct Constraints {
  std::optional<double> strokeMax;          // [m] max stroke <= strokeMax - strokeMargin
  double strokeMargin = 0;                  // [m]
  bool tyreDeflectionFromScene = false;     // tyre_deflection_max = "delta_max": the tyre's delta_max
  std::optional<double> tyreDeflectionMax;  // [m] a number
  std::optional<double> staticStrokeLower;  // [m] lg::staticStroke >= lower
  std::optional<double> staticStrokeUpper;  // [m] lg::staticStroke <= upper
  bool noBottoming = false;                 // no case may touch the bottoming stop (0/1 constraint)
  std::optional<double> reboundMax;         // [m] rebound height above touchdown, -min h, <= reboundMax
};

struct AlgorithmSettings {
  std::string name = "LN_COBYLA";  // NLopt algorithm name (nlopt_algorithm_from_string)
  std::string local;               // local optimiser of MLSL / AUGLAG (default LN_BOBYQA)
  int maxeval = 200;               // [-] 0: no limit
  double maxtime = 0;              // [s] 0: no limit
  double xtolRel = 1e-4;           // [-] on the scaled variables
  double ftolRel = 0;              // [-] 0: off
  unsigned seed = 1;               // nlopt::srand(seed), always called
  double penalty = 100;            // [-] exact-penalty weight (algorithms without native constraints)
  double initialStep = 0;          // [-] initial step in scaled units (0: NLopt's default)
};

struct Study {
  std::string file;       // study file as given (messages)
  std::string name;       // "name" key, default: file stem
  std::string sceneFile;  // resolved path of the scene
  std::string sceneDir;   // its directory (relative tables)
  Scene scene;            // baseline scene
  std::vector<Variable> variables;
  std::vector<StudyCase> cases;
  Objective objective;
  Constraints constraints;
  AlgorithmSettings algorithm;
};

// Parses and validates a study; throws lg::InputError (file, line, key, rule).
Study loadStudy(const std::string& path);
// 'file' names the text in messages; 'baseDir' resolves the scene path.
Study parseStudy(const std::string& text, const std::string& file, const std::string& baseDir = ".");

// True where NLopt handles inequality constraints itself (COBYLA, ISRES, AGS, AUGLAG family); the
// other local algorithms run inside LN_AUGLAG, the global ones get an exact penalty (optimizer.hpp).
bool nativeConstraints(const std::string& algorithm);

}  // namespace lg::optim
