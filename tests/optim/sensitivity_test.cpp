// Sensitivity studies on the seed gear: the [sensitivity] table and its errors, local elasticities
// against an independent central-difference calculation, failed runs counted and kept out of the
// estimators, the same bits on 1 and 2 threads, and the program's exit status on bad input.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <tuple>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "optim/sensitivity.hpp"
#include "optim/sensitivity_report.hpp"
#include "optim/study.hpp"
#include "sim/drop/certification.hpp"
#include "sim/drop/metrics.hpp"

#include "files_support.hpp"  // TempDir, readFile, writeFile

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;
using namespace lg::optim;

namespace {

const std::string kScene = std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml";

// This test process's temporary directory (removed when it exits).
fs::path tempDir() {
  static const lgtest::TempDir dir("sensitivity_test");
  return dir.path;
}

std::string write(const std::string& name, const std::string& text) {
  const std::string p = (tempDir() / name).string();
  lgtest::writeFile(p, text);
  return p;
}

// A study over strut.f1 and tyre.K on one matrix case; 'solver' and 'sens' go in (sens from line 13).
std::string study(const std::string& sens, const std::string& solver = "") {
  return "scene = \"" + kScene + "\"\n"      // 1
         "[[variable]]\n"                    // 2
         "path = \"strut.f1\"\n"             // 3
         "lower = 5e-5\n"                    // 4
         "upper = 1e-4\n"                    // 5
         "log = true\n"                      // 6
         "[[variable]]\n"                    // 7
         "path = \"tyre.K\"\n"               // 8
         "lower = 6e5\n"                     // 9
         "upper = 1e6\n"                     // 10
         "[[case]]\n"                        // 11
         "name = \"cert-limit-landing\"\n"   // 12
         + sens + solver;                    // 13...
}

SensitivityOptions withThreads(int threads) {
  SensitivityOptions o;
  o.threads = threads;
  return o;
}

void expectError(const std::string& sens, int line, const std::string& key, const std::string& words) {
  const std::string path = write("bad.cfg", study(sens));
  try {
    (void)loadStudy(path);
    FAIL("no InputError for\n" << sens);
  } catch (const lg::InputError& e) {
    INFO(e.what());
    CHECK(e.file() == path);
    CHECK(e.line() == line);
    CHECK(e.key() == key);
    CHECK(std::string(e.what()).find(words) != std::string::npos);
  }
}

}  // namespace

TEST_CASE("sensitivity: [sensitivity] defaults and a full table", "[optim][sensitivity]") {
  const Study d = loadStudy(write("default.cfg", study("")));
  CHECK(d.sensitivity.local);
  CHECK(d.sensitivity.morris);
  CHECK(d.sensitivity.sobol);
  CHECK(d.sensitivity.cases == std::vector<int>{0});          // the steering case
  // the seed gear measures every one but the four drag loads (no tyre declares mu_x)
  CHECK(d.sensitivity.metrics.size() == lg::metricCatalogue().size() - 4);
  for (const char* drag : {"drag_peak", "springback_peak", "drag_at_peak", "drag_ratio"})
    CHECK(std::find(d.sensitivity.metrics.begin(), d.sensitivity.metrics.end(), drag) == d.sensitivity.metrics.end());
  CHECK(d.sensitivity.samples == 256);
  CHECK(d.sensitivity.resamples == 100);
  const Study s = loadStudy(write("full.cfg", study("[sensitivity]\nmethods = [\"sobol\", \"local\"]\n"
                                                     "metrics = [\"stroke\", \"peak_load\"]\ncases = [\"cert-reserve\", \"cert-limit-landing\"]\n"
                                                     "seed = 7\nderivatives = \"central\"\nstep = 0.02\nlevels = 6\n"
                                                     "trajectories = 9\nsamples = 64\n"
                                                     "resamples = 50\nconfidence = 0.9\n")));
  const SensitivitySettings& g = s.sensitivity;
  CHECK(g.local);
  CHECK_FALSE(g.morris);
  CHECK(g.sobol);
  CHECK(g.metrics == std::vector<std::string>{"stroke", "peak_load"});
  REQUIRE(g.cases.size() == 2);
  CHECK(s.cases[g.cases[0]].dropCase.name == "cert-reserve");  // a check case may be of interest
  CHECK(g.seed == 7u);
  CHECK(g.step == 0.02);
  CHECK(g.levels == 6);
  CHECK(g.trajectories == 9);
  CHECK(g.samples == 64);
  CHECK(g.resamples == 50);
  CHECK(g.confidence == 0.9);
  const auto outs = sensitivityOutputs(s, g);
  REQUIRE(outs.size() == 4);
  CHECK(outs[1].label() == "stroke@cert-limit-landing");
  CHECK(outs[2].unit == "N");
  // the shipped study parses, over the three matrix drops
  const Study shipped = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_sensitivity.cfg");
  REQUIRE(shipped.sensitivity.cases.size() == 3);
  CHECK(shipped.cases[shipped.sensitivity.cases[2]].dropCase.name == "cert-reserve");
}

