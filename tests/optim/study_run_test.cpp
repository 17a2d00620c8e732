// Studies on the seed gear: bitwise determinism across thread counts, a short study that improves
// the objective within the constraints, and best.toml reproducing the reported metrics.
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "optim/evaluator.hpp"
#include "optim/report.hpp"
#include "optim/study.hpp"
#include "sim/drop/gradient.hpp"

#include "docs_support.hpp"   // docsText
#include "files_support.hpp"  // TempDir, readFile, writeFile

// After the project headers: glog (through Ceres) defines CHECK too; Catch's must win.
#include <catch2/catch.hpp>

namespace fs = std::filesystem;
using namespace lg::optim;

namespace {

// This test process's temporary directory (removed when it exits).
fs::path tempDir() {
  static const lgtest::TempDir dir("study_run_test");
  return dir.path;
}

using lgtest::readFile;

// The shipped nominal study (its constraints at the nominal point of the envelope), shortened, with its
// checks at the nominal point too: the mechanics of a study on the eight cases of the scene and its
// matrix. The robust main study is run whole below.
Study shippedStudy(int maxeval) {  // maxeval < 0: as shipped
  const std::string path = std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak_nominal.cfg";
  std::string text = readFile(path);
  const std::string from = "constraints = \"nominal\"";
  REQUIRE(text.find(from) != std::string::npos);
  text.replace(text.find(from), from.size(), from + "\nchecks = \"nominal\"");
  Study s = parseStudy(text, path, std::string(LG_SOURCE_DIR) + "/studies");
  if (maxeval >= 0) s.algorithm.maxeval = maxeval;
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
  CHECK(sameBits(a.energy_dissipated_J, b.energy_dissipated_J));
  CHECK(sameBits(a.rebound_velocity_mps, b.rebound_velocity_mps));
  CHECK(sameBits(a.stroke_margin_m, b.stroke_margin_m));
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
    REQUIRE(caseMetricsOf(e).size() == caseMetricsOf(e1).size());
    for (size_t i = 0; i < caseMetricsOf(e).size(); ++i) requireSameMetrics(caseMetricsOf(e)[i], caseMetricsOf(e1)[i]);
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

// The main job: the whole shipped study. Its optimum lowers the limit-case load, holds every constraint
// of the certification matrix, passes `certify` as written (best.toml), shows every case of the scene and
// the matrix in its report with the violations of its checks marked, and best.toml reproduces it.
TEST_CASE("study run: the main study's optimum passes its certification matrix and certify", "[optim][seed][main]") {
  const Study s = shippedStudy(-1);
  RunOptions o;
  o.outDir = (tempDir() / "main").string();
  o.threads = 2;
  o.plots = false;
  const StudyResult r = runStudy(s, o);
  const OptimizationResult& opt = r.opt;
  REQUIRE(opt.initial.ok);
  REQUIRE(opt.feasible);
  CHECK(opt.converged);
  for (double g : opt.best.constraints) CHECK(g <= 0.0);
  // every case of the study, its scene and its matrix, in Study::cases order
  const std::vector<std::string> names{"cert-limit-landing", "cert-limit-takeoff", "cert-reserve", "light", "medium",
                                       "limit", "reserve", "free-drop"};
  REQUIRE(r.bestCases.size() == names.size());
  REQUIRE(r.bestVerdicts.size() == names.size());
  for (size_t i = 0; i < names.size(); ++i) CHECK(r.bestCases[i].name == names[i]);
  // the limit-case load falls (landing weight), the matrix passes with the reserve case at its stroke margin
  CHECK(r.bestCases[0].peak_load_N < 0.85 * r.baselineCases[0].peak_load_N);
  CHECK(r.certified);
  for (int i = 0; i < 3; ++i) {
    INFO(names[i]);
    CHECK(r.bestVerdicts[i].pass);
    CHECK_FALSE(r.bestCases[i].bottomed);
    CHECK(r.bestCases[i].stroke_margin_m >= 0.01);
    CHECK(r.bestCases[i].tyre_margin_m >= 0.0);
    CHECK(r.bestCases[i].load_factor <= (i == 2 ? 3.75 : 2.5));
  }
  CHECK(r.bestCases[2].stroke_margin_m < 0.0101);  // the reserve case is what limits the design
  // the check cases are shown, violations and all: this optimum bottoms in the lift-free drop
  CHECK_FALSE(r.checksWithinLimits);
  CHECK_FALSE(r.bestVerdicts[7].pass);
  CHECK(r.bestCases[7].bottomed);
  const std::string report = readFile(fs::path(o.outDir) / "report.md");
  for (const auto& n : names) CHECK(report.find("| " + n + " | ") != std::string::npos);
  CHECK(report.find("| free-drop | check |") != std::string::npos);
  CHECK(report.find("**EXCEEDS**: ") != std::string::npos);
  CHECK(report.find("certification matrix: **PASS**") != std::string::npos);
  const std::string json = readFile(fs::path(o.outDir) / "result.json");
  CHECK(json.find("\"feasible\": true") != std::string::npos);
  CHECK(json.find("\"certification\": {\"basis\": \"part25\", \"role\": \"constraint\", \"pass\": true}") != std::string::npos);
  CHECK(json.find("\"checks_within_limits\": false") != std::string::npos);
  const std::string hist = readFile(fs::path(o.outDir) / "history.csv");
  CHECK(std::count(hist.begin(), hist.end(), '\n') == opt.evaluations + 2);
  // certify best.toml as written at the nominal point: every matrix case passes (exit 0) ...
  const fs::path cert = fs::path(o.outDir) / "certify";
  const std::string cmd = std::string(LG_BIN_DIR) + "/certify '" + (fs::path(o.outDir) / "best.toml").string() +
                          "' --out '" + cert.string() + "' --quiet";
  const int rc = std::system((cmd + " --nominal").c_str());
  REQUIRE(WIFEXITED(rc));
  CHECK(WEXITSTATUS(rc) == 0);
  CHECK(readFile(cert / "compliance.json").find("\"pass\": true,\n  \"checks_pass\": false") != std::string::npos);
  // ... and fails over its envelope: the reserve drop at the cold, under-charged corner with low oil and
  // large orifices comes within 0.4 mm of the bottoming stop (exit 1, that corner named)
  const int rc2 = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(rc2));
  CHECK(WEXITSTATUS(rc2) == 1);
  const std::string md = readFile(cert / "compliance.md");
  CHECK(md.find("**Verdict over the envelope: FAIL** (at the nominal point: PASS)") != std::string::npos);
  CHECK(md.find("| cert-reserve | stroke margin to the bottoming stop >= 0.01 m | cold-lowcharge-lowoil-largeorifice | ") !=
        std::string::npos);
  CHECK(readFile(cert / "compliance.json").find("\"worst_corner\": \"cold-lowcharge-lowoil-largeorifice\"") !=
        std::string::npos);
  // best.toml reproduces the reported metrics of the scene's cases, bit for bit
  const lg::Scene best = lg::parseScene(readFile(fs::path(o.outDir) / "best.toml"), "best.toml", s.sceneDir);
  for (size_t i = 3; i < names.size(); ++i) {
    const lg::DropCase* c = nullptr;
    for (const auto& bc : best.cases)
      if (bc.name == names[i]) c = &bc;
    REQUIRE(c != nullptr);
    requireSameMetrics(lg::runCase(best, *c).metrics, r.bestCases[i]);
  }
  std::printf("main study: %d evaluations, limit-case peak %.1f -> %.1f N, reserve stroke margin %.5f m\n",
              opt.evaluations, r.baselineCases[0].peak_load_N, r.bestCases[0].peak_load_N, r.bestCases[2].stroke_margin_m);
}

// A constraint case steers the design without entering the objective: the efficiency study keeps the
// reserve drop 10 mm clear of the bottoming stop while it maximises the efficiency of the other drops.
TEST_CASE("study run: a constraint case holds its limits and stays out of the objective", "[optim][seed]") {
  Study s = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_max_efficiency.cfg");
  s.algorithm.maxeval = 30;
  RunOptions o;
  o.outDir = (tempDir() / "eff").string();
  o.threads = 2;
  o.plots = false;
  const StudyResult r = runStudy(s, o);
  REQUIRE(r.opt.feasible);
  REQUIRE(s.cases[3].dropCase.name == "reserve");
  REQUIRE(s.cases[3].role == CaseRole::Constraint);
  CHECK(r.opt.best.objective > r.opt.initial.objective);
  double worst = 1;
  for (int i = 0; i < 3; ++i) worst = std::min(worst, r.bestCases[i].efficiency);
  CHECK(r.opt.best.objective == worst);  // the reserve case is not in it
  for (int i = 0; i < 4; ++i) {
    CHECK(r.bestCases[i].stroke_margin_m >= 0.01);
    CHECK(r.bestCases[i].tyre_margin_m >= 0.0);
  }
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

// Designs are set as data in the model (sim/scene/parameters.hpp), not as edited text: the results are the
// bits a scene rebuilt from the edited document gives, and the scene's rules still reject a bad design.
TEST_CASE("study run: a design set as data runs the bits of the rebuilt scene", "[optim][seed][parameters]") {
  const Study s = shippedStudy(0);
  std::vector<double> x;
  for (const auto& v : s.variables) x.push_back(0.37 * v.lower + 0.63 * v.upper);
  EvaluatorOptions o;
  o.threads = 2;
  const Evaluation e = evaluateDesign(s, x, o);
  REQUIRE(e.ok);
  const lg::Scene rebuilt = lg::buildScene(designDocument(s, x), s.sceneFile, s.sceneDir);
  const auto runs = lg::runCases(rebuilt, designCases(s, rebuilt, false), 2);
  REQUIRE(runs.size() == caseMetricsOf(e).size());
  for (size_t i = 0; i < runs.size(); ++i) requireSameMetrics(runs[i].metrics, caseMetricsOf(e)[i]);
  // the gas volume below the volume swept at the bottoming stroke: rejected with the scene's own rule
  std::vector<double> bad = x;
  bad[3] = 1.2e-3;
  const Evaluation r = evaluateDesign(s, bad, o);
  CHECK_FALSE(r.ok);
  CHECK(r.message.rfind("the scene rejects the design: strut.Omega0: gas volume 0.0012 m^3 must be larger", 0) == 0);
}

// A table's samples as study variables (the metering pin's areas early and mid-stroke): evaluated as
// data, and best.toml's document (the table written inline with the design's samples) rebuilds the
// same bits.
TEST_CASE("study run: the metering pin's samples as variables, best.toml's table inline", "[optim][parameters][metering_pin]") {
  const std::string text = "scene = \"" + std::string(LG_SOURCE_DIR) + "/data/seed_gear_metering_pin.toml\"\n"
                           "[[variable]]\npath = \"strut.f1_table[4]\"\nlower = 5e-5\nupper = 1e-4\n"
                           "[[variable]]\npath = \"strut.f1_table[16]\"\nlower = 3e-5\nupper = 9e-5\n"
                           "[[case]]\nname = \"limit\"\n";
  const Study s = lg::optim::parseStudy(text, "pin.cfg", std::string(LG_SOURCE_DIR) + "/data");
  const std::vector<double> x{9.1e-5, 4.4e-5};
  EvaluatorOptions o;
  o.threads = 2;
  const Evaluation e = evaluateDesign(s, x, o);
  REQUIRE(e.ok);
  const toml::table doc = designDocument(s, x);
  CHECK(lg::getParameter(doc, "strut.f1_table[4]") == 9.1e-5);
  CHECK(lg::getParameter(doc, "strut.f1_table[16]") == 4.4e-5);
  const lg::Scene rebuilt = lg::buildScene(doc, s.sceneFile, s.sceneDir);
  const auto runs = lg::runCases(rebuilt, designCases(s, rebuilt, false), 2);
  REQUIRE(runs.size() == caseMetricsOf(e).size());
  for (size_t i = 0; i < runs.size(); ++i) requireSameMetrics(runs[i].metrics, caseMetricsOf(e)[i]);
}

// The main study with exact derivatives: SLSQP reaches at least the derivative-free result (within
// 0.1 %), holding every limit of the matrix, in a fraction of COBYLA's evaluations.
TEST_CASE("study run: SLSQP with exact gradients reaches the COBYLA optimum of the main study", "[optim][seed][gradient]") {
  Study s = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak_slsqp.cfg");
  s.algorithm.maxeval = 40;
  RunOptions o;
  o.outDir = (tempDir() / "slsqp").string();
  o.threads = 2;
  o.plots = false;
  const StudyResult r = runStudy(s, o);
  REQUIRE(r.opt.feasible);
  CHECK(r.certified);
  RunOptions oc = o;
  oc.outDir = (tempDir() / "cobyla").string();
  const double cobyla = runStudy(shippedStudy(-1), oc).opt.best.objective;
  std::printf("SLSQP: %d evaluations (%d simulated), objective %.1f N (COBYLA %.1f N)\n", r.opt.evaluations,
              r.opt.simulations, r.opt.best.objective, cobyla);
  CHECK(r.opt.best.objective <= 1.001 * cobyla);
  CHECK(r.opt.simulations < 40);
}

TEST_CASE("study run: a design's exact gradient is the same for any thread count", "[optim][seed][gradient]") {
  const Study s = shippedStudy(0);
  std::vector<double> x;
  for (const auto& v : s.variables) x.push_back(0.5 * (v.lower + v.upper));
  EvaluatorOptions o1, o2;
  o1.threads = 1;
  o2.threads = 2;
  const Evaluation a = evaluateDesignGradient(s, x, o1), b = evaluateDesignGradient(s, x, o2);
  REQUIRE(a.ok);
  REQUIRE(a.hasGradient);
  CHECK(sameBits(a.objective, b.objective));
  REQUIRE(a.constraintGradients.size() == b.constraintGradients.size());
  for (size_t i = 0; i < x.size(); ++i) CHECK(sameBits(a.objectiveGradient[i], b.objectiveGradient[i]));
  for (size_t j = 0; j < a.constraintGradients.size(); ++j)
    for (size_t i = 0; i < x.size(); ++i) CHECK(sameBits(a.constraintGradients[j][i], b.constraintGradients[j][i]));
  // and the values agree with the plain evaluation's to round-off
  const Evaluation plain = evaluateDesign(s, x, o1);
  CHECK(std::abs(a.objective - plain.objective) <= 1e-10 * plain.objective);
}

// The main job as shipped: the robust study. Every constraint of the matrix holds at every point of the
// seed gear's envelope; the reserve drop's stroke margin binds at the cold, under-charged corner with low
// oil and large orifices; the nominal study runs first and its optimum breaks that corner; the price of
// robustness is reported; best.toml passes `certify` at every corner and still lowers the limit load.
TEST_CASE("study run: the robust main study holds its limits at every corner and passes certify there",
          "[optim][seed][main][envelope]") {
  const Study s = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak.cfg");
  REQUIRE(s.envelope.robust());
  REQUIRE(s.corners.size() == 17);
  CHECK(s.steeringCases() == 3 * 17);
  CHECK(s.items.size() == 9 * 17);
  RunOptions o;
  o.outDir = (tempDir() / "robust").string();
  o.threads = 2;
  o.plots = false;
  const StudyResult r = runStudy(s, o);
  REQUIRE(r.opt.feasible);
  CHECK(r.opt.converged);
  for (double g : r.opt.best.constraints) CHECK(g <= 0.0);
  CHECK(r.certified);
  const Robustness& b = r.robustness;
  REQUIRE(b.robust);
  REQUIRE(b.nominalRun);
  CHECK(b.points == 17);
  // the price: the nominal optimum is lower, the robust one still below the baseline
  CHECK(b.nominalObjective < r.opt.best.objective);
  CHECK(r.opt.best.objective < 0.9 * r.opt.initial.objective);
  CHECK(b.nominalViolated > 0);
  CHECK(b.nominalWorst == "stroke_margin_min@cert-reserve@cold-lowcharge-lowoil-largeorifice");
  bool cold = false;
  for (const auto& a : b.active) cold = cold || (a.caseName == "cert-reserve" && a.corner == "cold-lowcharge-lowoil-largeorifice");
  CHECK(cold);
  const std::string report = readFile(fs::path(o.outDir) / "report.md");
  CHECK(report.find("**Price of robustness:**") != std::string::npos);
  CHECK(readFile(fs::path(o.outDir) / "result.json").find("\"robustness\": {\"points\": 17") != std::string::npos);
  CHECK(fs::exists(fs::path(o.outDir) / "nominal" / "history.csv"));
  // best.toml is the scene file itself with the five tuned values replaced (comments, order and
  // spellings kept) under a comment head: a diff shows the design change and nothing else
  {
    std::vector<std::string> scene, best;
    std::istringstream a(readFile(fs::path(LG_SOURCE_DIR) / "data/seed_gear.toml")), c(readFile(fs::path(o.outDir) / "best.toml"));
    for (std::string l; std::getline(a, l);) scene.push_back(l);
    for (std::string l; std::getline(c, l);) best.push_back(l);
    REQUIRE(best.size() > scene.size());
    const std::size_t head = best.size() - scene.size();
    for (std::size_t i = 0; i < head; ++i) CHECK(best[i].rfind("# ", 0) == 0);
    std::vector<std::string> changed;
    for (std::size_t i = 0; i < scene.size(); ++i)
      if (best[head + i] != scene[i]) {
        const std::string key = scene[i].substr(0, scene[i].find(" = "));
        CHECK(best[head + i].rfind(key + " = ", 0) == 0);  // the same key on the same line
        changed.push_back(key);
      }
    CHECK(changed == std::vector<std::string>{"p01", "Omega0", "f1", "f2", "K"});
  }
  const fs::path cert = fs::path(o.outDir) / "certify";
  const std::string cmd = std::string(LG_BIN_DIR) + "/certify '" + (fs::path(o.outDir) / "best.toml").string() +
                          "' --out '" + cert.string() + "' --quiet";
  const int rc = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(rc));
  CHECK(WEXITSTATUS(rc) == 0);
  CHECK(readFile(cert / "compliance.md").find("**Verdict over the envelope: PASS**") != std::string::npos);
  // the docs' example output of the main job is this run's
  const std::string readme = lgtest::docsText();  // README.md and docs/
  char line[400];
  std::snprintf(line, sizeof line, "objective (min peak load, N): baseline %g -> best %g (feasible, evaluation %d)",
                r.opt.initial.objective, r.opt.best.objective, r.opt.bestIndex);
  CHECK(readme.find(line) != std::string::npos);
  std::snprintf(line, sizeof line, "price of robustness: the nominal study's optimum %.6g -> %.6g at the nominal point (%+.3g %%)",
                b.nominalObjective, b.atNominal, 100 * (b.atNominal - b.nominalObjective) / b.nominalObjective);
  CHECK(readme.find(line) != std::string::npos);
  std::snprintf(line, sizeof line, "converged: xtol_rel reached after %d evaluations", r.opt.evaluations);
  CHECK(readme.find(line) != std::string::npos);
  std::printf("robust main study: %d evaluations, limit-case peak %.1f N (nominal study %.1f N, price %.2f %%)\n",
              r.opt.evaluations, r.opt.best.objective, b.nominalObjective,
              100 * (r.opt.best.objective - b.nominalObjective) / b.nominalObjective);
}

// A robust design's evaluation: the same bits on 1 and 2 threads over its 51 cases x corners; its exact
// derivatives are each corner's (the cornered case's own derivatives, sign and all, for every constraint).
TEST_CASE("study run: a robust design evaluates to the same bits on 1 and 2 threads, its derivatives per corner",
          "[optim][seed][envelope]") {
  const Study s = loadStudy(std::string(LG_SOURCE_DIR) + "/studies/seed_gear_min_peak.cfg");
  std::vector<double> x;
  for (const auto& v : s.variables) x.push_back(v.initial);
  EvaluatorOptions o1, o2;
  o1.threads = 1;
  o2.threads = 2;
  const Evaluation e1 = evaluateDesign(s, x, o1), e2 = evaluateDesign(s, x, o2);
  REQUIRE(e1.ok);
  REQUIRE(e2.ok);
  REQUIRE(e1.constraints.size() == 153);
  CHECK(sameBits(e1.objective, e2.objective));
  for (size_t k = 0; k < e1.constraints.size(); ++k) CHECK(sameBits(e1.constraints[k], e2.constraints[k]));
  REQUIRE(caseMetricsOf(e1).size() == caseMetricsOf(e2).size());
  for (size_t i = 0; i < caseMetricsOf(e1).size(); ++i) requireSameMetrics(caseMetricsOf(e1)[i], caseMetricsOf(e2)[i]);
  const Evaluation g = evaluateDesignGradient(s, x, o2);
  REQUIRE(g.ok);
  REQUIRE(g.hasGradient);
  size_t k = 0;
  for (; k < s.items.size(); ++k)
    if (s.items[k].name == "stroke_margin_min@cert-reserve@cold-lowcharge-lowoil-largeorifice") break;
  REQUIRE(k < s.items.size());
  const StudyCase& c = s.cases[s.items[k].caseIndex];
  REQUIRE(c.dropCase.corner);
  const lg::CaseGradient cg = lg::caseGradient(s.scene, designCases(s, s.scene, false)[s.items[k].caseIndex], s.parameters);
  REQUIRE(cg.ok);
  const std::vector<double>& d = cg.find("stroke_margin")->d;
  for (size_t j = 0; j < x.size(); ++j) CHECK(g.constraintGradients[k][j] == -d[j]);
  // and the derivative in the corner's own direction is not the nominal one's
  size_t n = 0;
  for (; n < s.items.size(); ++n)
    if (s.items[n].name == "stroke_margin_min@cert-reserve") break;
  REQUIRE(n < s.items.size());
  CHECK(g.constraintGradients[n][0] != g.constraintGradients[k][0]);
}
