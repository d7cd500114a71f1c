#pragma once
/// \file
/// The default surface shader: glTF metallic-roughness materials (factors; base-colour, emissive
/// and specular-colour textures with sRGB decode, linear metallic-roughness, normal and specular
/// textures, read trilinearly from mip chains at the hit's footprint; alpha-mask cut-outs;
/// transmission; KHR_materials_specular) mapped onto igi's few BRDF parameters.
///
/// The mapping (per hit, with base = baseColorFactor x base-colour texture, linear):
/// - the dielectric part (weight (1 - metallic) x (1 - transmission)) is glTF's Fresnel mix of
///   a Lambertian base and a specular layer: F = specular x Fresnel(f0), f0 = ((ior - 1) /
///   (ior + 1))^2 x specularColor (4% for glTF's defaults; KHR_materials_specular's factors and
///   textures), albedo = base.rgb x (1 - max(F)); a specular factor of 0 leaves it exactly
///   Lambertian (igi's built-in scenes);
/// - metals reflect Fresnel(base.rgb): in their own colour, whiter towards grazing;
/// - Fresnel is Schlick's at the view's angle to the shading normal, its grazing rise damped by
///   roughness (rough_fresnel); the specular reflectance is metallic x Fresnel(base.rgb) +
///   dielectric weight x F;
/// - metallic and roughness are their factors times the metallic-roughness texture's blue and
///   green channels (linear, read at the footprint as the base colour) where there is one;
/// - roughness r gives the Phong exponent 2 / r^4 - 2 (the Blinn-Phong exponent matching a
///   Beckmann lobe of width alpha = r^2, Walter et al. 2007), at least 1; below
///   `mirror_roughness` the lobe is narrower than VPL lighting can show and the specular part
///   becomes a perfect mirror instead;
/// - transmission t (KHR_materials_transmission) applies to the dielectric part, so the glass
///   weight is t x (1 - metallic), with the ior; diffuse + specular + glass weights then never
///   exceed 1 per channel;
/// - alphaMode MASK: opaque where alpha >= alphaCutoff, the alpha read at the ray's point at full
///   resolution whatever its footprint; BLEND is rendered opaque;
/// - emission = emissiveFactor x strength x emissive texture, on front faces (both faces if
///   the material is double-sided), matching how the light sampler emits;
/// - the normal is the interpolated shading normal, tilted by the normal texture where there is
///   one (normal_mapped). Its tangent frame is the mesh's TANGENT attribute, interpolated,
///   where it has one (as the maps were baked); otherwise each triangle's uvs give it, and on a
///   curved mesh the tilt's direction can then step from triangle to triangle.
/// Each texture is read through its KHR_texture_transform (identity without one). Only TEXCOORD_0
/// reaches shading; a texture on another set is read with TEXCOORD_0 (the loader warns).

#include <algorithm>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/scalar_shader_adapter.hpp"
#include "igi/shading/texture_sampling.hpp"

