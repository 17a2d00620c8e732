// compare A B (apps/compare.cpp): the values that differ by their parameter paths, every shared case's
// metrics side by side with B - A exact, the same scene twice all zero, and bad command lines answered
// with one line, exit 2 and nothing written.
#include <sys/wait.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "files_support.hpp"

#include <catch2/catch.hpp>

namespace {

std::string q(const std::string& s) { return "'" + s + "'"; }

int compare(const std::string& args, std::string& out, std::string& err) {
  static lgtest::TempDir logs("compare_logs");
  const std::string o = logs / "out.txt", e = logs / "err.txt";
  const int st = std::system((q(lgtest::binPath("compare")) + " " + args + " >" + q(o) + " 2>" + q(e)).c_str());
  out = lgtest::readFile(o);
  err = lgtest::readFile(e);
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// The seed gear with its main orifice and the limit case's sink speed changed, in 'dir'.
std::string variant(const lgtest::TempDir& dir) {
  std::string text = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const auto f1 = text.find("f1 = 7.0e-5");
  REQUIRE(f1 != std::string::npos);
  text.replace(f1, 11, "f1 = 8.0e-5");
  const auto limit = text.find("name = \"limit\"\nsink_speed = 3.05");
  REQUIRE(limit != std::string::npos);
  text.replace(text.find("3.05", limit), 4, "3.10");
  const std::string path = dir / "variant.toml";
  lgtest::writeFile(path, text);
  return path;
}

std::vector<std::vector<std::string>> csvRows(const std::string& text) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> f;
    std::string cell;
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      else if (c == ',' && !quoted) f.push_back(cell), cell.clear();
      else cell += c;
    }
    f.push_back(cell);
    rows.push_back(f);
  }
  return rows;
}

}  // namespace

TEST_CASE("compare: the differing values by path, and each metric's B - A exact", "[apps][compare]") {
  lgtest::TempDir dir("compare_variant");
  const std::string b = variant(dir), scene = lgtest::sourcePath("data/seed_gear.toml");
  std::string out, err;
  REQUIRE(compare(q(scene) + " " + q(b) + " --case limit --case light --out " + q(dir / "o") + " --threads 2", out, err) == 0);
  INFO(out << err);
  CHECK(err.empty());
  CHECK(out.find("scene values that differ (A -> B):\n") != std::string::npos);
  CHECK(out.find("  limit.sink_speed             3.05 -> 3.1\n") != std::string::npos);
  CHECK(out.find("  strut.f1                     7e-05 -> 8e-05\n") != std::string::npos);
  CHECK(out.find("  strut.f1 ") < out.find("  limit.sink_speed "));  // in the order of the file
  CHECK(out.find("\ncase limit\n") < out.find("\ncase light\n"));  // the cases in the order given
  // A's figures are simulate's: the seed gear's limit drop peaks at 86253.7 N
  CHECK(out.find("  peak_load                    N            86253.7") != std::string::npos);
  const auto rows = csvRows(lgtest::readFile(dir / "o/compare.csv"));
  REQUIRE(rows.size() > 20);
  CHECK(rows[0] == std::vector<std::string>{"case", "metric", "unit", "A", "B", "B_minus_A", "relative[-]"});
  int peak = 0;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    REQUIRE(rows[i].size() == 7);
    const double a = std::stod(rows[i][3]), bb = std::stod(rows[i][4]), d = std::stod(rows[i][5]);
    if (std::isfinite(a) && std::isfinite(bb)) CHECK(d == bb - a);
    if (rows[i][1] == "peak_load") {
      ++peak;
      CHECK(bb != a);  // a larger orifice changes the peak in both cases
      CHECK(std::stod(rows[i][6]) == (bb - a) / std::abs(a));
    }
  }
  CHECK(peak == 2);
  const std::string json = lgtest::readFile(dir / "o/compare.json");
  CHECK(json.rfind("{\n  \"provenance\": {\"program\": \"compare\"", 0) == 0);
  CHECK(json.find("{\"path\": \"strut.f1\", \"a\": \"7e-05\", \"b\": \"8e-05\"}") != std::string::npos);
}

TEST_CASE("compare: a scene against itself differs nowhere", "[apps][compare]") {
  lgtest::TempDir dir("compare_same");
  const std::string scene = lgtest::sourcePath("data/seed_gear.toml");
  std::string out, err;
  REQUIRE(compare(q(scene) + " " + q(scene) + " --out " + q(dir / "o") + " --quiet", out, err) == 0);
  CHECK(out.empty());
  const auto rows = csvRows(lgtest::readFile(dir / "o/compare.csv"));
  std::set<std::string> cases;
  for (std::size_t i = 1; i < rows.size(); ++i) {
    cases.insert(rows[i][0]);
    if (rows[i][5] != "nan") CHECK(rows[i][5] == "0");  // the same bits: every difference is zero
  }
  CHECK(cases == std::set<std::string>{"light", "medium", "limit", "reserve", "free-drop"});  // every shared case
}

TEST_CASE("compare: a bad command line or case is one error line, exit 2, nothing written", "[apps][compare]") {
  lgtest::TempDir dir("compare_bad");
  const std::string scene = lgtest::sourcePath("data/seed_gear.toml"), o = dir / "o";
  lgtest::writeFile(dir / "other.toml", lgtest::readFile(scene) + "\n[[case]]\nname = \"extra\"\nsink_speed = 1.0\nlift_ratio = 1.0\n");
  const std::string other = dir / "other.toml";
  struct Bad {
    std::string args, words;
  } bad[] = {
      {q(scene) + " --out " + q(o), "error: command line: key 'B': missing: the B file comes second: compare A B [options] (see --help)"},
      {q(scene) + " " + q(scene) + " " + q(scene) + " --out " + q(o), "key 'B': 2 files only: "},
      {q(other) + " " + q(scene) + " --case extra --out " + q(o),
       "error: command line: key '--case': value 'extra' is not a case of " + scene + " (its cases: light, medium, limit, reserve, free-drop)"},
  };
  for (const auto& x : bad) {
    std::string out, err;
    INFO(x.args);
    CHECK(compare(x.args, out, err) == 2);
    CHECK(err.find(x.words) != std::string::npos);
    CHECK(std::count(err.begin(), err.end(), '\n') == 1);
    CHECK(!std::filesystem::exists(o));
  }
}
