// Test cases for check_skips.cmake, hidden from the suite (tag [.]): one that skips, one that
// fails and then asks to skip (which must stay a failure), one that skips after passing checks.
#include <catch2/catch.hpp>

#include "scenes.hpp"

TEST_CASE("skip: a missing scene skips", "[.][skip]") {
  IGI_REQUIRE_SCENE(igi::testing::scene_path("no such folder/no such scene.gltf"));
  FAIL("the scene above does not exist, so the test case must have ended");
}

TEST_CASE("skip: a failure before a skip stays a failure", "[.][skip]") {
  CHECK(1 + 1 == 3);  // fails on purpose: what check_skips.cmake looks for
  IGI_REQUIRE_SCENE(igi::testing::scene_path("no such folder/no such scene.gltf"));
}

TEST_CASE("skip: passed checks before a skip", "[.][skip]") {
  CHECK(1 + 1 == 2);
  IGI_REQUIRE_SCENE(igi::testing::scene_path("no such folder/no such scene.gltf"));
}