namespace igi {

/// `chain` read at `point`'s texture coordinates as `transform` maps them (KHR_texture_transform),
/// at the hit's footprint widened alike.
[[gnu::always_inline]] inline glm::vec4 sample_transformed(const TextureMips& chain, const UvTransform& transform,
                                                           const SurfacePoint& point) {
  return sample_filtered(chain, transform.apply(point.uv), point.texture_footprint * transform.footprint_scale());
}

/// The shading normal at `point` tilted by the normal texture `chain` (glTF normalTexture, linear,
/// read through `transform` at the hit's footprint), its x and y scaled by `scale`. The tangent
/// frame: x along dp/du' (u' the transformed coordinate) made perpendicular to the normal, y = normal x tangent turned to point along -dp/dv (glTF's
/// maps have +y up in the image, against v), so mirrored texture coordinates keep the relief. It is
/// built on the front face's normal and the result turned with it on a back face, as glTF flips a
/// double-sided material's normal there. Without a frame (no texture coordinates, or uvs that span
/// no area) or for a texel that gives no direction, the shading normal stays.
[[gnu::always_inline]] inline glm::vec3 normal_mapped(const TextureMips& chain, float scale, const UvTransform& transform,
                                                      const SurfacePoint& point) {
  const float side = point.front_face ? 1.0f : -1.0f;
  const glm::vec3 normal = point.shading_normal * side;
  // (dp/du', dp/dv') = (dp/du, dp/dv) A^-1 for the transform's linear part A.
  const glm::mat2 linear(transform.matrix[0], transform.matrix[1]);
  const float determinant = glm::determinant(linear);
  if (!(determinant != 0.0f) || !std::isfinite(determinant)) return point.shading_normal;
  const glm::mat2 inverse = glm::inverse(linear);
  const glm::vec3 dpdu = point.dpdu * inverse[0].x + point.dpdv * inverse[0].y;
  const glm::vec3 dpdv = point.dpdu * inverse[1].x + point.dpdv * inverse[1].y;
  glm::vec3 tangent = dpdu - normal * glm::dot(normal, dpdu);
  const float tangent_length2 = glm::dot(tangent, tangent);
  if (!(tangent_length2 > 0.0f) || !std::isfinite(tangent_length2)) return point.shading_normal;
  tangent /= std::sqrt(tangent_length2);
  glm::vec3 bitangent = glm::cross(normal, tangent);
  if (glm::dot(bitangent, dpdv) > 0.0f) bitangent = -bitangent;
  const glm::vec4 texel = sample_transformed(chain, transform, point);
  const glm::vec3 tilted = tangent * ((2.0f * texel.x - 1.0f) * scale) + bitangent * ((2.0f * texel.y - 1.0f) * scale) +
                           normal * (2.0f * texel.z - 1.0f);
  const float length2 = glm::dot(tilted, tilted);
  if (!(length2 > 0.0f) || !std::isfinite(length2)) return point.shading_normal;
  return tilted * (side / std::sqrt(length2));
}

/// Schlick's Fresnel reflectance from `f0` at normal incidence, rising towards 1 at grazing, for a
/// view at `cosine` to the shading normal, its rise damped to 1 - `roughness` (Lagarde and de
/// Rousiers, "Moving Frostbite to PBR", 2014). igi multiplies the filtered irradiance of all VPLs
/// by one diffuse reflectance, so the Fresnel weight cannot follow each VPL's half vector: it is
/// taken at the lobe's axis, exact for a mirror and for the peak of a lobe; a rough lobe's light
/// comes mostly from off its peak, where the half vector is steeper and the reflectance lower,
/// hence the damping (a roughness-1 surface keeps f0 at every angle).
[[gnu::always_inline]] inline glm::vec3 rough_fresnel(const glm::vec3& f0, float roughness, float cosine) {
  const float x = 1.0f - std::clamp(cosine, 0.0f, 1.0f);
  const float x2 = x * x;
  return f0 + (glm::max(glm::vec3(1.0f - roughness), f0) - f0) * (x2 * x2 * x);
}

/// Maps one hit on `material` to BRDF parameters (the mapping in this file's comment), its
/// textures read from `mips` (one chain per Scene::textures entry) at the hit's footprint.
// Always inlined into the shader's lane loop, with its texture lookups (see texture_sampling.hpp's mix_texels).
[[gnu::always_inline]] inline ScalarBrdfParameters gltf_material_parameters(std::span<const TextureMips> mips,
                                                                           const Material& material,
                                                                           const SurfacePoint& point,
                                                                           float mirror_roughness) {
  glm::vec4 base = material.base_color;
  if (material.base_color_texture >= 0) {
    const TextureMips& chain = mips[std::size_t(material.base_color_texture)];
    glm::vec4 texture = sample_transformed(chain, material.base_color_transform, point);
    // Cut-outs test the alpha at the ray's point: a filtered alpha would turn distant foliage
    // into solid sheets or nothing by its mean coverage, where point tests keep it on average.
    if (material.alpha_mode == AlphaMode::mask && point.texture_footprint > 0.0f)
      texture.a = sample_bilinear(chain.level(0), material.base_color_transform.apply(point.uv)).a;
    base *= texture;
  }
  float metallic = material.metallic, roughness = material.roughness;
  if (material.metallic_roughness_texture >= 0) {
    const glm::vec4 texture =
        sample_transformed(mips[std::size_t(material.metallic_roughness_texture)], material.metallic_roughness_transform, point);
    roughness *= texture.g;
    metallic *= texture.b;
  }
  metallic = std::clamp(metallic, 0.0f, 1.0f);
  roughness = std::clamp(roughness, 0.0f, 1.0f);
  const float transmission = std::clamp(material.transmission, 0.0f, 1.0f);
  const glm::vec3 color = glm::clamp(glm::vec3(base), glm::vec3(0.0f), glm::vec3(1.0f));

  ScalarBrdfParameters p;
  p.ior = material.ior > 0.0f && std::isfinite(material.ior) ? material.ior : 1.5f;  // glTF's default ior
  p.normal = material.normal_texture >= 0
                 ? normal_mapped(mips[std::size_t(material.normal_texture)], material.normal_scale, material.normal_transform, point)
                 : point.shading_normal;
  const float cosine = glm::dot(p.normal, point.wo);
  const float dielectric = (1.0f - metallic) * (1.0f - transmission);
  // The dielectric part's specular layer (KHR_materials_specular, glTF's defaults without it).
  float specular_weight = dielectric > 0.0f ? material.specular : 0.0f;
  if (specular_weight > 0.0f && material.specular_texture >= 0)
    specular_weight *= sample_transformed(mips[std::size_t(material.specular_texture)], material.specular_transform, point).a;
  specular_weight = std::clamp(specular_weight, 0.0f, 1.0f);
  glm::vec3 specular(0.0f);
  p.albedo = color * dielectric;
  if (specular_weight > 0.0f) {
    glm::vec3 specular_color = material.specular_color;
    if (material.specular_color_texture >= 0)
      specular_color *= glm::vec3(
          sample_transformed(mips[std::size_t(material.specular_color_texture)], material.specular_color_transform, point));
    const float ior_reflectance = (p.ior - 1.0f) * (p.ior - 1.0f) / ((p.ior + 1.0f) * (p.ior + 1.0f));
    const glm::vec3 f0 = glm::clamp(ior_reflectance * specular_color, glm::vec3(0.0f), glm::vec3(1.0f));
    const glm::vec3 fresnel = specular_weight * rough_fresnel(f0, roughness, cosine);
    p.albedo *= 1.0f - std::max(fresnel.x, std::max(fresnel.y, fresnel.z));
    specular = fresnel * dielectric;
  }
  if (metallic > 0.0f) specular += rough_fresnel(color, roughness, cosine) * metallic;
  if (roughness < mirror_roughness) {
    p.mirror = specular;
  } else {
    p.glossy = specular;
    const float alpha = roughness * roughness;
    // Exponents above 1e4 are already mirror-like; the cap keeps pow() well away from overflow.
    p.shininess = std::clamp(2.0f / (alpha * alpha) - 2.0f, 1.0f, 1e4f);
  }
  p.transmission = transmission * (1.0f - metallic);
  if (point.front_face || material.double_sided) {
    p.emission = material.emission;
    if (material.emissive_texture >= 0)
      p.emission *= glm::vec3(sample_transformed(mips[std::size_t(material.emissive_texture)], material.emissive_transform, point));
  }
  p.opaque = material.alpha_mode != AlphaMode::mask || base.a >= material.alpha_cutoff;
  return p;
}

/// Surface shader for glTF materials: factors and textures of the hit's material.
class GltfMaterialShader {
 public:
  /// Roughness below which the specular lobe is a perfect mirror: 0.1 gives a Phong exponent
  /// of 2e4, whose lobe (about 1 degree wide) no VPL-lit image can tell from a mirror.
  static constexpr float default_mirror_roughness = 0.1f;

