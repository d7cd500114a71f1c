#pragma once
/// \file
/// Importance sampling of the non-delta lobes of igi's BRDF model, with densities, for the
/// reference path tracer. The model is brdf_shaders.hpp's: a Lambert lobe of reflectance
/// `albedo` and an energy-normalised Phong lobe of reflectance `glossy` and exponent
/// `shininess` around the mirror direction r of wo about the shading normal n. A direction is
/// drawn from one lobe, chosen with probability proportional to its reflectance's largest
/// component; `pdf` is the mixture density over both (one-sample MIS with the balance
/// heuristic across the lobes), so f x cos / pdf is an unbiased estimate whichever lobe drew wi.
///   diffuse: cosine-weighted around n, density cos(theta_n) / pi;
///   glossy:  cos(alpha)^s-weighted around r, density (s + 1) / (2 pi) cos(alpha)^s.
/// Directions below the surface get a density too (the lobes are defined on the sphere); the
/// BRDF evaluates to zero there, which ends the path without bias.

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/glm.hpp>

#include "igi/lighting/lights.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/surface_hit.hpp"

namespace igi {

/// Sampling of the diffuse and glossy lobes at one hit (lane 0 of W = 1 packets).
class DiffuseGlossySampling {
 public:
  /// The lobes of `parameters` at `hit`, with the same shading normal the BRDF shaders use.
  DiffuseGlossySampling(const SurfaceHit<1>& hit, const BrdfParameters<1>& parameters) noexcept {
    normal_ = shading_frame_normal(hit, parameters)[0];
    const glm::vec3 wo = hit.wo[0];
    reflected_ = 2.0f * glm::dot(normal_, wo) * normal_ - wo;
    const float length = glm::length(reflected_);
    reflected_ = length > 0.0f ? reflected_ / length : normal_;
    const float s = parameters.shininess[0];
    // The same sanitising as phong_lobe(): non-finite exponents read as 1, negative as 0.
    shininess_ = std::max(std::isfinite(s) ? s : 1.0f, 0.0f);
    const glm::vec3 albedo = parameters.albedo[0], glossy = parameters.glossy[0];
    const bool opaque = parameters.opaque[0];
    diffuse_weight_ = opaque ? std::max(0.0f, std::max(albedo.x, std::max(albedo.y, albedo.z))) : 0.0f;
    glossy_weight_ = opaque ? std::max(0.0f, std::max(glossy.x, std::max(glossy.y, glossy.z))) : 0.0f;
  }

  /// Sum of the two lobes' largest reflectance components: 0 means there is nothing to sample.
  float weight() const noexcept { return diffuse_weight_ + glossy_weight_; }

  /// A unit direction: `u_lobe` picks the lobe, (u1, u2) the direction in it. Requires weight() > 0.
  glm::vec3 sample(float u_lobe, float u1, float u2) const noexcept {
    if (u_lobe * weight() < diffuse_weight_) return sample_cosine_hemisphere(normal_, u1, u2);
    // cos(alpha) = u1^(1/(s+1)) inverts the CDF of the cos^s lobe around r.
    const float cos_alpha = std::pow(std::max(u1, 0.0f), 1.0f / (shininess_ + 1.0f));
    const float sin_alpha = std::sqrt(std::max(0.0f, 1.0f - cos_alpha * cos_alpha));
    const float phi = 2.0f * std::numbers::pi_v<float> * u2;
    glm::vec3 t1, t2;
    orthonormal_basis(reflected_, t1, t2);
    return glm::normalize(t1 * (sin_alpha * std::cos(phi)) + t2 * (sin_alpha * std::sin(phi)) + reflected_ * cos_alpha);
  }

  /// Mixture density (per steradian) of drawing unit `wi` with `sample`.
  float pdf(const glm::vec3& wi) const noexcept {
    const float total = weight();
    if (!(total > 0.0f)) return 0.0f;
    float density = 0.0f;
    if (diffuse_weight_ > 0.0f)
      density += diffuse_weight_ / total * std::max(glm::dot(normal_, wi), 0.0f) * std::numbers::inv_pi_v<float>;
    if (glossy_weight_ > 0.0f) {
      const float cos_alpha = std::clamp(glm::dot(reflected_, wi), 0.0f, 1.0f);
      density += glossy_weight_ / total * (shininess_ + 1.0f) * 0.5f * std::numbers::inv_pi_v<float> *
                 std::pow(cos_alpha, shininess_);
    }
    return density;
  }

  /// The shading normal the lobes are built on.
  const glm::vec3& normal() const noexcept { return normal_; }

 private:
  glm::vec3 normal_{0.0f, 0.0f, 1.0f}, reflected_{0.0f, 0.0f, 1.0f};
  float shininess_ = 1.0f, diffuse_weight_ = 0.0f, glossy_weight_ = 0.0f;
};

}  // namespace igi
