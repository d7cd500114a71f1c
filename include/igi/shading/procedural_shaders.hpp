#pragma once
/// \file
/// Procedural surface shaders on packets (the paper's Figure 3): a constant diffuse surface and
/// marble, wood and bump-mapped brick patterns built on `perlin_noise`. Patterns are functions of
/// the world-space hit position, so each shader's settings carry a `scale`: the world-space size
/// of one pattern feature (a brick, a ring spacing, a marble band).

#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "igi/shading/noise.hpp"
#include "igi/shading/surface_hit.hpp"

namespace igi {

namespace procedural_detail {

/// BRDF parameters of a plain opaque Lambertian surface with albedo `albedo` on `mask`.
template <int W>
BrdfParameters<W> diffuse_parameters(const SurfaceHit<W>& hit, const vec3<W>& albedo, const vmask<W>& mask) noexcept {
  BrdfParameters<W> p;
  p.albedo = keep(albedo, mask);
  // Neutral values for the unused lobes (zero glossy, mirror and transmission weight).
  p.shininess = keep(vfloat<W>(1.0f), mask);
  p.ior = keep(vfloat<W>(1.0f), mask);
  p.normal = keep(hit.shading_normal, mask);
  p.opaque = mask;
  return p;
}

/// Lane-wise linear blend of two colours by t in [0, 1].
template <int W>
vec3<W> mix(const glm::vec3& a, const glm::vec3& b, const vfloat<W>& t) noexcept {
  return vec3<W>(a) + vec3<W>(b - a) * t;
}

/// Lane-wise fractional part.
template <int W>
vfloat<W> fract(const vfloat<W>& x) noexcept {
  return x - floor(x);
}

/// Hermite step from 0 at `edge0` to 1 at `edge1`.
template <int W>
vfloat<W> smoothstep(float edge0, float edge1, const vfloat<W>& x) noexcept {
  const vfloat<W> t = clamp((x - vfloat<W>(edge0)) / vfloat<W>(edge1 - edge0), vfloat<W>(0.0f), vfloat<W>(1.0f));
  return t * t * (vfloat<W>(3.0f) - vfloat<W>(2.0f) * t);
}

}  // namespace procedural_detail

/// Every hit is Lambertian with one albedo.
class ConstantDiffuseShader {
 public:
  /// Grey 0.8 ("white paint") unless told otherwise; components are clamped to [0, 1].
  explicit ConstantDiffuseShader(const glm::vec3& albedo = glm::vec3(0.8f))
      : albedo_(glm::clamp(albedo, glm::vec3(0.0f), glm::vec3(1.0f))) {}
  /// Policy name.
  static constexpr const char* name() noexcept { return "constant"; }
  /// The albedo on the lanes of `mask`, zeros elsewhere.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const noexcept {
    return procedural_detail::diffuse_parameters(hit, vec3<W>(albedo_), mask);
  }
  /// The albedo every hit gets.
  const glm::vec3& albedo() const noexcept { return albedo_; }

 private:
  glm::vec3 albedo_;
};

/// Looks of MarbleShader.
struct MarbleSettings {
  glm::vec3 stone{0.85f, 0.83f, 0.80f};  ///< Albedo between veins.
  glm::vec3 vein{0.20f, 0.18f, 0.20f};   ///< Albedo in the veins.
  float scale = 0.25f;                   ///< World-space width of one band.
  float distortion = 0.8f;               ///< Turbulence amplitude in bands (0.8: veins wander by most of a band).
  int octaves = 5;                       ///< Turbulence octaves (5: detail down to 1/32 band).
  std::uint32_t seed = 0;                ///< Noise seed.
};