  /// Shades hits on `scene` (kept by reference: it must outlive the shader), with a mip chain of
  /// every texture (built here, a third more texture memory, shared by copies). Throws
  /// std::invalid_argument if a material refers to a texture the scene lacks.
  explicit GltfMaterialShader(const Scene& scene, float mirror_roughness = default_mirror_roughness)
      : scene_(&scene), mirror_roughness_(mirror_roughness) {
    for (const Material& m : scene.materials) {
      for (const int texture : m.textures())
        if (texture >= int(scene.textures.size()))
          throw std::invalid_argument("GltfMaterialShader: material '" + m.name + "' uses texture " +
                                      std::to_string(texture) + " but the scene has " +
                                      std::to_string(scene.textures.size()));
    }
    // The textures' mip chains (each level's rows on oneTBB's threads), shared by the shader's copies.
    auto mips = std::make_shared<std::vector<TextureMips>>();
    mips->reserve(scene.textures.size());
    for (const Texture& texture : scene.textures) mips->emplace_back(texture);
    mips_ = std::move(mips);
  }
  /// Policy name.
  static constexpr const char* name() noexcept { return "gltf"; }

  /// BRDF parameters of the lanes of `mask`; other lanes zero. Throws std::out_of_range for a
  /// material or mesh index the scene lacks.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const {
    BrdfParameters<W> parameters;
    for (int i = 0; i < W; ++i) {
      if (!mask[i]) continue;
      const SurfacePoint point = surface_point(hit, i);
      set_lane(parameters, i, gltf_material_parameters(*mips_, material(point), point, mirror_roughness_),
               point.shading_normal);
    }
    return parameters;
  }

