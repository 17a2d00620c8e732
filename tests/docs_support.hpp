// The documentation as the tests read it: README.md and every page under docs/, in a fixed order (the
// README first, then the pages by path). Tests that check a printed figure or message against the docs
// search this text, so a line may move between pages without the test losing it.
#pragma once

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include "files_support.hpp"

namespace lgtest {

// The Markdown files of the documentation, README.md first, then docs/**/*.md sorted by path.
inline std::vector<std::filesystem::path> docsFiles() {
  namespace fs = std::filesystem;
  std::vector<fs::path> pages;
  const fs::path docs = fs::path(LG_SOURCE_DIR) / "docs";
  if (fs::is_directory(docs))
    for (const auto& e : fs::recursive_directory_iterator(docs))
      if (e.is_regular_file() && e.path().extension() == ".md") pages.push_back(e.path());
  std::sort(pages.begin(), pages.end());
  pages.insert(pages.begin(), fs::path(LG_SOURCE_DIR) / "README.md");
  return pages;
}

// Every documentation file's text, each preceded by a newline (so that "\n" + line finds a page's first
// line too).
inline std::string docsText() {
  std::string all;
  for (const auto& p : docsFiles()) all += "\n" + readFile(p.string());
  return all;
}

}  // namespace lgtest
