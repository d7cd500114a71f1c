#pragma once
/// \file
/// Virtual point lights and the per-packet geometry of connecting hit points to one of them.

#include <cstdint>
#include <limits>
#include <numbers>
#include <vector>

#include <glm/glm.hpp>

#include "igi/simd/simd.hpp"

namespace igi {

/// How a VPL emits.
enum class VplKind : std::uint8_t {
  surface,      ///< Cosine lobe around `normal` (area-light samples and bounce VPLs).
  omni,         ///< Isotropic point light.
  spot,         ///< Point light limited to a cone around `normal`, smooth between the cone angles.
  directional,  ///< Parallel light from direction -`normal`; `position` is unused.
};

/// One virtual point light.
struct Vpl {
  glm::vec3 position{0.0f};   ///< World position.
  glm::vec3 normal{0.0f, 1.0f, 0.0f};  ///< Surface normal (surface), cone axis (spot), or direction light travels (directional).
  glm::vec3 intensity{0.0f};  ///< surface: flux/pi (W/sr along the normal); omni, spot: W/sr; directional: irradiance W/m^2.
  VplKind kind = VplKind::surface;  ///< Emission profile.
  float cos_inner = 1.0f;     ///< Spot: cosine of the inner cone angle (full intensity inside).
  float cos_outer = 0.0f;     ///< Spot: cosine of the outer cone angle (zero outside).
  float radius = 0.0f;        ///< Surface: radius of the sphere its light is spread over for glossy lobes (vpl_spread.hpp); 0 is a point.
};

/// The VPLs of one frame: `sets` interleaving sets (S^2), each an equal share of the walks.
struct VplSets {
  std::vector<std::vector<Vpl>> sets;  ///< sets[s] = VPLs of interleaving set s.
};

/// W receivers connected to one VPL, computed by `connect`.
template <int W>
struct VplGeometry {
  vec3<W> wi;                 ///< Unit direction from receiver to the VPL (or against a directional light).
  vfloat<W> distance;         ///< Distance to the VPL (shadow-ray length); infinity for directional.
  vfloat<W> falloff;          ///< Emitter profile x 1/max(d^2, clamp^2): everything but the receiver's cosine and BRDF.
  vmask<W> reaches;           ///< Lanes the VPL can light at all (in front of both surfaces, inside the cone).
  /// sin^2 of the half-angle the VPL's sphere (Vpl::radius) subtends, r^2 / (d^2 + r^2) so that it
  /// is defined inside the sphere too (1 at its centre); 0 for a point. Glossy lobes widen by it.
  vfloat<W> spread;
  /// The most `falloff` x cos(theta_x) x (a BRDF lobe's value) may be: 1 / (pi clamp^2), what a
  /// head-on Lambertian receiver at the clamp distance takes. The 1/d^2 clamp bounds the diffuse
  /// part by it already; glossy lobes are cut to it, so one VPL adds at most intensity x
  /// (albedo + glossy reflectance) / (pi clamp^2) to a pixel whatever the lobe's sharpness.
  /// Infinite for directional VPLs and a zero clamp (nothing to bound: no 1/d^2 singularity, or
  /// clamping switched off).
  float transfer_limit = std::numeric_limits<float>::infinity();
};

/// Connects W receivers at `position` (with unit `normal`) to `vpl`. `clamp_distance` bounds the
/// 1/d^2 singularity: the bias of instant radiosity, which trades a darkening of concave corners
/// for the absence of fireflies; it also sets `transfer_limit`, the bound of the whole contribution
/// BRDF shaders apply to their glossy lobes. Inactive lanes yield zeros.
template <int W>
VplGeometry<W> connect(const Vpl& vpl, const vec3<W>& position, const vec3<W>& normal, float clamp_distance,
                       const vmask<W>& mask) noexcept {
  VplGeometry<W> g;
  if (vpl.kind == VplKind::directional) {
    g.wi = vec3<W>(-vpl.normal);
    g.distance = vfloat<W>(std::numeric_limits<float>::infinity());
    g.falloff = vfloat<W>(1.0f);
    g.reaches = mask & (dot(normal, g.wi) > vfloat<W>(0.0f));
  } else {
    const vec3<W> to_light = vec3<W>(vpl.position) - position;
    const vfloat<W> d2 = dot(to_light, to_light);
    g.distance = sqrt(d2);
    g.reaches = mask & (d2 > vfloat<W>(0.0f)) & (dot(normal, to_light) > vfloat<W>(0.0f));
    g.wi = to_light * keep(vfloat<W>(1.0f) / select(g.reaches, g.distance, vfloat<W>(1.0f)), g.reaches);
    const vfloat<W> cos_emit = -dot(vec3<W>(vpl.normal), g.wi);
    vfloat<W> profile(1.0f);
    if (vpl.kind == VplKind::surface) {
      profile = cos_emit;
      g.reaches &= cos_emit > vfloat<W>(0.0f);
    } else if (vpl.kind == VplKind::spot) {
      const float width = std::max(vpl.cos_inner - vpl.cos_outer, 1e-6f);  // avoids 0/0 for a hard-edged cone
      const vfloat<W> t = clamp((cos_emit - vfloat<W>(vpl.cos_outer)) / vfloat<W>(width), vfloat<W>(0.0f), vfloat<W>(1.0f));
      profile = t * t;
      g.reaches &= t > vfloat<W>(0.0f);
    }
    if (vpl.radius > 0.0f) {
      const vfloat<W> radius2(vpl.radius * vpl.radius);
      g.spread = radius2 / (d2 + radius2);
    }
    const float clamp2 = clamp_distance * clamp_distance;
    g.falloff = profile / max(d2, vfloat<W>(clamp2));
    if (clamp2 > 0.0f) g.transfer_limit = std::numbers::inv_pi_v<float> / clamp2;
  }
  g.wi = keep(g.wi, g.reaches);
  g.distance = keep(g.distance, g.reaches);
  g.falloff = keep(g.falloff, g.reaches);
  g.spread = keep(g.spread, g.reaches);
  return g;
}

}  // namespace igi
