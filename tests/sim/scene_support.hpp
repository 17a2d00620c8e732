// Helpers shared by the drop-test, scene and CLI tests: loading the shipped scenes, editing a scene
// document (as a design study would) and rebuilding it, temporary directories, reading files.
//
// Include order: the sim headers pull in glog (through ceres), whose CHECK macro replaces Catch's if it
// comes later; Catch is included here after them. Test files include this header (or other sim headers)
// before anything that includes Catch.
#pragma once

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "files_support.hpp"  // sourcePath, binPath, readFile, writeFile, TempDir
#include "sim/drop/run.hpp"
#include "sim/engine/engine.hpp"
#include "sim/io/results.hpp"
#include "sim/io/scene.hpp"

#include <catch2/catch.hpp>

namespace lgtest {

// The named table of array 'arr' ("body", "joint", "stop", "force", "case") of a scene document.
inline toml::table& element(toml::table& doc, const std::string& arr, const std::string& name) {
  toml::array* a = doc[arr].as_array();
  REQUIRE(a);
  for (auto& e : *a) {
    toml::table* t = e.as_table();
    if (t && t->get("name") && t->get("name")->value<std::string>() == name) return *t;
  }
  FAIL("no [[" << arr << "]] named " << name);
  throw std::logic_error("unreachable");
}

// A shipped scene's document, for editing.
inline toml::table shippedDoc(const std::string& rel) { return toml::parse_file(sourcePath(rel)); }
// A shipped scene with the law of the reduced reference models (tests/reference): every strut's friction
// regularised over 1e-3 m/s instead of the shipped exact Coulomb stick/slip (tests/sim/friction_test.cpp
// relates the two).
inline toml::table referenceDoc(const std::string& rel) {
  toml::table doc = shippedDoc(rel);
  if (toml::array* forces = doc["force"].as_array())
    for (auto& f : *forces)
      if (toml::table* t = f.as_table(); t && t->get("type") && t->get("type")->value_or(std::string()) == "shock_absorber") {
        t->insert_or_assign("friction", "regularised");
        t->insert_or_assign("friction_velocity", 1e-3);
      }
  return doc;
}

// A shipped (planar) scene's document as a model in space: without [scene] plane_normal (docs/scene.md: Planar
// models). For the checks that lean on where the 3-D run's steps land (central differences between
// neighbouring designs, a law that acts after the step holding a turning point) and for the elements a
// planar model cannot hold (bearing friction).
inline toml::table spatialDoc(toml::table doc) {
  if (toml::table* t = doc["scene"].as_table()) t->erase("plane_normal");
  return doc;
}
inline toml::table shippedSpatialDoc(const std::string& rel) { return spatialDoc(shippedDoc(rel)); }
// The same for a scene file's text: its plane_normal line removed.
inline std::string spatialText(std::string text) {
  const auto at = text.find("\nplane_normal");
  if (at != std::string::npos) text.erase(at + 1, text.find('\n', at + 1) - at);
  return text;
}

// Builds a scene from an edited document; relative tables resolve against the shipped data/ folder.
inline lg::Scene build(const toml::table& doc, const std::string& name = "edited.toml") {
  return lg::buildScene(doc, name, sourcePath("data"));
}

inline const lg::DropCase& findCase(const lg::Scene& sc, const std::string& name) {
  for (const auto& c : sc.cases)
    if (c.name == name) return c;
  FAIL("scene " << sc.name << " has no case " << name);
  throw std::logic_error("unreachable");
}

inline double relDiff(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }
// The largest relative difference of a run's main metrics (peak load, stroke, travel, tyre deflection,
// efficiency, absorbed energy) from a reference run's.
inline double largestMetricDifference(const lg::CaseMetrics& a, const lg::CaseMetrics& ref) {
  double worst = 0;
  for (auto [x, y] : {std::pair{a.peak_load_N, ref.peak_load_N}, {a.stroke_max_m, ref.stroke_max_m}, {a.h_max_m, ref.h_max_m},
                      {a.tyre_deflection_max_m, ref.tyre_deflection_max_m}, {a.efficiency, ref.efficiency},
                      {a.energy_absorbed_J, ref.energy_absorbed_J}})
    worst = std::max(worst, relDiff(x, y));
  return worst;
}

}  // namespace lgtest
