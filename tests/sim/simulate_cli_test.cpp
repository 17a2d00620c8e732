// The `simulate` program end to end (apps/simulate.cpp, sim/io/results.cpp): the files it writes,
// columns that follow the scene, plots, and thread-count independence.
#include "scene_support.hpp"  // sim headers, then Catch (see there)
#include "docs_support.hpp"   // docsText: README.md and docs/

#include <sys/wait.h>

#include <cstdlib>
#include <regex>
#include <sstream>

namespace {

int simulate(const std::string& args) {
  const std::string cmd = "'" + lgtest::binPath("simulate") + "' " + args + " --quiet >/dev/null 2>&1";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}
std::string firstLine(const std::string& text) { return text.substr(0, text.find('\n')); }
std::string q(const std::string& s) { return "'" + s + "'"; }

}  // namespace

TEST_CASE("simulate writes a CSV per case and summary.json", "[cli]") {
  lgtest::TempDir dir("cli");
  const std::string out = dir / "out";
  REQUIRE(simulate(q(lgtest::sourcePath("data/seed_gear.toml")) + " --out " + q(out) + " --threads 2") == 0);
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string summary = lgtest::readFile(out + "/summary.json");
  for (const auto& c : sc.cases) {
    INFO(c.name);
    const std::string csv = lgtest::readFile(out + "/" + c.name + ".csv");
    CHECK(firstLine(csv) ==
          "t[s],P_y[N],h[m],delta[m],s[m],s_dot[m/s],p_1[Pa],P_a[N],P_gas[N],P_friction[N],P_orifice1[N],"
          "P_orifice2[N],F_extension[N],F_bottoming[N],violation[m]");
    // rows: 15 numbers each, time from 0 to the case's duration
    const auto rows = std::count(csv.begin(), csv.end(), '\n') - 1;
    CHECK(rows > 100);
    const std::string second = csv.substr(csv.find('\n') + 1, csv.find('\n', csv.find('\n') + 1) - csv.find('\n') - 1);
    CHECK(std::count(second.begin(), second.end(), ',') == 14);
    CHECK(second.rfind("0,", 0) == 0);
    const std::string last = csv.substr(csv.rfind('\n', csv.size() - 2) + 1);
    CHECK(std::stod(last) == Approx(c.duration));
    CHECK(summary.find("\"" + c.name + "\": {") != std::string::npos);
  }
  for (const char* key : {"peak_load_N", "t_peak_s", "load_factor", "stroke_max_m", "h_max_m", "tyre_deflection_max_m",
                          "efficiency", "strut_efficiency", "energy_absorbed_J", "energy_dissipated_J",
                          "energy_to_absorb_J", "stroke_margin_m", "tyre_margin_m", "rebound_velocity_mps",
                          "inertia_load_factor", "sink_speed_mps", "mass_kg", "constraint_violation_max", "steps",
                          "wall_time_s"}) {
    INFO(key);
    // once per case, each with a number
    const std::regex re("\n +\"" + std::string(key) + "\": -?[0-9]");
    CHECK(std::distance(std::sregex_iterator(summary.begin(), summary.end(), re), std::sregex_iterator()) ==
          static_cast<long>(sc.cases.size()));
  }
  // Limits: the seed gear's free drop (no lift) takes its tyre past delta_max = 0.10 m; the others stay within.
  const std::regex within("\"limits\": \\{\"within\": (true|false)");
  std::vector<std::string> flags;
  for (auto it = std::sregex_iterator(summary.begin(), summary.end(), within); it != std::sregex_iterator(); ++it)
    flags.push_back((*it)[1]);
  CHECK(flags == std::vector<std::string>{"true", "true", "true", "true", "false"});
  CHECK(summary.find("\"violations\": \"tyre 'tyre' 0.1096 m > delta_max 0.1 m\"") != std::string::npos);
  // The summary holds what runCase computes (17 significant digits).
  const auto limit = lg::runCase(sc, lgtest::findCase(sc, "limit")).metrics;
  CHECK(summary.find("\"peak_load_N\": " + lg::jsonNumber(limit.peak_load_N)) != std::string::npos);
  CHECK(summary.find("\"stroke_max_m\": " + lg::jsonNumber(limit.stroke_max_m)) != std::string::npos);
}

