// The certification drop-test matrix (docs/certification.md):
// a [certification] table names the rules' basis and the unit's masses and limits; from it come the
// limit, takeoff-weight and reserve-energy cases with the rules' sink speeds and lift ratios, and the
// limits each case must meet. `certify` runs them; design studies use them as constraint cases.
//
//   [certification]
//   basis = "part25"            # part25 | cs25 | part23 | cs23 | custom
//   landing_mass = 4050.0       # [kg] mass on the unit at the design landing weight
//   takeoff_mass = 4300.0       # [kg] at the design takeoff weight (Part 25 / CS-25 takeoff case)
//   wing_loading = 120.0        # [kg/m^2] W/S of the aircraft (Part 23 / CS-23 sink speed)
//   lift_ratio = 1.0            # L of the limit cases (default 1; Part 23 at most and default 2/3)
//   reserve_lift_ratio = 1.0    # L of the reserve-energy case (default 1)
//   limit_load_factor = 2.5     # design limit load factor: n_g (Part 25), n = n_g + L (Part 23)
//   stroke_margin = 0.01        # [m] stroke to keep clear of every bottoming stop, in every case
//   tyre_limit = 0.10           # [m] largest tyre deflection (default: each tyre's delta_max)
//   mass_body = "airframe"      # the body whose mass makes up W (default: the scene's airframe)
//   duration = 0.8              # [s] of each case
//   forward_speed = 60.0        # [m/s] of every case: wheel spin-up on the tyres that declare mu_x (default:
//                               # the largest forward speed of the scene's own cases, 0 where they have none)
//   [[certification.case]]      # basis = "custom" only: name, kind = "limit" | "reserve",
//                               # sink_speed [m/s], lift_ratio, mass [kg]
//
// Part 25 / CS-25: limit at landing weight 3.05 m/s, limit at takeoff weight 1.83 m/s, reserve energy
// 3.66 m/s (CS-25: 3.7). Part 23 / CS-23: limit V = 4.4 (W/S)^(1/4) ft/s (W/S in lb/ft^2) clamped to
// 7 .. 10 ft/s, reserve 1.2 V at L = 1. Limits per case: the load factor within the design limit (the
// reserve case within ultimate = 1.5 x limit), the stroke margin to every bottoming stop, the tyre
// deflection, and a compression that ends within the simulated time. Part 23's floors n >= 2.67 and
// n_g >= 2.0 are reported for the unit.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "sim/drop/run.hpp"
#include "sim/core/input_error.hpp"
#include "sim/drop/metrics.hpp"
#include "sim/drop/servicing.hpp"

namespace lg {

enum class CertBasis { Part25, CS25, Part23, CS23, Custom };
bool certBasisFromName(const std::string& name, CertBasis& basis);
std::string certBasisNames();  // for messages

enum class CertKind { Limit, Reserve };
const char* certKindName(CertKind k);

// One case of the matrix.
struct CertCase {
  std::string name;       // "cert-limit-landing", ...
  CertKind kind = CertKind::Limit;
  double sinkSpeed = 0;   // [m/s]
  double liftRatio = 0;   // [-]
  double mass = 0;        // [kg] W, the mass on the unit
  double duration = 0.8;  // [s]
  double forwardSpeed = 0;  // [m/s] V_x: the ground under the tyres that declare mu_x (spin-up, spring-back)
  std::string rule;       // where its numbers come from, for people
};

struct Certification {
  std::string file;        // where the table was read (messages)
  int line = 0;
  CertBasis basis = CertBasis::Part25;
  std::string basisName = "part25";
  double landingMass = 0;        // [kg]
  double takeoffMass = 0;        // [kg] (Part 25 / CS-25)
  double wingLoading = 0;        // [kg/m^2] (Part 23 / CS-23)
  double liftRatio = 1;          // [-] limit cases
  double reserveLiftRatio = 1;   // [-]
  double limitLoadFactor = 0;    // [-] n_g (Part 25) or n (Part 23)
  double ultimateFactor = 1.5;   // [-] ultimate / limit
  double strokeMargin = 0;       // [m]
  double tyreLimit = 0;          // [m]; 0: each tyre's delta_max
  std::string massBody;          // body whose mass makes W up
  double duration = 0.8;         // [s]
  double forwardSpeed = 0;       // [m/s] of every matrix case (spin-up where a tyre declares mu_x)
  std::string forwardSpeedSource;  // where it comes from, for people
  std::vector<CertCase> cases;   // the matrix, generated (or custom)

