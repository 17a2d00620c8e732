// Design parameters by path, on a scene's parsed document (declared in sim/io/scene.hpp): an element
// found by name (or an unnamed force element by its type), "<element>.<key>" split and resolved to a
// number of the document or to a sample of an inline table ("strut.f1_table[3]"), read and written;
// table files replaced by inline tables so that their samples can be written (best.toml,
// calibrated.toml, --set); and the document written back as TOML.
#include <sstream>

#include "sim/io/scene.hpp"
#include "sim/engine/engine.hpp"

namespace lg {

namespace {
toml::table* findElement(toml::table& doc, const std::string& name) {
  if (name == "envelope") return doc["envelope"].as_table();  // the [envelope] table's point
  for (const char* arr : {"body", "joint", "stop", "force", "case"}) {
    toml::array* a = doc[arr].as_array();
    if (!a) continue;
    for (auto& e : *a) {
      toml::table* t = e.as_table();
      if (!t) continue;
      const toml::node* n = t->get("name");
      if (n && n->value<std::string>() && *n->value<std::string>() == name) return t;
      // unnamed force elements are known by their type
      if (!n && std::string(arr) == "force" && t->get("type") && t->get("type")->value<std::string>() &&
          *t->get("type")->value<std::string>() == name)
        return t;
    }
  }
  return nullptr;
}
void splitPath(const std::string& path, std::string& element, std::string& key, const std::string& where) {
  const auto dot = path.rfind('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == path.size())
    throw InputError(where, 0, path, "parameter path must read <element>.<key>, e.g. strut.f1");
  element = path.substr(0, dot);
  key = path.substr(dot + 1);
}
}  // namespace

namespace {
// "f1_table[3]" -> ("f1_table", 3); any other key -> (key, -1).
std::pair<std::string, long> indexedKey(const std::string& key) {
  const auto open = key.find('[');
  if (open == std::string::npos || open == 0 || key.back() != ']') return {key, -1};
  const std::string digits = key.substr(open + 1, key.size() - open - 2);
  if (digits.empty() || digits.size() > 6 || digits.find_first_not_of("0123456789") != std::string::npos) return {key, -1};
  return {key.substr(0, open), std::stol(digits)};
}
// The node of a parameter: a number, or the area sample of an inline table.
toml::node* parameterNode(toml::table& doc, const std::string& path, const std::string& where) {
  std::string element, key;
  splitPath(path, element, key, where);
  toml::table* t = findElement(doc, element);
  if (!t) throw InputError(where, 0, path, "no body, joint, stop, force or case named '" + element + "' in the scene");
  const auto [base, k] = indexedKey(key);
  toml::node* n = t->get(base);
  if (!n) throw InputError(where, 0, path, "element '" + element + "' has no key '" + base + "' in the scene");
  if (k < 0) return n;
  if (n->is_string())
    throw InputError(where, 0, path, "'" + element + "." + base + "' is a table file: inline it first (inlineTables)");
  toml::array* area = n->is_table() ? (*n->as_table())["area"].as_array() : nullptr;
  if (!area || k >= static_cast<long>(area->size()))
    throw InputError(where, 0, path, "'" + element + "." + base + "' has no sample " + std::to_string(k));
  return area->get(static_cast<size_t>(k));
}
}  // namespace

namespace {
// "envelope.<key>" of the [envelope] table: a key of its point may be absent (its default: nominal).
bool envelopeDefault(const toml::table& doc, const std::string& path, double& v) {
  if (path.rfind("envelope.", 0) != 0) return false;
  const std::string key = path.substr(9);
  const toml::table* t = doc["envelope"].as_table();
  if (!t) return false;
  if (!isEnvelopePointKey(key) || t->contains(key)) return false;
  v = key == "temperature_C" ? (*t)["service_temperature_C"].value<double>().value_or(15.0) : 0.0;
  return true;
}
}  // namespace

double getParameter(const toml::table& doc, const std::string& path, const std::string& where) {
  if (double v; envelopeDefault(doc, path, v)) return v;
  const toml::node* n = parameterNode(const_cast<toml::table&>(doc), path, where);
  if (auto v = n->value<double>()) return *v;
  throw InputError(where, 0, path, "'" + path + "' is not a number in the scene");
}

void setParameter(toml::table& doc, const std::string& path, double value, const std::string& where) {
  if (double v; envelopeDefault(doc, path, v)) {
    doc["envelope"].as_table()->insert_or_assign(path.substr(9), value);
    return;
  }
  (void)getParameter(doc, path, where);
  std::string element, key;
  splitPath(path, element, key, where);
  const auto [base, k] = indexedKey(key);
  if (k >= 0) {
    *parameterNode(doc, path, where)->as_floating_point() = value;
    return;
  }
  toml::table* t = findElement(doc, element);
  t->insert_or_assign(key, value);
}

bool tableSample(const std::string& path) {
  const auto dot = path.rfind('.');
  return dot != std::string::npos && indexedKey(path.substr(dot + 1)).second >= 0;
}

void inlineTables(toml::table& doc, const Scene& scene, const std::vector<std::string>& paths) {
  for (const std::string& path : paths) {
    if (!tableSample(path)) continue;
    const auto dot = path.rfind('.');
    const std::string element = path.substr(0, dot), base = indexedKey(path.substr(dot + 1)).first;
    toml::table* t = findElement(doc, element);
    const int f = scene.model.forceIndex(element);
    if (!t || f < 0 || !t->get(base) || !t->get(base)->is_string()) continue;
    const auto* sa = std::get_if<ShockAbsorber<double>>(&scene.model.forces[static_cast<size_t>(f)].type);
    if (!sa) continue;
    const bool main = base == "f1_table", extension = base == "f1_extension_table";
    const std::shared_ptr<const Table1D>& table = main ? sa->f1Table : sa->f1eTable;
    if (!(main || extension) || !table) continue;
    toml::array stroke, area;
    for (double x : table->xs()) stroke.push_back(x);
    for (double y : main ? sa->f1Values : sa->f1eValues) area.push_back(y);
    toml::table inl{{"stroke", std::move(stroke)}, {"area", std::move(area)}};
    inl.is_inline(true);
    t->insert_or_assign(base, std::move(inl));
  }
}

std::string toTomlString(const toml::table& doc) {
  std::ostringstream o;
  o << doc << "\n";
  return o.str();
}

}  // namespace lg
