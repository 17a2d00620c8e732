// Sensitivity studies of a gear (`sensitivity STUDY`): the study file's variables and ranges, the
// [sensitivity] table's methods, metrics and cases of interest (study.hpp, SensitivitySettings).
//
//  - local: elasticities d ln f / d ln x_i of every metric of every case at the baseline (the
//    variables' initial values), by central differences with relative step h (uq/local.hpp);
//  - Morris: elementary effects on a p-level grid in the scaled variables, r trajectories
//    (uq/morris.hpp);
//  - Sobol: first-order and total indices, Saltelli scheme on a shifted Sobol sequence, N(d+2) designs
//    (uq/sobol_indices.hpp), with a convergence table over N/8, N/4, N/2, N.
// The global methods sample each variable uniformly in its scaled coordinate (study.hpp): uniform
// between its bounds, or log-uniform with log = true.
//
// One run is one design on every case of interest; its outputs are the metrics of interest of each
// case (a failed case: NaN outputs for that case only, with the reason kept). Runs are spread over MPI
// ranks and threads (uq/batch.hpp) and every estimate is made from the gathered runs in run order, so
// the results are the same bits for any thread and rank count. Seeds: one user seed; the Sobol shift,
// the Morris trajectories and the bootstraps get their own streams of it (uq::streamSeed).
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "optim/study.hpp"
#include "uq/batch.hpp"
#include "uq/local.hpp"
#include "uq/morris.hpp"
#include "uq/sobol_indices.hpp"

namespace lg::optim {

// One output of a run: a metric of a case.
struct SensitivityOutput {
  int caseIndex = 0;     // into Study::cases
  std::string caseName;
  std::string metric;    // a name of lg::metricCatalogue()
  std::string unit;      // its SI unit
  std::string label() const { return metric + "@" + caseName; }
};

// The outputs in their order: metric-major (every case of interest of the first metric, then the next).
std::vector<SensitivityOutput> sensitivityOutputs(const Study& s, const SensitivitySettings& g);

// The derivative source printed in every local report.
std::string derivativeSource(const SensitivitySettings& g);

// Checks what the study file's parser cannot know (the methods and the sample size may come from the
// command line): local sensitivities need every variable's baseline nonzero; the drops of every
// method together at most kMaxSensitivityDrops, the bootstrap's work (resamples x N) at most
// kMaxBootstrapWork. 'samplesFlag' ("--samples", or "" for the file's key) names the size's source.
// Throws lg::InputError.
constexpr double kMaxSensitivityDrops = 1e7, kMaxBootstrapWork = 1e9;
void checkSensitivity(const Study& s, const SensitivitySettings& g, const std::string& samplesFlag = "");
// The drops the settings ask for: local 1 + D (exact) or 1 + 2D (central), Morris r (D + 1), Sobol
// N (D + 2), each over the chosen cases.
double sensitivityDrops(const Study& s, const SensitivitySettings& g);

// A run that failed somewhere: where and why.
struct RunFailure {
  std::size_t run = 0;
  std::string where;    // "baseline", "strut.f1 +h", "trajectory 3 step 2", "block 17 AB^2"
  std::string message;  // "case 'cert-reserve': ..."
};

struct LocalStudy {
  std::vector<double> x0;              // baseline (physical)
  bool exact = true;                   // exact derivatives (one run with them); false: central differences
  double h = 0;                        // relative step (central differences)
  std::vector<std::string> oneSided;   // per output: why its exact derivatives are one-sided ("" smooth)
  std::vector<double> points;          // 2d+1 designs (physical), row-major
  std::vector<uq::Outcome> runs;
  std::vector<uq::Elasticities> outputs;  // per output
};

struct MorrisStudy {
  uq::MorrisDesign design;             // scaled points
  std::vector<double> points;          // the same designs in physical units
  std::vector<uq::Outcome> runs;
  std::vector<uq::MorrisIndices> outputs;
};

struct SobolStudy {
  uq::SaltelliDesign design;           // scaled points
  std::vector<double> points;          // physical units
  std::vector<uq::Outcome> runs;
  std::vector<uq::SobolIndices> outputs;
  std::vector<std::size_t> convergenceN;                  // N/8, N/4, N/2, N (those >= 4)
  std::vector<std::vector<uq::SobolIndices>> convergence; // [level][output], point estimates
};

struct MethodFailures {
  std::size_t runs = 0;                       // runs with any failed case
  std::vector<std::size_t> perCase;           // per case of interest: runs where it failed
  std::vector<RunFailure> list;               // every failed run, in run order
};

struct SensitivityResult {
  SensitivitySettings settings;                // as used (command-line overrides applied)
  std::vector<SensitivityOutput> outputs;
  std::optional<LocalStudy> local;
  std::optional<MorrisStudy> morris;
  std::optional<SobolStudy> sobol;
  MethodFailures localFailures, morrisFailures, sobolFailures;
  std::size_t designs = 0, drops = 0;          // designs run, drops simulated (designs x cases)
};

struct SensitivityOptions {
  int threads = 1;                             // OpenMP threads within a rank
  uq::Communicator* comm = nullptr;            // null: one process
  std::function<bool()> stop;                  // polled before each design and by the simulator (Ctrl-C)
  // Progress of this rank: the method, runs done, this rank's runs of the method.
  std::function<void(const std::string& method, std::size_t done, std::size_t mine)> progress;
};

// One design on the cases of interest: the outputs in sensitivityOutputs() order. Never throws. 'stop'
// (may be null) is polled by the simulator.
uq::Outcome evaluateSensitivityDesign(const Study& s, const SensitivitySettings& g, const std::vector<double>& x,
                                      const std::function<bool()>& stop = {});

// Runs the methods of 'g'. Every rank returns the same result.
SensitivityResult runSensitivity(const Study& s, const SensitivitySettings& g, const SensitivityOptions& o);

}  // namespace lg::optim
