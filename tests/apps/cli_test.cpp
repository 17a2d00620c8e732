// The shared command line (apps/cli.hpp): every program answers a bad command line with one line
// "error: command line: key '--flag': <rule>", exit status 2, nothing written; a table per class of
// mistake, run against all five programs.
#include <sys/stat.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/cli.hpp"
#include "docs_support.hpp"  // docsText: README.md and docs/
#include "files_support.hpp"

#include <catch2/catch.hpp>

namespace {

// The five programs and a valid input of each (from the source tree).
struct Program {
  const char* name;
  const char* input;
};
const Program kPrograms[] = {{"simulate", "data/seed_gear.toml"},
                             {"certify", "data/seed_gear.toml"},
                             {"optimize", "studies/seed_gear_min_peak.cfg"},
                             {"sensitivity", "studies/seed_gear_sensitivity.cfg"},
                             {"calibrate", "studies/seed_gear_calibration.cfg"}};

std::string q(const std::string& s) { return "'" + s + "'"; }

// Runs 'program args' (args already quoted for the shell); the exit status, stdout and stderr apart.
int run(const std::string& program, const std::string& args, std::string& out, std::string& err) {
  static lgtest::TempDir logs("cli_logs");
  const std::string o = logs / "out.txt", e = logs / "err.txt";
  const int st = std::system((q(lgtest::binPath(program)) + " " + args + " >" + q(o) + " 2>" + q(e)).c_str());
  out = lgtest::readFile(o);
  err = lgtest::readFile(e);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// The promised answer to a bad command line: exit 2, one "error: " line holding 'words', nothing on
// stdout, no output directory.
void expectUsageError(const std::string& program, const std::string& args, const std::string& words,
                      const std::string& outDir) {
  std::string out, err;
  INFO(program << " " << args);
  CHECK(run(program, args, out, err) == 2);
  INFO("stderr: " << err);
  CHECK(err.rfind("error: ", 0) == 0);
  CHECK(std::count(err.begin(), err.end(), '\n') == 1);
  CHECK(err.find(words) != std::string::npos);
  CHECK(out.empty());
  CHECK(!std::filesystem::exists(outDir));
}

// What the program calls its input: "scene", "study", "calibration".
std::string inputKind(const Program& p) {
  const std::string n = p.name;
  return n == "optimize" || n == "sensitivity" ? "study" : n == "calibrate" ? "calibration" : "scene";
}

}  // namespace

TEST_CASE("cli: numbers are read by the project's rules, never the parser's", "[cli][input]") {
  struct Case {
    const char* text;
    const char* error;  // "" for a value taken
  };
  for (const Case& c : std::vector<Case>{{"8", ""},
                                         {" 16 ", ""},
                                         {"1e3", ""},
                                         {"abc", "value 'abc' is not an integer: it must be an integer in [8, 4096]"},
                                         {"", "value '' is not an integer"},
                                         {"3.5", "value '3.5' is not a whole number: it must be an integer in [8, 4096]"},
                                         {"0x10", "value '0x10' is not an integer"},
                                         {"nan", "value 'nan' is not an integer"},
                                         {"1e400", "value '1e400' is not an integer"},
                                         {"99999999999999999999", "value '99999999999999999999' must be an integer in [8, 4096]"},
                                         {"-1", "value -1 must be an integer in [8, 4096]"},
                                         {"4097", "value 4097 must be an integer in [8, 4096]"}}) {
    INFO(c.text);
    long long v = -7;
    const std::string got = lg::cli::integerError(c.text, 8, 4096, "", &v);
    INFO(got);
    CHECK(got.rfind(c.error, 0) == 0);  // the words, up to the end the table gives
    if (std::string(c.error).empty()) CHECK((got.empty() && v >= 8));
  }
  for (const Case& c : std::vector<Case>{{"1e-3", ""},
                                         {"2", ""},
                                         {"abc", "value 'abc' is not a number of s (e.g. 1e-3)"},
                                         {"1.5x", "value '1.5x' is not a number of s"},
                                         {"0x10", "value '0x10' is not a number of s"},
                                         {"nan", "value 'nan' must be a finite number > 0"},
                                         {"1e400", "value '1e400' must be a finite number > 0"},
                                         {"-inf", "value '-inf' must be a finite number > 0"},
                                         {"0", "value 0 s must be > 0"},
                                         {"-1", "value -1 s must be > 0"}}) {
    INFO(c.text);
    double v = 0;
    const std::string got = lg::cli::numberError(c.text, true, "s", &v);
    INFO(got);
    CHECK(got.rfind(c.error, 0) == 0);
    if (std::string(c.error).empty()) CHECK((got.empty() && v > 0));
  }
  // a long value is quoted cut, never echoed whole
  CHECK(lg::cli::numberError(std::string(100000, '7') + "x", true, "", nullptr).size() < 120);
}

TEST_CASE("cli: every program answers each class of command-line mistake in the one promised form", "[cli][input]") {
  lgtest::TempDir dir("cli_classes");
  const std::string outDir = dir / "out";
  struct Mistake {
    const char* what;
    std::string args;   // after the input file
    std::string words;  // in the error
  };
  for (const Program& p : kPrograms) {
    const std::string in = q(lgtest::sourcePath(p.input)) + " --out " + q(outDir);
    const std::vector<Mistake> mistakes{
        {"an unknown option", "--no-such-flag", "error: command line: key '--no-such-flag': not an option of " + std::string(p.name)},
        {"a misspelt option", "--thread 2", "key '--thread': not an option of " + std::string(p.name) + " (did you mean --threads?)"},
        {"a short option", "-x", "key '-x': not an option of " + std::string(p.name) + " (options are written --name"},
        {"a value missing at the end", "--threads", "key '--threads': needs a value: --threads INT"},
        {"an empty --flag= (it never takes the next argument)", "--threads= --quiet",
         "key '--threads': the value is empty: --threads INT"},
        {"an option where the value belongs", "--threads --quiet", "key '--threads': needs a value, not the option '--quiet'"},
        {"an empty value", "--threads ''", "key '--threads': the value is empty"},
        {"a value given twice", "--threads 1 --threads 2", "key '--threads': given twice ('1' and '2'): give it once"},
        {"a switch given a value", "--quiet=yes", "key '--quiet': a switch takes no value: write --quiet alone"},
        {"not an integer", "--threads abc", "key '--threads': value 'abc' is not an integer: it must be an integer in [0, 4096] (0: all cores)"},
        {"out of range", "--threads -1", "key '--threads': value -1 must be an integer in [0, 4096] (0: all cores)"},
        {"a second input file", q(lgtest::sourcePath(p.input)), "is one too many"},
        {"--out empty", "--out=", "key '--out': the value is empty"},
    };
    for (const Mistake& m : mistakes) {
      INFO(m.what);
      expectUsageError(p.name, in + " " + m.args, m.words, outDir);
    }
    // the input file missing
    const std::string kind = inputKind(p);
    expectUsageError(p.name, "--out " + q(outDir), "error: command line: key '" + kind + "': missing: the " + kind + " file comes first", outDir);
  }
}

TEST_CASE("cli: each program's own values in the one promised form", "[cli][input]") {
  lgtest::TempDir dir("cli_values");
  const std::string outDir = dir / "out";
  auto with = [&](const Program& p) { return q(lgtest::sourcePath(p.input)) + " --out " + q(outDir) + " "; };
  struct Bad {
    int program;  // index into kPrograms
    std::string args;
    std::string words;
  };
  for (const Bad& b : std::vector<Bad>{
           {0, "--rtol abc", "error: command line: key '--rtol': value 'abc' is not a number"},
           {0, "--rtol nan", "key '--rtol': value 'nan' must be a finite number > 0"},
           {0, "--step 0", "key '--step': value 0 s must be > 0"},
           {0, "--output-interval 1e400", "key '--output-interval': value '1e400' must be a finite number > 0"},
           {0, "--integrator rk5", "key '--integrator': value 'rk5' must be dopri5, ros34pw2, ros2, rk4 or euler"},
           {0, "--gradient strut.f1,", "key '--gradient': value 'strut.f1,' has an empty path: PATH[,PATH...]"},
           {0, "--case nope", "key '--case': value 'nope' is no case of the scene"},
           {0, "--set solver.integrator=rk4", "key '--set solver.integrator': solver settings are not parameters of the scene: "
                                              "give them with --integrator"},
           {0, "--set strut.D=100", "error: command line: key '--set strut.D': the scene is invalid with strut.D=100: "},
           {0, "--set =1", "key '--set': value '=1' has no PATH before '='"},
           {1, "--basis part26", "key '--basis': value 'part26' must be part25, cs25, part23, cs23 or custom"},
           {2, "--maxeval 0", "key '--maxeval': value 0 must be an integer in [1, 100000000] (for no limit, maxeval = 0"},
           {2, "--maxeval 1e9", "key '--maxeval': value 1e9 must be an integer in [1, 100000000]"},
           {3, "--samples 3.5", "key '--samples': value '3.5' is not a whole number"},
           {3, "--samples 7", "key '--samples': value 7 must be an integer in [8, 1048576] (a power of two)"},
           {3, "--samples 12", "key '--samples': value 12 must be a power of two in [8, 2^20]"},
           {3, "--seed -1", "key '--seed': value -1 must be an integer in [0, 9223372036854775807]"},
           {3, "--method LOCAL", "key '--method': value 'LOCAL' must be local, morris, sobol or all"},
           {4, "--set strut.f1=abc", "key '--set strut.f1': value 'abc' must be a finite number"},
       }) {
    expectUsageError(kPrograms[b.program].name, with(kPrograms[b.program]) + b.args, b.words, outDir);
  }
}

TEST_CASE("cli: an input that is not a regular file is named for what it is", "[cli][input]") {
  lgtest::TempDir dir("cli_files");
  const std::string outDir = dir / "out";
  REQUIRE(::mkfifo((dir / "fifo").c_str(), 0644) == 0);
  for (const Program& p : kPrograms)
    for (const auto& [path, why] : std::vector<std::pair<std::string, std::string>>{
             {dir / "absent.toml", "no such file"},
             {dir.path.string(), "a directory, not a file"},
             {dir / "fifo", "not a regular file (a pipe, a socket or a device)"},
             {"/dev/null", "not a regular file (a pipe, a socket or a device)"}})
      expectUsageError(p.name, q(path) + " --out " + q(outDir),
                       "error: " + path + ": cannot read the " + inputKind(p) + " file: " + why, outDir);
}

TEST_CASE("cli: the docs' command-line errors are the programs' words", "[cli][readme]") {
  const std::string readme = lgtest::docsText();  // README.md and docs/
  lgtest::TempDir dir("cli_readme");
  const std::string scene = q(lgtest::sourcePath("data/seed_gear.toml")) + " --out " + q(dir / "out") + " ";
  for (const char* args : {"--threads abc", "--out --quiet", "--thread 2", "--set solver.integrator=rk4"}) {
    std::string out, err;
    INFO(args);
    CHECK(run("simulate", scene + args, out, err) == 2);
    CHECK(err.rfind("error: command line: ", 0) == 0);
    CHECK(readme.find("\n" + err) != std::string::npos);  // the whole line, as the docs print it
  }
}
