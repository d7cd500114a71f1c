#pragma once
/// \file
/// `EmbreeBackend<W>` (W = 1, 4, 8, 16): Embree 3 behind the igi Backend interface. The header
/// users include; it joins two parts:
///   - igi/backends/embree/embree_scene.hpp, `EmbreeScene`: the device, the scene build (static
///     instances flattened into one world-space BVH, traced alone while nothing is instanced;
///     moved or deformed instances as Embree instances of per-mesh scenes), commit(), instance
///     and vertex updates, and Embree errors as igi::EmbreeError;
///   - igi/backends/embree/embree_tracing.hpp: the rtcIntersect1/4/8/16 and rtcOccluded1/4/8/16
///     call per width, in place on the packets (their layout checked against Embree's types),
///     as two calls on the halves where the device has no kernels of the packet's width (16 on
///     CPUs without AVX-512, whose 16-wide calls would ignore the mask: detail::EmbreePacketWidths),
///     and coherent 16-wide occlusion with the incoherent flag while Embree's coherent 16-wide
///     occlusion kernel can loop (`detail::embree_coherent_occlusion16_may_loop`).
/// Link with the CMake target igi::embree. Embree runs much faster with denormals flushed to zero
/// (_MM_SET_FLUSH_ZERO_MODE / _MM_SET_DENORMALS_ZERO_MODE on each tracing thread); the backend
/// leaves the caller's floating-point mode alone.

#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <utility>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/backends/coherence.hpp"
#include "igi/backends/embree/embree_scene.hpp"
#include "igi/backends/embree/embree_tracing.hpp"
#include "igi/backends/packet.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Embree 3 with a two-level scene, traced in packets of W = 1, 4, 8 or 16 rays.
template <int W>
  requires(W == 1 || W == 4 || W == 8 || W == 16)
class EmbreeBackend {
  static_assert(detail::packet_layout_matches<W>() && detail::packet_layout_matches<1>());

 public:
  /// Lanes per packet.
  static constexpr int width = W;
  /// Name for tables and messages.
  static constexpr const char* name() noexcept { return "embree"; }

  /// Flattening copies at most this many world-space triangles by default (see EmbreeScene).
  static constexpr std::size_t default_flatten_limit = EmbreeScene::default_flatten_limit;

  /// Builds the scene on a new Embree device made with `device_config` (Embree's rtcNewDevice
  /// string, e.g. "threads=1"), flattening up to `flatten_limit` triangles (0: only meshes with a
  /// single instance); throws std::invalid_argument on a malformed scene and EmbreeError when
  /// Embree reports a problem.
  explicit EmbreeBackend(const Scene& scene, const std::string& device_config = "",
                         std::size_t flatten_limit = default_flatten_limit)
      : scene_(std::make_unique<EmbreeScene>(scene, device_config, flatten_limit)),
        packet_widths_(detail::EmbreePacketWidths::of(scene_->device())) {}

  /// Moves a backend; the source is left empty.
  EmbreeBackend(EmbreeBackend&&) noexcept = default;
  /// Moves a backend; the source is left empty.
  EmbreeBackend& operator=(EmbreeBackend&&) noexcept = default;
  /// Not copyable: it owns Embree objects.
  EmbreeBackend(const EmbreeBackend&) = delete;
  /// Not copyable: it owns Embree objects.
  EmbreeBackend& operator=(const EmbreeBackend&) = delete;
  /// Releases every Embree object.
  ~EmbreeBackend() = default;

  /// Closest hit of the rays in `mask` (coherent packet hint for W > 1): hit lanes get tfar =
  /// distance, ids and object-space Ng; missing lanes get invalid ids; other lanes are untouched.
  template <int N>
    requires(N == W || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, const vmask<N>& mask) const {
    intersect(rays, hits, Coherence::coherent, mask);
  }

  /// intersect() with Embree's coherence flag chosen by the caller (incoherent for bounce rays).
  template <int N>
    requires(N == W || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, Coherence coherence, const vmask<N>& mask) const {
    detail::embree_intersect<N>(scene_->traced_scene(), packet_widths_, rays, hits, coherence, mask);
    scene_->remap_flattened(hits, mask);
  }

  /// Lanes of `mask` whose interval [tnear, tfar] is blocked; Embree sets their tfar to -inf.
  template <int N>
    requires(N == W || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, const vmask<N>& mask) const {
    return occluded(rays, Coherence::coherent, mask);
  }

  /// occluded() with Embree's coherence flag chosen by the caller.
  template <int N>
    requires(N == W || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, Coherence coherence, const vmask<N>& mask) const {
    return detail::embree_occluded<N>(scene_->traced_scene(), packet_widths_, rays, coherence, mask);
  }

  /// Moves instance `index`; the top level is re-committed at commit().
  void set_instance_transform(int index, const glm::mat4& transform) { scene_->set_instance_transform(index, transform); }

  /// Replaces the vertex positions of mesh `index` (same count); its BVH is refitted at commit().
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) { scene_->set_mesh_positions(index, positions); }

  /// Commits what changed (see EmbreeScene::commit).
  void commit() { scene_->commit(); }

  /// Occlusion and closest-hit queries pass the alpha cut-outs' triangles where `test` finds them
  /// transparent (Embree filter functions; see CutoutTestingBackend). Only between frames.
  void set_cutout_test(CutoutTest test) { scene_->set_cutout_test(std::move(test)); }
  /// Whether a cut-out test is set.
  bool cutout_test_set() const noexcept { return scene_->cutout_test_set(); }

  /// The Embree device, for callers who add their own Embree objects (errors still surface here).
  RTCDevice device() const noexcept { return scene_->device(); }
  /// The Embree scene rays are traced in: the flattened scene itself while no instance is an
  /// Embree instance, else the instance level above it.
  RTCScene embree_scene() const noexcept { return scene_->traced_scene(); }

  /// Throws EmbreeError if Embree recorded an error on this device since the last check; `what`
  /// names the operation in the message.
  void check(const std::string& what) const { scene_->check(what); }

 private:
  std::unique_ptr<EmbreeScene> scene_;  ///< The Embree objects, at a stable address for Embree's error callback.
  detail::EmbreePacketWidths packet_widths_;  ///< The packet widths the device traces natively (the others go as halves).
};

static_assert(Backend<EmbreeBackend<1>> && Backend<EmbreeBackend<4>> && Backend<EmbreeBackend<8>> && Backend<EmbreeBackend<16>>);
static_assert(CutoutTestingBackend<EmbreeBackend<16>>);

}  // namespace igi
