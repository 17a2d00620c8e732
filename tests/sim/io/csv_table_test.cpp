// Numeric CSV files (sim/io/csv_table.hpp): each fault is one InputError at the CSV's file, line and
// column, with the context of the file that names it; the unit-suffixed headers the programs write are
// read by their bare names.
#include "sim/io/csv_table.hpp"

#include <string>
#include <vector>

#include "docs_support.hpp"  // docsText: README.md and docs/
#include "files_support.hpp"
#include "sim/io/scene.hpp"

#include <catch2/catch.hpp>

TEST_CASE("csv: a table reads its columns by name, with or without units, comments and blank lines skipped", "[io][csv]") {
  lgtest::TempDir dir("csv_ok");
  const std::string path = dir / "t.csv";
  lgtest::writeFile(path, "# a comment\n\nstroke[m], area [m^2],note\n0,8e-5,x\n# mid\n0.05,+7e-5,y\r\n0.1,6e-5,z\n");
  const lg::CsvTable t(path, "table", "stroke,area");
  CHECK(t.headerLine() == 3);
  CHECK(t.rows() == 3);
  CHECK(t.rowLine(1) == 6);
  CHECK(t.column("stroke") == 0);
  CHECK(t.column("area") == 1);
  CHECK(t.column("stroke[m]") == 0);
  CHECK(t.column("load") == -1);
  CHECK(t.numbers("area") == std::vector<double>{8e-5, 7e-5, 6e-5});
}

TEST_CASE("csv: each fault names the file, the line and the column", "[io][csv][input]") {
  lgtest::TempDir dir("csv_bad");
  struct Bad {
    const char* what;
    std::string text;
    int line;
    std::string key;
    std::string rule;
  };
  const std::string ctx = " (the table of force[3].load_table in gear.toml)";
  for (const Bad& b : std::vector<Bad>{
           {"semicolons", "deflection;load\n0;0\n", 1, "header",
            "'deflection;load' is separated by ';': columns are separated by commas, e.g. deflection,load" + ctx},
           {"tabs", "deflection\tload\n0\t0\n", 1, "header", "is separated by tabs: columns are separated by commas"},
           {"numbers before the header", "# c\n0,0\ndeflection,load\n", 2, "header",
            "the first line (after # comments) must name the columns, e.g. deflection,load; it holds '0,0'" + ctx},
           {"no header", "# only a comment\n", 0, "header",
            "no header line: the table must begin (after # comments) with the names of its columns, e.g. deflection,load"},
           {"an empty file", "", 0, "header", "no header line"},
           {"a name twice", "load,load\n", 1, "load", "the header names this column twice"},
           {"a name twice, once with its unit", "load,load [N]\n", 1, "load [N]", "the header names this column twice"},
           {"an unnamed column", "deflection,,load\n", 1, "header", "column 2 has no name"},
           {"a short row", "deflection,load\n0,0\n0.1\n", 3, "load",
            "the row has 1 fields, the header (line 1) 2: this column is missing" + ctx},
           {"a long row", "deflection,load\n0,0,0\n", 2, "column 3", "the row has 3 fields, the header (line 1: deflection, load) 2"},
           {"a word", "deflection,load\n0,0\n0.1,abc\n", 3, "load", "value 'abc' is not a number" + ctx},
           {"a NaN", "deflection,load\n0,nan\n", 2, "load", "value 'nan' must be a finite number"},
           {"a column missing", "deflection,force\n0,0\n", 1, "load",
            "the header has no column 'load' (it names: deflection, force); expected e.g. deflection,load" + ctx},
           {"a huge line", "deflection," + std::string(10000000, 'x') + "\n", 1, "",
            "the line has 10000011 characters, more than 65536: not a row of a table" + ctx},
       }) {
    INFO(b.what);
    const std::string path = dir / "t.csv";
    lgtest::writeFile(path, b.text);
    std::string msg;
    try {
      const lg::CsvTable t(path, "table", "deflection,load", ctx);
      t.numbers("deflection");
      t.numbers("load");
      FAIL("no error");
    } catch (const lg::InputError& e) {
      msg = e.what();
      CHECK(e.file() == path);
      CHECK(e.line() == b.line);
      CHECK(e.key() == b.key);
    }
    INFO(msg);
    CHECK(msg.find(b.rule) != std::string::npos);
    CHECK(msg.size() < 700);  // a huge input is never echoed
  }
}