  /// Whether a shadow ray's candidate on an alpha cut-out is opaque: shade()'s alpha test alone
  /// (base colour factor's alpha times the texture's at full resolution, against alphaCutoff),
  /// at the candidate's texture coordinates interpolated as make_surface_hit does, for
  /// test_cutouts_with. Throws std::out_of_range for ids the scene lacks.
  bool opaque_at(const OcclusionCandidate& candidate) const {
    if (candidate.mesh >= scene_->meshes.size() || candidate.primitive >= scene_->meshes[candidate.mesh].triangles.size())
      throw std::out_of_range("GltfMaterialShader: triangle " + std::to_string(candidate.primitive) + " of mesh " +
                              std::to_string(candidate.mesh) + " is not in the scene");
    const Mesh& mesh = scene_->meshes[candidate.mesh];
    if (mesh.material >= int(scene_->materials.size()))
      throw std::out_of_range("GltfMaterialShader: material " + std::to_string(mesh.material) + " is not in the scene");
    const Material& material = scene_->material_of(int(candidate.mesh));
    if (material.alpha_mode != AlphaMode::mask) return true;
    float alpha = material.base_color.a;
    if (material.base_color_texture >= 0) {
      glm::vec2 uv(0.0f);
      const glm::uvec3 triangle = mesh.triangles[candidate.primitive];
      if (mesh.uvs.size() == mesh.positions.size() && triangle.x < mesh.uvs.size() && triangle.y < mesh.uvs.size() &&
          triangle.z < mesh.uvs.size()) {
        const float b1 = candidate.u, b2 = candidate.v, b0 = 1.0f - b1 - b2;
        uv = b0 * mesh.uvs[triangle.x] + b1 * mesh.uvs[triangle.y] + b2 * mesh.uvs[triangle.z];
      }
      alpha *= sample_bilinear((*mips_)[std::size_t(material.base_color_texture)].level(0), material.base_color_transform.apply(uv)).a;
    }
    return alpha >= material.alpha_cutoff;
  }

 private:
  const Material& material(const SurfacePoint& point) const {
    if (point.material >= int(scene_->materials.size()))
      throw std::out_of_range("GltfMaterialShader: material " + std::to_string(point.material) +
                              " is not in the scene");
    if (point.material >= 0) return scene_->materials[std::size_t(point.material)];
    if (point.mesh < 0 || point.mesh >= int(scene_->meshes.size()))
      throw std::out_of_range("GltfMaterialShader: mesh " + std::to_string(point.mesh) + " is not in the scene");
    return scene_->material_of(point.mesh);
  }

  const Scene* scene_;
  std::shared_ptr<const std::vector<TextureMips>> mips_;  ///< Per scene texture, its mip chain.
  float mirror_roughness_;
};

}  // namespace igi
