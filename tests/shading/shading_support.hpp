#pragma once
// What the shading tests share (they are compiled together, tests/CMakeLists.txt says why).

namespace igi::testing {

/// The packet width of the shading tests: wide enough to mix active and inactive lanes in a mask.
inline constexpr int W = 8;

}  // namespace igi::testing