/// Marble: sine bands along x distorted by turbulence, light stone with dark veins.
class MarbleShader {
 public:
  /// Its settings type.
  using Settings = MarbleSettings;
  /// Marble with `settings`.
  explicit MarbleShader(const Settings& settings = {}) : settings_(settings) {}
  /// Policy name.
  static constexpr const char* name() noexcept { return "marble"; }
  /// Marble albedo at the hit positions of `mask`.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const noexcept {
    const vec3<W> p = hit.position * vfloat<W>(1.0f / settings_.scale);
    // Phase in bands: one band per scale along x, shifted by turbulence.
    const vfloat<W> phase = p.x + vfloat<W>(settings_.distortion) * turbulence(p, settings_.octaves, settings_.seed);
    // A smoothed triangle wave (a cheap sine on packets) in [0, 1]; the square root widens the
    // stone and thins the veins.
    const vfloat<W> triangle = abs(vfloat<W>(2.0f) * procedural_detail::fract(phase) - vfloat<W>(1.0f));
    const vfloat<W> band = sqrt(procedural_detail::smoothstep(0.0f, 1.0f, triangle));
    return procedural_detail::diffuse_parameters(hit, procedural_detail::mix(settings_.vein, settings_.stone, band), mask);
  }

 private:
  Settings settings_;
};

/// Looks of WoodShader.
struct WoodSettings {
  glm::vec3 light{0.72f, 0.50f, 0.28f};  ///< Early-wood albedo.
  glm::vec3 dark{0.42f, 0.24f, 0.10f};   ///< Late-wood albedo (the ring lines).
  glm::vec3 center{0.0f};                ///< A point on the trunk axis.
  glm::vec3 axis{0.0f, 1.0f, 0.0f};      ///< Trunk direction (normalised on construction).
  float scale = 0.05f;                   ///< World-space ring spacing.
  float wobble = 0.6f;                   ///< Noise displacement of the rings, in ring spacings.
  std::uint32_t seed = 0;                ///< Noise seed.
};

/// Wood: concentric rings around an axis through `center`, wobbled by noise.
class WoodShader {
 public:
  /// Its settings type.
  using Settings = WoodSettings;
  /// Wood with `settings`; a zero axis becomes +Y.
  explicit WoodShader(const Settings& settings = {}) : settings_(settings) {
    const float length2 = glm::dot(settings_.axis, settings_.axis);
    settings_.axis = length2 > 0.0f ? settings_.axis / std::sqrt(length2) : glm::vec3(0.0f, 1.0f, 0.0f);
  }
  /// Policy name.
  static constexpr const char* name() noexcept { return "wood"; }
  /// Wood albedo at the hit positions of `mask`.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const noexcept {
    const vec3<W> offset = hit.position - vec3<W>(settings_.center);
    const vec3<W> radial = offset - vec3<W>(settings_.axis) * dot(offset, vec3<W>(settings_.axis));
    const vfloat<W> inverse_scale(1.0f / settings_.scale);
    // Noise sampled at 4 rings per unit of noise keeps the wobble smooth across several rings.
    const vfloat<W> noise = fbm(offset * (inverse_scale * vfloat<W>(0.25f)), 3, settings_.seed);
    const vfloat<W> rings = length(radial) * inverse_scale + vfloat<W>(settings_.wobble) * noise;
    // Sharp dark line at the end of each ring: ring position to the 4th power.
    const vfloat<W> t = procedural_detail::fract(rings);
    const vfloat<W> late = t * t * t * t;
    return procedural_detail::diffuse_parameters(hit, procedural_detail::mix(settings_.light, settings_.dark, late), mask);
  }

 private:
  Settings settings_;
};

/// Looks of BrickBumpShader.
struct BrickBumpSettings {
  glm::vec3 brick{0.60f, 0.22f, 0.14f};   ///< Brick albedo.
  glm::vec3 mortar{0.75f, 0.73f, 0.70f};  ///< Mortar albedo.
  float brick_width = 0.2f;               ///< World-space brick length.
  float brick_height = 0.08f;             ///< World-space brick (row) height.
  float mortar_width = 0.012f;            ///< World-space joint width.
  float bump = 1.0f;                      ///< Strength of the normal perturbation (0 = flat).
  std::uint32_t seed = 0;                 ///< Noise seed.
};

/// Bricks with sunken mortar joints: the joint profile and a noisy brick surface perturb the
/// shading normal (bump mapping by the gradient of a height field), as in the paper's Figure 3.
/// Bricks are laid in the plane across the normal's dominant axis, rows along world y where
/// possible, every other row shifted by half a brick.
class BrickBumpShader {
 public:
  /// Its settings type.
  using Settings = BrickBumpSettings;
  /// Bricks with `settings`.
  explicit BrickBumpShader(const Settings& settings = {}) : settings_(settings) {}
  /// Policy name.
  static constexpr const char* name() noexcept { return "brick-bump"; }

