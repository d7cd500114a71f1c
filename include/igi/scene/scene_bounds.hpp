#pragma once
/// \file
/// `SceneBounds`: a scene's world-space bounds kept per mesh and per instance, so that a frame
/// gets them in O(instances) and a moved instance costs O(1), whatever its mesh's size (walking
/// every vertex of every instance took 724 ms a frame at 51 M instanced triangles). Only a mesh
/// whose vertices changed is walked again.

#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "igi/scene/scene.hpp"

namespace igi {

/// The world bounds of a scene's instances, updated one instance or mesh at a time. `bounds()`
/// equals `Scene::bounds()` bit for bit: each instance's box is placed exactly as there, and min
/// and max do not round, so the order of the union does not matter. Not for concurrent use: the
/// union is summed when first asked for after a change.
class SceneBounds {
 public:
  /// No instances: empty bounds.
  SceneBounds() = default;
  /// Walks every mesh of `scene` once.
  explicit SceneBounds(const Scene& scene) {
    meshes_.reserve(scene.meshes.size());
    for (const Mesh& mesh : scene.meshes) meshes_.push_back(mesh_bounds(mesh));
    instances_.reserve(scene.instances.size());
    for (const Instance& instance : scene.instances) instances_.push_back(of_instance(instance));
    stale_ = true;
  }

  /// Instance `instance` of `scene` has a new transform: its box is placed again (O(1)).
  void instance_moved(const Scene& scene, int instance) {
    check(scene);
    instances_.at(std::size_t(instance)) = of_instance(scene.instances.at(std::size_t(instance)));
    stale_ = true;
  }

  /// Mesh `mesh` of `scene` has new vertex positions: its box is walked again and every instance
  /// of it placed again.
  void mesh_changed(const Scene& scene, int mesh) {
    check(scene);
    meshes_.at(std::size_t(mesh)) = mesh_bounds(scene.meshes.at(std::size_t(mesh)));
    for (std::size_t i = 0; i < scene.instances.size(); ++i)
      if (scene.instances[i].mesh == mesh) instances_[i] = of_instance(scene.instances[i]);
    stale_ = true;
  }

  /// The bounds of every instance together.
  const Bounds& bounds() const noexcept {
    if (stale_) {
      // Summed here, not at each change, so that moving every instance of a frame costs
      // O(instances), not O(instances^2).
      total_ = Bounds{};
      for (const Bounds& b : instances_) total_.extend(b);
      stale_ = false;
    }
    return total_;
  }

 private:
  /// The world box of one instance, placed as Scene::bounds() places it.
  Bounds of_instance(const Instance& instance) const {
    return placed(meshes_.at(std::size_t(instance.mesh)), instance.transform);
  }
  /// Throws if `scene` is not the scene these bounds were made for (meshes or instances added or removed).
  void check(const Scene& scene) const {
    if (scene.instances.size() != instances_.size() || scene.meshes.size() != meshes_.size())
      throw std::invalid_argument("SceneBounds: the scene has " + std::to_string(scene.instances.size()) +
                                  " instances of " + std::to_string(scene.meshes.size()) +
                                  " meshes, these bounds were made for " + std::to_string(instances_.size()) +
                                  " instances of " + std::to_string(meshes_.size()));
  }

  std::vector<Bounds> meshes_;     ///< Per mesh, in object space, in scene order.
  std::vector<Bounds> instances_;  ///< Per instance, in world space, in scene order.
  mutable Bounds total_;           ///< Their union, once summed.
  mutable bool stale_ = false;     ///< True if an instance changed since the union was summed.
};

}  // namespace igi
