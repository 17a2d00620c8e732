// A document written as an edit of its source text (sim/io/toml_rewrite.hpp): the user's comments, order
// and spellings kept, only the changed values replaced; every other case refused with its reason.
#include "sim/io/toml_rewrite.hpp"

#include <cmath>
#include <limits>
#include <string>

#include <catch2/catch.hpp>

namespace {

toml::table parsed(const std::string& text) { return toml::parse(std::string_view(text), std::string_view("t.toml")); }

const char* kScene = R"(# The reference gear (comments stay)
name = "seed"   # its name

[solver]
integrator = "dopri5"
rtol = 1e-6     # tight

[[force]]
name = "strut"
f1 = 7e-5       # [m^2] main orifice
p01 = 3.0e6
table = "area.csv"

[[force]]
name = "tyre"
K = 8e5
stroke = [0.0, 0.1,
          0.2, 0.3]   # a multi-line array

[[case]]
name = "limit"
sink_speed = 3.05
)";

}  // namespace

TEST_CASE("toml rewrite: a changed value is replaced in place, everything else kept byte for byte, comments in their column", "[io][toml_rewrite]") {
  toml::table doc = parsed(kScene);
  doc["force"][0].as_table()->insert_or_assign("f1", 7.981164373e-05);
  doc["force"][1]["stroke"].as_array()->get(2)->as_floating_point()->get() = 0.25;
  doc.insert_or_assign("name", "s2");
  const lg::TomlRewrite r = lg::rewriteToml(kScene, "t.toml", doc);
  INFO(r.reason);
  REQUIRE(r.text);
  std::string want = kScene;
  want.replace(want.find("7e-5       #"), 12, "7.981164373e-05 #");  // the comment moves as little as it can
  want.replace(want.find("\"seed\"   #"), 10, "\"s2\"     #");        // and keeps its column after a shorter value
  want.replace(want.find("0.2, 0.3]"), 3, "0.25");
  CHECK(*r.text == want);
}

TEST_CASE("toml rewrite: an unchanged document is its source", "[io][toml_rewrite]") {
  const lg::TomlRewrite r = lg::rewriteToml(kScene, "t.toml", parsed(kScene));
  REQUIRE(r.text);
  CHECK(*r.text == kScene);
}

TEST_CASE("toml rewrite: keys added under their header, at the root, and tables and elements appended", "[io][toml_rewrite]") {
  toml::table doc = parsed(kScene);
  doc["solver"].as_table()->insert_or_assign("atol", 1e-8);
  doc.insert_or_assign("gravity", 9.81);
  doc.insert_or_assign("envelope", toml::table{{"charge_tolerance", 0.03}});
  doc["case"].as_array()->push_back(toml::table{{"name", "m1"}, {"sink_speed", 2.5}});
  const lg::TomlRewrite r = lg::rewriteToml(kScene, "t.toml", doc);
  INFO(r.reason);
  REQUIRE(r.text);
  std::string want = kScene;
  want.insert(want.find("\n\n[solver]") + 1, "gravity = 9.81\n");
  want.insert(want.find("\n\n[[force]]") + 1, "atol = 1e-08\n");
  want += "\n[[case]]\nname = \"m1\"\nsink_speed = 2.5\n\n[envelope]\ncharge_tolerance = 0.03\n";
  CHECK(*r.text == want);
}

TEST_CASE("toml rewrite: a removed key's line goes, and a value that becomes a table is written inline", "[io][toml_rewrite]") {
  toml::table doc = parsed(kScene);
  doc["solver"].as_table()->erase("rtol");
  doc["force"][0].as_table()->insert_or_assign("table", toml::table{{"stroke", toml::array{0.0, 0.3}}, {"area", toml::array{1e-4, 5e-5}}});
  const lg::TomlRewrite r = lg::rewriteToml(kScene, "t.toml", doc);
  INFO(r.reason);
  REQUIRE(r.text);
  std::string want = kScene;
  want.erase(want.find("rtol = 1e-6     # tight\n"), std::string("rtol = 1e-6     # tight\n").size());
  want.replace(want.find("\"area.csv\""), 10, "{ area = [1e-04, 5e-05], stroke = [0.0, 0.3] }");
  CHECK(*r.text == want);
}

