#pragma once
/// \file
/// What a ray-tracing backend is. The pipeline only ever talks to this interface.

#include <concepts>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/coherence.hpp"
#include "igi/backends/packet.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// A backend traces packets of `width` rays against a Scene it was built from. `intersect` and
/// `occluded` are const and safe to call from many threads at once; scene updates (instance
/// transforms, mesh vertex positions) are made between frames and take effect at `commit()`.
/// Lanes outside the mask are neither traced nor written (hits stay as they were). A `Coherence`
/// hint may change how fast a packet is traced, never its result.
template <class B>
concept Backend = requires(B& backend, const B& traced, RayPacket<B::width>& rays, HitPacket<B::width>& hits,
                           RayPacket<1>& ray, HitPacket<1>& hit, const vmask<B::width>& mask, int index,
                           const glm::mat4& transform, std::span<const glm::vec3> positions) {
  { B::width } -> std::convertible_to<int>;
  { B::name() } -> std::convertible_to<const char*>;
  requires std::constructible_from<B, const Scene&>;
  { traced.intersect(rays, hits, mask) } -> std::same_as<void>;
  { traced.occluded(rays, mask) } -> std::same_as<vmask<B::width>>;
  { traced.intersect(rays, hits, Coherence::incoherent, mask) } -> std::same_as<void>;
  { traced.occluded(rays, Coherence::incoherent, mask) } -> std::same_as<vmask<B::width>>;
  { traced.intersect(ray, hit, vmask<1>(true)) } -> std::same_as<void>;
  { traced.occluded(ray, vmask<1>(true)) } -> std::same_as<vmask<1>>;
  { backend.set_instance_transform(index, transform) } -> std::same_as<void>;
  { backend.set_mesh_positions(index, positions) } -> std::same_as<void>;
  { backend.commit() } -> std::same_as<void>;
};

/// A triangle an occlusion query met on an alpha cut-out mesh (material alphaMode MASK), as a
/// CutoutTest sees it: the ray in world space, the hit's distance along it and its barycentrics.
struct OcclusionCandidate {
  glm::vec3 origin{0.0f};     ///< World-space ray origin.
  glm::vec3 direction{0.0f};  ///< World-space ray direction, as traced (not normalised).
  float distance = 0.0f;      ///< Ray parameter of the hit.
  float u = 0.0f;             ///< Barycentric coordinate of the triangle's second vertex.
  float v = 0.0f;             ///< Barycentric coordinate of its third vertex.
  std::uint32_t mesh = 0;      ///< Mesh index.
  std::uint32_t instance = 0;  ///< Instance index.
  std::uint32_t primitive = 0; ///< Triangle index within the mesh.
};

/// Whether a cut-out's triangle blocks an occlusion query where it was met (true: opaque there).
/// Called from every tracing thread at once: it must be thread-safe.
using CutoutTest = std::function<bool(const OcclusionCandidate&)>;

/// The meshes of a scene whose material a rule picks; empty when it picks none, so scenes
/// without such meshes pay nothing. A material index the scene lacks is never picked
/// (validate_scene and the shaders report it).
class MaterialMeshes {
 public:
  /// None.
  MaterialMeshes() = default;
  /// The meshes of `scene` whose material `picked(material)` is true for (materials do not
  /// change with the frame, only transforms and positions).
  template <class Pick>
  MaterialMeshes(const Scene& scene, Pick picked) {
    for (std::size_t mesh = 0; mesh < scene.meshes.size(); ++mesh) {
      const int material = scene.meshes[mesh].material;
      if (material >= 0 && std::size_t(material) < scene.materials.size() && picked(scene.materials[std::size_t(material)])) {
        meshes_.resize(scene.meshes.size(), false);
        meshes_[mesh] = true;
      }
    }
  }
  /// Whether any mesh is picked.
  bool any() const noexcept { return !meshes_.empty(); }
  /// Whether mesh `mesh` is picked (false for ids outside the scene).
  bool contains(std::size_t mesh) const noexcept { return mesh < meshes_.size() && meshes_[mesh]; }

 private:
  std::vector<bool> meshes_;
};

/// Which meshes of a scene are alpha cut-outs (their material's alphaMode is MASK).
class CutoutMeshes : public MaterialMeshes {
 public:
  /// None.
  CutoutMeshes() = default;
  /// The cut-out meshes of `scene`.
  explicit CutoutMeshes(const Scene& scene)
      : MaterialMeshes(scene, [](const Material& material) { return material.alpha_mode == AlphaMode::mask; }) {}
};

/// Which meshes of a scene light passes straight through in part (Material::see_through:
/// thin-walled transmission, alphaMode BLEND), so shadow rays crossing them are attenuated,
/// not stopped.
class SeeThroughMeshes : public MaterialMeshes {
 public:
  /// None.
  SeeThroughMeshes() = default;
  /// The see-through meshes of `scene`.
  explicit SeeThroughMeshes(const Scene& scene)
      : MaterialMeshes(scene, [](const Material& material) { return material.see_through(); }) {}
};

/// A backend whose queries can pass through alpha cut-outs during traversal: with a test set, a
/// triangle of a cut-out mesh blocks an occlusion query and is a closest hit only where the test
/// says it is opaque (Embree: occlusion and intersection filter functions on those meshes). `cutout_test_set()` says whether one is set;
/// set it between frames, never while rays are traced. Without one, cut-outs block everywhere.
template <class B>
concept CutoutTestingBackend = Backend<B> && requires(B& backend, const B& traced, CutoutTest test) {
  { backend.set_cutout_test(std::move(test)) } -> std::same_as<void>;
  { traced.cutout_test_set() } -> std::same_as<bool>;
};

}  // namespace igi
