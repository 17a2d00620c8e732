#include <catch2/catch.hpp>
#include "sim/drop_test.hpp"
TEST_CASE("seed gear limit case runs", "[smoke]") {
  lg::Scene sc = lg::loadScene(std::string(LG_SOURCE_DIR) + "/data/seed_gear.toml");
  auto r = lg::runCase(sc, sc.cases[2]);
  INFO(r.metrics.message);
  CHECK(r.metrics.ok);
}
