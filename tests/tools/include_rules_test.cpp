// The layering rules (tools/include_rules.hpp): a "never" include, a cycle, a paid debt and a malformed
// rule each found and named; the project's own tree holds its rules.
#include "tools/include_rules.hpp"

#include <filesystem>
#include <string>

#include "files_support.hpp"

#include <catch2/catch.hpp>

namespace fs = std::filesystem;

namespace {

void put(const lgtest::TempDir& d, const std::string& rel, const std::string& text) {
  fs::create_directories((d.path / rel).parent_path());
  lgtest::writeFile(d / rel, text);
}

std::vector<lg::tools::IncludeRule> rules(const std::string& text) {
  std::vector<std::string> problems;
  auto r = lg::tools::parseIncludeRules(text, "rules.txt", problems);
  REQUIRE(problems.empty());
  return r;
}

}  // namespace

TEST_CASE("include rules: a 'never' include is named with its file, line and rule", "[tools][include_rules]") {
  lgtest::TempDir d("include_never");
  put(d, "sim/core/math.hpp", "#pragma once\n#include <vector>\n");
  put(d, "sim/core/model.hpp", "#pragma once\n#include \"sim/core/math.hpp\"\n#include \"sim/forces/spring.hpp\"\n");
  put(d, "sim/forces/spring.hpp", "#pragma once\n#include \"sim/core/math.hpp\"\n");
  const auto rep = lg::tools::checkIncludes(d.path.string(), {"sim"},
                                            rules("never sim/core/ sim/forces/ : the vocabulary names no force element\n"));
  CHECK(rep.files == 3);
  CHECK(rep.includes == 3);
  REQUIRE(rep.problems.size() == 1);
  CHECK(rep.problems[0] ==
        "sim/core/model.hpp:3: includes sim/forces/spring.hpp: never sim/core/ -> sim/forces/ (the vocabulary names no force element)");
}

TEST_CASE("include rules: 'sim/*' is the files directly in sim/, a module is its .hpp and .cpp", "[tools][include_rules]") {
  lgtest::TempDir d("include_patterns");
  put(d, "sim/drop.hpp", "#pragma once\n");
  put(d, "sim/drop.cpp", "#include \"sim/drop.hpp\"\n#include \"sim/io/scene.hpp\"\n");
  put(d, "sim/io/scene.hpp", "#pragma once\n");
  put(d, "sim/io/writer.cpp", "#include \"sim/io/scene.hpp\"\n");
  const auto rep = lg::tools::checkIncludes(d.path.string(), {"sim"}, rules("never sim/* sim/io/ : no files below\n"));
  REQUIRE(rep.problems.size() == 1);  // sim/io/writer.cpp is not "directly in sim/"
  CHECK(rep.problems[0].rfind("sim/drop.cpp:2: includes sim/io/scene.hpp: never sim/* -> sim/io/", 0) == 0);
}

TEST_CASE("include rules: a cycle of modules is named with the includes that close it", "[tools][include_rules]") {
  lgtest::TempDir d("include_cycle");
  put(d, "a/x.hpp", "#pragma once\n#include \"a/y.hpp\"\n");
  put(d, "a/y.hpp", "#pragma once\n");
  put(d, "a/y.cpp", "#include \"a/y.hpp\"\n#include \"a/x.hpp\"\n");
  put(d, "a/z.hpp", "#pragma once\n#include \"a/x.hpp\"\n");
  const auto rep = lg::tools::checkIncludes(d.path.string(), {"a"}, {});
  REQUIRE(rep.problems.size() == 1);
  CHECK(rep.problems[0] ==
        "include cycle of 2 modules: a/x, a/y\n  a/x.hpp:2: includes a/y.hpp\n  a/y.cpp:2: includes a/x.hpp");
}

TEST_CASE("include rules: a debt is tolerated while it exists, and an error once paid", "[tools][include_rules]") {
  lgtest::TempDir d("include_debt");
  put(d, "a/x.hpp", "#pragma once\n#include \"a/y.hpp\"\n");
  put(d, "a/y.hpp", "#pragma once\n#include \"a/x.hpp\"\n");
  const auto owed = rules("never a/y a/x : y sits below x\ndebt a/y.hpp a/x.hpp : until y is split\n");
  const auto rep = lg::tools::checkIncludes(d.path.string(), {"a"}, owed);
  CHECK(rep.problems.empty());  // neither the rule nor the cycle: the debt covers the include
  REQUIRE(rep.debts.size() == 1);
  CHECK(rep.debts[0] == "a/y.hpp -> a/x.hpp (until y is split)");
  put(d, "a/y.hpp", "#pragma once\n");
  const auto paid = lg::tools::checkIncludes(d.path.string(), {"a"}, owed);
  REQUIRE(paid.problems.size() == 1);
  CHECK(paid.problems[0] == "rules.txt:2: the debt a/y.hpp -> a/x.hpp is paid (no such include): delete its line");
}

TEST_CASE("include rules: a malformed rule is named at its line", "[tools][include_rules]") {
  std::vector<std::string> problems;
  lg::tools::parseIncludeRules("# comment\nnever a/ b/ : fine\nforbid a/ b/ : no\nnever a/ b/ :\n", "rules.txt", problems);
  REQUIRE(problems.size() == 2);
  CHECK(problems[0] == "rules.txt:3: a rule reads 'never FROM TO : WHY' or 'debt FILE TARGET : WHY'");
  CHECK(problems[1] == "rules.txt:4: the rule says no why after ':'");
}

TEST_CASE("include rules: the project's tree holds its own rules", "[tools][include_rules]") {
  std::vector<std::string> problems;
  const auto r = lg::tools::parseIncludeRules(lgtest::readFile(lgtest::sourcePath("tools/include_rules.txt")),
                                              "tools/include_rules.txt", problems);
  CHECK(problems.empty());
  int never = 0;
  for (const auto& x : r) never += !x.debt;
  CHECK(never >= 20);
  const auto rep = lg::tools::checkIncludes(LG_SOURCE_DIR, {"apps", "bench", "calib", "optim", "sim", "tools", "uq"}, r);
  for (const auto& p : rep.problems) FAIL_CHECK(p);
  CHECK(rep.files > 150);
  // Every debt is paid: an include that breaks a rule is an error, never a new debt.
  for (const auto& d : rep.debts) FAIL_CHECK("debt owed: " << d);
  // Each layer of the simulator is a folder: no source sits loose in sim/ (the "sim/*" of no layer).
  for (const auto& e : std::filesystem::directory_iterator(lgtest::sourcePath("sim")))
    if (e.is_regular_file()) FAIL_CHECK("a source outside the layers: sim/" << e.path().filename().string());
  std::printf("include rules: %d files, %d includes, %d rules, %zu debts owed\n", rep.files, rep.includes, never,
              rep.debts.size());
}
