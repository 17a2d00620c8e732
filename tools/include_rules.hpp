// The layering rules of the source tree, checked on its #include lines (tools/include_check.cpp runs
// them in every build; tools/include_rules.txt holds the rules).
//
// A module is a source file without its extension (sim/io/scene.hpp and sim/io/scene.cpp are the module
// sim/io/scene). An edge "a -> b" is an #include "b.hpp" in a file of module a. The rules file has one
// rule a line ('#' starts a comment):
//
//   never FROM TO : WHY    no file matching FROM includes a file matching TO
//   debt FILE TARGET : WHY a known include that breaks a rule or closes a cycle, tolerated until it is
//                          removed; a debt that no longer exists is an error (delete its line), so the
//                          list only shrinks
//
// FROM and TO are a folder ("sim/core/": everything under it), the files directly in a folder
// ("sim/*"), or one module or file ("optim/optimizer"). Besides the "never" rules the module graph must
// have no cycle (debts left out). Every problem is one line naming the file, its line, the include and
// the rule.
#pragma once

#include <string>
#include <vector>

namespace lg::tools {

struct IncludeRule {
  bool debt = false;
  std::string from, to, why;
  std::string source;  // the rules file
  int line = 0;        // its line there
};

struct IncludeReport {
  int files = 0, includes = 0;
  std::vector<std::string> problems;  // each a whole line: "file:line: ..."
  std::vector<std::string> debts;     // the debts in use, for the summary
};

// The rules of a rules file's text; a malformed line is a problem naming 'rulesFile' and its line.
std::vector<IncludeRule> parseIncludeRules(const std::string& text, const std::string& rulesFile,
                                           std::vector<std::string>& problems);

// The project's sources under 'root' (the folders 'dirs', files ending .hpp or .cpp) checked against
// 'rules'.
IncludeReport checkIncludes(const std::string& root, const std::vector<std::string>& dirs,
                            const std::vector<IncludeRule>& rules);

}  // namespace lg::tools