TEST_CASE("sensitivity: bad [sensitivity] tables name file, line and key", "[optim][sensitivity]") {
  const std::string t = "[sensitivity]\n";  // line 13, the keys from line 14
  expectError(t + "methods = [\"fast\"]\n", 14, "sensitivity.methods", "must be \"local\", \"morris\" or \"sobol\"");
  expectError(t + "methods = []\n", 14, "sensitivity.methods", "names nothing");
  expectError(t + "methods = [\"local\", \"local\"]\n", 14, "sensitivity.methods", "appears twice");
  expectError(t + "metrics = [\"peak\"]\n", 14, "sensitivity.metrics", "must be a case metric");
  expectError(t + "metrics = 3\n", 14, "sensitivity.metrics", "must be a list of strings");
  expectError(t + "cases = [\"nope\"]\n", 14, "sensitivity.cases", "'nope' is not a case");
  expectError(t + "seed = 1\nsamples = 100\n", 15, "sensitivity.samples", "must be a power of two");
  expectError(t + "samples = 4\n", 14, "sensitivity.samples", "must be in [8, 1048576]");
  expectError(t + "levels = 5\n", 14, "sensitivity.levels", "must be even");
  expectError(t + "trajectories = 1\n", 14, "sensitivity.trajectories", "must be in [2, 100000]");
  expectError(t + "resamples = 5\n", 14, "sensitivity.resamples", "must be in [10, 100000]");
  expectError(t + "confidence = 1.0\n", 14, "sensitivity.confidence", "must be in [0.5, 1)");
  expectError(t + "derivatives = \"central\"\nstep = 0.9\n", 15, "sensitivity.step", "must be <= 0.5");
  expectError(t + "derivatives = \"central\"\nstep = -0.1\n", 15, "sensitivity.step", "must be > 0");
  expectError(t + "step = 0.01\n", 14, "sensitivity.step", "the exact derivatives take none");
  expectError(t + "derivatives = \"finite\"\n", 14, "sensitivity.derivatives", "must be \"exact\"");
  expectError(t + "seed = -1\n", 14, "sensitivity.seed", "must be in [0,");
  expectError(t + "sample = 64\n", 14, "sensitivity.sample", "unknown key");
  // a local study needs nonzero baselines: said by the program's check, not by the parser (optimize
  // reads the same file)
  const Study z = loadStudy(write("zero.cfg", study("[[variable]]\npath = \"free-drop.lift_ratio\"\nlower = 0\nupper = 1\n")));
  try {
    checkSensitivity(z, z.sensitivity);
    FAIL("no error for a zero baseline");
  } catch (const lg::InputError& e) {
    CHECK(e.line() == 13);
    CHECK(e.key() == "variable[2].initial");
  }
  SensitivitySettings noLocal = z.sensitivity;
  noLocal.local = false;
  CHECK_NOTHROW(checkSensitivity(z, noLocal));
  // a study too large to hold is refused before anything is allocated: the drops of every method
  // (2 variables, 1 case: Sobol N (D + 2) = 4N) and the bootstrap's draws (resamples x N)
  const Study big = loadStudy(write("big.cfg", study("[sensitivity]\nsamples = 1048576\nresamples = 1000\n")));
  CHECK(sensitivityDrops(big, big.sensitivity) == 3 + 20 * 3 + 1048576.0 * 4);
  for (const auto& [flag, key, line] : {std::tuple<std::string, std::string, int>{"", "sensitivity.resamples", 13},
                                        {"--samples", "--samples", 0}})
    try {
      checkSensitivity(big, big.sensitivity, flag);
      FAIL("no error for 4.2e6 designs");
    } catch (const lg::InputError& e) {
      INFO(e.what());
      CHECK(e.key() == key);
      CHECK(e.line() == line);
      CHECK(std::string(e.what()).find("the bootstrap would redraw N = 1048576 samples 1000 times (1048576000 draws), more "
                                       "than 1000000000: lower resamples or N") != std::string::npos);
    }
  SensitivitySettings many = big.sensitivity;
  many.resamples = 100;
  many.cases.assign(3, 0);
  try {
    checkSensitivity(big, many);
    FAIL("no error for 1.26e7 drops");
  } catch (const lg::InputError& e) {
    CHECK(e.key() == "sensitivity.samples");
    CHECK(std::string(e.what()).find("the methods ask for 12583101 drops (2 variables, 3 cases, Sobol N = 1048576, Morris r = 20), "
                                     "more than 10000000: lower N or r, or run the methods apart") != std::string::npos);
  }
}

