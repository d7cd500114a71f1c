#pragma once
/// \file
/// The scene model: what glTF 2.0 holds that rendering needs, and no more. Meshes are single
/// glTF primitives (one material each), placed by instances with 4x4 transforms; lights are
/// glTF punctual lights plus the emissive triangles of the meshes (found by the lighting layer),
/// and an environment around it all (a sky: environment.hpp).

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "igi/scene/environment.hpp"

namespace igi {

/// A decoded 8-bit RGBA image, decoded once at load time.
struct Texture {
  std::string name{};                ///< File name or glTF image name, for messages.
  int width = 0;                     ///< Texels per row.
  int height = 0;                    ///< Rows.
  std::vector<std::uint8_t> texels{}; ///< RGBA8, row-major, top row first (glTF's uv origin).
  bool srgb = true;                  ///< True if texels are sRGB-encoded (base colour, emission), false if linear (metallic-roughness, normals).
};

/// A texture's glTF KHR_texture_transform: uv' = offset + rotation x scale x uv, as a 2 x 3
/// matrix (identity by default, which is the texture's own coordinates).
struct UvTransform {
  glm::mat3x2 matrix{1.0f};  ///< Columns: the images of u and v, then the offset.

  /// The extension's transform: scale, then rotate by `rotation` radians (u towards -v), then offset.
  static UvTransform from(const glm::vec2& offset, float rotation, const glm::vec2& scale) noexcept {
    const float c = std::cos(rotation), s = std::sin(rotation);
    return {glm::mat3x2(glm::vec2(c * scale.x, -s * scale.x), glm::vec2(s * scale.y, c * scale.y), offset)};
  }
  /// `uv` transformed.
  glm::vec2 apply(const glm::vec2& uv) const noexcept { return matrix * glm::vec3(uv, 1.0f); }
  /// The factor by which it widens a footprint: the square root of its area scale.
  float footprint_scale() const noexcept {
    return std::sqrt(std::abs(matrix[0].x * matrix[1].y - matrix[0].y * matrix[1].x));
  }
};

/// How a material's alpha is used (glTF `alphaMode`).
enum class AlphaMode { opaque, mask, blend };

/// A glTF metallic-roughness material with the extensions igi renders.
struct Material {
  std::string name{};                                  ///< For messages.
  glm::vec4 base_color{1.0f};                          ///< Linear RGBA factor.
  int base_color_texture = -1;                         ///< Index into Scene::textures, or -1.
  int base_color_uv_set = 0;                           ///< TEXCOORD_n used by that texture.
  UvTransform base_color_transform{};                  ///< That texture's KHR_texture_transform (also the alpha cut-outs').
  float metallic = 1.0f;                               ///< glTF default 1.
  float roughness = 1.0f;                              ///< glTF default 1.
  /// glTF metallicRoughnessTexture: index into Scene::textures (linear, not sRGB), or -1. Its
  /// green channel scales `roughness`, its blue channel `metallic`.
  int metallic_roughness_texture = -1;
  UvTransform metallic_roughness_transform{}; ///< That texture's KHR_texture_transform.
  /// glTF normalTexture: index into Scene::textures (linear), or -1. Tangent-space normals: x
  /// along increasing u, y along decreasing v (the image's up), z along the shading normal.
  int normal_texture = -1;
  /// glTF normalTexture.scale: scales the map's x and y (0 leaves the normal as it is).
  float normal_scale = 1.0f;
  UvTransform normal_transform{}; ///< That texture's KHR_texture_transform (its tangent frame follows it).
  glm::vec3 emission{0.0f};                            ///< Emitted radiance: factor x KHR_materials_emissive_strength.
  int emissive_texture = -1;                           ///< Index into Scene::textures, or -1.
  UvTransform emissive_transform{};                    ///< That texture's KHR_texture_transform.
  float transmission = 0.0f;                           ///< KHR_materials_transmission factor.
  float ior = 1.5f;                                    ///< KHR_materials_ior (glTF default 1.5).
  /// KHR_materials_volume thicknessFactor: 0 (glTF's default, and without the extension) makes
  /// the transmission thin-walled, a sheet light passes straight through; above 0 the mesh
  /// bounds a solid that refracts.
  float thickness = 0.0f;
  /// KHR_materials_volume attenuationDistance: how far light travels in the solid before
  /// attenuation_color is left of it (infinite: no absorption). Parsed; igi's glass does not absorb.
  float attenuation_distance = std::numeric_limits<float>::infinity();
  glm::vec3 attenuation_color{1.0f};  ///< KHR_materials_volume attenuationColor (linear).
  /// KHR_materials_specular specularFactor: scales the dielectric part's specular reflection (its
  /// Fresnel reflectance at normal and grazing incidence). glTF's default 1 gives every
  /// non-metal the 4% reflection of ior 1.5; 0 makes it exactly Lambertian (igi's built-in
  /// scenes, whose measured reflectances are diffuse).
  float specular = 1.0f;
  /// specularTexture: index into Scene::textures (linear; its alpha scales `specular`), or -1.
  int specular_texture = -1;
  UvTransform specular_transform{};      ///< That texture's KHR_texture_transform.
  glm::vec3 specular_color{1.0f};        ///< specularColorFactor: tints the normal-incidence reflectance (linear).
  /// specularColorTexture: index into Scene::textures (sRGB; its rgb scales `specular_color`), or -1.
  int specular_color_texture = -1;
  UvTransform specular_color_transform{}; ///< That texture's KHR_texture_transform.
  /// KHR_materials_clearcoat clearcoatFactor: the weight of a clear, colourless dielectric coat
  /// (ior 1.5) over the whole material, lacquer or varnish; 0 (glTF's default) is no coat.
  float clearcoat = 0.0f;
  /// clearcoatTexture: index into Scene::textures (linear; its red channel scales `clearcoat`), or -1.
  int clearcoat_texture = -1;
  UvTransform clearcoat_transform{};  ///< That texture's KHR_texture_transform.
  float clearcoat_roughness = 0.0f;   ///< clearcoatRoughnessFactor: the coat's roughness (glTF default 0).
  /// clearcoatRoughnessTexture: index into Scene::textures (linear; its green channel scales
  /// `clearcoat_roughness`), or -1.
  int clearcoat_roughness_texture = -1;
  UvTransform clearcoat_roughness_transform{}; ///< That texture's KHR_texture_transform.
  AlphaMode alpha_mode = AlphaMode::opaque;            ///< glTF alphaMode.
  float alpha_cutoff = 0.5f;                           ///< glTF default 0.5.
  bool double_sided = false;                           ///< glTF doubleSided.
  /// Every texture slot's index into Scene::textures (-1 where the slot is empty).
  std::array<int, 8> textures() const noexcept {
    return {base_color_texture, emissive_texture,       metallic_roughness_texture, normal_texture,
            specular_texture,   specular_color_texture, clearcoat_texture,          clearcoat_roughness_texture};
  }
  /// Every texture slot's KHR_texture_transform.
  std::array<const UvTransform*, 8> transforms() const noexcept {
    return {&base_color_transform, &emissive_transform,       &metallic_roughness_transform, &normal_transform,
            &specular_transform,   &specular_color_transform, &clearcoat_transform,          &clearcoat_roughness_transform};
  }
  /// True if its transmission is glTF's thin-walled kind: some, and no volume (thickness 0), or
  /// alpha-blended (a blended surface is a sheet whatever its thickness).
  bool thin_walled() const noexcept { return transmission > 0.0f && (!(thickness > 0.0f) || alpha_mode == AlphaMode::blend); }
  /// True if light passes the surface straight on in part: thin-walled transmission or alphaMode BLEND.
  bool see_through() const noexcept { return thin_walled() || alpha_mode == AlphaMode::blend; }
  /// True if the material emits light.
  bool emissive() const noexcept { return emission.x > 0.0f || emission.y > 0.0f || emission.z > 0.0f; }
};

/// An indexed triangle mesh in object space with one material (one glTF primitive).
struct Mesh {
  std::string name{};                      ///< glTF mesh name (with primitive index if several).
  std::vector<glm::vec3> positions{};      ///< Vertex positions.
  std::vector<glm::vec3> normals{};        ///< Unit vertex normals (computed when the file has none).
  std::vector<glm::vec2> uvs{};            ///< TEXCOORD_0, empty if absent.
  std::vector<glm::vec2> uvs1{};           ///< TEXCOORD_1, empty if absent (for materials with uv set 1).
  /// glTF TANGENT, empty if absent: a unit tangent along increasing u in xyz and in w the sign (+-1)
  /// of the bitangent cross(normal, tangent), which runs along increasing v's image +y of a normal
  /// map; all zero for a vertex whose tangent was unusable (normal maps then take the uv frame).
  std::vector<glm::vec4> tangents{};
  std::vector<glm::uvec3> triangles{};     ///< Vertex indices, counter-clockwise front faces.
  int material = -1;                       ///< Index into Scene::materials, or -1 for the default.
};

/// A placement of a mesh in the world.
struct Instance {
  std::string name{};                ///< glTF node name.
  int mesh = 0;                      ///< Index into Scene::meshes.
  glm::mat4 transform{1.0f};         ///< Object to world.
};

/// Kinds of glTF KHR_lights_punctual lights.
enum class PunctualKind { point, spot, directional };

/// A KHR_lights_punctual light in world space. Photometric glTF units are read as radiometric:
/// point and spot intensity is radiant intensity (W/sr), directional intensity is irradiance (W/m^2).
struct PunctualLight {
  std::string name{};                  ///< glTF light name.
  PunctualKind kind = PunctualKind::point;  ///< point, spot or directional.
  glm::vec3 color{1.0f};               ///< Linear RGB.
  float intensity = 1.0f;              ///< Scale of color.
  glm::vec3 position{0.0f};            ///< World position (point, spot).
  glm::vec3 direction{0.0f, 0.0f, -1.0f};  ///< Unit world direction the light shines to (spot, directional).
  float range = 0.0f;                  ///< 0 = unlimited.
  float inner_cone = 0.0f;             ///< Spot inner cone angle, radians.
  float outer_cone = 0.7853981634f;    ///< Spot outer cone angle, radians (glTF default pi/4).
  /// Field by field.
  bool operator==(const PunctualLight&) const = default;
};

/// A perspective pinhole camera; looks down its local -Z with +Y up, as in glTF.
struct Camera {
  std::string name{};                ///< glTF camera or node name.
  glm::mat4 camera_to_world{1.0f};   ///< Rigid transform of the camera.
  float yfov = 0.6860488f;           ///< Vertical field of view, radians (39.3077 deg, Cornell's).
  float aspect = 0.0f;               ///< The file's aspectRatio (0: none); frames keep square pixels with yfov, whatever it is.
  float znear = 1e-3f;               ///< Near distance along the view axis.
  /// World-space position of the eye.
  glm::vec3 position() const noexcept { return glm::vec3(camera_to_world[3]); }
};

/// An axis-aligned box.
struct Bounds {
  glm::vec3 lower{std::numeric_limits<float>::infinity()};   ///< Minimum corner.
  glm::vec3 upper{-std::numeric_limits<float>::infinity()};  ///< Maximum corner.
  /// Grows the box to hold `p`.
  void extend(const glm::vec3& p) noexcept {
    lower = glm::min(lower, p);
    upper = glm::max(upper, p);
  }
  /// Grows the box to hold `b`.
  void extend(const Bounds& b) noexcept {
    lower = glm::min(lower, b.lower);
    upper = glm::max(upper, b.upper);
  }
  /// True if nothing was added.
  bool empty() const noexcept { return !(lower.x <= upper.x); }
  /// Centre point.
  glm::vec3 center() const noexcept { return 0.5f * (lower + upper); }
  /// Diagonal vector.
  glm::vec3 extent() const noexcept { return upper - lower; }
};

/// The bounds of `points`.
inline Bounds bounds_of(std::span<const glm::vec3> points) noexcept {
  Bounds box;
  for (const glm::vec3& p : points) box.extend(p);
  return box;
}

/// The object-space bounds of `mesh`'s vertices.
inline Bounds mesh_bounds(const Mesh& mesh) noexcept { return bounds_of(mesh.positions); }

/// The world box of an object-space `box` placed by `transform`: its eight corners transformed
/// and bounded. It holds every point of the box. For translations and scales it equals the
/// bounds of the transformed vertices bit for bit (their coordinates transform monotonically and
/// the box's corners are vertices' coordinates); under a rotation it is looser, by at most the
/// box of the rotated box. It costs the same for a mesh of any size, which is what lets a frame
/// that moves every instance keep its set-up independent of the triangle count.
inline Bounds placed(const Bounds& box, const glm::mat4& transform) noexcept {
  Bounds world;
  if (box.empty()) return world;
  for (int corner = 0; corner < 8; ++corner) {
    const glm::vec3 p((corner & 1) ? box.upper.x : box.lower.x, (corner & 2) ? box.upper.y : box.lower.y,
                      (corner & 4) ? box.upper.z : box.lower.z);
    world.extend(glm::vec3(transform * glm::vec4(p, 1.0f)));
  }
  return world;
}

// Motion as a glTF file describes it: nodes, animations, skins, morph targets (plain data;
// igi/scene/animation_sampling.hpp samples it at a time into SceneChanges).

/// How an animation channel interpolates between its keys (glTF sampler `interpolation`).
enum class Interpolation {
  step,         ///< The value of the last key at or before the time.
  linear,       ///< Linear between keys; rotations by shortest-path spherical interpolation.
  cubic_spline  ///< Cubic Hermite spline with the keys' in- and out-tangents.
};

/// The node property an animation channel drives (glTF channel `target.path`).
enum class AnimatedProperty { translation, rotation, scale, weights };

/// One keyframed property of one node: a glTF channel together with its sampler.
struct AnimationChannel {
  int node = -1;                                     ///< Index into SceneAnimations::nodes.
  AnimatedProperty property = AnimatedProperty::translation;  ///< What it drives.
  Interpolation interpolation = Interpolation::linear;        ///< How it interpolates.
  std::vector<float> times{};                        ///< Key times in seconds, strictly increasing.
  /// Key values, `components` floats per element: one element per key, or three per key with
  /// cubic_spline (in-tangent, value, out-tangent). Rotations are quaternions x, y, z, w.
  std::vector<float> values{};
  int components = 3;                                ///< 3 (translation, scale), 4 (rotation) or the morph target count.
};

/// A glTF animation: channels played together.
struct NodeAnimation {
  std::string name{};                      ///< glTF name, or "animation N".
  std::vector<AnimationChannel> channels{}; ///< Its channels.
  float duration = 0.0f;                   ///< Time of its last key over all channels (it starts at time 0).
};

/// A glTF node as animations see it: its rest transform and place in the hierarchy.
struct SceneNode {
  std::string name{};                      ///< glTF name, or "node N".
  int parent = -1;                         ///< Index of its parent, -1 for a root.
  glm::vec3 translation{0.0f};             ///< Rest translation.
  glm::vec4 rotation{0.0f, 0.0f, 0.0f, 1.0f};  ///< Rest rotation: a unit quaternion x, y, z, w, as glTF stores it.
  glm::vec3 scale{1.0f};                   ///< Rest scale.
  /// True if the file gave a `matrix` (then `matrix` is the local transform and no channel may move it).
  bool uses_matrix = false;
  glm::mat4 matrix{1.0f};                  ///< Local transform when uses_matrix.
  std::vector<float> weights{};            ///< Rest morph weights (node.weights, else its mesh's).
};

/// A glTF skin: the joints whose motion deforms a mesh.
struct Skin {
  std::string name{};                            ///< glTF name, or "skin N".
  std::vector<int> joints{};                     ///< Joint nodes; JOINTS_n values index this list.
  std::vector<glm::mat4> inverse_bind_matrices{}; ///< Per joint: mesh space to the joint's space at bind time.
  int skeleton = -1;                             ///< The skeleton's root node (informative), -1 if unnamed.
};

/// A morph target's displacements of a mesh's vertices (empty where the target leaves the attribute alone).
struct MorphTarget {
  std::vector<glm::vec3> positions{}; ///< POSITION displacement per vertex.
  std::vector<glm::vec3> normals{};  ///< NORMAL displacement per vertex.
  std::vector<glm::vec3> tangents{}; ///< TANGENT xyz displacement per vertex.
};

/// A mesh that a skin or morph targets deform: its undeformed vertices and what deforms them.
/// Such a mesh belongs to one instance only, whose node it follows.
struct DeformableMesh {
  int mesh = -1;      ///< Index into Scene::meshes.
  int instance = -1;  ///< Index into Scene::instances of its one instance.
  int node = -1;      ///< The node that holds it (its morph weights; with a skin, its transform is ignored).
  int skin = -1;      ///< Index into SceneAnimations::skins, -1 if only morphed.
  std::vector<glm::vec3> rest_positions{}; ///< Mesh-space positions before morphing and skinning.
  std::vector<glm::vec3> rest_normals{};  ///< Unit normals before deformation.
  std::vector<glm::vec4> rest_tangents{}; ///< Tangents before deformation (empty if the mesh has none).
  /// Joint influences, `influence_sets` entries of four per vertex (JOINTS_0/WEIGHTS_0, then _1):
  /// entry v * influence_sets + s. Empty without a skin.
  std::vector<glm::uvec4> joints{};
  std::vector<glm::vec4> weights{}; ///< Weights matching `joints`, normalized to sum 1 per vertex.
  int influence_sets = 0;          ///< 1 or 2 with a skin, 0 without.
  std::vector<MorphTarget> targets{}; ///< Morph targets, in the file's order.
};

/// Everything about a scene's motion that its file gives (empty for scenes built in code).
struct SceneAnimations {
  std::vector<SceneNode> nodes{};         ///< Every node of the file, by glTF index.
  std::vector<int> node_order{};          ///< Nodes of the rendered scene, each after its parent.
  std::vector<NodeAnimation> animations{}; ///< The file's animations.
  std::vector<Skin> skins{};              ///< The file's skins.
  std::vector<DeformableMesh> deformables{}; ///< Skinned or morphed meshes.
  std::vector<int> instance_nodes{};      ///< Per Scene::instances entry: the node placing it (-1: none).
  std::vector<int> camera_nodes{};        ///< Per Scene::cameras entry: its node (-1: none).
  std::vector<int> light_nodes{};         ///< Per Scene::lights entry: its node (-1: none).

