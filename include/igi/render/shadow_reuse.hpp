#pragma once
/// \file
/// Which of a frame's VPLs are the delta lights whose shadow rays a later frame may reuse: a
/// point, spot or directional light's one exact VPL, the same from frame to frame while the light
/// stays (the sun's VPL is drawn at a new point of its disc each frame, but only its direction
/// and irradiance light a pixel). The environment's directional VPLs are drawn anew every frame,
/// so they match nothing in the frame before and are traced as always.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

#include "igi/filters/filter.hpp"
#include "igi/lighting/vpl.hpp"

namespace igi {

/// Most delta lights whose shadow answers a pixel keeps: one bit each in ShadowBits.
inline constexpr std::size_t most_reused_shadow_lights = 32;

/// What lights a pixel through a delta light's VPL: equal keys in two frames shade alike.
struct DeltaLightKey {
  VplKind kind = VplKind::omni;  ///< omni, spot or directional.
  glm::vec3 position{0.0f};      ///< Where it is (zero for a directional light, whose VPL's point does not matter).
  glm::vec3 normal{0.0f};        ///< Cone axis (spot) or direction of travel (directional).
  glm::vec3 intensity{0.0f};     ///< Its VPL's intensity.
  float cos_inner = 0.0f;        ///< Spot cone.
  float cos_outer = 0.0f;        ///< Spot cone.
  /// The key of a delta light's VPL.
  static DeltaLightKey of(const Vpl& vpl) noexcept {
    const bool directional = vpl.kind == VplKind::directional;
    return {vpl.kind, directional ? glm::vec3(0.0f) : vpl.position, vpl.normal, vpl.intensity, vpl.cos_inner, vpl.cos_outer};
  }
  /// Same light, bit for bit.
  bool operator==(const DeltaLightKey&) const = default;
};

/// The delta lights of a frame's VPL sets, each once, in the order first met (at most
/// most_reused_shadow_lights; the ones beyond get no bit and are always traced).
inline std::vector<DeltaLightKey> delta_light_keys(const VplSets& vpls) {
  std::vector<DeltaLightKey> keys;
  for (const std::vector<Vpl>& set : vpls.sets)
    for (const Vpl& vpl : set) {
      if (vpl.kind == VplKind::surface) continue;
      const DeltaLightKey key = DeltaLightKey::of(vpl);
      if (std::find(keys.begin(), keys.end(), key) == keys.end() && keys.size() < most_reused_shadow_lights) keys.push_back(key);
    }
  return keys;
}

/// For each of `now`'s lights, its bit in `before` (-1 where `before` has no such light).
inline std::array<std::int8_t, most_reused_shadow_lights> previous_shadow_bits(const std::vector<DeltaLightKey>& now,
                                                                              const std::vector<DeltaLightKey>& before) {
  std::array<std::int8_t, most_reused_shadow_lights> bits;
  bits.fill(-1);
  for (std::size_t i = 0; i < now.size() && i < bits.size(); ++i) {
    const auto found = std::find(before.begin(), before.end(), now[i]);
    if (found != before.end()) bits[i] = std::int8_t(found - before.begin());
  }
  return bits;
}

/// `bits` renumbered from the frame before's lights to this frame's first `lights` (`previous_bit`
/// as previous_shadow_bits gives it): lights that frame did not have are unknown.
inline ShadowBits renumber(const ShadowBits& bits, const std::array<std::int8_t, most_reused_shadow_lights>& previous_bit,
                           std::size_t lights) noexcept {
  ShadowBits now;
  for (std::size_t i = 0; i < std::min(lights, previous_bit.size()); ++i) {
    if (previous_bit[i] < 0 || !((bits.known >> previous_bit[i]) & 1u)) continue;
    now.known |= 1u << i;
    now.visible |= ((bits.visible >> previous_bit[i]) & 1u) << i;
  }
  return now;
}

}  // namespace igi