  /// Height of the wall surface at `p` (joints low, bricks high and slightly rough), in units
  /// of the joint depth; `s_is_x` / `t_is_y` select the in-plane axes per lane.
  template <int W>
  vfloat<W> height(const vec3<W>& p, const vmask<W>& s_is_x, const vmask<W>& t_is_y) const noexcept {
    const vfloat<W> s = select(s_is_x, p.x, p.z);
    const vfloat<W> t = select(t_is_y, p.y, p.z);
    const vfloat<W> row = floor(t / vfloat<W>(settings_.brick_height));
    // Every other row is shifted by half a brick: (row mod 2) / 2.
    const vfloat<W> shift = vfloat<W>(0.5f) * (row - vfloat<W>(2.0f) * floor(row * vfloat<W>(0.5f)));
    const vfloat<W> fs = procedural_detail::fract(s / vfloat<W>(settings_.brick_width) + shift);
    const vfloat<W> ft = t / vfloat<W>(settings_.brick_height) - row;
    const vfloat<W> to_joint = min(min(fs, vfloat<W>(1.0f) - fs) * vfloat<W>(settings_.brick_width),
                                   min(ft, vfloat<W>(1.0f) - ft) * vfloat<W>(settings_.brick_height));
    // Joints are half a mortar width each side of a brick edge; the rounded brick edge spans the next half width.
    const vfloat<W> profile = procedural_detail::smoothstep(0.5f * settings_.mortar_width, settings_.mortar_width, to_joint);
    // Brick roughness: noise with features of half a brick height, 15% of the joint depth.
    const vfloat<W> rough = vfloat<W>(0.15f) * perlin_noise(p * vfloat<W>(2.0f / settings_.brick_height), settings_.seed);
    return profile * (vfloat<W>(1.0f) + rough);
  }

  /// Brick or mortar albedo and the bump-mapped normal on the lanes of `mask`.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const noexcept {
    const vec3<W>& n = hit.shading_normal;
    const vfloat<W> ax = abs(n.x), ay = abs(n.y), az = abs(n.z);
    // Dominant axis x: bricks in (z, y); dominant y (floors): bricks in (x, z); else (x, y).
    const vmask<W> dominant_x = (ax >= ay) & (ax >= az);
    const vmask<W> dominant_y = (!dominant_x) & (ay >= az);
    const vmask<W> s_is_x = !dominant_x;
    const vmask<W> t_is_y = !dominant_y;

    const vfloat<W> h = height(hit.position, s_is_x, t_is_y);
    // Central differences a fifth of a joint wide resolve the joint profile without aliasing it.
    const float step = 0.2f * settings_.mortar_width;
    const auto difference = [&](const glm::vec3& axis) {
      const vec3<W> delta(axis * step);
      return (height(hit.position + delta, s_is_x, t_is_y) - height(hit.position - delta, s_is_x, t_is_y)) *
             vfloat<W>(1.0f / (2.0f * step));
    };
    const vec3<W> gradient(difference({1, 0, 0}), difference({0, 1, 0}), difference({0, 0, 1}));
    // Height is in joint-depth units over world distance; scaling by the mortar width makes
    // `bump` = 1 tilt the normal by about 45 degrees on the joint flanks.
    const vec3<W> tangential = gradient - n * dot(gradient, n);
    const vec3<W> bumped = normalize(n - tangential * vfloat<W>(settings_.bump * 0.5f * settings_.mortar_width));

    BrdfParameters<W> p = procedural_detail::diffuse_parameters(hit, procedural_detail::mix(settings_.mortar, settings_.brick, clamp(h, vfloat<W>(0.0f), vfloat<W>(1.0f))), mask);
    p.normal = keep(select(length_squared(bumped) > vfloat<W>(0.0f), bumped, n), mask);
    return p;
  }

 private:
  Settings settings_;
};

}  // namespace igi