TEST_CASE("sensitivity: the program exits with status 2 on bad input and writes nothing", "[optim][sensitivity]") {
  const std::string bad = write("bad_program.cfg", study("[sensitivity]\nsamples = 100\n"));
  const std::string good = write("good_program.cfg", study(""));
  const fs::path out = tempDir() / "never";
  const std::string exe = std::string(LG_BIN_DIR) + "/sensitivity ";
  const std::string sink = " --quiet > /dev/null 2>&1";
  for (const std::string& args : std::vector<std::string>{"'" + bad + "'", "'" + good + "' --samples 100", "'" + good + "' --samples 0", "'" + good + "' --method fast",
                                  "'" + good + "' --seed -3", "'" + good + "' --threads -1", "'" + good + "' --set strut.nope=1", "'/no/such/study.cfg'"}) {
    INFO(args);
    const int status = std::system((exe + args + " --out '" + out.string() + "'" + sink).c_str());
    REQUIRE(WIFEXITED(status));
    CHECK(WEXITSTATUS(status) == 2);
    CHECK_FALSE(fs::exists(out));
  }
}

// The library's elasticities against central differences computed here from the scene file itself:
// the parameter scaled by 1 +- h in the document, the scene rebuilt, the matrix case run.
TEST_CASE("sensitivity: local elasticities on the seed gear against an independent central difference", "[optim][sensitivity][seed]") {
  const Study s = loadStudy(write("local.cfg", study("[sensitivity]\nmethods = [\"local\"]\nmetrics = [\"peak_load\", \"stroke\"]\n"
                                                     "derivatives = \"central\"\n")));
  const SensitivityResult r = runSensitivity(s, s.sensitivity, withThreads(2));
  // the exact ones (the default) agree with these to the differences' truncation error, O(h^2) ~ 1e-4
  SensitivitySettings exact = s.sensitivity;
  exact.exactDerivatives = true;
  const SensitivityResult rx = runSensitivity(s, exact, withThreads(2));
  REQUIRE(rx.local);
  CHECK(rx.local->runs.size() == 1);  // one run with the derivatives
  CHECK(derivativeSource(exact) == "exact (forward mode through the run, ceres::Jet)");
  REQUIRE(r.local);
  CHECK(r.localFailures.runs == 0);
  REQUIRE(r.outputs.size() == 2);
  const double h = 0.01;
  auto metrics = [&](const std::string& path, double factor) {
    lg::Scene base = lg::loadScene(kScene);
    toml::table doc = base.doc;
    lg::setParameter(doc, path, lg::getParameter(doc, path) * factor);
    const lg::Scene sc = lg::buildScene(doc, kScene, fs::path(kScene).parent_path().string());
    const lg::DropCase c = lg::certDropCase(sc, *sc.certification, *sc.certification->findCase("cert-limit-landing"));
    return lg::runCase(sc, c).metrics;
  };
  const lg::CaseMetrics m0 = metrics("strut.f1", 1.0);
  const std::vector<std::string> paths{"strut.f1", "tyre.K"};
  for (std::size_t i = 0; i < paths.size(); ++i) {
    const lg::CaseMetrics mp = metrics(paths[i], 1 + h), mm = metrics(paths[i], 1 - h);
    const double ePeak = (mp.peak_load_N - mm.peak_load_N) / (2 * h * m0.peak_load_N);
    const double eStroke = (mp.stroke_max_m - mm.stroke_max_m) / (2 * h * m0.stroke_max_m);
    INFO(paths[i] << ": peak " << r.local->outputs[0].E[i] << " vs " << ePeak << ", stroke " << r.local->outputs[1].E[i]
                  << " vs " << eStroke);
    CHECK(r.local->outputs[0].E[i] == Approx(ePeak).epsilon(1e-12));
    CHECK(r.local->outputs[1].E[i] == Approx(eStroke).epsilon(1e-12));
    CHECK(rx.local->outputs[0].E[i] == Approx(ePeak).epsilon(5e-4));
    CHECK(rx.local->outputs[1].E[i] == Approx(eStroke).epsilon(5e-4));
  }
  CHECK(r.local->outputs[0].baseline == m0.peak_load_N);
  // what they say about the gear: a larger main orifice lowers the peak load and lengthens the stroke,
  // a stiffer tyre raises the peak load
  CHECK(r.local->outputs[0].E[0] < -0.5);
  CHECK(r.local->outputs[1].E[0] > 0.1);
  CHECK(r.local->outputs[0].E[1] > 0.05);
  // and the step is small enough: h/2 changes them by under 1 %
  SensitivitySettings half = s.sensitivity;
  half.step = h / 2;
  const SensitivityResult r2 = runSensitivity(s, half, withThreads(2));
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t i = 0; i < 2; ++i) CHECK(r2.local->outputs[k].E[i] == Approx(r.local->outputs[k].E[i]).epsilon(0.01));
  CHECK(derivativeSource(s.sensitivity) == "central differences, relative step h = 0.01");
}

