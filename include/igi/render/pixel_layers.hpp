#pragma once
/// \file
/// One pixel's shading before composition: what the pipeline's compose step adds into radiance,
/// and what temporal reuse keeps of a frame to reproject into the next one.

#include <glm/glm.hpp>

#include "igi/filters/filter.hpp"
#include "igi/shading/constants.hpp"

namespace igi {

/// A pixel's filtered shading terms and first-hit geometry; radiance() composes them.
struct PixelLayers {
  glm::vec3 irradiance{0.0f};  ///< Filtered VPL irradiance, demodulated (before albedo / pi).
  glm::vec3 glossy{0.0f};      ///< Filtered glossy VPL radiance.
  glm::vec3 albedo{0.0f};      ///< Diffuse albedo of the first hit (after texturing).
  glm::vec3 rest{0.0f};        ///< Radiance not filtered: emission, mirror and glass paths, the background.
  glm::vec3 normal{0.0f};      ///< Unit shading normal of the first hit; zero on a miss.
  float depth = 0.0f;          ///< Distance along sub-sample 0's primary ray to the first hit; 0 on a miss.
  bool hit = false;            ///< Whether sub-sample 0's primary ray hit geometry.
  ShadowBits shadows{};        ///< The delta lights' shadow answers at that hit (what the next frame may reuse).

  /// The pixel's radiance: rest + albedo x irradiance / pi + glossy where the first ray hit, else rest.
  glm::vec3 radiance() const noexcept { return hit ? rest + (albedo * irradiance * inv_pi + glossy) : rest; }
};

}  // namespace igi