TEST_CASE("simulate: the columns follow what the scene declares", "[cli]") {
  // A wheel on the rig's guide: a tyre and an airframe, no strut and no stops.
  lgtest::TempDir dir("cli_nostrut");
  lgtest::writeFile(dir / "wheel.toml", R"(
[scene]
name = "wheel_drop"
airframe = "wheel"
[[body]]
name = "wheel"
mass = 100.0
inertia = [1.0, 1.0, 1.0]
position = [0.0, 0.3, 0.0]
[[joint]]
name = "rig"
type = "prismatic"
body1 = "wheel"
body2 = "ground"
point = [0.0, 0.3, 0.0]
axis = [0.0, 1.0, 0.0]
[[force]]
type = "gravity"
[[force]]
type = "tyre"
body = "wheel"
radius = 0.3
K = 1.0e5
delta_max = 0.1
[[case]]
name = "drop"
sink_speed = 1.0
duration = 0.3
)");
  const std::string out = dir / "out";
  REQUIRE(simulate(q(dir / "wheel.toml") + " --out " + q(out)) == 0);
  CHECK(firstLine(lgtest::readFile(out + "/drop.csv")) == "t[s],P_y[N],h[m],delta[m],violation[m]");
  CHECK(lgtest::readFile(out + "/summary.json").find("\"drop\"") != std::string::npos);
}

TEST_CASE("simulate --plots draws PNGs when gnuplot is present", "[cli][plots]") {
  if (std::system("command -v gnuplot >/dev/null 2>&1") != 0) {
    WARN("gnuplot is not installed: plot test skipped");
    return;
  }
  lgtest::TempDir dir("cli_plots");
  const std::string out = dir / "out";
  REQUIRE(simulate(q(lgtest::sourcePath("data/seed_gear.toml")) + " --case limit --plots --out " + q(out)) == 0);
  const std::string png = lgtest::readFile(out + "/limit.png");
  REQUIRE(png.size() > 1000);
  CHECK(png.substr(1, 3) == "PNG");
}

TEST_CASE("simulate: results do not depend on the thread count", "[cli][determinism]") {
  lgtest::TempDir dir("cli_threads");
  const std::string scene = q(lgtest::sourcePath("data/seed_gear.toml"));
  REQUIRE(simulate(scene + " --threads 1 --out " + q(dir / "t1")) == 0);
  REQUIRE(simulate(scene + " --threads 2 --out " + q(dir / "t2")) == 0);
  const std::regex wall("\"wall_time_s\": [^\n]*");
  int files = 0;
  for (const auto& e : std::filesystem::directory_iterator(dir.path / "t1")) {
    const std::string name = e.path().filename().string();
    INFO(name);
    std::string a = lgtest::readFile(e.path().string()), b = lgtest::readFile(dir / ("t2/" + name));
    if (name == "summary.json") {  // (the provenance block names each run's command line and date)
      CHECK(a.find("\"provenance\": {\"program\": \"simulate\"") != std::string::npos);
      a = lgtest::withoutProvenance(a);
      b = lgtest::withoutProvenance(b);
      a = std::regex_replace(a, wall, "\"wall_time_s\": X");
      b = std::regex_replace(b, wall, "\"wall_time_s\": X");
    }
    if (name == "summary.csv") {  // the last column is the wall time
      const std::regex lastField(",[^,\n]*\n");
      a = std::regex_replace(a, lastField, ",X\n");
      b = std::regex_replace(b, lastField, ",X\n");
    }
    CHECK(!a.empty());
    CHECK(a == b);
    ++files;
  }
  CHECK(files == 7);  // 5 cases, summary.json, summary.csv
}

