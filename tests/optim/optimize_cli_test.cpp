// The `optimize` program end to end (apps/optimize.cpp): the shared command-line conventions, --set,
// a study stopped by Ctrl-C (exit 130, the best design so far written), a study stopped during its
// baseline (nothing logged as a failed design), failed evaluations logged whole and resumed.
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <sys/wait.h>
#include <unistd.h>

#include "optim/report.hpp"
#include "optim/study.hpp"

#include "files_support.hpp"  // TempDir, readFile

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;
using namespace lg::optim;

namespace {

// A fresh directory 'tag' in this test process's temporary directory (removed when it exits).
fs::path tempDir(const std::string& tag) {
  static const lgtest::TempDir root("optimize_cli");
  const fs::path d = root.path / tag;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}
using lgtest::readFile;
std::string q(const std::string& s) { return "'" + s + "'"; }
const std::string kStudy = std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak.cfg";

int optimize(const std::string& args, std::string& out) {
  const fs::path log = tempDir("log") / "log.txt";
  const std::string cmd = "'" + std::string(LG_BIN_DIR) + "/optimize' " + args + " > " + q(log.string()) + " 2>&1";
  const int st = std::system(cmd.c_str());
  out = readFile(log);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

}  // namespace

TEST_CASE("optimize: --help, --version and usage errors follow the shared conventions", "[optim][cli]") {
  std::string out;
  CHECK(optimize("--help", out) == 0);
  CHECK(out.find("--set") != std::string::npos);
  CHECK(optimize("--version", out) == 0);
  CHECK(out.rfind("optimize ", 0) == 0);
  const fs::path dir = tempDir("usage");
  for (const std::string& bad : {std::string("--maxeval abc"), std::string("--threads -2"), std::string("--set strut.f1"),
                                 std::string("--set strut.nope=1"), std::string("--no-plots")}) {
    INFO(bad);
    CHECK(optimize(q(kStudy) + " --out " + q((dir / "out").string()) + " " + bad, out) == 2);
    CHECK(out.rfind("error: ", 0) == 0);
    CHECK(!fs::exists(dir / "out"));
  }
}

TEST_CASE("optimize: --set changes the study's scene before anything reads it", "[optim][cli]") {
  const Study plain = loadStudy(kStudy);
  const Study set = loadStudy(kStudy, {lg::parseOverride("strut.xi1=1.8"), lg::parseOverride("airframe.mass=3900")});
  CHECK(lg::getParameter(set.scene.doc, "strut.xi1") == 1.8);
  CHECK(set.scene.model.bodies[4].mass == 3900.0);
  // the certification matrix makes W up through the airframe: its mass on the unit is unchanged
  CHECK(set.cases[0].dropCase.masses.at("airframe") == plain.cases[0].dropCase.masses.at("airframe"));
  try {
    (void)loadStudy(kStudy, {lg::parseOverride("strut.Omega0=1e-3")});
    FAIL("no InputError");
  } catch (const lg::InputError& e) {
    CHECK(std::string(e.what()).find("must be larger than the volume swept") != std::string::npos);
  }
}

TEST_CASE("optimize: Ctrl-C stops the study, writes the best design so far and exits 130", "[optim][cli]") {
  const fs::path dir = tempDir("sigint");
  // The main study without its xtol_rel (it would converge in about a second): it runs until stopped.
  // Ctrl-C comes once a few evaluations are logged, however fast the machine.
  std::string text = readFile(kStudy);
  text.replace(text.find("xtol_rel = 1e-4"), 15, "xtol_rel = 0");
  const std::string sceneRel = "\"../data/seed_gear.toml\"";
  text.replace(text.find(sceneRel), sceneRel.size(), q(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml"));
  const std::string study = (dir / "endless.cfg").string();
  std::ofstream(study) << text;
  const std::string histPath = (dir / "out/history.csv").string();
  const std::string cmd = "'" + std::string(LG_BIN_DIR) + "/optimize' " + q(study) + " --out " +
                          q((dir / "out").string()) + " --maxeval 100000 --threads 1 --quiet > " +
                          q((dir / "log.txt").string()) + " 2>&1 & pid=$!; for i in $(seq 600); do [ -f " + q(histPath) +
                          " ] && [ $(wc -l < " + q(histPath) + ") -ge 4 ] && break; sleep 0.05; done; kill -INT $pid; wait $pid";
  const int st = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(st));
  CHECK(WEXITSTATUS(st) == 130);
  const std::string json = readFile(dir / "out/result.json");
  CHECK(json.find("\"interrupted\": true") != std::string::npos);
  CHECK(json.find("\"reason\": \"stopped: interrupted") != std::string::npos);
  CHECK(fs::exists(dir / "out/best.toml"));
  // the provenance block heads result.json, report.md and best.toml: the study and the scene with their hashes
  CHECK(json.rfind("{\n  \"provenance\": {\"program\": \"optimize\"", 0) == 0);
  CHECK(json.find("{\"role\": \"study\", \"path\": \"" + study + "\", \"sha256\": \"" + lg::fileSha256(study) + "\"}") !=
        std::string::npos);
  CHECK(json.find("{\"role\": \"scene\", \"path\": \"" + std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml\", \"sha256\": \"" +
                  lg::fileSha256(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml") + "\"}") != std::string::npos);
  CHECK(readFile(dir / "out/best.toml").rfind("# Written by optimize ", 0) == 0);
  // every logged evaluation is whole: as many fields as the header
  std::istringstream hist(readFile(dir / "out/history.csv"));
  std::string header, line;
  std::getline(hist, header);
  const auto fields = std::count(header.begin(), header.end(), ',');
  int lines = 0;
  while (std::getline(hist, line)) {
    CHECK(std::count(line.begin(), line.end(), ',') == fields);
    ++lines;
  }
  CHECK(lines >= 3);
}

TEST_CASE("optimize: a stop during the baseline logs no failed design", "[optim][seed]") {
  const Study s = loadStudy(kStudy);
  RunOptions o;
  o.outDir = (tempDir("baseline") / "out").string();
  o.threads = 1;
  o.stop = [] { return true; };  // Ctrl-C already pressed: the baseline's cases stop at their first step
  const StudyResult r = runStudy(s, o);
  CHECK(r.opt.history.empty());
  CHECK(r.opt.interrupted);
  CHECK(r.opt.reason == "stopped: interrupted before the baseline evaluation finished (no design evaluated)");
  const std::string hist = readFile(fs::path(o.outDir) / "history.csv");
  CHECK(std::count(hist.begin(), hist.end(), '\n') == 1);  // the header only
  CHECK(readFile(fs::path(o.outDir) / "result.json").find("\"interrupted\": true") != std::string::npos);
  CHECK_FALSE(fs::exists(fs::path(o.outDir) / "best.toml"));
}

TEST_CASE("optimize: failed evaluations are logged whole and resumed without simulating again", "[optim][seed]") {
  // The gas volume's range reaches below the volume swept at the bottoming stroke: there the scene
  // rejects the design, an evaluation that fails with its reason.
  Study s = loadStudy(kStudy);
  s.variables = {s.variables[3]};  // strut.Omega0
  s.variables[0].lower = 1.0e-3;
  s.variables[0].initial = 1.0e-3;
  s.algorithm.maxeval = 4;
  RunOptions o;
  o.outDir = (tempDir("failed") / "out").string();
  o.threads = 2;
  const StudyResult r1 = runStudy(s, o);
  REQUIRE_FALSE(r1.opt.history.empty());
  CHECK_FALSE(r1.opt.history[0].evaluation.ok);
  const std::string hist = readFile(fs::path(o.outDir) / "history.csv");
  std::istringstream in(hist);
  std::string header, first;
  std::getline(in, header);
  std::getline(in, first);
  CHECK(std::count(first.begin(), first.end(), ',') >= std::count(header.begin(), header.end(), ','));
  CHECK(first.find("the scene rejects the design") != std::string::npos);
  o.resume = true;
  const StudyResult r2 = runStudy(s, o);
  CHECK(r2.opt.simulations == 0);
  CHECK(readFile(fs::path(o.outDir) / "history.csv") == hist);
}