TEST_CASE("scene tables: a fault inside a CSV is named at its line and column, with the scene key that names it",
          "[io][csv][input]") {
  lgtest::TempDir dir("csv_scene");
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string tyre = "K = 8.0e5                      # [N/m]\n";
  const std::string orifice = "f1 = 7.0e-5";
  REQUIRE(seed.find(tyre) != std::string::npos);
  REQUIRE(seed.find(orifice) != std::string::npos);
  const std::string tyreScene = dir / "tyre.toml", pinScene = dir / "pin.toml";
  {
    std::string s = seed;
    s.replace(s.find(tyre), tyre.size(), "law = \"table\"\nload_table = \"tyre.csv\"\n");
    s.erase(s.find("alpha = 0.5\n"), std::string("alpha = 0.5\n").size());
    lgtest::writeFile(tyreScene, s);
    std::string p = seed;
    p.replace(p.find(orifice), orifice.size(), "f1_table = \"pin.csv\"");
    lgtest::writeFile(pinScene, p);
  }
  struct Bad {
    const char* what;
    std::string scene, csv, text;
    int line;
    std::string key, rule;
  };
  const std::string tyreCtx = " (the table of force[3].load_table in " + tyreScene + ")";
  const std::string pinCtx = " (the table of force[2].f1_table in " + pinScene + ")";
  for (const Bad& b : std::vector<Bad>{
           {"a falling load", tyreScene, "tyre.csv", "# c\ndeflection,load\n0.0,0.0\n0.05,4e4\n0.1,3e4\n0.15,9e4\n", 5, "load",
            "load 30000 N must be larger than the row before's 40000 N (a tyre's load rises with its deflection)" + tyreCtx},
           {"not starting unloaded", tyreScene, "tyre.csv", "deflection,load\n0.0,100.0\n0.05,4e4\n0.1,8e4\n0.15,12e4\n", 2,
            "load", "the first row must be deflection 0 with load 0 (got 0, 100)"},
           {"uneven spacing", tyreScene, "tyre.csv", "deflection,load\n0,0\n0.05,4e4\n0.12,8e4\n0.15,12e4\n", 4, "deflection",
            "deflection 0.12 m: the deflections must be uniformly spaced (0.05 m apart)"},
           {"a short table", tyreScene, "tyre.csv", "deflection,load\n0,0\n0.1,9e4\n", 1, "deflection",
            "the table has 2 rows: it needs at least 4 of (deflection, load)" + tyreCtx},
           {"semicolons", tyreScene, "tyre.csv", "deflection;load\n0;0\n", 1, "header", "is separated by ';'"},
           {"a row of 3 fields", tyreScene, "tyre.csv", "deflection,load\n0,0,0\n", 2, "column 3", "the row has 3 fields"},
           {"a negative area", pinScene, "pin.csv", "stroke,area\n0,8e-5\n0.08,-6e-5\n0.16,4e-5\n0.24,4e-5\n", 3, "area",
            "area -6e-05 m^2 must be > 0" + pinCtx},
           {"a falling stroke", pinScene, "pin.csv", "stroke,area\n0,8e-5\n0.08,6e-5\n0.04,4e-5\n0.16,4e-5\n", 4, "stroke",
            "stroke 0.04 m must be larger than the row before's 0.08 m"},
           {"a word", pinScene, "pin.csv", "stroke [m],area [m^2]\n0,8e-5\n0.08,six\n0.16,4e-5\n0.24,4e-5\n", 3, "area [m^2]",
            "value 'six' is not a number" + pinCtx},
       }) {
    INFO(b.what);
    lgtest::writeFile(dir / b.csv, b.text);
    std::string msg;
    try {
      lg::loadScene(b.scene);
      FAIL("no error");
    } catch (const lg::InputError& e) {
      msg = e.what();
      CHECK(e.file() == dir / b.csv);
      CHECK(e.line() == b.line);
      CHECK(e.key() == b.key);
    }
    INFO(msg);
    CHECK(msg.find(b.rule) != std::string::npos);
  }
  // the units the programs write in their own headers are read
  lgtest::writeFile(dir / "pin.csv", "stroke[m],area[m^2]\n0,8e-5\n0.08,6e-5\n0.16,4e-5\n0.24,4e-5\n");
  CHECK_NOTHROW(lg::loadScene(pinScene));
}

TEST_CASE("csv: the docs' table errors are the program's words", "[io][csv][readme]") {
  const std::string readme = lgtest::docsText();  // README.md and docs/
  lgtest::TempDir dir("csv_readme");
  const std::string seed = lgtest::readFile(lgtest::sourcePath("data/seed_gear.toml"));
  const std::string tyre = "K = 8.0e5                      # [N/m]\n";
  std::string withTyre = seed, withPin = seed;
  withTyre.replace(withTyre.find(tyre), tyre.size(), "law = \"table\"\nload_table = \"tyre.csv\"\n");
  withTyre.erase(withTyre.find("alpha = 0.5\n"), std::string("alpha = 0.5\n").size());
  withPin.replace(withPin.find("f1 = 7.0e-5"), std::string("f1 = 7.0e-5").size(), "f1_table = \"pin.csv\"");
  struct Example {
    std::string scene, csv, text;
  };
  for (const Example& e : std::vector<Example>{
           {withTyre, "tyre.csv", "# c\ndeflection,load\n0.0,0.0\n0.05,4e4\n0.1,3e4\n0.15,9e4\n"},
           {withPin, "pin.csv", "stroke;area\n0;8e-5\n"},
           {withPin, "pin.csv", "0,8e-5\n0.1,7e-5\n"},
       }) {
    const std::string scene = dir / "gear.toml";
    lgtest::writeFile(scene, e.scene);
    lgtest::writeFile(dir / e.csv, e.text);
    std::string msg;
    try {
      lg::loadScene(scene);
    } catch (const lg::InputError& err) {
      msg = std::string("error: ") + err.what();
    }
    INFO(msg);
    REQUIRE(msg.rfind("error: " + (dir / e.csv) + ":", 0) == 0);
    // the docs' line names the files by their bare names
    std::string bare = msg;
    bare.replace(bare.find(dir / e.csv), (dir / e.csv).size(), e.csv);
    bare.replace(bare.find(scene), scene.size(), "gear.toml");
    CHECK(readme.find("\n" + bare + "\n") != std::string::npos);
  }
}