// The solver overrides of the command line: the same case with the linearly implicit integrator at a
// loose tolerance takes far fewer steps and stays within 0.2 % of the scene's reference-quality run;
// a bad override is bad input (exit status 2, the flag named, nothing written).
TEST_CASE("simulate: --integrator and --rtol override the scene's solver", "[cli]") {
  lgtest::TempDir dir("cli_solver");
  const std::string scene = q(lgtest::sourcePath("data/seed_gear.toml"));
  REQUIRE(simulate(scene + " --case limit --out " + q(dir / "ref")) == 0);
  REQUIRE(simulate(scene + " --case limit --integrator ros34pw2 --rtol 2e-3 --out " + q(dir / "fast")) == 0);
  auto number = [](const std::string& json, const std::string& key) {
    const size_t at = json.find("\"" + key + "\": ");
    REQUIRE(at != std::string::npos);
    return std::stod(json.substr(at + key.size() + 4));
  };
  const std::string ref = lgtest::readFile(dir / "ref/summary.json");
  const std::string fast = lgtest::readFile(dir / "fast/summary.json");
  INFO("reference: " << number(ref, "steps") << " steps, peak " << number(ref, "peak_load_N") << "; ros34pw2: "
                     << number(fast, "steps") << " steps, peak " << number(fast, "peak_load_N"));
  CHECK(number(fast, "steps") < 0.5 * number(ref, "steps"));
  CHECK(std::abs(number(fast, "peak_load_N") / number(ref, "peak_load_N") - 1) < 2e-3);

  for (const std::pair<const char*, const char*>& bad :
       {std::pair{"--integrator nope", "'--integrator'"}, {"--rtol -1", "'--rtol'"}, {"--rtol 0", "'--rtol'"},
        {"--atol -1e-9", "'--atol'"}, {"--step 0", "'--step'"}}) {
    INFO(bad.first);
    const std::string out = dir / "bad";
    const std::string cmd = "'" + lgtest::binPath("simulate") + "' " + scene + " " + bad.first + " --out " + q(out) +
                            " --quiet 2>" + q(dir / "err.txt");
    const int st = std::system(cmd.c_str());
    CHECK(WEXITSTATUS(st) == 2);
    CHECK(lgtest::readFile(dir / "err.txt").find(bad.second) != std::string::npos);
    CHECK(!std::filesystem::exists(out));
  }
}

TEST_CASE("simulate: the terminal table marks a case beyond its limits", "[cli][limits]") {
  lgtest::TempDir dir("cli_limits");
  const std::string log = dir / "table.txt";
  const std::string cmd = "'" + lgtest::binPath("simulate") + "' " + q(lgtest::sourcePath("data/seed_gear.toml")) +
                          " --case limit --case free-drop --threads 1 --out " + q(dir / "out") + " > " + q(log) + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);  // beyond a limit is a result, not a failed run
  const std::string text = lgtest::readFile(log);
  INFO(text);
  CHECK(std::regex_search(text, std::regex("\nlimit .* ok\n")));
  CHECK(std::regex_search(text, std::regex("\nfree-drop .* EXCEEDED: tyre 'tyre' 0.1096 m > delta_max 0.1 m\n")));
}

namespace {
// Runs simulate with 'args' (no --quiet added); returns the exit status, stdout+stderr in 'out'.
int simulateCapture(const std::string& args, std::string& out, const std::string& prefix = "") {
  lgtest::TempDir tmp("cli_capture");
  const std::string log = tmp / "log.txt";
  const std::string cmd = prefix + "'" + lgtest::binPath("simulate") + "' " + args + " > '" + log + "' 2>&1";
  const int st = std::system(cmd.c_str());
  out = lgtest::readFile(log);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}
}  // namespace

TEST_CASE("simulate: --help, --version and usage errors follow the shared conventions", "[cli][input]") {
  std::string out;
  CHECK(simulateCapture("--help", out) == 0);
  CHECK(out.find("--output-interval") != std::string::npos);
  CHECK(simulateCapture("--version", out) == 0);
  CHECK(out.rfind("simulate ", 0) == 0);
  lgtest::TempDir dir("cli_usage");
  const std::string scene = q(lgtest::sourcePath("data/seed_gear.toml")) + " --out " + q(dir / "out");
  for (const std::string& bad : {std::string("--rtol abc"), std::string("--threads -1"), std::string("--no-such-flag"),
                                 std::string("--set strut.f1"), std::string("--set strut.f9=1"),
                                 std::string("--set strut.f1=-1e-5"), std::string("--sink-speeds 1:0:2"),
                                 std::string("--case limit --sink-speeds 2"), std::string("--output-interval 0")}) {
    INFO(bad);
    CHECK(simulateCapture(scene + " " + bad, out) == 2);
    CHECK(out.rfind("error: ", 0) == 0);
    CHECK(std::count(out.begin(), out.end(), '\n') == 1);
    CHECK(!std::filesystem::exists(dir / "out"));
  }
  // sizes: a matrix of 1e8 cases (each list under its own cap) and 8e11 rows are refused before any run
  for (const auto& [bad, rule] : {std::pair<std::string, std::string>{"--sink-speeds 1:0.0001:2 --lift-ratios 0:0.0001:1",
                                                                      "key '--lift-ratios': the matrix has 100020001 cases (sink "
                                                                      "speeds x lift ratios), more than 10000: run it in parts"},
                                  {"--case limit --output-interval 1e-12",
                                   "key '--output-interval': value 1e-12 s gives 8e+11 rows over case 'limit' (0.8 s), more than "
                                   "1000000 per case"}}) {
    INFO(bad);
    CHECK(simulateCapture(scene + " " + bad, out) == 2);
    CHECK(out.find(rule) != std::string::npos);
    CHECK(std::count(out.begin(), out.end(), '\n') == 1);
    CHECK(!std::filesystem::exists(dir / "out"));
  }
  // an interval longer than the run: one row, and a warning says so
  CHECK(simulateCapture(scene + " --case limit --output-interval 2 --quiet", out) == 0);
  CHECK(out.find("warning: --output-interval 2 s is longer than case 'limit' (0.8 s): one row, at t = 0") != std::string::npos);
  std::filesystem::remove_all(dir / "out");
  // the rules of the file apply to an override: strut.f1 = -1e-5 is named like the scene's own key
  simulateCapture(scene + " --set strut.f1=-1e-5", out);
  CHECK(out.find("key 'force[2].f1': value -1e-05 must be > 0") != std::string::npos);
  // --threads 0 is all cores, as everywhere
  CHECK(simulateCapture(scene + " --case limit --threads 0 --quiet", out) == 0);
}

