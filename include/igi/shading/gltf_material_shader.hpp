#pragma once
/// \file
/// The default surface shader: glTF metallic-roughness materials (factors; base-colour, emissive
/// and specular-colour textures with sRGB decode, linear metallic-roughness, normal and specular
/// textures, read trilinearly from mip chains at the hit's footprint; alpha-mask cut-outs;
/// transmission; KHR_materials_specular and _clearcoat) mapped onto igi's few BRDF parameters.
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
///   exceed 1 per channel. Without KHR_materials_volume (thickness 0) it is thin-walled, as
///   glTF defines it: light passes straight through, tinted by the base colour; with a
///   thickness the mesh bounds a solid that refracts;
/// - alphaMode MASK: opaque where alpha >= alphaCutoff, the alpha read at the ray's point at full
///   resolution whatever its footprint; BLEND: the surface does alpha's share of everything
///   (reflection, transmission, emission) and passes 1 - alpha straight on (pass_through);
/// - KHR_materials_clearcoat: a clear coat over all of it (add_clearcoat);
/// - emission = emissiveFactor x strength x emissive texture, on front faces (both faces if
///   the material is double-sided), matching how the light sampler emits;
/// - the normal is the interpolated shading normal, tilted by the normal texture where there is
///   one (normal_mapped). Its tangent frame is the mesh's TANGENT attribute, interpolated,
///   where it has one (as the maps were baked); otherwise each triangle's uvs give it, and on a
///   curved mesh the tilt's direction can then step from triangle to triangle.
/// Each texture is read through its KHR_texture_transform (identity without one). Only TEXCOORD_0
/// reaches shading; a texture on another set is read with TEXCOORD_0 (the loader warns).
///
/// The shader works on packets: the lanes on one material are shaded together (a packet of
/// neighbouring pixels mostly holds one or two materials), each lane reading its own mip levels.

#include <algorithm>
#include <array>
#include <memory>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/surface_hit.hpp"
#include "igi/shading/texture_sampling.hpp"

