// Files and programs for every test executable: the source and binary trees, reading and writing whole
// files, and temporary directories. No project or Catch headers (see the include order notes of
// tests/sim/scene_support.hpp and tests/calib/calib_support.hpp).
#pragma once

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

namespace lgtest {

inline std::string sourcePath(const std::string& rel) { return std::string(LG_SOURCE_DIR) + "/" + rel; }
inline std::string binPath(const std::string& name) { return std::string(LG_BIN_DIR) + "/" + name; }

inline std::string readFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}
inline void writeFile(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// A fresh, empty directory under the system temp dir (removed by the destructor).
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& tag) {
    std::random_device rd;
    path = std::filesystem::temp_directory_path() /
           ("lg_" + tag + "_" + std::to_string(rd()) + "_" + std::to_string(rd()));
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path, ec);
  }
  std::string operator/(const std::string& name) const { return (path / name).string(); }
};

// An output without its provenance block (sim/io/provenance.hpp), the one part that changes from run to
// run: the "provenance" member of a JSON file (its three lines), the "## Provenance" section of a
// markdown file, the "# " comment head of a written scene.
inline std::string withoutProvenance(std::string text) {
  if (const auto at = text.find("  \"provenance\": {"); at != std::string::npos) {
    const auto end = text.find("]},\n", at);
    if (end != std::string::npos) text.erase(at, end + 4 - at);
  }
  if (const auto at = text.find("## Provenance\n"); at != std::string::npos) {
    const auto next = text.find("\n## ", at + 1);
    text.erase(at, next == std::string::npos ? std::string::npos : next + 1 - at);
  }
  while (text.rfind("# Written by ", 0) == 0 || text.rfind("# command line: ", 0) == 0 ||
         (text.rfind("# ", 0) == 0 && text.find(" sha256 ") < text.find('\n')))
    text.erase(0, text.find('\n') + 1);
  return text;
}

}  // namespace lgtest
