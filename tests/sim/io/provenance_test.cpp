// The provenance block (sim/io/provenance.cpp): SHA-256 against the FIPS 180-4 examples, the inputs of a
// scene with a table (one changed byte, another hash), and two runs of certify that differ only there.
#include "../scene_support.hpp"  // sim headers, then Catch (see there)

#include <sys/wait.h>

#include "sim/io/provenance.hpp"

TEST_CASE("provenance: SHA-256 of the FIPS 180-4 examples", "[provenance]") {
  CHECK(lg::sha256Hex("") == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855");
  CHECK(lg::sha256Hex("abc") == "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
  CHECK(lg::sha256Hex("abcdbcdecdefdefgefghfghighijhijkijkljklmklmnlmnomnopnopq") ==
        "248d6a61d20638b8e5c026930c3e6039a33ce45964ff2167f6ecedd419db06c1");
  CHECK(lg::sha256Hex(std::string(1000000, 'a')) == "cdc76e5c9914fb9281a1c7e284d73e67f1809a48a497200e046d39ccc7112cd0");
  // 55, 56 and 64 bytes: the padding's edge cases (one or two blocks)
  CHECK(lg::sha256Hex(std::string(55, 'a')) == "9f4390f8d30c2dd92ec9f095b65e2b9ae9b0a925a5258e241c9f1e910f734318");
  CHECK(lg::sha256Hex(std::string(56, 'a')) == "b35439a4ac6f0948b6d6f9e3c6af0f5f590ce20f1bde7090ef7970686ec6738a");
  CHECK(lg::sha256Hex(std::string(64, 'a')) == "ffe054fe7ae0cb6dc65c3af9b61d5209f439851db43d0ba5997337df154668eb");
}

TEST_CASE("provenance: a scene's inputs with their hashes, and one changed byte of a table changes its hash", "[provenance]") {
  const lgtest::TempDir dir("provenance");
  const std::string table = lgtest::readFile(lgtest::sourcePath("data/tables/metering_pin.csv"));
  std::string scene = lgtest::readFile(lgtest::sourcePath("data/seed_gear_metering_pin.toml"));
  const std::string from = "tables/metering_pin.csv";
  REQUIRE(scene.find(from) != std::string::npos);
  for (auto at = scene.find(from); at != std::string::npos; at = scene.find(from)) scene.replace(at, from.size(), "pin.csv");
  lgtest::writeFile(dir / "gear.toml", scene);
  lgtest::writeFile(dir / "pin.csv", table);
  const char* argv[] = {"certify", "gear.toml", "--out", "o"};
  const lg::Provenance a = lg::makeProvenance("certify", 4, argv, lg::sceneInputs(lg::loadScene(dir / "gear.toml")));
  REQUIRE(a.inputs.size() == 2);
  CHECK(a.inputs[0].role == "scene");
  CHECK(a.inputs[0].sha256 == lg::sha256Hex(scene));
  CHECK(a.inputs[1].role == "table");
  CHECK(a.inputs[1].path == dir / "pin.csv");
  CHECK(a.inputs[1].sha256 == lg::sha256Hex(table));
  CHECK(a.commandLine == "certify gear.toml --out o");
  CHECK(a.version == std::string(lg::buildVersion()));
  CHECK(!a.commit.empty());
  CHECK(a.date.size() == 20);
  std::string changed = table;
  changed[changed.size() - 2] = changed[changed.size() - 2] == '1' ? '2' : '1';
  lgtest::writeFile(dir / "pin.csv", changed);
  const lg::Provenance b = lg::makeProvenance("certify", 4, argv, lg::sceneInputs(lg::loadScene(dir / "gear.toml")));
  CHECK(b.inputs[1].sha256 != a.inputs[1].sha256);
  CHECK(b.inputs[0].sha256 == a.inputs[0].sha256);
  // in the outputs: JSON, markdown, TOML comments
  CHECK(lg::provenanceJson(a).find("\"sha256\": \"" + a.inputs[1].sha256 + "\"") != std::string::npos);
  CHECK(lg::provenanceMarkdown(a).find("`" + a.inputs[1].sha256 + "`") != std::string::npos);
  CHECK(lg::provenanceComment(a).rfind("# Written by certify ", 0) == 0);
}

TEST_CASE("provenance: two runs of certify differ in their provenance block alone", "[provenance][cli]") {
  const lgtest::TempDir dir("provenance_runs");
  const std::string scene = lgtest::sourcePath("data/seed_gear.toml");
  for (const char* out : {"a", "b"}) {
    const std::string cmd = "'" + lgtest::binPath("certify") + "' '" + scene + "' --nominal --out '" + (dir / out) + "' --quiet";
    const int st = std::system(cmd.c_str());
    REQUIRE(WIFEXITED(st));
    REQUIRE(WEXITSTATUS(st) == 0);
  }
  for (const char* f : {"compliance.json", "compliance.md"}) {
    const std::string a = lgtest::readFile(dir / (std::string("a/") + f)), b = lgtest::readFile(dir / (std::string("b/") + f));
    INFO(f);
    CHECK(a != b);  // the command lines name their own folders
    CHECK(lgtest::withoutProvenance(a) == lgtest::withoutProvenance(b));
    CHECK(a.find(lg::buildCommit()) != std::string::npos);
    CHECK(a.find(lg::fileSha256(scene)) != std::string::npos);
  }
}
