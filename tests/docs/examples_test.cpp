// Every example of the documentation whose output is shown is run, and its printed lines are checked, so
// that an example cannot drift from the program.
//
// The examples are the ```console blocks of README.md and docs/**/*.md. In a block, a line that starts
// with "$ " is a command, run by the shell from a scratch copy of the project root (its files linked,
// build/bin the programs just built, out/ empty); every other line is a line the command prints (stdout
// and stderr together), in any order. "[...]" stands for any text within a line (a wall time, a date),
// and a line that is "[...]" alone for lines left out. A block with no command, or a command's shown
// line that it does not print, fails with the page, the line and the output. The pages run in order
// (README.md first, then docs/ by path) in one scratch root, so a page may use what an earlier one wrote
// (docs/compare.md compares the tour's best.toml with the scene); a command writes under out/ only.

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "docs_support.hpp"
#include "files_support.hpp"

#include <catch2/catch.hpp>

namespace fs = std::filesystem;

namespace {

struct Command {
  std::string page;  // the docs file, relative to the project root
  int line = 0;      // the "$ " line's number in it
  std::string text;  // the command, without "$ "
  std::vector<std::pair<int, std::string>> shown;  // the lines it prints, with their line numbers
};

std::string trimRight(std::string s) {
  while (!s.empty() && (s.back() == ' ' || s.back() == '\r' || s.back() == '\t')) s.pop_back();
  return s;
}

// The commands of every ```console block of one page; a block without a command is reported in 'bad'.
std::vector<Command> commandsOf(const fs::path& page, std::vector<std::string>& bad) {
  std::vector<Command> out;
  std::istringstream in(lgtest::readFile(page.string()));
  const std::string rel = fs::relative(page, LG_SOURCE_DIR).string();
  bool inConsole = false, inOther = false;
  int blockLine = 0, commandsInBlock = 0;
  int n = 0;
  for (std::string line; std::getline(in, line);) {
    ++n;
    line = trimRight(line);
    const bool fence = line.rfind("```", 0) == 0;
    if (!inConsole && !inOther) {
      if (fence) {
        inConsole = line == "```console";
        inOther = !inConsole;
        blockLine = n;
        commandsInBlock = 0;
      }
      continue;
    }
    if (fence && line == "```") {
      if (inConsole && commandsInBlock == 0) bad.push_back(rel + ":" + std::to_string(blockLine) + ": a console block without a '$ ' command");
      inConsole = inOther = false;
      continue;
    }
    if (inOther) continue;
    if (line.rfind("$ ", 0) == 0) {
      out.push_back(Command{rel, n, line.substr(2), {}});
      ++commandsInBlock;
    } else if (line != "[...]" && !line.empty()) {
      if (out.empty() || commandsInBlock == 0)
        bad.push_back(rel + ":" + std::to_string(n) + ": an output line before the block's first command");
      else
        out.back().shown.emplace_back(n, line);
    }
  }
  if (inConsole || inOther) bad.push_back(rel + ":" + std::to_string(blockLine) + ": a code block that is never closed");
  return out;
}

// Whether 'pattern' ("[...]" matching any text) matches the whole of 'line'.
bool matches(const std::string& pattern, const std::string& line) {
  std::vector<std::string> parts;
  for (std::size_t from = 0;;) {
    const auto at = pattern.find("[...]", from);
    parts.push_back(pattern.substr(from, at == std::string::npos ? std::string::npos : at - from));
    if (at == std::string::npos) break;
    from = at + 5;
  }
  if (parts.size() == 1) return pattern == line;
  if (line.rfind(parts.front(), 0) != 0) return false;
  std::size_t pos = parts.front().size();
  for (std::size_t i = 1; i + 1 < parts.size(); ++i) {
    const auto at = line.find(parts[i], pos);
    if (at == std::string::npos) return false;
    pos = at + parts[i].size();
  }
  const std::string& last = parts.back();
  return line.size() >= pos + last.size() && line.compare(line.size() - last.size(), last.size(), last) == 0;
}

// A scratch project root: every top-level entry of the source tree linked (build/ and out/ aside),
// build/bin the programs of this build.
void prepareRoot(const fs::path& root) {
  for (const auto& e : fs::directory_iterator(LG_SOURCE_DIR)) {
    const std::string name = e.path().filename().string();
    if (name == "build" || name == "out" || name.rfind(".", 0) == 0) continue;
    fs::create_symlink(e.path(), root / name);
  }
  fs::create_directories(root / "build");
  fs::create_symlink(LG_BIN_DIR, root / "build" / "bin");
}

}  // namespace

TEST_CASE("docs: every console example prints the lines the docs show", "[docs][examples]") {
  std::vector<std::string> bad;
  std::vector<Command> commands;
  for (const auto& page : lgtest::docsFiles()) {
    auto c = commandsOf(page, bad);
    commands.insert(commands.end(), c.begin(), c.end());
  }
  for (const auto& b : bad) FAIL_CHECK(b);
  REQUIRE(!commands.empty());

  lgtest::TempDir dir("docs_examples");
  const fs::path root = dir.path / "root";
  fs::create_directories(root);
  prepareRoot(root);
  int checkedLines = 0;
  for (const auto& c : commands) {
    const std::string captured = (dir.path / "output.txt").string();
    const std::string cmd = "cd '" + root.string() + "' && ( " + c.text + " ) > '" + captured + "' 2>&1";
    const int rc = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(rc));
    const std::string output = lgtest::readFile(captured);
    std::vector<std::string> lines;
    std::istringstream in(output);
    for (std::string l; std::getline(in, l);) lines.push_back(trimRight(l));
    for (const auto& [n, shown] : c.shown) {
      bool found = false;
      for (const auto& l : lines) found = found || matches(shown, l);
      INFO(c.page << ":" << n << ": the line of '$ " << c.text << "' (" << c.page << ":" << c.line
                  << "), exit status " << WEXITSTATUS(rc) << ", printed:\n"
                  << output.substr(0, 6000));
      CHECK(found);
      checkedLines += found;
    }
  }
  std::printf("docs examples: %zu commands, %d shown lines checked\n", commands.size(), checkedLines);
}