TEST_CASE("simulate: an output that cannot be written is an error, found before the run", "[cli][output]") {
  lgtest::TempDir dir("cli_write");
  const std::string scene = q(lgtest::sourcePath("data/seed_gear.toml"));
  std::string out;
  // an output directory below a regular file cannot exist (for root too): exit 1 at once
  lgtest::writeFile(dir / "file", "x");
  CHECK(simulateCapture(scene + " --out " + q(dir / "file/out"), out) == 1);
  CHECK(out.rfind("error: cannot create the output directory", 0) == 0);
  // a write that fails (here the file-size limit, as a full disk would) is an error, never a "wrote" line,
  // and leaves no half-written file
  const std::string full = dir / "full";
  CHECK(simulateCapture(scene + " --case limit --out " + q(full), out, "trap '' XFSZ; ulimit -f 8; ") == 1);
  CHECK(out.find("error: cannot write '") != std::string::npos);
  CHECK(out.find("wrote") == std::string::npos);
  for (const auto& e : std::filesystem::directory_iterator(full)) {
    INFO(e.path());
    CHECK(e.path().filename().string().find(".tmp") == std::string::npos);
  }
}

TEST_CASE("simulate: --set and a sink-speed matrix run what the equivalent scene file runs", "[cli]") {
  lgtest::TempDir dir("cli_set");
  // the equivalent scene: f1 and K changed, and the cases of the matrix written out
  std::string text = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  text.replace(text.find("f1 = 7.0e-5"), 11, "f1 = 8.0e-5");
  text.replace(text.find("K = 8.0e5"), 9, "K = 9.0e5");
  text = text.substr(0, text.find("# ---- drop cases"));
  for (double V : {2.0, 3.0})
    for (const char* L : {"0.5", "1"})
      text += "[[case]]\nname = \"V" + std::string(V == 2.0 ? "2" : "3") + "_L" + L + "\"\nsink_speed = " +
              std::to_string(V) + "\nlift_ratio = " + L + "\nduration = 0.6\n";
  lgtest::writeFile(dir / "edited.toml", text);
  REQUIRE(simulate(q(dir / "edited.toml") + " --out " + q(dir / "a") + " --threads 2") == 0);
  REQUIRE(simulate(q(lgtest::sourcePath("data/seed_gear.toml")) + " --set strut.f1=8e-5 --set tyre.K=9e5 " +
                   "--sink-speeds 2:1:3 --lift-ratios 0.5,1 --duration 0.6 --out " + q(dir / "b") + " --threads 2") == 0);
  for (const char* c : {"V2_L0.5", "V2_L1", "V3_L0.5", "V3_L1"}) {
    INFO(c);
    const std::string a = lgtest::readFile(dir / ("a/" + std::string(c) + ".csv"));
    CHECK(a.size() > 1000);
    CHECK(a == lgtest::readFile(dir / ("b/" + std::string(c) + ".csv")));
  }
}