  bool part23() const { return basis == CertBasis::Part23 || basis == CertBasis::CS23; }
  // Design limit ground-reaction factor n_g,lim: the declared factor (Part 25, custom) or n_lim - L (Part 23).
  double limitGroundFactor() const { return part23() ? limitLoadFactor - liftRatio : limitLoadFactor; }
  const CertCase* findCase(const std::string& name) const;
};

// Part 23 / CS-23 limit sink speed [m/s] for a wing loading W/S [kg/m^2]: 4.4 (W/S)^(1/4) ft/s with W/S
// in lb/ft^2 (1 kg/m^2 = 0.204816 lb/ft^2), clamped to 7 .. 10 ft/s.
double part23SinkSpeed(double wingLoading);

// The cases a basis prescribes for the certification's masses, lift ratios, duration and forward speed
// (Part 25 / CS-25: limit at landing and takeoff weight, reserve energy; Part 23 / CS-23: limit at
// V(W/S) and reserve at 1.2 V); none for "custom", whose cases are its own. The [certification] table is
// read by sim/io/certification.hpp.
std::vector<CertCase> basisCases(const Certification& c);

// The drop case of a matrix case on a scene: the mass body's mass set so that the scene's total is W.
DropCase certDropCase(const Scene& scene, const Certification& c, const CertCase& cc);

// A limit a case must meet: metric <= bound (upper) or metric >= bound.
struct Limit {
  std::string metric;  // a name of metricCatalogue()
  bool upper = true;
  double bound = 0;    // [metric's unit]
  std::string rule;    // "limit load factor", "stroke margin", ...
};
// The limits of a matrix case, and those the scene's own cases are checked against (stroke margin and
// tyre, without loads: their conditions are not the rules').
std::vector<Limit> caseLimits(const Certification& c, const CertCase& cc, const Scene& scene);
std::vector<Limit> checkLimits(const Certification* c, const Scene& scene);

struct LimitResult {
  Limit limit;
  double value = 0;
  bool pass = false;
};

// One case's verdict: the limits, the simulation's own status, and the compression within the run.
struct CaseVerdict {
  std::string name;
  std::string role;          // "certification" or "check"
  CertCase cert;             // for matrix cases (kind, rule); for checks the case's V, L, W
  CaseMetrics metrics;
  std::vector<LimitResult> limits;
  bool pass = false;
  std::vector<std::string> reasons;  // why it fails, for people
};
CaseVerdict assessCase(const std::string& role, const CertCase& cc, const CaseMetrics& m, const std::vector<Limit>& limits);

// A requirement on the unit's design (Part 23's load-factor floors).
struct UnitItem {
  std::string name;
  double value = 0, bound = 0;
  bool pass = false;
  std::string rule;
};

// The worst point of the envelope for one limit of a case: the least margin over the points.
struct WorstCorner {
  Limit limit;
  std::string corner;       // its name
  double value = 0;         // [metric's unit] there
  double margin = 0;        // bound - value (an upper limit) or value - bound; < 0 breaks it; NaN: a run failed
  bool pass = false;        // the limit holds at every point
};

// One case over the envelope: its verdict at every point (Compliance::corners order, nominal first).
struct EnvelopeVerdict {
  std::string name;
  std::string role;                 // "certification" or "check"
  std::vector<CaseVerdict> at;      // per point
  std::vector<WorstCorner> worst;   // per limit of the case
  int failing = 0;                  // points at which it fails
  bool pass = false;                // it passes at every point
};
// The worst corner of each limit of a case's verdicts at the points (same limits at each).
std::vector<WorstCorner> worstCorners(const std::vector<CaseVerdict>& at, const std::vector<EnvelopeCorner>& corners);

struct Compliance {
  std::string scene;
  const Certification* spec = nullptr;
  std::vector<UnitItem> unit;
  std::vector<CaseVerdict> cases;   // the matrix (at the nominal point where an envelope is run)
  std::vector<CaseVerdict> checks;  // the scene's own cases
  bool pass = false;                // every matrix case and unit item passes (at every point of the envelope)
  bool checksPass = false;          // every check case stays within its limits (reported, not the verdict)
  // Over the scene's [envelope] (assessCompliance with 'envelope'): every case at every point.
  const Envelope* envelope = nullptr;         // null: the scene's point only
  std::vector<EnvelopeCorner> corners;        // the nominal point, then the corners
  std::vector<EnvelopeVerdict> envelopeCases, envelopeChecks;
  bool nominalPass = false;                   // every matrix case passes at the nominal point
  long drops = 0;                             // runs of the engine (cases x points; reruns of --accuracy not counted)
  long rhsEvaluations = 0;                    // their right-hand-side evaluations, all together
  // The strut at rest and its servicing chart (sim/drop/servicing.hpp) at the matrix's landing mass; absent
  // where not computed.
  std::optional<ServicingCurve> servicing;
  std::string provenanceJson, provenanceMarkdown;  // the run's provenance block (sim/io/provenance.hpp), if given
  const Scene* sceneRun = nullptr;  // the scene the cases ran on (the dossier's configuration; assessCompliance sets it)
};

// The unit items of a certification.
std::vector<UnitItem> unitItems(const Certification& c);

// Runs the matrix and the scene's own cases (as checks) and judges them. 'runs' (optional) receives
// the case results in the order matrix cases, then checks.
// With 'envelope' and a scene that declares one, every case runs at every point of its envelope (the
// nominal point, then the corners; cases x points in parallel, the same bits for any thread count) and
// passes only where it passes at all of them; 'runs' then holds the nominal point's.
Compliance assessCompliance(const Scene& scene, const Certification& c, int threads, const CaseOptions& opt = {},
                            std::vector<CaseResult>* runs = nullptr, bool envelope = false);

}  // namespace lg
