#pragma once
/// \file
/// Scalar surface shading for users who do not want to write packet code: a plain function from
/// one `SurfacePoint` (GLM types) to one `ScalarBrdfParameters`, lifted to packets by
/// `ScalarShaderAdapter<F>`, which calls it once per active lane.

#include <cmath>
#include <concepts>
#include <type_traits>
#include <utility>

#include <glm/glm.hpp>

#include "igi/shading/surface_hit.hpp"
#include "igi/shading/surface_shader.hpp"

namespace igi {

/// One hit point in world space, the scalar view of one lane of a SurfaceHit.
struct SurfacePoint {
  glm::vec3 position{0.0f};          ///< World-space hit point.
  glm::vec3 geometric_normal{0.0f};  ///< Unit triangle normal facing the ray.
  glm::vec3 shading_normal{0.0f};    ///< Unit interpolated normal, in the geometric hemisphere.
  glm::vec3 wo{0.0f};                ///< Unit direction back towards the ray origin.
  glm::vec2 uv{0.0f};                ///< TEXCOORD_0.
  glm::vec3 dpdu{0.0f};              ///< World-space derivative of the position along u (0 without texture coordinates).
  glm::vec3 dpdv{0.0f};              ///< World-space derivative of the position along v.
  float texture_footprint = 0.0f;    ///< SurfaceHit::texture_footprint: the ray's footprint in texture coordinates (0: full resolution).
  float distance = 0.0f;             ///< Distance from the ray origin.
  int material = -1;                 ///< Index into Scene::materials, -1 for the default.
  int mesh = 0;                      ///< Index into Scene::meshes.
  int instance = 0;                  ///< Index into Scene::instances.
  int triangle = 0;                  ///< Triangle within the mesh.
  bool front_face = true;            ///< True on the side the triangle's winding faces.
};

/// One lane of BrdfParameters in GLM types; defaults describe a grey Lambertian surface.
struct ScalarBrdfParameters {
  glm::vec3 albedo{0.8f};       ///< Diffuse reflectance (0.8: a common "white paint").
  glm::vec3 glossy{0.0f};       ///< Phong-lobe reflectance.
  float shininess = 1.0f;       ///< Phong exponent.
  glm::vec3 mirror{0.0f};       ///< Perfect-mirror reflectance.
  float transmission = 0.0f;    ///< Fraction refracted by a dielectric.
  float ior = 1.5f;             ///< Index of refraction (1.5: common glass, glTF's default).
  glm::vec3 normal{0.0f};       ///< Shading normal after bump mapping; zero keeps the hit's shading normal.
  glm::vec3 emission{0.0f};     ///< Emitted radiance.
  bool opaque = true;           ///< False for an alpha cut-out.
};

/// Lane `i` of `hit` as a SurfacePoint.
template <int W>
SurfacePoint surface_point(const SurfaceHit<W>& hit, int i) noexcept {
  return {.position = hit.position[i],
          .geometric_normal = hit.geometric_normal[i],
          .shading_normal = hit.shading_normal[i],
          .wo = hit.wo[i],
          .uv = {hit.u[i], hit.v[i]},
          .dpdu = hit.dpdu[i],
          .dpdv = hit.dpdv[i],
          .texture_footprint = hit.texture_footprint[i],
          .distance = hit.distance[i],
          .material = hit.material[i],
          .mesh = hit.mesh[i],
          .instance = hit.instance[i],
          .triangle = hit.triangle[i],
          .front_face = hit.front_face[i]};
}

/// Writes `value` into lane `i` of `parameters`; a zero or non-finite normal becomes
/// `fallback_normal`, other normals are normalised, so the BRDF shader always gets a unit normal.
template <int W>
void set_lane(BrdfParameters<W>& parameters, int i, const ScalarBrdfParameters& value,
              const glm::vec3& fallback_normal) noexcept {
  parameters.albedo.set(i, value.albedo);
  parameters.glossy.set(i, value.glossy);
  parameters.shininess.set(i, value.shininess);
  parameters.mirror.set(i, value.mirror);
  parameters.transmission.set(i, value.transmission);
  parameters.ior.set(i, value.ior);
  const float length2 = glm::dot(value.normal, value.normal);
  const bool usable = length2 > 0.0f && std::isfinite(length2);
  parameters.normal.set(i, usable ? value.normal / std::sqrt(length2) : fallback_normal);
  parameters.emission.set(i, value.emission);
  parameters.opaque.set(i, value.opaque);
}

/// True for a callable that maps a SurfacePoint to ScalarBrdfParameters.
template <class F>
concept ScalarSurfaceFunction = std::regular_invocable<const F&, const SurfacePoint&> &&
                                std::convertible_to<std::invoke_result_t<const F&, const SurfacePoint&>, ScalarBrdfParameters>;

/// Lifts a scalar surface function to a packet SurfaceShader by calling it on each active lane.
template <ScalarSurfaceFunction F>
class ScalarShaderAdapter {
 public:
  /// Wraps `function`.
  explicit ScalarShaderAdapter(F function) : function_(std::move(function)) {}
  /// Policy name.
  static constexpr const char* name() noexcept { return "scalar-adapter"; }
  /// Calls the function on each lane of `mask`; other lanes are zero.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const {
    BrdfParameters<W> parameters;
    for (int i = 0; i < W; ++i)
      if (mask[i]) set_lane(parameters, i, ScalarBrdfParameters(function_(surface_point(hit, i))), hit.shading_normal[i]);
    return parameters;
  }

 private:
  F function_;
};

}  // namespace igi
