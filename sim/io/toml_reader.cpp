// TOML input tables with file/line-aware errors (toml_reader.hpp).
#include "sim/io/toml_reader.hpp"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <set>
#include <sstream>

namespace lg {
namespace {
int lineOfNode(const toml::node& n) { return static_cast<int>(n.source().begin.line); }
}  // namespace

std::string fmt(double v) {
  std::ostringstream o;
  o.precision(10);
  o << v;
  return o.str();
}

// ---- TomlReader ------------------------------------------------------------------------------------
int TomlReader::line() const { return lineOfNode(t_); }
int TomlReader::lineOf(const std::string& key) const {
  const toml::node* n = t_.get(key);
  return n ? lineOfNode(*n) : line();
}
void TomlReader::fail(const std::string& key, const std::string& rule) const {
  throw InputError(file_, lineOf(key), full(key), rule);
}

void TomlReader::allowOnly(std::initializer_list<const char*> keys) const {
  std::set<std::string> ok(keys.begin(), keys.end());
  for (const auto& [k, v] : t_) {
    const std::string key(k.str());
    if (!ok.count(key)) {
      std::string list;
      for (const auto& a : ok) list += (list.empty() ? "" : ", ") + a;
      throw InputError(file_, lineOfNode(v), full(key), "unknown key (allowed here: " + list + ")");
    }
  }
}

double TomlReader::number(const std::string& key) const {
  const toml::node* n = t_.get(key);
  if (!n) fail(key, "missing required number");
  return toNumber(*n, key);
}
double TomlReader::number(const std::string& key, double def) const {
  const toml::node* n = t_.get(key);
  return n ? toNumber(*n, key) : def;
}
double TomlReader::positive(const std::string& key) const { return checkPositive(key, number(key)); }
double TomlReader::positive(const std::string& key, double def) const {
  return has(key) ? checkPositive(key, number(key)) : def;
}
double TomlReader::nonNegative(const std::string& key, double def) const {
  const double v = number(key, def);
  if (!(v >= 0)) fail(key, "value " + fmt(v) + " must be >= 0");
  return v;
}
long long TomlReader::integer(const std::string& key, long long def) const {
  const toml::node* n = t_.get(key);
  if (!n) return def;
  if (!n->is_integer()) fail(key, "must be an integer");
  return *n->value<int64_t>();
}
std::string TomlReader::string(const std::string& key) const {
  const toml::node* n = t_.get(key);
  if (!n) fail(key, "missing required string");
  if (!n->is_string()) fail(key, "must be a string");
  return std::string(*n->value<std::string>());
}
std::string TomlReader::string(const std::string& key, const std::string& def) const {
  return has(key) ? string(key) : def;
}
bool TomlReader::boolean(const std::string& key, bool def) const {
  const toml::node* n = t_.get(key);
  if (!n) return def;
  if (!n->is_boolean()) fail(key, "must be true or false");
  return *n->value<bool>();
}
Vec3<double> TomlReader::vec3(const std::string& key) const {
  const toml::node* n = t_.get(key);
  if (!n) fail(key, "missing required vector [x, y, z]");
  const toml::array* a = n->as_array();
  if (!a || a->size() != 3) fail(key, "must be a vector of 3 numbers [x, y, z]");
  Vec3<double> v;
  for (int i = 0; i < 3; ++i) v[i] = toNumber(*a->get(i), key);
  return v;
}
Vec3<double> TomlReader::vec3(const std::string& key, const Vec3<double>& def) const {
  return has(key) ? vec3(key) : def;
}
Vec3<double> TomlReader::unitVec3(const std::string& key) const { return normalize(key, vec3(key)); }
Vec3<double> TomlReader::unitVec3(const std::string& key, const Vec3<double>& def) const {
  return has(key) ? unitVec3(key) : def;
}
Vec3<double> TomlReader::normalize(const std::string& key, const Vec3<double>& v) const {
  if (!(v.norm() > 1e-12)) fail(key, "direction must be a non-zero vector");
  return v.normalized();
}
double TomlReader::toNumber(const toml::node& n, const std::string& key) const {
  double v = 0;
  if (n.is_floating_point()) v = *n.value<double>();
  else if (n.is_integer()) v = static_cast<double>(*n.value<int64_t>());
  else fail(key, "must be a number");
  if (!std::isfinite(v)) fail(key, "value must be finite");
  return v;
}
double TomlReader::checkPositive(const std::string& key, double v) const {
  if (!(v > 0)) fail(key, "value " + fmt(v) + " must be > 0");
  return v;
}

// ---- whole tables and files ------------------------------------------------------------------------
std::vector<const toml::table*> tablesOf(const toml::table& doc, const std::string& key, const std::string& file) {
  std::vector<const toml::table*> out;
  const toml::node* n = doc.get(key);
  if (!n) return out;
  const toml::array* a = n->as_array();
  if (!a) throw InputError(file, lineOfNode(*n), key, "must be an array of tables [[" + key + "]]");
  for (const auto& e : *a) {
    const toml::table* t = e.as_table();
    if (!t) throw InputError(file, lineOfNode(e), key, "each entry must be a table [[" + key + "]]");
    out.push_back(t);
  }
  return out;
}

const toml::table* tableOf(const toml::table& doc, const std::string& key, const std::string& file) {
  const toml::node* n = doc.get(key);
  if (!n) return nullptr;
  const toml::table* t = n->as_table();
  if (!t) throw InputError(file, lineOfNode(*n), key, "must be a table [" + key + "]");
  return t;
}

std::string readText(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path, 0, "", "cannot open the " + what);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

}  // namespace lg
