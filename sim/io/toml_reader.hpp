// Reading TOML input tables with errors that name the file, line and key: shared by the scene parser
// (sim/io/scene.cpp) and the study parser (optim/study.cpp), so that both speak the same way about
// the same mistakes ("missing required number", "value 0 must be > 0", "unknown key (allowed here: ...)").
#pragma once

#include <initializer_list>
#include <map>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "sim/core/math.hpp"
#include "sim/core/input_error.hpp"

namespace lg {

template <class S> struct Model;  // sim/model/model.hpp

// A number as the error messages write it (10 significant digits).
std::string fmt(double v);

// True for a valid element or case name (TomlReader::name); nameRule() says the rule in words.
bool isName(const std::string& s);
std::string nameRule();

// One table of an input file: typed getters that throw InputError(file, line, prefix.key, rule), and a
// closed set of keys. A getter with a default returns it unchecked when the key is absent: the rules
// apply to what the file says, not to the program's own defaults.
class TomlReader {
 public:
  TomlReader(const toml::table& t, std::string file, std::string prefix)
      : t_(t), file_(std::move(file)), prefix_(std::move(prefix)) {}

  // The table's line; lineOf(key) is the key's line, or the table's where the key is absent.
  int line() const;
  int lineOf(const std::string& key) const;
  // The key as the messages name it: "body[0].mass".
  std::string full(const std::string& key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  const std::string& file() const { return file_; }
  [[noreturn]] void fail(const std::string& key, const std::string& rule) const;
  bool has(const std::string& key) const { return t_.contains(key); }
  const toml::node* get(const std::string& key) const { return t_.get(key); }

  // Rejects any key not in 'keys', at that key's line.
  void allowOnly(std::initializer_list<const char*> keys) const;

  double number(const std::string& key) const;
  double number(const std::string& key, double def) const;
  double positive(const std::string& key) const;
  double positive(const std::string& key, double def) const;
  double nonNegative(const std::string& key, double def) const;
  // A drop's duration [s]: > 0 and at most kMaxDuration (a drop test lasts seconds, never hours).
  double duration(const std::string& key, double def) const;
  static constexpr double kMaxDuration = 60.0;  // [s]
  long long integer(const std::string& key, long long def) const;
  // A count: a whole number in [lo, hi] (a TOML integer, or a float with an integral value, 1e6).
  long long count(const std::string& key, long long def, long long lo, long long hi) const;
  // A name that becomes file names and CSV columns: letters, digits, '_', '-' and '.', starting with a
  // letter, a digit or '_', at most 64 characters (isName).
  std::string name(const std::string& key) const;
  std::string name(const std::string& key, const std::string& def) const;
  std::string string(const std::string& key) const;
  std::string string(const std::string& key, const std::string& def) const;
  bool boolean(const std::string& key, bool def) const;
  Vec3<double> vec3(const std::string& key) const;
  Vec3<double> vec3(const std::string& key, const Vec3<double>& def) const;
  Vec3<double> unitVec3(const std::string& key) const;
  Vec3<double> unitVec3(const std::string& key, const Vec3<double>& def) const;
  // v normalized; an error at 'key' if it is (nearly) zero.
  Vec3<double> normalize(const std::string& key, const Vec3<double>& v) const;
  // A finite number from any node (an array element, say), at most kMaxMagnitude in magnitude; errors name 'key'.
  double toNumber(const toml::node& n, const std::string& key) const;
  static constexpr double kMaxMagnitude = 1e15;  // [SI] beyond any mass, stiffness or pressure of a gear (a test's belt: 1e12 kg)
  // The table 'key' of body = mass [kg] (a drop case's masses), each body one of model m's, each mass
  // > 0, into 'masses' (absent: nothing).
  void masses(const std::string& key, const Model<double>& m, std::map<std::string, double>& masses) const;

 private:
  double checkPositive(const std::string& key, double v) const;
  const toml::table& t_;
  std::string file_, prefix_;
};

// Rows of the array-of-tables 'key' of doc (absent: none). Errors if it is not an array of tables.
std::vector<const toml::table*> tablesOf(const toml::table& doc, const std::string& key, const std::string& file);

// The table 'key' of doc (absent: nullptr). Errors if it is something else.
const toml::table* tableOf(const toml::table& doc, const std::string& key, const std::string& file);

// Parses TOML text; a syntax error is an InputError naming the file, the line and the key of the
// statement it belongs to (an unterminated multi-line string: the line it opens on).
toml::table parseToml(const std::string& text, const std::string& file);

// The whole file; InputError(path, 0, "", "cannot open the <what>") if it cannot be read, and for
// anything but a regular file (a directory, a pipe: never blocks on a FIFO).
std::string readText(const std::string& path, const std::string& what = "file");
// Why 'path' cannot be read as an input file ("no such file", "a directory, not a file", "not a
// regular file (a pipe, ...)"), or "" if it can.
std::string fileProblem(const std::string& path);

}  // namespace lg