TEST_CASE("simulate: --output-interval samples the dense output uniformly and changes no result", "[cli][output]") {
  lgtest::TempDir dir("cli_interval");
  const std::string scene = q(lgtest::sourcePath("data/seed_gear.toml")) + " --case limit --threads 1";
  REQUIRE(simulate(scene + " --out " + q(dir / "steps")) == 0);
  REQUIRE(simulate(scene + " --output-interval 0.002 --out " + q(dir / "uniform")) == 0);
  // the same run: summaries equal but for the wall time
  const std::regex wall("\"wall_time_s\": [^\n]*");
  CHECK(std::regex_replace(lgtest::withoutProvenance(lgtest::readFile(dir / "steps/summary.json")), wall, "") ==
        std::regex_replace(lgtest::withoutProvenance(lgtest::readFile(dir / "uniform/summary.json")), wall, ""));
  // rows at t = 0, 0.002, ..., 0.8; h(t) between the step rows' values around it (a monotone stretch)
  std::istringstream in(lgtest::readFile(dir / "uniform/limit.csv"));
  std::string line;
  std::getline(in, line);
  CHECK(line == lgtest::readFile(dir / "steps/limit.csv").substr(0, line.size()));
  int rows = 0;
  while (std::getline(in, line)) {
    CHECK(std::stod(line) == Approx(0.002 * rows).margin(1e-12));
    ++rows;
  }
  CHECK(rows == 401);
}

TEST_CASE("simulate --gradient writes every metric's derivatives, with units", "[cli][gradient]") {
  lgtest::TempDir dir("cli_gradient");
  const std::string out = dir / "out";
  REQUIRE(simulate(q(lgtest::sourcePath("data/seed_gear.toml")) + " --case limit --gradient strut.f1,tyre.K --gradient "
                   "limit.sink_speed --out " + q(out)) == 0);
  const std::string csv = lgtest::readFile(out + "/gradient.csv");
  CHECK(firstLine(csv) == "case,metric,unit,value,d/dstrut.f1[unit per m^2],d/dtyre.K[unit per N/m],"
                          "d/dlimit.sink_speed[unit per m/s],smooth,note");
  const lg::Scene sc = lg::loadScene(lgtest::sourcePath("data/seed_gear.toml"));
  const lg::CaseGradient g =
      lg::caseGradient(sc, lgtest::findCase(sc, "limit"),
                       {lg::resolveParameter(sc, "strut.f1"), lg::resolveParameter(sc, "tyre.K"),
                        lg::resolveParameter(sc, "limit.sink_speed")});
  const std::string json = lgtest::readFile(out + "/summary.json");
  CHECK(json.find("\"parameters\": [{\"path\": \"strut.f1\", \"unit\": \"m^2\"}") != std::string::npos);
  CHECK(json.find("\"peak_load\": {\"value\": " + lg::jsonNumber(g.find("peak_load")->value) + ", \"unit\": \"N\", \"d\": "
                  "{\"strut.f1\": " + lg::jsonNumber(g.find("peak_load")->d[0])) != std::string::npos);
  CHECK(json.find("\"stroke\": {") != std::string::npos);
  CHECK(std::count(csv.begin(), csv.end(), '\n') == 1 + static_cast<long>(lg::gradientMetrics().size()));
  // a parameter without a derivative, or none of the scene's, is bad input
  CHECK(simulate(q(lgtest::sourcePath("data/seed_gear.toml")) + " --gradient limit.duration --out " + q(dir / "bad")) == 2);
  CHECK(simulate(q(lgtest::sourcePath("data/seed_gear.toml")) + " --gradient strut.xyz --out " + q(dir / "bad")) == 2);
  CHECK(!std::filesystem::exists(dir / "bad"));
}

TEST_CASE("benchmarks: --help, --version and usage errors follow the shared conventions", "[cli][input]") {
  lgtest::TempDir tmp("bench_cli");
  auto run = [&](const std::string& program, const std::string& args, std::string& out) {
    const std::string log = tmp / "log.txt";
    const std::string cmd = "cd '" + tmp.path.string() + "' && '" + lgtest::binPath(program) + "' " + args + " > '" + log + "' 2>&1";
    const int st = std::system(cmd.c_str());
    out = lgtest::readFile(log);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  };
  std::string out;
  for (const std::string program : {"bench_drop", "bench_engine", "bench_gradient"}) {
    INFO(program);
    CHECK(run(program, "--help", out) == 0);
    CHECK(out.find("--version") != std::string::npos);
    CHECK(run(program, "--version", out) == 0);
    CHECK(out.rfind(program + " ", 0) == 0);
    CHECK(run(program, "--no-such-flag", out) == 2);
    CHECK(out.rfind("error: ", 0) == 0);
    CHECK(std::count(out.begin(), out.end(), '\n') == 1);
  }
  // bench_drop outside the project root: its default scene is not there, an error with exit 2, no abort
  CHECK(run("bench_drop", "", out) == 2);
  CHECK(out.rfind("error: data/seed_gear.toml", 0) == 0);
  const std::string scene = "'" + lgtest::sourcePath("data/seed_gear.toml") + "'";
  CHECK(run("bench_drop", scene + " --case no-such-case", out) == 2);
  CHECK(out.find("no case named 'no-such-case' (cases: light, medium, limit, reserve, free-drop)") != std::string::npos);
  CHECK(std::count(out.begin(), out.end(), '\n') == 1);
}

