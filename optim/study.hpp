// Design studies of a gear scene (docs/study.md): a study file (TOML, ".cfg" or ".toml")
// names a scene, the design variables (scene parameters by path), the drop cases with their roles,
// the objective, the constraints, the certification matrix and the NLopt algorithm. `optimize` runs it.
//
//   scene = "../data/seed_gear.toml"          # relative to the study file
//   [solver]      integrator = "ros34pw2", rtol = 1e-4, atol, step | accuracy = 1e-3   # into the scene's [solver]
//                 (absent: the scene's setting if accurate enough for the study's tolerances, else the
//                 accuracy they need; Study::solverChoice says which)
//   [[variable]]  path = "strut.f1", lower = 4e-5, upper = 1.2e-4, initial = 7e-5, log = true
//   [[case]]      name = "limit", role = "objective"      # a case of the scene or of the matrix ...
//   [[case]]      name = "hard", role = "constraint", sink_speed = 3.3, lift_ratio = 1.0, duration = 0.8,
//                 weight = 2, [case.masses] airframe = 4200.0   # ... or a new one
//   [objective]   kind = "min_peak_load" | "max_efficiency", aggregate = "worst" | "weighted_sum"
//   [[constraint]] metric = "stroke_margin", min = 0.01, max = ..., cases = ["reserve"] | "steering" | ...
//   [certification] role = "constraint" | "check", and any key of the scene's [certification] to override
//   [algorithm]   name = "LN_COBYLA", local = "LN_BOBYQA", maxeval = 200, maxtime = 0, xtol_rel = 1e-4,
//                 ftol_rel = 0, seed = 1, penalty = 100, initial_step = 0
//   [sensitivity] methods = ["local", "morris", "sobol"], metrics = ["peak_load", ...], cases = [...],
//                 seed = 1, step = 0.01, levels = 4, trajectories = 20, samples = 256, resamples = 100,
//                 confidence = 0.95       (read by `sensitivity` only; optim/sensitivity.hpp)
//
// Roles. An objective case enters the objective (and the constraints that name it); a constraint case
// enters only the constraints; a check case is simulated and reported for the baseline and the best
// design, never steers. Every case of the scene and of its certification matrix that the study does not
// name joins as a check, so a study's result is always shown on all of them.
//
// Constraints. Each [[constraint]] bounds a per-case metric (sim/drop/metrics.hpp) on each case it names,
// one smooth NLopt inequality per case (no max over cases, no 0/1 step): g = value - max <= 0 or
// g = min - value <= 0. "static_stroke" is a metric of the design (the strut settled under 1 g), not of
// a case. The certification matrix (role "constraint") adds its limits on its cases: load factor within
// the design limit (ultimate for the reserve case), stroke margin to every bottoming stop, tyre limit.
//
// The parser validates at the edge: every error is an lg::InputError naming the study file, the line,
// the key (e.g. "variable[1].upper", zero-based like the scene's) and the rule.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "optim/optimizer.hpp"
#include "sim/drop/certification.hpp"
#include "sim/drop/run.hpp"
#include "sim/io/overrides.hpp"
#include "sim/scene/parameters.hpp"

