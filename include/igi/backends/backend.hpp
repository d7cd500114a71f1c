#pragma once
/// \file
/// What a ray-tracing backend is. The pipeline only ever talks to this interface.

#include <concepts>
#include <span>

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

}  // namespace igi