namespace igi {

/// The hit's texture coordinates (u, v) as `transform` maps them (KHR_texture_transform).
template <int W>
[[gnu::always_inline]] inline std::array<vfloat<W>, 2> transformed_uv(const UvTransform& transform,
                                                                      const SurfaceHit<W>& hit) noexcept {
  const glm::mat3x2& m = transform.matrix;
  return {vfloat<W>(m[0].x) * hit.u + vfloat<W>(m[1].x) * hit.v + vfloat<W>(m[2].x),
          vfloat<W>(m[0].y) * hit.u + vfloat<W>(m[1].y) * hit.v + vfloat<W>(m[2].y)};
}

/// `chain` read at the hit's texture coordinates as `transform` maps them (KHR_texture_transform),
/// at the hit's footprint widened alike, on the lanes of `mask` (zero elsewhere).
template <int W>
inline TexelPacket<W> sample_transformed(const TextureMips& chain, const UvTransform& transform, const SurfaceHit<W>& hit,
                                         const vmask<W>& mask) noexcept {
  const auto [u, v] = transformed_uv(transform, hit);
  return sample_filtered(chain, u, v, hit.texture_footprint * vfloat<W>(transform.footprint_scale()), mask);
}

/// The shading normal tilted by the normal texture `chain` (glTF normalTexture, linear, read
/// through `transform` at the hit's footprint), its x and y scaled by `scale`, on the lanes of
/// `mask`. The tangent frame: x along dp/du' (u' the transformed coordinate) made perpendicular
/// to the normal, y = normal x tangent turned to point along -dp/dv (glTF's maps have +y up in
/// the image, against v), so mirrored texture coordinates keep the relief. It is built on the
/// front face's normal and the result turned with it on a back face, as glTF flips a
/// double-sided material's normal there. Without a frame (no texture coordinates, or uvs that
/// span no area) or for a texel that gives no direction, the shading normal stays.
template <int W>
inline vec3<W> normal_mapped(const TextureMips& chain, float scale, const UvTransform& transform, const SurfaceHit<W>& hit,
                             const vmask<W>& mask) noexcept {
  // (dp/du', dp/dv') = (dp/du, dp/dv) A^-1 for the transform's linear part A, one per material.
  const glm::mat2 linear(transform.matrix[0], transform.matrix[1]);
  const float determinant = glm::determinant(linear);
  if (!(determinant != 0.0f) || !std::isfinite(determinant)) return hit.shading_normal;
  const glm::mat2 inverse = glm::inverse(linear);
  const vfloat<W> side = select(hit.front_face, vfloat<W>(1.0f), vfloat<W>(-1.0f));
  const vec3<W> normal = hit.shading_normal * side;
  const vec3<W> dpdu = hit.dpdu * vfloat<W>(inverse[0].x) + hit.dpdv * vfloat<W>(inverse[0].y);
  const vec3<W> dpdv = hit.dpdu * vfloat<W>(inverse[1].x) + hit.dpdv * vfloat<W>(inverse[1].y);
  vec3<W> tangent = dpdu - normal * dot(normal, dpdu);
  const vfloat<W> tangent_length2 = dot(tangent, tangent);
  const vmask<W> framed = mask & (tangent_length2 > vfloat<W>(0.0f)) & isfinite(tangent_length2);
  if (none(framed)) return hit.shading_normal;
  tangent = tangent * (vfloat<W>(1.0f) / sqrt(select(framed, tangent_length2, vfloat<W>(1.0f))));
  vec3<W> bitangent = cross(normal, tangent);
  bitangent = select(dot(bitangent, dpdv) > vfloat<W>(0.0f), -bitangent, bitangent);
  const TexelPacket<W> texel = sample_transformed(chain, transform, hit, framed);
  const vfloat<W> one(1.0f), two(2.0f), scaled(scale);
  const vec3<W> tilted = tangent * ((two * texel.r - one) * scaled) + bitangent * ((two * texel.g - one) * scaled) +
                         normal * (two * texel.b - one);
  const vfloat<W> length2 = dot(tilted, tilted);
  const vmask<W> usable = framed & (length2 > vfloat<W>(0.0f)) & isfinite(length2);
  return select(usable, tilted * (side / sqrt(select(usable, length2, one))), hit.shading_normal);
}

/// Schlick's Fresnel reflectance from `f0` at normal incidence, rising towards 1 at grazing, for a
/// view at `cosine` to the shading normal, its rise damped to 1 - `roughness` (Lagarde and de
/// Rousiers, "Moving Frostbite to PBR", 2014). igi multiplies the filtered irradiance of all VPLs
/// by one diffuse reflectance, so the Fresnel weight cannot follow each VPL's half vector: it is
/// taken at the lobe's axis, exact for a mirror and for the peak of a lobe; a rough lobe's light
/// comes mostly from off its peak, where the half vector is steeper and the reflectance lower,
/// hence the damping (a roughness-1 surface keeps f0 at every angle).
template <int W>
[[gnu::always_inline]] inline vec3<W> rough_fresnel(const vec3<W>& f0, const vfloat<W>& roughness, const vfloat<W>& cosine) noexcept {
  const vfloat<W> x = vfloat<W>(1.0f) - clamp(cosine, vfloat<W>(0.0f), vfloat<W>(1.0f));
  const vfloat<W> x2 = x * x;
  const vfloat<W> smooth = vfloat<W>(1.0f) - roughness;
  return f0 + (max(vec3<W>(smooth, smooth, smooth), f0) - f0) * (x2 * x2 * x);
}

/// `value` limited to [0, 1] per channel.
template <int W>
[[gnu::always_inline]] inline vec3<W> saturate(const vec3<W>& value) noexcept {
  const vfloat<W> zero(0.0f), one(1.0f);
  return {clamp(value.x, zero, one), clamp(value.y, zero, one), clamp(value.z, zero, one)};
}

/// KHR_materials_clearcoat on the lanes of `mask` of `p`, the parameters of what lies below the
/// coat: a clear dielectric (ior 1.5, so f0 = 4%) reflects F = clearcoat x rough_fresnel(f0, coat
/// roughness, the view's cosine to the shading normal: the extension's coat does not take the
/// base's normal map), and everything below it (diffuse, specular, transmitted and emitted light)
/// keeps 1 - F. Below the mirror roughness the coat is a mirror, else it joins the glossy lobe:
/// igi has one glossy lobe per hit, which then takes the exponent of whichever of the two
/// reflects more. (Mirror rays leave along the one normal igi keeps per hit, the base's.)
template <int W>
inline void add_clearcoat(std::span<const TextureMips> mips, const Material& material, const SurfaceHit<W>& hit,
                          const vmask<W>& mask, float mirror_roughness, BrdfParameters<W>& p) {
  const vfloat<W> zero(0.0f), one(1.0f);
  vfloat<W> coat(material.clearcoat);
  if (material.clearcoat_texture >= 0)
    coat = coat * sample_transformed(mips[std::size_t(material.clearcoat_texture)], material.clearcoat_transform, hit, mask).r;
  coat = clamp(coat, zero, one);
  const vmask<W> coated = mask & (coat > zero);
  if (none(coated)) return;
  vfloat<W> roughness(material.clearcoat_roughness);
  if (material.clearcoat_roughness_texture >= 0)
    roughness = roughness * sample_transformed(mips[std::size_t(material.clearcoat_roughness_texture)],
                                               material.clearcoat_roughness_transform, hit, coated)
                                .g;
  roughness = clamp(roughness, zero, one);
  constexpr float coat_f0 = 0.04f;  // ((1.5 - 1) / (1.5 + 1))^2: the extension fixes the coat's ior at 1.5
  const vfloat<W> cosine = dot(hit.shading_normal, hit.wo);
  const vfloat<W> reflected = keep(coat * rough_fresnel(vec3<W>(glm::vec3(coat_f0)), roughness, cosine).x, coated);
  const vfloat<W> below = one - reflected;
  p.albedo *= below;
  p.glossy *= below;
  p.mirror *= below;
  p.emission *= below;
  p.transmission = p.transmission * below;
  const vec3<W> coat_reflection(reflected, reflected, reflected);
  const vmask<W> mirror = roughness < vfloat<W>(mirror_roughness);
  p.mirror += select(mirror, coat_reflection, vec3<W>());
  const vmask<W> glossy = coated & !mirror;
  const vfloat<W> lobe_width = roughness * roughness;
  const vfloat<W> coat_shininess = clamp(vfloat<W>(2.0f) / (lobe_width * lobe_width) - vfloat<W>(2.0f), one, vfloat<W>(1e4f));
  const vfloat<W> base_glossy = max(p.glossy.x, max(p.glossy.y, p.glossy.z));
  p.shininess = select(glossy & (reflected > base_glossy), coat_shininess, p.shininess);
  p.glossy += select(glossy, coat_reflection, vec3<W>());
}

/// Maps the lanes of `mask`, all on `material`, to BRDF parameters (the mapping in this file's
/// comment; other lanes zero), its textures read from `mips` (one chain per Scene::textures entry)
/// at the hits' footprints. The normal is unit: a tilted normal that is zero or not finite
/// falls back to the hit's shading normal.
template <int W>
inline BrdfParameters<W> gltf_material_parameters(std::span<const TextureMips> mips, const Material& material,
                                                  const SurfaceHit<W>& hit, const vmask<W>& mask, float mirror_roughness) {
  const vfloat<W> zero(0.0f), one(1.0f);
  vec3<W> color(glm::vec3(material.base_color));
  vfloat<W> alpha(material.base_color.a);
  if (material.base_color_texture >= 0) {
    const TextureMips& chain = mips[std::size_t(material.base_color_texture)];
    const TexelPacket<W> texture = sample_transformed(chain, material.base_color_transform, hit, mask);
    color = color * texture.rgb();
    vfloat<W> texture_alpha = texture.a;
    // Cut-outs test the alpha at the ray's point: a filtered alpha would turn distant foliage
    // into solid sheets or nothing by its mean coverage, where point tests keep it on average.
    const vmask<W> point_alpha = mask & (hit.texture_footprint > zero);
    if (material.alpha_mode == AlphaMode::mask && any(point_alpha)) {
      const auto [u, v] = transformed_uv(material.base_color_transform, hit);
      texture_alpha = select(point_alpha, sample_bilinear_alpha(chain.level(0), u, v, point_alpha), texture_alpha);
    }
    alpha = alpha * texture_alpha;
  }
  vfloat<W> metallic(material.metallic), roughness(material.roughness);
  if (material.metallic_roughness_texture >= 0) {
    const TexelPacket<W> texture =
        sample_transformed(mips[std::size_t(material.metallic_roughness_texture)], material.metallic_roughness_transform, hit, mask);
    roughness = roughness * texture.g;
    metallic = metallic * texture.b;
  }
  metallic = clamp(metallic, zero, one);
  roughness = clamp(roughness, zero, one);
  const float transmission = std::clamp(material.transmission, 0.0f, 1.0f);
  color = saturate(color);

  BrdfParameters<W> p;
  p.ior = vfloat<W>(material.ior > 0.0f && std::isfinite(material.ior) ? material.ior : 1.5f);  // glTF's default ior
  const vec3<W> normal = material.normal_texture >= 0 ? normal_mapped(mips[std::size_t(material.normal_texture)], material.normal_scale,
                                                                      material.normal_transform, hit, mask)
                                                      : hit.shading_normal;
  const vfloat<W> cosine = dot(normal, hit.wo);
  const vfloat<W> dielectric = (one - metallic) * vfloat<W>(1.0f - transmission);
  // The dielectric part's specular layer (KHR_materials_specular, glTF's defaults without it).
  vfloat<W> specular_weight = select(dielectric > zero, vfloat<W>(material.specular), zero);
  if (material.specular > 0.0f && material.specular_texture >= 0)
    specular_weight = specular_weight * sample_transformed(mips[std::size_t(material.specular_texture)], material.specular_transform,
                                                           hit, mask & (specular_weight > zero))
                                            .a;
  specular_weight = clamp(specular_weight, zero, one);
  vec3<W> specular;
  p.albedo = color * dielectric;
  const vmask<W> layered = mask & (specular_weight > zero);
  if (any(layered)) {
    vec3<W> specular_color(material.specular_color);
    if (material.specular_color_texture >= 0)
      specular_color = specular_color * sample_transformed(mips[std::size_t(material.specular_color_texture)],
                                                           material.specular_color_transform, hit, layered)
                                            .rgb();
    const float ior = p.ior[0];
    const float ior_reflectance = (ior - 1.0f) * (ior - 1.0f) / ((ior + 1.0f) * (ior + 1.0f));
    const vec3<W> f0 = saturate(specular_color * vfloat<W>(ior_reflectance));
    const vec3<W> fresnel = rough_fresnel(f0, roughness, cosine) * specular_weight;
    // Zero where the weight is: albedo and specular stay as they are on those lanes.
    p.albedo *= one - max(fresnel.x, max(fresnel.y, fresnel.z));
    specular = fresnel * dielectric;
  }
  if (any(mask & (metallic > zero))) specular += rough_fresnel(color, roughness, cosine) * metallic;
  const vmask<W> mirror = roughness < vfloat<W>(mirror_roughness);
  p.mirror = select(mirror, specular, vec3<W>());
  p.glossy = select(mirror, vec3<W>(), specular);
  const vfloat<W> lobe_width = roughness * roughness;
  // Exponents above 1e4 are already mirror-like; the cap keeps pow() well away from overflow.
  p.shininess = select(mirror, one, clamp(vfloat<W>(2.0f) / (lobe_width * lobe_width) - vfloat<W>(2.0f), one, vfloat<W>(1e4f)));
  p.transmission = vfloat<W>(transmission) * (one - metallic);
  const vmask<W> emitting = material.double_sided ? mask : mask & hit.front_face;
  if (any(emitting)) {
    vec3<W> emission(material.emission);
    if (material.emissive_texture >= 0)
      emission = emission * sample_transformed(mips[std::size_t(material.emissive_texture)], material.emissive_transform, hit, emitting).rgb();
    p.emission = select(emitting, emission, vec3<W>());
  }
  if (material.clearcoat > 0.0f) add_clearcoat(mips, material, hit, mask, mirror_roughness, p);
  if (material.thin_walled()) {
    p.thin_walled = mask;
    p.transmission_tint = color;  // glTF tints transmitted light by the base colour
  }
  if (material.alpha_mode == AlphaMode::blend) {
    // Compositing "over" what lies behind: alpha's share of everything the surface does, the rest passes on.
    const vfloat<W> coverage = clamp(alpha, zero, one);
    p.albedo *= coverage;
    p.glossy *= coverage;
    p.mirror *= coverage;
    p.emission *= coverage;
    p.transmission = p.transmission * coverage;
    p.pass_through = one - coverage;
  }
  p.opaque = material.alpha_mode != AlphaMode::mask ? mask : mask & (alpha >= vfloat<W>(material.alpha_cutoff));
  // A unit normal for the BRDF shader: the tilted one where it is usable, else the hit's.
  const vfloat<W> length2 = dot(normal, normal);
  const vmask<W> usable = (length2 > zero) & isfinite(length2);
  p.normal = select(usable, normal * (one / sqrt(select(usable, length2, one))), hit.shading_normal);
  // Inactive lanes yield zeros.
  BrdfParameters<W> result;
  result.assign(p, mask);
  return result;
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

  /// BRDF parameters of the lanes of `mask`; other lanes zero. Lanes on one material are shaded
  /// together, a packet per material it holds. Throws std::out_of_range for a material or mesh
  /// index the scene lacks.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const {
    std::array<const Material*, W> materials{};
    for (int i = 0; i < W; ++i)
      if (mask[i]) materials[std::size_t(i)] = &material(hit.material[i], hit.mesh[i]);
    vmask<W> left = mask;
    BrdfParameters<W> parameters;
    while (any(left)) {
      int first = 0;
      while (!left[first]) ++first;
      const Material* shared = materials[std::size_t(first)];
      vmask<W> same;
      for (int i = first; i < W; ++i) same.set(i, left[i] && materials[std::size_t(i)] == shared);
      const BrdfParameters<W> shaded = gltf_material_parameters(*mips_, *shared, hit, same, mirror_roughness_);
      if (same == mask) return shaded;
      parameters.assign(shaded, same);
      left &= !same;
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
      alpha *= sample_bilinear_alpha((*mips_)[std::size_t(material.base_color_texture)].level(0), material.base_color_transform.apply(uv));
    }
    return alpha >= material.alpha_cutoff;
  }

 private:
  /// The material of a hit on `mesh` whose material index is `index` (-1: the mesh's own).
  const Material& material(int index, int mesh) const {
    if (index >= int(scene_->materials.size()))
      throw std::out_of_range("GltfMaterialShader: material " + std::to_string(index) + " is not in the scene");
    if (index >= 0) return scene_->materials[std::size_t(index)];
    if (mesh < 0 || mesh >= int(scene_->meshes.size()))
      throw std::out_of_range("GltfMaterialShader: mesh " + std::to_string(mesh) + " is not in the scene");
    return scene_->material_of(mesh);
  }

  const Scene* scene_;
  std::shared_ptr<const std::vector<TextureMips>> mips_;  ///< Per scene texture, its mip chain.
  float mirror_roughness_;
};

}  // namespace igi
