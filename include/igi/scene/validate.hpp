#pragma once
/// \file
/// Checks on scenes, shared by the glTF loader and by scenes built in code: non-finite values and
/// broken cross references are errors naming the mesh (and vertex, triangle or index); zero-area
/// triangles are recoverable, so they are dropped and counted in a warning.

#include <cmath>
#include <cstddef>
#include <iostream>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include "igi/scene/error.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

namespace detail {

/// Sends `message` to `warnings` when given, else to stderr as one line.
inline void report_warning(std::vector<std::string>* warnings, std::string message) {
  if (warnings != nullptr) {
    warnings->push_back(std::move(message));
  } else {
    std::cerr << "igi warning: " << message << '\n';
  }
}

/// "where: problem", or just the problem when `where` is empty.
inline std::string located(std::string_view where, const std::string& problem) {
  return where.empty() ? problem : std::string(where) + ": " + problem;
}

/// "(x, y, z)" for messages.
inline std::string to_text(const glm::vec3& v) {
  std::ostringstream out;
  out << '(' << v.x << ", " << v.y << ", " << v.z << ')';
  return out.str();
}

/// True if all components are finite.
inline bool finite(const glm::vec3& v) noexcept { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); }

/// True if all 16 entries are finite.
inline bool finite(const glm::mat4& m) noexcept {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(m[c][r])) return false;
  return true;
}

}  // namespace detail

/// True if the triangle spans no area: its edge cross product, computed in double from the stored floats, is exactly zero.
inline bool zero_area(const glm::vec3& a, const glm::vec3& b, const glm::vec3& c) noexcept {
  // Double precision makes the test exact for float inputs up to the product's rounding, so only
  // truly collinear or coincident vertices count; thin but real slivers are kept.
  const glm::dvec3 normal = glm::cross(glm::dvec3(b) - glm::dvec3(a), glm::dvec3(c) - glm::dvec3(a));
  return normal.x == 0.0 && normal.y == 0.0 && normal.z == 0.0;
}

/// Throws SceneError naming the mesh and vertex if a position is NaN or infinite; `where` prefixes the message.
inline void check_positions_finite(const Mesh& mesh, std::string_view where = {}) {
  for (std::size_t v = 0; v < mesh.positions.size(); ++v)
    if (!detail::finite(mesh.positions[v]))
      throw SceneError(detail::located(where, "mesh '" + mesh.name + "' vertex " + std::to_string(v) +
                                                  " has a non-finite position " + detail::to_text(mesh.positions[v])));
}

/// Throws SceneError if the mesh's arrays disagree, a triangle indexes past the vertices, or a normal or uv is not finite.
inline void check_mesh(const Mesh& mesh, std::string_view where = {}) {
  const std::string name = "mesh '" + mesh.name + "'";
  const std::size_t vertex_count = mesh.positions.size();
  if (!mesh.normals.empty() && mesh.normals.size() != vertex_count)
    throw SceneError(detail::located(where, name + " has " + std::to_string(mesh.normals.size()) + " normals for " +
                                                std::to_string(vertex_count) + " vertices"));
  if (!mesh.uvs.empty() && mesh.uvs.size() != vertex_count)
    throw SceneError(detail::located(where, name + " has " + std::to_string(mesh.uvs.size()) + " uvs for " +
                                                std::to_string(vertex_count) + " vertices"));
  if (!mesh.uvs1.empty() && mesh.uvs1.size() != vertex_count)
    throw SceneError(detail::located(where, name + " has " + std::to_string(mesh.uvs1.size()) +
                                                " TEXCOORD_1 uvs for " + std::to_string(vertex_count) + " vertices"));
  if (!mesh.tangents.empty() && mesh.tangents.size() != vertex_count)
    throw SceneError(detail::located(where, name + " has " + std::to_string(mesh.tangents.size()) + " tangents for " +
                                                std::to_string(vertex_count) + " vertices"));
  check_positions_finite(mesh, where);
  for (std::size_t v = 0; v < mesh.normals.size(); ++v)
    if (!detail::finite(mesh.normals[v]))
      throw SceneError(detail::located(where, name + " vertex " + std::to_string(v) + " has a non-finite normal " +
                                                  detail::to_text(mesh.normals[v])));
  for (std::size_t v = 0; v < mesh.uvs.size(); ++v)
    if (!std::isfinite(mesh.uvs[v].x) || !std::isfinite(mesh.uvs[v].y))
      throw SceneError(detail::located(where, name + " vertex " + std::to_string(v) + " has a non-finite uv"));
  for (std::size_t v = 0; v < mesh.tangents.size(); ++v)
    if (!detail::finite(glm::vec3(mesh.tangents[v])) || !std::isfinite(mesh.tangents[v].w))
      throw SceneError(detail::located(where, name + " vertex " + std::to_string(v) + " has a non-finite tangent"));
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int corner = 0; corner < 3; ++corner)
      if (mesh.triangles[t][corner] >= vertex_count)
        throw SceneError(detail::located(
            where, name + " triangle " + std::to_string(t) + " uses vertex " + std::to_string(mesh.triangles[t][corner]) +
                       " but the mesh has " + std::to_string(vertex_count) + " vertices"));
}

