// Studies on the seed gear: bitwise determinism across thread counts, a short study that improves
// the objective within the constraints, and best.toml reproducing the reported metrics.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "optim/evaluator.hpp"
#include "optim/report.hpp"
#include "optim/study.hpp"

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;
using namespace lg::optim;

namespace {

fs::path tempDir() {
  const fs::path d = fs::temp_directory_path() / ("lg_study_run_test_" + std::to_string(::getpid()));
  fs::create_directories(d);
  return d;
}

std::string readFile(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// The shipped study, shortened.
Study shippedStudy(int maxeval) {
  Study s = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak.cfg");
  s.algorithm.maxeval = maxeval;
  return s;
}

bool sameBits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

void requireSameMetrics(const lg::CaseMetrics& a, const lg::CaseMetrics& b) {
  INFO("case " << a.name);
  CHECK(a.name == b.name);
  CHECK(a.ok == b.ok);
  CHECK(sameBits(a.peak_load_N, b.peak_load_N));
  CHECK(sameBits(a.t_peak_s, b.t_peak_s));
  CHECK(sameBits(a.stroke_max_m, b.stroke_max_m));
  CHECK(sameBits(a.h_max_m, b.h_max_m));
  CHECK(sameBits(a.tyre_deflection_max_m, b.tyre_deflection_max_m));
  CHECK(sameBits(a.efficiency, b.efficiency));
  CHECK(sameBits(a.energy_absorbed_J, b.energy_absorbed_J));
  CHECK(sameBits(a.rebound_h_min_m, b.rebound_h_min_m));
  CHECK(a.bottomed == b.bottomed);
  CHECK(a.steps == b.steps);
}

}  // namespace

TEST_CASE("study run: a design evaluates to the same bits on 1, 2 and 3 threads", "[optim][seed]") {
  const Study s = shippedStudy(0);
  std::vector<double> x;
  for (const auto& v : s.variables) x.push_back(0.5 * (v.lower + v.upper));
  EvaluatorOptions o1;
  o1.threads = 1;
  const Evaluation e1 = evaluateDesign(s, x, o1);
  REQUIRE(e1.ok);
  for (int t : {2, 3}) {
    EvaluatorOptions o;
    o.threads = t;
    const Evaluation e = evaluateDesign(s, x, o);
    REQUIRE(e.ok);
    CHECK(sameBits(e.objective, e1.objective));
    REQUIRE(e.constraints.size() == e1.constraints.size());
    for (size_t k = 0; k < e.constraints.size(); ++k) CHECK(sameBits(e.constraints[k], e1.constraints[k]));
    for (size_t i = 0; i < e.cases.size(); ++i) requireSameMetrics(e.cases[i], e1.cases[i]);
  }
}

TEST_CASE("study run: a short study is identical on 1 and 3 threads", "[optim][seed]") {
  const Study s = shippedStudy(12);
  RunOptions a;
  a.outDir = (tempDir() / "t1").string();
  a.threads = 1;
  a.plots = false;
  RunOptions b = a;
  b.outDir = (tempDir() / "t3").string();
  b.threads = 3;
  const StudyResult r1 = runStudy(s, a);
  const StudyResult r3 = runStudy(s, b);
  CHECK(readFile(fs::path(a.outDir) / "history.csv") == readFile(fs::path(b.outDir) / "history.csv"));
  CHECK(r1.bestToml.substr(r1.bestToml.find("\n[")) == r3.bestToml.substr(r3.bestToml.find("\n[")));
  CHECK(readFile(fs::path(a.outDir) / "history.csv").size() > 100);
}

TEST_CASE("study run: the shipped study improves the limit case within the constraints and best.toml reproduces it",
          "[optim][seed]") {
  const Study s = shippedStudy(30);
  RunOptions o;
  o.outDir = (tempDir() / "short").string();
  o.threads = 2;
  o.plots = false;
  const StudyResult r = runStudy(s, o);
  const OptimizationResult& opt = r.opt;
  REQUIRE(opt.initial.ok);
  REQUIRE(opt.feasible);
  CHECK(opt.best.objective < opt.initial.objective);
  CHECK(opt.evaluations == 30);
  CHECK(opt.reason == "stopped: maxeval reached");
  for (double g : opt.best.constraints) CHECK(g <= 0.0);
  // limit case against the baseline, stroke and tyre limits on every case
  REQUIRE(r.bestCases.size() == 3);
  REQUIRE(r.baselineCases.size() == 3);
  CHECK(r.bestCases[2].name == "limit");
  CHECK(r.bestCases[2].peak_load_N < r.baselineCases[2].peak_load_N);
  for (const auto& m : r.bestCases) {
    CHECK(m.ok);
    CHECK(m.stroke_max_m <= 0.15);
    CHECK(m.tyre_deflection_max_m <= 0.10);
    CHECK_FALSE(m.bottomed);
  }
  // outputs exist; the history has one line per evaluation plus the header
  for (const char* f : {"history.csv", "result.json", "best.toml", "report.md"}) CHECK(fs::exists(fs::path(o.outDir) / f));
  const std::string hist = readFile(fs::path(o.outDir) / "history.csv");
  CHECK(std::count(hist.begin(), hist.end(), '\n') == opt.evaluations + 2);
  const std::string json = readFile(fs::path(o.outDir) / "result.json");
  CHECK(json.find("\"reason\": \"stopped: maxeval reached\"") != std::string::npos);
  CHECK(json.find("\"peak_load_N\": " + jsonNumber(r.bestCases[2].peak_load_N)) != std::string::npos);
  // re-simulate best.toml: the same metrics, bit for bit
  const lg::Scene best = lg::parseScene(readFile(fs::path(o.outDir) / "best.toml"), "best.toml", s.sceneDir);
  for (size_t i = 0; i < s.cases.size(); ++i) {
    const lg::DropCase* c = nullptr;
    for (const auto& bc : best.cases)
      if (bc.name == s.cases[i].dropCase.name) c = &bc;
    REQUIRE(c != nullptr);
    requireSameMetrics(lg::runCase(best, *c).metrics, r.bestCases[i]);
  }
  CHECK(sameBits(r.bestCases[2].peak_load_N, opt.best.cases.empty() ? r.bestCases[2].peak_load_N : opt.best.cases[2].peak_load_N));
}

TEST_CASE("study run: --resume reuses the history without simulating again", "[optim][seed]") {
  const Study s = shippedStudy(10);
  RunOptions o;
  o.outDir = (tempDir() / "resume").string();
  o.threads = 2;
  o.plots = false;
  const StudyResult r1 = runStudy(s, o);
  const std::string h1 = readFile(fs::path(o.outDir) / "history.csv");
  o.resume = true;
  const StudyResult r2 = runStudy(s, o);
  CHECK(r2.opt.simulations == 0);
  CHECK(readFile(fs::path(o.outDir) / "history.csv") == h1);
  CHECK(sameBits(r2.opt.best.objective, r1.opt.best.objective));
}
