// The scene parser's internals, shared by its source files and by nothing else: the table readers
// (sim/io/scene_tables.cpp), and SceneBuilder, the state that the steps of lg::buildScene share while
// they read one document into a Scene (the scene being built, the file and its folder, the bodies'
// initial poses, the names used so far, each constraint's line, the gravity declared). Each step is one
// member function: the [scene] and [solver] tables, bodies, joints and stops
// (sim/io/scene_elements.cpp), force elements one type at a time (sim/io/scene_forces.cpp), drop cases
// (sim/io/scene_elements.cpp); buildScene (sim/io/scene.cpp) runs them in order and checks the result.
#pragma once

#include <memory>
#include <set>
#include <string>
#include <vector>

#include <toml++/toml.h>

#include "sim/engine/engine.hpp"
#include "sim/core/input_error.hpp"
#include "sim/scene/scene.hpp"
#include "sim/io/toml_reader.hpp"

namespace lg {
class CsvTable;
}

namespace lg::detail {

// A body's position and orientation at t = 0 (scene axes).
struct Pose {
  Vec3<double> r = Vec3<double>::Zero();
  Mat3<double> R = Mat3<double>::Identity();
};

// ---- tables (sim/io/scene_tables.cpp) ----------------------------------------------------------------
// Two columns of a table, from a CSV file (csv set: errors name its lines) or inline in the scene.
struct ColumnPair {
  std::vector<double> x, y;
  std::shared_ptr<const CsvTable> csv;
  const char* names[2];
  // An error at sample 'row' (-1: the table as a whole) of column 0 or 1: at the CSV's line, or at the
  // scene's key for an inline table.
  [[noreturn]] void fail(const TomlReader& r, const std::string& key, long row, int column, const std::string& rule) const;
};
// The two columns 'cx', 'cy' of the CSV table 'path' that the scene's 'key' names.
ColumnPair readColumns(const std::string& path, const TomlReader& r, const std::string& key, const char* cx, const char* cy);
// A path of the scene relative to its folder.
std::string scenePath(const TomlReader& r, const std::string& key, const std::string& baseDir);
// A table's samples checked: at least 4, stroke increasing and uniformly spaced, every area > 0.
std::shared_ptr<const Table1D> checkedTable(ColumnPair t, const std::string& source, const TomlReader& r,
                                            const std::string& key);
// Reads a two-column CSV table "stroke,area" [m, m^2].
std::shared_ptr<const Table1D> readTable(const std::string& path, const TomlReader& r, const std::string& key);
// An inline table: { stroke = [...] [m], area = [...] [m^2] }.
std::shared_ptr<const Table1D> inlineTable(const toml::table& t, const TomlReader& r, const std::string& key);
// A tyre's load-deflection curve: CSV "deflection,load" [m, N].
std::shared_ptr<const CurveTable> readCurve(const std::string& path, const TomlReader& r, const std::string& key);

// ---- the builder -----------------------------------------------------------------------------------
struct SceneBuilder {
  SceneBuilder(Scene& scene, const toml::table& document, const std::string& fileName, const std::string& folder)
      : sc(scene), m(scene.model), doc(document), file(fileName), baseDir(folder) {}

  Scene& sc;                        // the scene being built
  Model<double>& m;                 // sc.model
  const toml::table& doc;
  const std::string& file;          // as given (for messages)
  const std::string& baseDir;       // resolves relative table paths
  std::string airframe;             // [scene] airframe, "" if not declared
  std::vector<Pose> poses;          // per body, at t = 0
  std::set<std::string> names;      // the element names used so far
  std::vector<int> constraintLine;  // per constraint: its table's line
  std::vector<const toml::table*> forceTables;  // the [[force]] rows
  std::vector<std::pair<ForceElement<double>, int>> pads;  // the elastic stops and their [[stop]] rows,
                                                           // added after the [[force]] elements
  Vec3<double> g = Vec3<double>::Zero();        // the gravity element's g
  bool hasGravity = false;
  int planeLine = 0;                            // [scene] plane_normal's line (a planar model)

  // Helpers of the steps (sim/io/scene_elements.cpp).
  // The element's name: valid, not "ground", not used before.
  std::string uniqueName(const TomlReader& r);
  // The body named at 'key' (kGround for "ground" where groundOk).
  int bodyRef(const TomlReader& r, const std::string& key, bool groundOk = true) const;
  // A point / a direction of the scene in body b's axes (the ground's are the scene's).
  Vec3<double> toBody(int b, const Vec3<double>& p) const;
  Vec3<double> dirToBody(int b, const Vec3<double>& d) const;

  // The steps, in buildScene's order (sim/io/scene_elements.cpp unless noted).
  void readSceneTable();
  void readSolver();
  void readBodies();
  void readBody(const toml::table& t, size_t i);
  void readJoints();
  void readJoint(const toml::table& t, size_t i);
  void readStops();
  void readCases();
  void readCase(const toml::table& t, size_t i, std::set<std::string>& caseNames);

  // Force elements (sim/io/scene_forces.cpp).
  void readForces();
  void readForce(size_t i);
  void readGravity(const TomlReader& r, ForceElement<double>& f);
  void readLift(const TomlReader& r, ForceElement<double>& f);
  void readConstant(const TomlReader& r, ForceElement<double>& f);
  void readShockAbsorber(const TomlReader& r, ForceElement<double>& f);
  void readStrutOrifices(const TomlReader& r, ShockAbsorber<double>& s);
  void readStrutGas(const TomlReader& r, ShockAbsorber<double>& s);
  void readStrutCheckValve(const TomlReader& r, ShockAbsorber<double>& s);
  void readTyreDamping(const TomlReader& r, Tyre<double>& t);
  void readTyre(const TomlReader& r, ForceElement<double>& f);
  void readTyreLaw(const TomlReader& r, Tyre<double>& t);
  void readTyreLongitudinal(const TomlReader& r, Tyre<double>& t);
  void readSpringDamper(const TomlReader& r, ForceElement<double>& f);
  void readBushing(const TomlReader& r, ForceElement<double>& f);
  void readBearingFriction(const TomlReader& r, ForceElement<double>& f);
  // After the force elements: |g| and up, each lift element's direction, the bearings' struts, the
  // elastic stops (after every [[force]] row, whose indices stay those of the file), the airframe.
  void finishLifts();
  void finishBearings();
  void finishStops();
  void findAirframe();
};

}  // namespace lg::detail
