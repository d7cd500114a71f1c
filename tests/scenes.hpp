#pragma once
// Access to ../shared/scenes for tests: a scene that is missing makes the test skip with a
// message (Catch2 v2 has no skip, so it warns and returns) instead of failing.

#include <filesystem>
#include <string>

#include <catch2/catch.hpp>

namespace igi::testing {

/// Path of a file under the shared scenes folder.
inline std::filesystem::path scene_path(const std::string& relative) {
  return std::filesystem::path(IGI_SCENES_DIR) / relative;
}

/// Path of a file under tests/data.
inline std::filesystem::path data_path(const std::string& relative) {
  return std::filesystem::path(IGI_TEST_DATA_DIR) / relative;
}

}  // namespace igi::testing

/// Skips the rest of a test (with a warning naming the file) when a shared scene is missing.
#define IGI_REQUIRE_SCENE(path)                                                               \
  do {                                                                                        \
    if (!std::filesystem::exists(path)) {                                                     \
      WARN("skipped: " << (path).string() << " is missing (../shared/scenes not present)"); \
      return;                                                                                 \
    }                                                                                         \
  } while (false)
