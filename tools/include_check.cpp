// include_check ROOT: checks the source tree's #include lines against ROOT/tools/include_rules.txt
// (tools/include_rules.hpp); every build runs it, so a back-arrow or a cycle fails the build.
// Prints one line per problem and exits 1, or a one-line summary (and the debts still owed) and exits 0.
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "tools/include_rules.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: include_check ROOT\n");
    return 2;
  }
  const std::string root = argv[1];
  const std::string rulesFile = root + "/tools/include_rules.txt";
  std::ifstream in(rulesFile);
  if (!in) {
    std::fprintf(stderr, "error: %s: cannot be read\n", rulesFile.c_str());
    return 2;
  }
  std::ostringstream text;
  text << in.rdbuf();
  std::vector<std::string> problems;
  const auto rules = lg::tools::parseIncludeRules(text.str(), "tools/include_rules.txt", problems);
  const auto rep = lg::tools::checkIncludes(root, {"apps", "bench", "calib", "optim", "sim", "tools", "uq"}, rules);
  problems.insert(problems.end(), rep.problems.begin(), rep.problems.end());
  for (const auto& p : problems) std::fprintf(stderr, "error: %s\n", p.c_str());
  if (!problems.empty()) return 1;
  int never = 0;
  for (const auto& r : rules) never += !r.debt;
  std::printf("include rules: %d files, %d includes, %d rules hold, no cycle; %zu debts owed\n", rep.files,
              rep.includes, never, rep.debts.size());
  for (const auto& d : rep.debts) std::printf("  debt: %s\n", d.c_str());
  return 0;
}
