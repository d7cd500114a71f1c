#pragma once
// Access to the shared scenes (../shared/scenes, or the folder the environment variable
// IGI_SCENES_DIR names) and to tests/data. A test whose scene is missing is reported by CTest as
// skipped, not passed: Catch2 v2 has no skip, so IGI_SKIP records the reason and returns, and the
// listener in main.cpp prints `skip_marker` when the test case ends - only if nothing in it failed,
// so that a skip can never hide a failure (CTest calls a test skipped whenever its output matches
// SKIP_REGULAR_EXPRESSION, whatever else happened).

#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <string>

#include <catch2/catch.hpp>

namespace igi::testing {

/// What a skipped test case prints; tests/CMakeLists.txt gives CTest the same text as SKIP_REGULAR_EXPRESSION.
inline constexpr const char* skip_marker = "SKIPPED: ";

/// The reason the running test case skipped, empty while it has not (main.cpp's listener reads and clears it).
inline std::string& skip_reason() {
  static std::string reason;
  return reason;
}

/// Folder of the shared scenes: $IGI_SCENES_DIR when set (so a test can point it to an empty
/// folder and see every scene test skip), else the folder the build was configured with.
inline std::filesystem::path scenes_folder() {
  const char* from_environment = std::getenv("IGI_SCENES_DIR");
  return from_environment && *from_environment ? std::filesystem::path(from_environment)
                                               : std::filesystem::path(IGI_SCENES_DIR);
}

/// Path of a file under the shared scenes folder.
inline std::filesystem::path scene_path(const std::string& relative) { return scenes_folder() / relative; }

/// Path of a file under tests/data.
inline std::filesystem::path data_path(const std::string& relative) {
  return std::filesystem::path(IGI_TEST_DATA_DIR) / relative;
}

}  // namespace igi::testing

/// Ends the running test case as skipped, with `reason` (a stream expression) in its output.
#define IGI_SKIP(reason)                                         \
  do {                                                           \
    std::ostringstream igi_skip_stream;                          \
    igi_skip_stream << reason;                                   \
    igi::testing::skip_reason() = igi_skip_stream.str();         \
    return;                                                      \
  } while (false)

/// Skips the rest of a test (naming the file) when a shared scene is missing. Put it first in a
/// test case about one scene: a case over several scenes would skip them all for one missing.
#define IGI_REQUIRE_SCENE(path)                                                                         \
  do {                                                                                                  \
    if (!std::filesystem::exists(path))                                                                 \
      IGI_SKIP((path).string() << " is missing (the shared scenes folder " << igi::testing::scenes_folder().string() \
                               << " lacks it; set IGI_SCENES_DIR)");                                   \
  } while (false)