namespace lg::optim {

enum class CaseRole { Objective, Constraint, Check };
const char* roleName(CaseRole r);
// Where a case comes from: the scene's [[case]] (re-read from each design's scene), the study's own
// [[case]] with its numbers, or the certification matrix (its W made up for each design).
enum class CaseOrigin { Scene, Study, Certification };
const char* originName(CaseOrigin o);

struct StudyCase {
  DropCase dropCase;        // resolved case ("<case>@<corner>" at a corner of the envelope; dropCase.corner)
  std::string baseName;     // the case's own name (the scene's or the matrix's: "cert-reserve")
  std::string corner;       // the envelope point it runs at ("nominal", a corner's name); empty: the scene's point
  CaseRole baseRole = CaseRole::Objective;  // the role the study gave the case (a corner copy of an
                                            // objective case constrains where the objective is nominal)
  CaseRole role = CaseRole::Objective;
  CaseOrigin origin = CaseOrigin::Study;
  double weight = 1;        // [-] weight in aggregate = "weighted_sum"
  int line = 0;             // its [[case]] table (0: added by the study itself)
  bool steers() const { return role != CaseRole::Check; }
};

enum class ObjectiveKind { MinPeakLoad, MaxEfficiency };
enum class Aggregate { Worst, WeightedSum };

// Per objective case figure f_i: peak load P_y,max [N] (minimised) or efficiency eta [-] (maximised).
// aggregate "worst" takes the worst objective case (max_i P_i, resp. min_i eta_i); "weighted_sum"
// sum_i w_i f_i.
struct Objective {
  ObjectiveKind kind = ObjectiveKind::MinPeakLoad;
  Aggregate aggregate = Aggregate::Worst;
};

// A bound on a metric: value <= bound (upper) or value >= bound, on each of 'cases' (indices into
// Study::cases), or on the design for "static_stroke" (cases empty).
struct ConstraintSpec {
  std::string metric;        // a name of lg::metricCatalogue(), or "static_stroke"
  bool upper = true;
  double bound = 0;          // [metric's unit]
  double scale = 1;          // [metric's unit] g is divided by it for NLopt
  std::vector<int> cases;
  std::string source;        // "study" or "certification"
  std::string rule;          // for people: "stroke margin to the bottoming stop"
  int line = 0;
};

// One scalar constraint g_j <= 0 as NLopt sees it: a spec on one case.
struct ConstraintItem {
  int spec = 0;              // index into Study::constraints
  int caseIndex = -1;        // index into Study::cases, -1 for a design metric
  std::string name;          // "stroke_margin@cert-reserve", "static_stroke"
};

// [sensitivity]: what `sensitivity` computes on the study's variables and ranges (optim/sensitivity.hpp).
struct SensitivitySettings {
  bool local = true, morris = true, sobol = true;  // methods
  std::vector<std::string> metrics;  // names of lg::metricCatalogue() (default: every one the scene measures)
  std::vector<int> cases;            // indices into Study::cases (default: the steering cases)
  unsigned long long seed = 1;       // Sobol shift, Morris trajectories, bootstrap
  bool exactDerivatives = true;      // local: exact derivatives (forward mode); false: central differences
  double step = 0.01;                // [-] local: relative step h of the central differences
  int levels = 4;                    // [-] Morris: grid levels p (even)
  int trajectories = 20;             // [-] Morris: r
  int samples = 256;                 // [-] Sobol: base sample N (a power of two)
  int resamples = 100;               // [-] bootstrap replicates
  double confidence = 0.95;          // [-] bootstrap interval
  int line = 0;                      // the [sensitivity] table (0: absent)
};

// [envelope] of a study: where its cases run in the scene's servicing and temperature envelope
// (sim/scene/envelope.hpp), and any key of the scene's [envelope] to override.
//   constraints = "corners" | "nominal"   the steering cases (and so every constraint) at every point of
//                                          the envelope, or at the nominal point only
//   objective = "nominal" | "worst"       the objective at the nominal point (its corner copies constrain),
//                                          or the worst over every point (aggregate "worst": an epigraph)
//   checks = "corners" | "nominal"        the check cases (re-checked for baseline and best) likewise
//   nominal_study = true                  a robust study first runs the nominal one (the same study at the
//                                          nominal point) for the price of robustness (report.md, result.json)
// Without the table a study runs its steering cases at the scene's point and, where the scene declares
// an envelope, re-checks the checks at every corner (a violation there is shown, never hidden).
struct EnvelopeUse {
  bool constraintsAtCorners = false;
  bool objectiveWorst = false;
  bool checksAtCorners = true;
  bool nominalStudy = true;
  int line = 0;            // the study's [envelope] table (0: absent)
  bool robust() const { return constraintsAtCorners || objectiveWorst; }
};

struct Study {
  std::string file;       // study file as given (messages)
  std::string name;       // "name" key, default: file stem
  std::string sceneFile;  // resolved path of the scene
  std::string sceneDir;   // its directory (relative tables)
  Scene scene;            // baseline scene (the study's [solver] and [certification] written into its doc)
  std::vector<Variable> variables;
  std::vector<Parameter> parameters;   // the variables resolved in the scene (one each, same order)
  std::vector<StudyCase> cases;        // steering cases first (study order), then the checks
  Objective objective;
  std::vector<ConstraintSpec> constraints;
  std::vector<ConstraintItem> items;   // the g_j, in order
  std::shared_ptr<const Certification> certification;  // the matrix (scene's, with the study's overrides)
  CaseRole certificationRole = CaseRole::Check;         // of the matrix cases the study does not name
  bool staticStrokeNeeded = false;
  AlgorithmSettings algorithm;
  SensitivitySettings sensitivity;
  EnvelopeUse envelope;                // the study's [envelope]
  std::vector<EnvelopeCorner> corners; // the scene's envelope points the cases run at (nominal first; empty: none)
  std::vector<ParameterOverride> sets; // the command line's --set (the nominal variant of a robust study reads them)
  // The drop-test solver: the relative accuracy of the metrics the study's tolerances need (a tenth of the
  // smallest of xtol_rel and ftol_rel, within 1e-5 .. 1e-2), and the setting the study runs with, in
  // words, with why (reports and the terminal). Without a [solver] of its own the study keeps the
  // scene's setting where that is accurate enough (sim/drop/accuracy.hpp, impliedAccuracy), else it runs at
  // the accuracy it needs (written into best.toml's [solver] as `accuracy`).
  double accuracyNeeded = 1e-5;
  std::string solverChoice;

  int steeringCases() const;  // objective and constraint cases: cases[0 .. steeringCases())
};

// Parses and validates a study; throws lg::InputError (file, line, key, rule). 'sets' (the command
// line's --set) override parameters of the study's scene before anything else reads it.
// 'nominal': the study's nominal variant (its [envelope] constraints and objective at the nominal point).
Study loadStudy(const std::string& path, const std::vector<ParameterOverride>& sets = {}, bool nominal = false);
// 'file' names the text in messages; 'baseDir' resolves the scene path.
Study parseStudy(const std::string& text, const std::string& file, const std::string& baseDir = ".",
                 const std::vector<ParameterOverride>& sets = {}, bool nominal = false);

}  // namespace lg::optim