/// Removes the zero-area triangles of `mesh` (see zero_area) and returns how many it removed.
inline std::size_t drop_zero_area_triangles(Mesh& mesh) {
  std::size_t kept = 0;
  for (const glm::uvec3& triangle : mesh.triangles)
    if (!zero_area(mesh.positions[triangle.x], mesh.positions[triangle.y], mesh.positions[triangle.z]))
      mesh.triangles[kept++] = triangle;
  const std::size_t dropped = mesh.triangles.size() - kept;
  mesh.triangles.resize(kept);
  return dropped;
}

/// Checks `mesh` (check_mesh) and drops its zero-area triangles with one warning giving their count.
inline void validate_mesh(Mesh& mesh, std::vector<std::string>* warnings = nullptr, std::string_view where = {}) {
  check_mesh(mesh, where);
  if (const std::size_t dropped = drop_zero_area_triangles(mesh); dropped > 0)
    detail::report_warning(warnings, detail::located(where, "mesh '" + mesh.name + "': dropped " +
                                                                std::to_string(dropped) + " zero-area triangle" +
                                                                (dropped == 1 ? "" : "s")));
}

/// Largest world-space coordinate magnitude igi traces: 1e12 keeps every product of three
/// coordinate differences (ray-triangle determinants, a cross product dotted with an edge: up to
/// 3 (2e12)^3 ~ 2.4e37) below float's 3.4e38, so hit distances, squared VPL distances and normals
/// stay finite. Real scenes are many orders of magnitude smaller.
inline constexpr float max_scene_coordinate = 1e12f;

/// The first vertex of `positions` that `transform` places beyond +-max_scene_coordinate, if any.
inline std::optional<std::size_t> first_vertex_beyond_limit(const glm::mat4& transform,
                                                            std::span<const glm::vec3> positions) noexcept {
  for (std::size_t v = 0; v < positions.size(); ++v) {
    const glm::vec3 world(transform * glm::vec4(positions[v], 1.0f));
    if (!glm::all(glm::lessThanEqual(glm::abs(world), glm::vec3(max_scene_coordinate)))) return v;
  }
  return std::nullopt;
}

/// "instance 'I' places mesh 'M' vertex V at (x, y, z), beyond +-1e12, ...": the message of a vertex out of range.
inline std::string beyond_limit_message(const glm::mat4& transform, std::span<const glm::vec3> positions,
                                        std::size_t vertex, std::string_view instance, std::string_view mesh) {
  const glm::vec3 world(transform * glm::vec4(positions[vertex], 1.0f));
  return "instance '" + std::string(instance) + "' places mesh '" + std::string(mesh) + "' vertex " +
         std::to_string(vertex) + " at " + detail::to_text(world) + ", beyond +-1e12, the largest coordinate igi traces";
}

