// Bad scene files for the element tests: each must give one InputError naming the file, the line, the key
// and the rule, and `simulate` on it must exit with status 2 and write nothing (as tests/sim/io/scene_test.cpp
// checks for the scene's own keys).
#pragma once

#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "scene_support.hpp"  // sim headers, then Catch (see there)

namespace lgtest {

// 1-based line of the first occurrence of 'needle' in 'text' (0 if absent).
inline int lineOfText(const std::string& text, const std::string& needle) {
  const auto pos = text.find(needle);
  if (pos == std::string::npos) return 0;
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<long>(pos), '\n'));
}

// Replaces the first occurrence of 'from' (which must exist) by 'to'.
inline std::string replacedText(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  return text.replace(pos, from.size(), to);
}

struct BadInput {
  std::string what;    // what is wrong
  std::string text;    // the scene
  std::string marker;  // text starting on the line the error must name
  std::string key;     // what the message must name as the key
  std::string rule;    // words of the rule (and the value, where the rule quotes it)
};

inline int runSimulateOn(const std::string& scene, const std::string& out, const std::string& errFile) {
  const std::string cmd = "'" + binPath("simulate") + "' '" + scene + "' --out '" + out + "' --quiet --threads 1 2>'" +
                          errFile + "' >/dev/null";
  const int st = std::system(cmd.c_str());
  return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

// Each scene, written to 'dir', fails to load with the message asked for; `simulate` exits with 2, prints
// that message and writes nothing. 'dir' also holds any table the scenes name (relative to it).
inline void checkBadInputs(const std::vector<BadInput>& bad, const TempDir& dir) {
  for (size_t i = 0; i < bad.size(); ++i) {
    const BadInput& b = bad[i];
    const std::string file = dir / ("bad" + std::to_string(i) + ".toml");
    writeFile(file, b.text);
    const int line = lineOfText(b.text, b.marker);
    REQUIRE(line > 0);
    INFO(b.what);
    std::string msg;
    try {
      lg::loadScene(file);
      FAIL("no InputError for: " << b.what);
    } catch (const lg::InputError& e) {
      msg = e.what();
    }
    INFO("message: " << msg);
    CHECK(msg.find(file + ":" + std::to_string(line) + ":") != std::string::npos);
    CHECK(msg.find("'" + b.key + "'") != std::string::npos);
    CHECK(msg.find(b.rule) != std::string::npos);
    const std::string out = dir / ("out" + std::to_string(i));
    const int rc = runSimulateOn(file, out, dir / "stderr.txt");
    CHECK(rc == 2);
    CHECK(!std::filesystem::exists(out));
    CHECK(readFile(dir / "stderr.txt").find(msg) != std::string::npos);
  }
}

}  // namespace lgtest
