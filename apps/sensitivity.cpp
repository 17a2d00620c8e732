// sensitivity STUDY [--out DIR] [--threads N] [--method local|morris|sobol|all] [--samples N] [--seed S]
//             [--set PATH=VALUE]... [--plots] [--quiet]
// Local, Morris and Sobol sensitivities of a study's metrics to its variables (optim/sensitivity.hpp),
// written to DIR (optim/sensitivity_report.hpp). Under an MPI launcher (mpirun -n K sensitivity ...)
// the runs are spread over the ranks and rank 0 writes exactly what one process writes. Exit status
// (apps/cli.hpp): 0 done, 1 an output could not be written, 2 bad input (nothing written), 130
// interrupted by Ctrl-C (nothing written).
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>

#include <omp.h>

#include "apps/cli.hpp"
#include "sim/io/provenance.hpp"
#include "optim/sensitivity.hpp"
#include "optim/sensitivity_report.hpp"
#include "optim/study.hpp"
#include "sim/io/files.hpp"
#include "sim/io/overrides.hpp"
#include "sim/drop/metrics.hpp"
#ifdef LG_HAVE_MPI
#include "uq/mpi.hpp"
#endif

namespace {

constexpr int kNotGiven = std::numeric_limits<int>::min();

struct Cli {
  std::string study, out, method;
  std::vector<std::string> sets;
  int threads = 0;
  int samples = kNotGiven;           // (any value given is checked: 0 too)
  long long seed = kNotGiven;
  bool plots = false, quiet = false;
  std::vector<std::string> argv;  // the command line as given (the provenance block)
};

// Applies the command line to the study's [sensitivity]; a bad value is an InputError naming the flag.
void applyCli(const Cli& c, lg::optim::SensitivitySettings& g) {
  if (!c.method.empty()) {
    g.local = c.method == "local" || c.method == "all";
    g.morris = c.method == "morris" || c.method == "all";
    g.sobol = c.method == "sobol" || c.method == "all";  // (one of the four: addChoice)
  }
  if (c.samples != kNotGiven) {
    if (c.samples < 8 || c.samples > (1 << 20) || (c.samples & (c.samples - 1)) != 0)
      throw lg::InputError("command line", 0, "--samples",
                           "value " + std::to_string(c.samples) + " must be a power of two in [8, 2^20]");
    g.samples = c.samples;
  }
  if (c.seed != kNotGiven) {
    g.seed = static_cast<unsigned long long>(c.seed);
  }
}

// "peak_load@cert-reserve: strut.f1 (ST 0.61), ..." lines: the largest driver per method.
void printSummary(const lg::optim::Study& s, const lg::optim::SensitivityResult& r) {
  std::printf("%-36s %-26s %-26s %-26s\n", "output", "largest |elasticity|", "largest mu*", "largest ST");
  auto best = [&](const std::vector<double>& v, bool absolute) {
    int k = -1;
    for (size_t i = 0; i < v.size(); ++i)
      if (std::isfinite(v[i]) && (k < 0 || (absolute ? std::abs(v[i]) > std::abs(v[k]) : v[i] > v[k]))) k = static_cast<int>(i);
    if (k < 0) return std::string("-");
    char b[80];
    std::snprintf(b, sizeof b, "%s %.3g", s.variables[k].path.c_str(), v[k]);
    return std::string(b);
  };
  for (size_t j = 0; j < r.outputs.size(); ++j)
    std::printf("%-36s %-26s %-26s %-26s\n", r.outputs[j].label().c_str(),
                r.local ? best(r.local->outputs[j].E, true).c_str() : "-",
                r.morris ? best(r.morris->outputs[j].muStar, false).c_str() : "-",
                r.sobol ? best(r.sobol->outputs[j].ST, false).c_str() : "-");
}

// The command line: -1 to go on, otherwise the exit status (0 after --help or --version, 2 after a
// usage error; only rank 0 speaks).
int parseCommandLine(int argc, char** argv, bool root, Cli& c) {
  CLI::App app{"Local, Morris and Sobol sensitivities of a gear study (docs/sensitivity.md)"};
  lg::cli::addVersion(app, "sensitivity");
  lg::cli::addInputFile(app, "study", c.study, "study file (TOML, .cfg or .toml): variables, ranges, cases, [sensitivity]");
  lg::cli::addText(app, "--out", c.out, "output directory (default: <study stem>-sensitivity in the current directory)");
  lg::cli::addThreads(app, c.threads, "the designs, per process (0: the cores this process may use)");
  lg::cli::addChoice(app, "--method", c.method, "local, morris, sobol or all (default: [sensitivity] methods, else all)",
                     {"local", "morris", "sobol", "all"});
  lg::cli::addInteger(app, "--samples", c.samples, "Sobol base sample N, a power of two in [8, 2^20] (default: [sensitivity] samples)",
                      8, 1 << 20, "a power of two");
  lg::cli::addInteger(app, "--seed", c.seed, "seed of the Sobol shift, the Morris trajectories and the bootstraps", 0,
                      9223372036854775807LL);
  lg::cli::addTexts(app, "--set", c.sets, "override a parameter of the study's scene, PATH=VALUE in SI units (repeatable)");
  app.add_flag("--plots", c.plots, "draw the report's pictures with gnuplot (the data and scripts are written regardless)");
  app.add_flag("--quiet", c.quiet, "no progress line or summary");
  return lg::cli::parse(app, argc, argv, root);  // the other ranks parse silently: rank 0 says what is wrong
}

// Writes the outputs and prints the summary (rank 0); returns the exit status.
int finish(const Cli& c, const lg::optim::Study& study, const lg::optim::SensitivityResult& r, int ranks, int threads,
           double wall) {
  lg::optim::SensitivityFiles files;
  try {
    std::vector<lg::InputFile> inputs{{"study", c.study, ""}};
    for (const auto& f : lg::sceneInputs(study.scene)) inputs.push_back(f);
    std::vector<const char*> args;
    for (const auto& a : c.argv) args.push_back(a.c_str());
    const lg::Provenance provenance = lg::makeProvenance("sensitivity", static_cast<int>(args.size()), args.data(), inputs);
    files = lg::optim::writeSensitivity(study, r, c.out, c.plots, &provenance);
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kFailed;
  }
  const size_t shown = 10;
  for (size_t k = 0; k < files.warnings.size() && k < shown; ++k)
    std::cerr << "sensitivity: warning: " << files.warnings[k] << "\n";
  if (files.warnings.size() > shown)
    std::cerr << "sensitivity: warning: ... " << files.warnings.size() - shown << " more in report.md\n";
  if (c.quiet) return 0;
  printSummary(study, r);
  const int cores = ranks * threads;
  std::printf("%s: %zu designs, %zu drops in %.1f s on %d process(es) x %d thread(s): %.1f drops/s, %.1f per core\n",
              study.name.c_str(), r.designs, r.drops, wall, ranks, threads, r.drops / wall, r.drops / wall / cores);
  std::printf("  wrote %s/{report.md,indices.json,indices_*.csv,samples_*.csv%s}\n", c.out.c_str(),
              r.sobol ? ",convergence_sobol.csv" : "");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::unique_ptr<lg::uq::Communicator> comm;
#ifdef LG_HAVE_MPI
  lg::uq::MpiCommunicator* mpi = nullptr;
  if (lg::uq::launchedByMpi()) {
    auto m = std::make_unique<lg::uq::MpiCommunicator>(&argc, &argv);
    mpi = m.get();
    comm = std::move(m);
  }
#endif
  if (!comm) comm = std::make_unique<lg::uq::SingleProcess>();
  const bool root = comm->rank() == 0;
  auto fail = [&](int status) {  // one rank alone in trouble must not leave the others waiting
#ifdef LG_HAVE_MPI
    if (mpi && mpi->size() > 1) mpi->abort(status);
#endif
    return status;
  };

  Cli c;
  for (int i = 0; i < argc; ++i) c.argv.push_back(argv[i]);
  if (const int status = parseCommandLine(argc, argv, root, c); status >= 0) return status;
  // Every rank reads and checks the input: bad input stops them all alike, before anything is written.
  lg::optim::Study study;
  lg::optim::SensitivitySettings settings;
  try {
    std::vector<lg::ParameterOverride> overrides;
    for (const auto& s : c.sets) overrides.push_back(lg::parseOverride(s));
    study = lg::optim::loadStudy(c.study, overrides);
    settings = study.sensitivity;
    applyCli(c, settings);
    lg::optim::checkSensitivity(study, settings, c.samples != kNotGiven ? "--samples" : "");
  } catch (const lg::InputError& e) {
    if (root) std::cerr << "error: " << e.what() << "\n";
    return lg::cli::kUsage;
  }
  if (c.out.empty()) c.out = lg::safeFileStem(std::filesystem::path(c.study).stem().string()) + "-sensitivity";
  if (root) try {
      lg::prepareOutputDir(c.out);  // before any work: a directory that takes no file fails now
    } catch (const std::exception& e) {
      std::cerr << "error: " << e.what() << "\n";
      return fail(lg::cli::kFailed);
    }
  const int threads = c.threads > 0 ? c.threads : std::max(1, omp_get_num_procs());
  const bool tty = root && !c.quiet && isatty(fileno(stderr));
  lg::cli::installInterruptHandler();

  lg::optim::SensitivityOptions o;
  o.threads = threads;
  o.comm = comm.get();
  o.stop = [] { return lg::cli::interrupted(); };
  const auto t0 = std::chrono::steady_clock::now();
  double lastPrint = -1;
  if (tty)
    o.progress = [&](const std::string& method, std::size_t done, std::size_t mine) {
      const double t = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
      if (t - lastPrint < 0.2 && done < mine) return;
      lastPrint = t;
      std::fprintf(stderr, "\r  %-7s %6zu / %zu designs (rank 0)   elapsed %7.1f s   ", method.c_str(), done, mine, t);
      std::fflush(stderr);
    };
  lg::optim::SensitivityResult r;
  try {
    r = lg::optim::runSensitivity(study, settings, o);
  } catch (const std::exception& e) {
    std::cerr << "error: rank " << comm->rank() << ": " << e.what() << "\n";
    return fail(lg::cli::kFailed);
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (tty) std::fprintf(stderr, "\n");
  if (lg::cli::interrupted()) {  // the runs skipped after Ctrl-C would look like failures: write nothing
    if (root) std::cerr << "sensitivity: interrupted, nothing written\n";
    return fail(lg::cli::kInterrupted);
  }
  if (!root) return lg::cli::kOk;
  const int status = finish(c, study, r, comm->size(), threads, wall);
  return status == lg::cli::kOk ? status : fail(status);
}