  /// True if nothing ever moves: no animation (deformables at rest are already in the scene).
  bool empty() const noexcept { return animations.empty(); }
};

/// Everything there is to render.
struct Scene {
  std::string name{};                        ///< File name or "cornell".
  std::vector<Mesh> meshes{};                ///< Geometry in object space.
  std::vector<Instance> instances{};         ///< Placements of meshes.
  std::vector<Material> materials{};         ///< Referenced by meshes.
  std::vector<Texture> textures{};           ///< Referenced by materials.
  SceneAnimations animations{};              ///< The file's nodes, animations, skins and deformed meshes (empty for built-in scenes).
  std::vector<PunctualLight> lights{};       ///< KHR_lights_punctual lights.
  std::vector<Camera> cameras{};             ///< Cameras by name, in file order.
  /// Light from infinitely far away (a sky), seen by rays that leave the scene; none if null.
  /// Shared, immutable: copies of a scene share one map and its sampling distribution.
  std::shared_ptr<const Environment> environment{};

  /// Triangles as rendered: every instance counts its mesh's triangles.
  std::size_t triangle_count() const noexcept {
    std::size_t n = 0;
    for (const Instance& instance : instances) n += meshes[std::size_t(instance.mesh)].triangles.size();
    return n;
  }
  /// Triangles stored once per mesh.
  std::size_t unique_triangle_count() const noexcept {
    std::size_t n = 0;
    for (const Mesh& mesh : meshes) n += mesh.triangles.size();
    return n;
  }
  /// World-space bounds of all instances: each instance's mesh box placed by its transform
  /// (`placed`), so they cost O(vertices + instances), not O(instances x vertices); exact where
  /// instances are translated and scaled, a little loose where they are rotated.
  Bounds bounds() const {
    std::vector<Bounds> boxes;
    boxes.reserve(meshes.size());
    for (const Mesh& mesh : meshes) boxes.push_back(mesh_bounds(mesh));
    Bounds b;
    for (const Instance& instance : instances) b.extend(placed(boxes[std::size_t(instance.mesh)], instance.transform));
    return b;
  }
  /// True if something in the scene emits light: a punctual light, an instance of an emissive
  /// material, or an environment that is not black.
  bool has_lights() const noexcept {
    if (!lights.empty() || (environment && environment->emits())) return true;
    for (const Instance& instance : instances)
      if (instance.mesh >= 0 && std::size_t(instance.mesh) < meshes.size() && emits_light(instance.mesh)) return true;
    return false;
  }
  /// Whether `mesh`'s material emits light (moving the mesh moves a light).
  bool emits_light(int mesh) const noexcept { return material_of(mesh).emissive(); }
  /// The material of `mesh`, or a default white diffuse one.
  const Material& material_of(int mesh) const noexcept {
    // glTF's default material is white metal; a grey diffuse surface (albedo 0.8, a common
    // "white paint", no specular layer) is what a user expects of an untextured model such as the bunny.
    static const Material fallback{
        .name = "default", .base_color = glm::vec4(0.8f, 0.8f, 0.8f, 1.0f), .metallic = 0.0f, .specular = 0.0f};
    const int m = meshes[std::size_t(mesh)].material;
    return m >= 0 ? materials[std::size_t(m)] : fallback;
  }
};

/// Lights `scene` with the neutral sky (neutral_sky(scale)) if it has no light of its own, as
/// glTF viewers do for the many files that carry none; returns true if it did.
inline bool light_with_default_sky(Scene& scene, float scale = 1.0f) {
  if (scene.has_lights()) return false;
  scene.environment = std::make_shared<const Environment>(neutral_sky(scale));
  return true;
}

}  // namespace igi