// Omega0 down to 1.1e-3 m^3, below the volume swept at the bottoming stroke (1.2566e-3 m^3): the scene
// rejects those designs, and the study must count them and keep them out of every estimate.
TEST_CASE("sensitivity: failed runs are counted, located and dropped by whole Sobol blocks, and 1 and 2 threads give the same bits",
          "[optim][sensitivity][seed]") {
  const std::string text = "scene = \"" + kScene + "\"\n[solver]\nintegrator = \"ros34pw2\"\nrtol = 3e-3\n"
                           "[[variable]]\npath = \"strut.Omega0\"\nlower = 1.1e-3\nupper = 1.6e-3\ninitial = 1.3e-3\n"
                           "[[variable]]\npath = \"strut.f1\"\nlower = 5e-5\nupper = 1e-4\n"
                           "[[variable]]\npath = \"light.sink_speed\"\nlower = 1.5\nupper = 2.5\n"  // not a case of interest
                           "[[case]]\nname = \"cert-limit-landing\"\n"
                           "[sensitivity]\nmetrics = [\"peak_load\", \"stroke\"]\ntrajectories = 4\nsamples = 16\n";
  const Study s = loadStudy(write("fail.cfg", text));
  const SensitivityResult r1 = runSensitivity(s, s.sensitivity, withThreads(1));
  const SensitivityResult r2 = runSensitivity(s, s.sensitivity, withThreads(2));
  REQUIRE(r1.sobol);
  CHECK(r1.sobol->runs.size() == 16 * 5);
  CHECK(r1.designs == 1 + 4 * 4 + 16 * 5);  // the exact local study runs the baseline once
  const MethodFailures& f = r1.sobolFailures;
  CHECK(f.runs > 0);
  CHECK(f.runs < 40);
  CHECK(f.perCase == std::vector<std::size_t>{f.runs});
  REQUIRE_FALSE(f.list.empty());
  CHECK(f.list[0].message.find("the scene rejects the design") != std::string::npos);
  CHECK(f.list[0].where.find("block") == 0);
  // every failed run's block is dropped from both outputs, the rest estimated without a NaN
  const lg::uq::SobolIndices& x = r1.sobol->outputs[0];
  for (const auto& run : f.list)
    CHECK(std::find(x.dropped.begin(), x.dropped.end(), lg::uq::saltelliBlock(run.run, 3)) != x.dropped.end());
  REQUIRE(x.estimated);
  for (std::size_t i = 0; i < 2; ++i) {
    CHECK(std::isfinite(x.S1[i]));
    CHECK(std::isfinite(x.ST[i]));
    CHECK(std::isfinite(x.STci[i].lo));
  }
  // a variable no output depends on (the sink speed of a case not of interest): 0 with a zero-width
  // interval, in every output and method
  for (std::size_t k = 0; k < 2; ++k) {
    const lg::uq::SobolIndices& y = r1.sobol->outputs[k];
    CHECK(y.S1[2] == 0.0);
    CHECK(y.ST[2] == 0.0);
    CHECK(y.S1ci[2].lo == 0.0);
    CHECK(y.S1ci[2].hi == 0.0);
    CHECK(y.STci[2].lo == 0.0);
    CHECK(y.STci[2].hi == 0.0);
    CHECK(r1.morris->outputs[k].muStar[2] == 0.0);
    CHECK(r1.morris->outputs[k].muStarCi[2].hi == 0.0);
    CHECK(r1.local->outputs[k].E[2] == 0.0);
  }
  CHECK(r1.localFailures.runs == 0);  // the baseline and its neighbours are physical
  const std::string json = sensitivityJson(s, r1);
  CHECK(json.find("\"blocks_dropped\": [") != std::string::npos);
  CHECK(sensitivityMarkdown(s, r1, "").find("| sobol | 80 | " + std::to_string(f.runs) + " |") != std::string::npos);
  // the same bits on 2 threads: every index and every sample
  CHECK(sensitivityJson(s, r2) == json);
  for (const char* m : {"local", "morris", "sobol"}) {
    CHECK(samplesCsv(s, r2, m) == samplesCsv(s, r1, m));
    CHECK(indicesCsv(s, r2, m) == indicesCsv(s, r1, m));
  }
  CHECK(convergenceCsv(s, r2) == convergenceCsv(s, r1));
}

// The local table marks a one-sided derivative only where its kink bends that parameter: the lift
// plateau (after lift-off with L = 1) in the lift ratio alone, two close humps in every parameter.
TEST_CASE("sensitivity: a one-sided note applies per parameter", "[optim][sensitivity]") {
  const std::string humps = "two maxima of P_y within 0.05 % (at t = 0.05 s and 0.2 s): the peak can jump between them";
  const std::string plateau = "lift equal to the weight: after lift-off no net force acts, and with L > 1 the largest upward "
                              "velocity moves to the end of the run: its derivative in the lift ratio is one-sided (the side of L <= 1)";
  CHECK(oneSidedFor(humps + "; " + plateau, "strut.f1") == humps);
  CHECK(oneSidedFor(humps + "; " + plateau, "limit.lift_ratio") == humps + "; " + plateau);
  CHECK(oneSidedFor(plateau, "tyre.K").empty());
  CHECK(oneSidedFor("", "limit.lift_ratio").empty());
}
