// The layering rules checked on the #include lines (include_rules.hpp).
#include "tools/include_rules.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <sstream>

namespace fs = std::filesystem;

namespace lg::tools {
namespace {

std::string moduleOf(const std::string& file) {
  const auto dot = file.rfind('.');
  return dot == std::string::npos ? file : file.substr(0, dot);
}

// Whether 'file' (a path from the root, with its extension) matches a FROM/TO pattern.
bool matches(const std::string& pattern, const std::string& file) {
  if (pattern.size() > 2 && pattern.compare(pattern.size() - 2, 2, "/*") == 0) {
    const std::string dir = pattern.substr(0, pattern.size() - 1);
    return file.rfind(dir, 0) == 0 && file.find('/', dir.size()) == std::string::npos;
  }
  if (!pattern.empty() && pattern.back() == '/') return file.rfind(pattern, 0) == 0;
  return file == pattern || moduleOf(file) == pattern;
}

struct Include {
  std::string file;    // the including file
  int line = 0;
  std::string target;  // the included project file
};

}  // namespace

std::vector<IncludeRule> parseIncludeRules(const std::string& text, const std::string& rulesFile,
                                           std::vector<std::string>& problems) {
  std::vector<IncludeRule> rules;
  std::istringstream in(text);
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream words(line);
    std::string kind, from, to, colon;
    if (!(words >> kind)) continue;
    IncludeRule r;
    r.source = rulesFile;
    r.line = n;
    if ((kind != "never" && kind != "debt") || !(words >> from >> to >> colon) || colon != ":") {
      problems.push_back(rulesFile + ":" + std::to_string(n) +
                         ": a rule reads 'never FROM TO : WHY' or 'debt FILE TARGET : WHY'");
      continue;
    }
    r.debt = kind == "debt";
    r.from = from;
    r.to = to;
    std::getline(words, r.why);
    r.why.erase(0, r.why.find_first_not_of(' '));
    if (r.why.empty()) {
      problems.push_back(rulesFile + ":" + std::to_string(n) + ": the rule says no why after ':'");
      continue;
    }
    rules.push_back(r);
  }
  return rules;
}

IncludeReport checkIncludes(const std::string& root, const std::vector<std::string>& dirs,
                            const std::vector<IncludeRule>& rules) {
  IncludeReport rep;
  std::vector<std::string> files;
  for (const auto& d : dirs) {
    if (!fs::is_directory(fs::path(root) / d)) continue;
    for (const auto& e : fs::recursive_directory_iterator(fs::path(root) / d)) {
      const std::string ext = e.path().extension().string();
      if (e.is_regular_file() && (ext == ".hpp" || ext == ".cpp"))
        files.push_back(e.path().lexically_relative(root).generic_string());  // (links not resolved)
    }
  }
  std::sort(files.begin(), files.end());
  rep.files = static_cast<int>(files.size());

  std::vector<Include> includes;
  for (const auto& f : files) {
    std::ifstream in(fs::path(root) / f);
    int n = 0;
    for (std::string line; std::getline(in, line);) {
      ++n;
      const auto at = line.find_first_not_of(" \t");
      if (at == std::string::npos || line.compare(at, 8, "#include") != 0) continue;
      const auto open = line.find('"', at);
      const auto close = open == std::string::npos ? open : line.find('"', open + 1);
      if (close == std::string::npos) continue;  // <system>
      const std::string target = line.substr(open + 1, close - open - 1);
      if (std::binary_search(files.begin(), files.end(), target)) includes.push_back({f, n, target});
    }
  }
  rep.includes = static_cast<int>(includes.size());

  // debts: each must still exist; its includes leave the rules and the cycle check
  std::set<std::pair<std::string, std::string>> debts;
  for (const auto& r : rules) {
    if (!r.debt) continue;
    const bool used = std::any_of(includes.begin(), includes.end(),
                                  [&](const Include& i) { return i.file == r.from && i.target == r.to; });
    if (!used)
      rep.problems.push_back(r.source + ":" + std::to_string(r.line) + ": the debt " + r.from + " -> " + r.to +
                             " is paid (no such include): delete its line");
    else
      rep.debts.push_back(r.from + " -> " + r.to + " (" + r.why + ")");
    debts.insert({r.from, r.to});
  }
  auto owed = [&](const Include& i) { return debts.count({i.file, i.target}) > 0; };

  for (const auto& i : includes) {
    if (owed(i)) continue;
    for (const auto& r : rules)
      if (!r.debt && matches(r.from, i.file) && matches(r.to, i.target))
        rep.problems.push_back(i.file + ":" + std::to_string(i.line) + ": includes " + i.target + ": never " + r.from +
                               " -> " + r.to + " (" + r.why + ")");
  }

  // cycles of modules (Tarjan's strongly connected components), debts left out
  std::map<std::string, std::set<std::string>> graph;
  std::map<std::pair<std::string, std::string>, const Include*> witness;
  for (const auto& i : includes) {
    const std::string a = moduleOf(i.file), b = moduleOf(i.target);
    graph[a];
    graph[b];
    if (a == b || owed(i)) continue;
    graph[a].insert(b);
    witness.emplace(std::make_pair(a, b), &i);
  }
  std::map<std::string, int> index, low;
  std::set<std::string> onStack;
  std::vector<std::string> stack;
  int counter = 0;
  std::function<void(const std::string&)> visit = [&](const std::string& v) {
    index[v] = low[v] = counter++;
    stack.push_back(v);
    onStack.insert(v);
    for (const auto& w : graph[v]) {
      if (!index.count(w)) {
        visit(w);
        low[v] = std::min(low[v], low[w]);
      } else if (onStack.count(w)) {
        low[v] = std::min(low[v], index[w]);
      }
    }
    if (low[v] != index[v]) return;
    std::vector<std::string> scc;
    for (std::string w; w != v;) {
      w = stack.back();
      stack.pop_back();
      onStack.erase(w);
      scc.push_back(w);
    }
    if (scc.size() < 2) return;
    std::sort(scc.begin(), scc.end());
    std::string names, edges;
    for (const auto& m : scc) names += (names.empty() ? "" : ", ") + m;
    for (const auto& [ab, inc] : witness)
      if (std::binary_search(scc.begin(), scc.end(), ab.first) && std::binary_search(scc.begin(), scc.end(), ab.second))
        edges += "\n  " + inc->file + ":" + std::to_string(inc->line) + ": includes " + inc->target;
    rep.problems.push_back("include cycle of " + std::to_string(scc.size()) + " modules: " + names + edges);
  };
  for (const auto& [v, _] : graph)
    if (!index.count(v)) visit(v);
  return rep;
}

}  // namespace lg::tools
