#pragma once
/// \file
/// `SceneChanges`: the scene state that changes between frames (camera, punctual lights, instance
/// transforms, the vertices of deformed meshes), as absolute values. Animations produce it, renderers apply it, and the tile farm
/// broadcasts it to every rank at the start of a frame.

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/scene/error.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// New vertices of one mesh whose topology stays (a skinned or morphed mesh at a new time).
struct MeshVertices {
  int mesh = -1;                     ///< Index into Scene::meshes.
  std::vector<glm::vec3> positions;  ///< One per vertex of the mesh.
  std::vector<glm::vec3> normals;    ///< Unit, one per vertex (empty: the normals stay).
  std::vector<glm::vec4> tangents;   ///< As Mesh::tangents, one per vertex (empty: the tangents stay).
};

/// Scene state that changes between frames. Values are absolute (not deltas), so applying the same
/// changes twice is harmless.
struct SceneChanges {
  Camera camera;                                      ///< The frame's camera.
  std::vector<std::pair<int, PunctualLight>> lights;  ///< Punctual lights replaced, by index.
  std::vector<std::pair<int, glm::mat4>> instances;   ///< Instance transforms replaced, by index.
  std::vector<MeshVertices> meshes;                   ///< Mesh vertices replaced (same count, same triangles).

  /// Throws SceneError if an index does not exist in `scene`.
  void check(const Scene& scene) const {
    for (const auto& [index, light] : lights)
      if (index < 0 || std::size_t(index) >= scene.lights.size())
        throw SceneError("scene change names punctual light " + std::to_string(index) + " but the scene has " +
                         std::to_string(scene.lights.size()));
    for (const auto& [index, transform] : instances)
      if (index < 0 || std::size_t(index) >= scene.instances.size())
        throw SceneError("scene change names instance " + std::to_string(index) + " but the scene has " +
                         std::to_string(scene.instances.size()));
    for (const MeshVertices& vertices : meshes) {
      if (vertices.mesh < 0 || std::size_t(vertices.mesh) >= scene.meshes.size())
        throw SceneError("scene change names mesh " + std::to_string(vertices.mesh) + " but the scene has " +
                         std::to_string(scene.meshes.size()));
      const std::size_t count = scene.meshes[std::size_t(vertices.mesh)].positions.size();
      if (vertices.positions.size() != count || (!vertices.normals.empty() && vertices.normals.size() != count) ||
          (!vertices.tangents.empty() && vertices.tangents.size() != count))
        throw SceneError("scene change gives mesh " + std::to_string(vertices.mesh) + " " +
                         std::to_string(vertices.positions.size()) + " positions, " + std::to_string(vertices.normals.size()) +
                         " normals and " + std::to_string(vertices.tangents.size()) + " tangents; it has " +
                         std::to_string(count) + " vertices");
    }
  }

  /// Whether applying the changes would change `scene`'s lights, instance transforms or mesh
  /// positions (the camera aside); indices must exist (check()).
  bool alters(const Scene& scene) const {
    return std::any_of(lights.begin(), lights.end(),
                       [&](const auto& change) { return !(scene.lights[std::size_t(change.first)] == change.second); }) ||
           std::any_of(instances.begin(), instances.end(),
                       [&](const auto& change) { return scene.instances[std::size_t(change.first)].transform != change.second; }) ||
           std::any_of(meshes.begin(), meshes.end(),
                       [&](const MeshVertices& vertices) { return scene.meshes[std::size_t(vertices.mesh)].positions != vertices.positions; });
  }

  /// Applies the changes to `scene` itself (no backend follows: for a scene not yet rendered, or
  /// traced by a backend built afresh); throws SceneError, before changing anything, as check() does.
  void apply_to(Scene& scene) const {
    check(scene);
    for (const auto& [index, light] : lights) scene.lights[std::size_t(index)] = light;
    for (const auto& [index, transform] : instances) scene.instances[std::size_t(index)].transform = transform;
    for (const MeshVertices& vertices : meshes) {
      Mesh& mesh = scene.meshes[std::size_t(vertices.mesh)];
      mesh.positions = vertices.positions;
      if (!vertices.normals.empty()) mesh.normals = vertices.normals;
      if (!vertices.tangents.empty()) mesh.tangents = vertices.tangents;
    }
  }
};

}  // namespace igi
