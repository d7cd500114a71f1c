#pragma once
// What several lighting tests share (they are compiled together, tests/CMakeLists.txt says why).

#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

namespace igi::testing {

/// π in the single precision the lighting code computes in.
inline constexpr float pi = std::numbers::pi_v<float>;

/// True if every component of `v` is finite.
inline bool finite(const glm::vec3& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

}  // namespace igi::testing
