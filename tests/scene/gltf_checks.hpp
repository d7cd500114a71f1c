#pragma once
// Checks the glTF tests share: vectors equal to float rounding, and loading a file that must
// load without a warning.

#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "igi/scene/gltf.hpp"

namespace igi::testing {

/// Float rounding of a few chained float operations on values of order 10.
inline constexpr float tolerance = 1e-5f;

/// True if `a` and `b` agree to `within` in every component.
inline bool near(const glm::vec3& a, const glm::vec3& b, float within = tolerance) {
  return glm::all(glm::lessThanEqual(glm::abs(a - b), glm::vec3(within)));
}

/// Loads `file`, requiring no warnings.
inline igi::Scene load_clean(const std::filesystem::path& file) {
  std::vector<std::string> warnings;
  igi::Scene scene = igi::load_gltf(file, &warnings);
  for (const std::string& warning : warnings) UNSCOPED_INFO(warning);
  CHECK(warnings.empty());
  return scene;
}

}  // namespace igi::testing
