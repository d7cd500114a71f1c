#pragma once
/// \file
/// What the shading, lighting and rendering layers share, each defined once here: 1/pi, the
/// limit on alpha cut-out layers, and the one rule for where rays leaving a surface start.
///
/// The ray-offset rule: every ray that leaves a surface (shadow rays, mirror and glass rays, path
/// tracer bounces, VPL random walks) starts `ray_offset(scene bounds)` off it along the geometric
/// normal, on the side the ray goes to (`leave_surface`); a ray continued through an alpha
/// cut-out at distance t continues from t + that offset; a ray from a light starts that far along
/// itself; a shadow ray towards a point stops twice that short of it.

#include <algorithm>
#include <numbers>

#include <glm/glm.hpp>

#include "igi/scene/scene.hpp"
#include "igi/simd/simd.hpp"

namespace igi {

/// 1/pi as a float: the normalisation of the diffuse (Lambert) BRDF, albedo/pi.
inline constexpr float inv_pi = std::numbers::inv_pi_v<float>;

/// Most alpha cut-out layers one ray passes through before the pipeline, the path tracer and the
/// VPL walks give up on it: Sponza's foliage stacks a few, so 16 is far more than any pixel needs
/// and bounds the loop.
inline constexpr int max_cutout_layers = 16;

/// How far rays start off surfaces in a scene of world `bounds`: 1e-5 of the scene's diagonal plus
/// its distance from the origin stays above the float rounding of positions (about 6e-8 of their
/// magnitude, which that distance bounds) yet far below any feature size; an empty scene counts
/// as one unit across, one unit from the origin.
inline float ray_offset(const Bounds& bounds) noexcept {
  const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.extent());
  const float reach = bounds.empty() ? 1.0f : std::max(glm::length(bounds.lower), glm::length(bounds.upper));
  return 1e-5f * (diagonal + reach);
}

/// Where a ray along `direction` leaving the surface point `position` of geometric normal
/// `geometric_normal` starts: `offset` (ray_offset) off the surface on the side the ray goes to.
template <int W>
vec3<W> leave_surface(const vec3<W>& position, const vec3<W>& geometric_normal, const vec3<W>& direction,
                      float offset) noexcept {
  const vec3<W> side = select(dot(direction, geometric_normal) >= vfloat<W>(0.0f), geometric_normal, -geometric_normal);
  return position + side * vfloat<W>(offset);
}

}  // namespace igi