TEST_CASE("toml rewrite: what the source cannot hold by an edit is refused with its reason", "[io][toml_rewrite]") {
  SECTION("a key added to a table made by dotted keys would land at the root: the read-back catches it") {
    const std::string src = "gear.mass = 1.0\n";
    toml::table doc = parsed(src);
    doc["gear"].as_table()->insert_or_assign("span", 2.0);
    const lg::TomlRewrite r = lg::rewriteToml(src, "t.toml", doc);
    CHECK_FALSE(r.text);
    CHECK(r.reason == "the edited text does not read back as the document");
  }
  SECTION("a removed table") {
    toml::table doc = parsed(kScene);
    doc.erase("solver");
    const lg::TomlRewrite r = lg::rewriteToml(kScene, "t.toml", doc);
    CHECK_FALSE(r.text);
    CHECK(r.reason == "the table 'solver' would be removed");
  }
  SECTION("a lost element of an array of tables") {
    toml::table doc = parsed(kScene);
    doc["force"].as_array()->erase(doc["force"].as_array()->begin());
    const lg::TomlRewrite r = lg::rewriteToml(kScene, "t.toml", doc);
    CHECK_FALSE(r.text);
    CHECK(r.reason == "'force' loses elements");
  }
  SECTION("no source") {
    const lg::TomlRewrite r = lg::rewriteToml("", "t.toml", parsed(kScene));
    CHECK_FALSE(r.text);
    CHECK(r.reason == "no source text");
  }
}

TEST_CASE("toml rewrite: columns count code points, so a value after non-ASCII text is found", "[io][toml_rewrite]") {
  const std::string src = "name = \"Fahrwerk Süd\"\nx = [\"éé\", 1.5]  # ü\n";
  toml::table doc = parsed(src);
  doc["x"].as_array()->get(1)->as_floating_point()->get() = 2.5;
  const lg::TomlRewrite r = lg::rewriteToml(src, "t.toml", doc);
  INFO(r.reason);
  REQUIRE(r.text);
  CHECK(*r.text == "name = \"Fahrwerk Süd\"\nx = [\"éé\", 2.5]  # ü\n");
}

TEST_CASE("toml rewrite: floats in their shortest round-trip form, always floats", "[io][toml_rewrite]") {
  CHECK(lg::tomlFloat(0.45) == "0.45");
  CHECK(lg::tomlFloat(2.0) == "2.0");
  CHECK(lg::tomlFloat(3e6) == "3e+06");  // shorter than 3000000.0
  CHECK(lg::tomlFloat(7.981164373e-05) == "7.981164373e-05");
  CHECK(lg::tomlFloat(-1e300) == "-1e+300");
  CHECK(lg::tomlFloat(std::numeric_limits<double>::infinity()) == "inf");
  CHECK(lg::tomlFloat(std::nan("")) == "nan");
  for (const double v : {0.1 + 0.2, 1.0 / 3.0, 6.02214076e23, 5e-324}) {
    const toml::table t = parsed("v = " + lg::tomlFloat(v) + "\n");
    CHECK(t["v"].value<double>() == v);
  }
}

TEST_CASE("toml rewrite: sameToml compares data, floats to the bit", "[io][toml_rewrite]") {
  CHECK(lg::sameToml(parsed("a = 1.0\nb = [1, 2]\n"), parsed("b = [1,2]\na = 1.0 # x\n")));
  CHECK_FALSE(lg::sameToml(parsed("a = 1.0\n"), parsed("a = 1\n")));
  CHECK_FALSE(lg::sameToml(parsed("a = 0.30000000000000004\n"), parsed("a = 0.3\n")));
  CHECK(lg::sameToml(parsed("a = nan\n"), parsed("a = nan\n")));
  CHECK_FALSE(lg::sameToml(parsed("a = { b = 1 }\n"), parsed("a = { b = 1, c = 2 }\n")));
}