/// Throws SceneError naming the instance, mesh and vertex if a world-space vertex lies beyond +-max_scene_coordinate; instances with a bad mesh index are left to the other checks.
inline void check_scene_extent(const Scene& scene, std::string_view where = {}) {
  for (const Instance& instance : scene.instances) {
    if (instance.mesh < 0 || std::size_t(instance.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
    if (const auto vertex = first_vertex_beyond_limit(instance.transform, mesh.positions))
      throw SceneError(
          detail::located(where, beyond_limit_message(instance.transform, mesh.positions, *vertex, instance.name, mesh.name)));
  }
}

/// Checks a whole scene (meshes, references between its parts, finite transforms, lights and cameras) and drops zero-area triangles with a warning.
inline void validate_scene(Scene& scene, std::vector<std::string>* warnings = nullptr, std::string_view where = {}) {
  const std::string default_where = "scene '" + scene.name + "'";
  if (where.empty()) where = default_where;
  for (Mesh& mesh : scene.meshes) {
    validate_mesh(mesh, warnings, where);
    if (mesh.material < -1 || mesh.material >= int(scene.materials.size()))
      throw SceneError(detail::located(where, "mesh '" + mesh.name + "' uses material " + std::to_string(mesh.material) +
                                                  " but the scene has " + std::to_string(scene.materials.size())));
  }
  for (const Instance& instance : scene.instances) {
    if (instance.mesh < 0 || instance.mesh >= int(scene.meshes.size()))
      throw SceneError(detail::located(where, "instance '" + instance.name + "' uses mesh " + std::to_string(instance.mesh) +
                                                  " but the scene has " + std::to_string(scene.meshes.size())));
    if (!detail::finite(instance.transform))
      throw SceneError(detail::located(where, "instance '" + instance.name + "' has a non-finite transform"));
  }
  check_scene_extent(scene, where);
  for (const Material& material : scene.materials) {
    for (const int texture : material.textures())
      if (texture < -1 || texture >= int(scene.textures.size()))
        throw SceneError(detail::located(where, "material '" + material.name + "' uses texture " + std::to_string(texture) +
                                                    " but the scene has " + std::to_string(scene.textures.size())));
    if (!std::isfinite(material.base_color.r) || !std::isfinite(material.base_color.g) ||
        !std::isfinite(material.base_color.b) || !std::isfinite(material.base_color.a) ||
        !detail::finite(material.emission) || !std::isfinite(material.metallic) || !std::isfinite(material.roughness) ||
        !std::isfinite(material.transmission) || !std::isfinite(material.ior) || !std::isfinite(material.alpha_cutoff) ||
        !std::isfinite(material.normal_scale) || !std::isfinite(material.specular) || !detail::finite(material.specular_color) ||
        !std::isfinite(material.clearcoat) || !std::isfinite(material.clearcoat_roughness))
      throw SceneError(detail::located(where, "material '" + material.name + "' has a non-finite parameter"));
    if (!(material.thickness >= 0.0f) || !std::isfinite(material.thickness) || !(material.attenuation_distance > 0.0f) ||
        !detail::finite(material.attenuation_color))
      throw SceneError(detail::located(where, "material '" + material.name + "' has a negative or non-finite volume thickness, a "
                                                  "non-positive attenuation distance or a non-finite attenuation colour"));
    for (const UvTransform* transform : material.transforms())
      for (int column = 0; column < 3; ++column)
        if (!std::isfinite(transform->matrix[column].x) || !std::isfinite(transform->matrix[column].y))
          throw SceneError(detail::located(where, "material '" + material.name + "' has a non-finite texture transform"));
  }
  for (const Texture& texture : scene.textures)
    if (texture.width <= 0 || texture.height <= 0 ||
        texture.texels.size() != std::size_t(texture.width) * std::size_t(texture.height) * 4)
      throw SceneError(detail::located(where, "texture '" + texture.name + "' has " + std::to_string(texture.texels.size()) +
                                                  " bytes for " + std::to_string(texture.width) + "x" +
                                                  std::to_string(texture.height) + " RGBA8 texels"));
  for (const PunctualLight& light : scene.lights) {
    if (!detail::finite(light.color) || glm::any(glm::lessThan(light.color, glm::vec3(0.0f))) ||
        !std::isfinite(light.intensity) || light.intensity < 0.0f || !detail::finite(light.position) ||
        !detail::finite(light.direction) || !std::isfinite(light.range) || light.range < 0.0f)
      throw SceneError(detail::located(where, "light '" + light.name + "' has a non-finite or negative parameter"));
    if (light.kind == PunctualKind::spot &&
        !(light.inner_cone >= 0.0f && light.inner_cone < light.outer_cone && light.outer_cone <= glm::half_pi<float>()))
      throw SceneError(detail::located(where, "light '" + light.name +
                                                  "' needs spot cone angles 0 <= inner < outer <= pi/2"));
  }
  for (const Camera& camera : scene.cameras)
    if (!detail::finite(camera.camera_to_world) || !(camera.yfov > 0.0f && camera.yfov < glm::pi<float>()) ||
        !(camera.aspect >= 0.0f) || !std::isfinite(camera.aspect) || !(camera.znear > 0.0f))
      throw SceneError(detail::located(where, "camera '" + camera.name +
                                                  "' needs a finite transform, 0 < yfov < pi, aspect >= 0 and znear > 0"));
}

}  // namespace igi
