#pragma once
/// \file
/// Constants the shading, lighting and rendering layers share, each defined once here.

#include <numbers>

namespace igi {

/// 1/pi as a float: the normalisation of the diffuse (Lambert) BRDF, albedo/pi.
inline constexpr float inv_pi = std::numbers::inv_pi_v<float>;

/// Most alpha cut-out layers one ray passes through before the pipeline, the path tracer and the
/// VPL walks give up on it: Sponza's foliage stacks a few, so 16 is far more than any pixel needs
/// and bounds the loop.
inline constexpr int max_cutout_layers = 16;

}  // namespace igi
