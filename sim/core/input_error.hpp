// Bad input: the one error type of every reader (scenes, studies, calibrations, the command line). Its
// message is one line, "file:line: key 'key': rule", that the programs print before exiting with status
// 2; the drop layer's own checks (sim/scene/check.hpp) and parameter paths (sim/scene/parameters.hpp) throw it
// too, so it sits below them and includes nothing of the project.
#pragma once

#include <cstddef>
#include <stdexcept>
#include <string>

namespace lg {

// Bad input: a message naming file, line, key and rule.
class InputError : public std::runtime_error {
 public:
  InputError(const std::string& file, int line, const std::string& key, const std::string& rule)
      : std::runtime_error(format(file, line, key, rule)), file_(file), line_(line), key_(cut(key, kKeyChars)),
        rule_(cut(rule, kRuleChars)) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }
  const std::string& rule() const { return rule_; }  // the words after "key '...': "
  // "file:line: key 'k': rule"; a key or a rule that quotes a huge input is cut (an error is one
  // readable line, never the input echoed).
  static std::string format(const std::string& file, int line, const std::string& key, const std::string& rule) {
    std::string s = cut(file, kRuleChars);
    if (line > 0) s += ":" + std::to_string(line);
    if (!key.empty()) s += ": key '" + cut(key, kKeyChars) + "'";
    return s + ": " + cut(rule, kRuleChars);
  }
  static constexpr size_t kKeyChars = 80, kRuleChars = 480;
  static std::string cut(const std::string& s, size_t n) {
    return s.size() <= n ? s : s.substr(0, n - 20) + "... (" + std::to_string(s.size()) + " characters)";
  }

 private:
  std::string file_;
  int line_;
  std::string key_, rule_;
};

}  // namespace lg