TEST_CASE("simulate --accuracy: the stiffness hand-over and its handed-back trials reach the terminal, "
          "summary.csv and summary.json",
          "[cli][accuracy]") {
  lgtest::TempDir dir("cli_stiff");
  std::string text;
  REQUIRE(simulateCapture(q(lgtest::sourcePath("data/main_gear.toml")) + " --accuracy 1e-3 --threads 1 --out " +
                              q(dir / "main"),
                          text) == 0);
  INFO(text);
  // limit-spinup: ros34pw2's trial costs more and is handed back; reserve-spinup never reaches the bound.
  CHECK(text.find("limit-spinup: dopri5 at its stability bound, but ros34pw2 cost more on 1 trial(s): dopri5 "
                  "throughout\n") != std::string::npos);
  CHECK(text.find("reserve-spinup: dopri5") == std::string::npos);
  CHECK(text.find("reserve-spinup: stiff") == std::string::npos);
  CHECK(text.find("reserve-spinup: drag at V_x = 60.0 m/s: spin-up ") != std::string::npos);  // (every spin-up drop)
  const std::string csv = lgtest::readFile(dir / "main/summary.csv");
  CHECK(firstLine(csv).find(",stiff_from[s],stiff_handbacks[-],accuracy[-],t_peak_condition[-],accuracy_rerun[-],steps,") !=
        std::string::npos);
  // (the accuracy asked for, the peak's condition (empty: its sharp peak is no smooth maximum), no second run)
  CHECK(std::regex_search(csv, std::regex("\nlimit-spinup,.*,,1,0\\.001,[0-9.e-]*,,[0-9]+,[0-9]+,[0-9.e-]+\n")));
  CHECK(std::regex_search(csv, std::regex("\nreserve-spinup,.*,,0,0\\.001,[0-9.e-]*,,[0-9]+,[0-9]+,[0-9.e-]+\n")));
  const std::string json = lgtest::readFile(dir / "main/summary.json");
  CHECK(std::regex_search(
      json, std::regex("\"stiff_from_s\": null,\n *\"stiff_handbacks\": 1,\n *\"accuracy\": 0\\.001,\n *\"accuracy_rerun\": null,")));
  // The seed gear's limit drop hands over for good once at rest after its rebound.
  REQUIRE(simulateCapture(q(lgtest::sourcePath("data/seed_gear.toml")) + " --case limit --accuracy 1e-3 --threads 1 --out " +
                              q(dir / "seed"),
                          text) == 0);
  CHECK(std::regex_search(text, std::regex("\nlimit: stiff from t = 0\\.40691 s \\(dopri5 at its stability bound\\): "
                                           "ros34pw2 from there\n")));
  CHECK(std::regex_search(lgtest::readFile(dir / "seed/summary.json"),
                          std::regex("\"stiff_from_s\": 0\\.4069[0-9]+,\n *\"stiff_handbacks\": 0,")));
}

// The docs' example of every friction on one slide (data/friction_gear.toml): the terminal lines of this
// run, the table cut after its "steps" column (wall time and limits left out).
TEST_CASE("simulate: the docs' friction gear example is this run's", "[cli][bearing_friction]") {
  lgtest::TempDir dir("cli_friction_gear");
  std::string out;
  REQUIRE(simulateCapture(q(lgtest::sourcePath("data/friction_gear.toml")) + " --threads 1 --out " + q(dir / "out"), out) == 0);
  const std::string readme = lgtest::docsText();  // README.md and docs/
  std::istringstream lines(out);
  std::string header;
  std::getline(lines, header);
  const size_t cut = header.find("steps") + 5;
  REQUIRE(cut > 5);
  CHECK(readme.find(header.substr(0, cut) + "\n") != std::string::npos);
  int n = 1;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("wrote ", 0) == 0) continue;  // (the output folder differs)
    if (n <= 3) line = line.substr(0, cut);
    INFO(line);
    CHECK(readme.find(line + "\n") != std::string::npos);
    ++n;
  }
  CHECK(n == 7);
}
