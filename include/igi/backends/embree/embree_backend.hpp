#pragma once
/// \file
/// `EmbreeBackend<W>` (W = 1, 4, 8, 16): Embree 3 behind the igi Backend interface.
///
/// Static geometry is flattened: every instance that has not moved since construction has its
/// triangles in world space in one Embree scene, so Embree builds a single BVH over the whole
/// static scene, and while every instance is flattened the rays are traced in that scene alone
/// (one level). (Sponza's 170 instances of 44 meshes as Embree instances overlap so much that
/// rays traced several times slower.) An instance leaves the flattened scene the first time it
/// moves or its mesh's vertices change, and from then on is an Embree instance of a per-mesh scene
/// (geomID = mesh index): moving it re-commits only the small top level, and changing the mesh's
/// vertices refits that mesh's BVH. When flattening would copy more than the constructor's
/// `flatten_limit` triangles (a mesh instanced many times, like the paper's power plant),
/// meshes used by several instances stay instanced from the start. Either way hits report
/// geomID = mesh index and instID = instance index. Packets go to rtcIntersect1/4/8/16 and
/// rtcOccluded1/4/8/16 (coherent 16-wide occlusion as two 8-wide calls while Embree's coherent
/// 16-wide occlusion kernel can loop: `detail::embree_coherent_occlusion16_may_loop`); Embree
/// errors become igi::EmbreeError carrying Embree's message.
/// Link with the CMake target igi::embree. Embree runs much faster with denormals flushed to zero
/// (_MM_SET_FLUSH_ZERO_MODE / _MM_SET_DENORMALS_ZERO_MODE on each tracing thread); the backend
/// leaves the caller's floating-point mode alone.

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstring>
#include <limits>
#include <memory>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/backends/coherence.hpp"
#include "igi/backends/packet.hpp"
#include "igi/backends/world_triangles.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// An error reported by Embree, with Embree's own message.
class EmbreeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {

/// Embree's name of an error code.
inline const char* embree_error_name(RTCError code) noexcept {
  switch (code) {
    case RTC_ERROR_NONE: return "RTC_ERROR_NONE";
    case RTC_ERROR_UNKNOWN: return "RTC_ERROR_UNKNOWN";
    case RTC_ERROR_INVALID_ARGUMENT: return "RTC_ERROR_INVALID_ARGUMENT";
    case RTC_ERROR_INVALID_OPERATION: return "RTC_ERROR_INVALID_OPERATION";
    case RTC_ERROR_OUT_OF_MEMORY: return "RTC_ERROR_OUT_OF_MEMORY";
    case RTC_ERROR_UNSUPPORTED_CPU: return "RTC_ERROR_UNSUPPORTED_CPU";
    case RTC_ERROR_CANCELLED: return "RTC_ERROR_CANCELLED";
  }
  return "unknown Embree error";
}

/// True while the linked Embree's coherent 16-wide occlusion kernel can loop forever, so that
/// EmbreeBackend<16> must not reach it. In Embree before 4.4.1, `occludedCoherent` (kernels/bvh/
/// bvh_intersector_hybrid.cpp) keeps its valid mask in a `size_t`; GCC before 14 stores the 16-bit
/// AVX-512 mask to a stack slot with `kmovw` and reads it back as 64 bits (`cmpq`, `tzcnt`), so
/// whatever the slot held before lands above bit 15. The octant loop
/// `do { i = bsf(valid_bits); ...; valid_bits &= ~movemask(octant_valid); } while (valid_bits);`
/// then picks a lane index of 16 or more, whose octant matches no lane, and never clears those
/// bits. Debian 12's libembree3 3.13.5 is built with GCC 12.2; gdb on a hung igi-render shows the
/// `kmovw %k6,0x640(%rsp)` / `cmpq $0x0,0x640(%rsp)` pair. What the slot holds depends on the
/// code that ran before, so the loop shows on some CPUs and `-march` builds and not on others.
/// Embree fixed it in 4.4.1 (RenderKit/embree pull request 574: the mask as `unsigned short`).
/// igi is written against Embree 3, whose RTC_VERSION is below 40000, so this is true for every
/// Embree igi can link today; the guard can go once igi moves to Embree 4.4.1 or later.
/// Embree 3.13.5's 4- and 8-wide coherent kernels and its coherent closest-hit kernels share the
/// loop's source, but not the miscompile: scripts/embree_mask_scan.py finds the 16-bit store read
/// back as 64 bits in the 16-wide occlusion kernels only (BVH4 and BVH8, robust or not), and
/// tests/backends/embree_hang_test.cpp traces every width and kind coherently after filling the
/// stack with ones (which makes Embree's own coherent 16-wide occlusion loop every time in a
/// two-level scene) and they return. So only that one kernel is avoided.
inline constexpr bool embree_coherent_occlusion16_may_loop = RTC_VERSION < 40401;

/// rtcOccluded16 as two rtcOccluded8 calls on the packet's halves, with the same `context`: the
/// coherent 8-wide kernel does not loop where the 16-wide one can. Blocked lanes get tfar = -inf,
/// as rtcOccluded16 gives them.
inline void occluded16_as_halves(const int* valid, RTCScene scene, RTCIntersectContext* context, RTCRay16& rays) {
  for (int base = 0; base < 16; base += 8) {
    alignas(32) RTCRay8 half;
    alignas(32) int half_valid[8];  // Embree loads valid[] with aligned vector loads
    for (int lane = 0; lane < 8; ++lane) {
      half_valid[lane] = valid[base + lane];
      half.org_x[lane] = rays.org_x[base + lane];
      half.org_y[lane] = rays.org_y[base + lane];
      half.org_z[lane] = rays.org_z[base + lane];
      half.tnear[lane] = rays.tnear[base + lane];
      half.dir_x[lane] = rays.dir_x[base + lane];
      half.dir_y[lane] = rays.dir_y[base + lane];
      half.dir_z[lane] = rays.dir_z[base + lane];
      half.time[lane] = rays.time[base + lane];
      half.tfar[lane] = rays.tfar[base + lane];
      half.mask[lane] = rays.mask[base + lane];
      half.id[lane] = rays.id[base + lane];
      half.flags[lane] = rays.flags[base + lane];
    }
    rtcOccluded8(half_valid, scene, context, &half);
    for (int lane = 0; lane < 8; ++lane) rays.tfar[base + lane] = half.tfar[lane];
  }
}

/// Embree's packet types for each width.
template <int W>
struct EmbreePacketTypes;
/// Width 1: Embree's single ray.
template <>
struct EmbreePacketTypes<1> {
  using Ray = RTCRay;        ///< Ray.
  using RayHit = RTCRayHit;  ///< Ray and hit.
};
/// Width 4.
template <>
struct EmbreePacketTypes<4> {
  using Ray = RTCRay4;        ///< Ray packet.
  using RayHit = RTCRayHit4;  ///< Ray and hit packet.
};
/// Width 8.
template <>
struct EmbreePacketTypes<8> {
  using Ray = RTCRay8;        ///< Ray packet.
  using RayHit = RTCRayHit8;  ///< Ray and hit packet.
};
/// Width 16.
template <>
struct EmbreePacketTypes<16> {
  using Ray = RTCRay16;        ///< Ray packet.
  using RayHit = RTCRayHit16;  ///< Ray and hit packet.
};

/// Checks at compile time that RayPacket<W> / HitPacket<W> have Embree's field offsets, so
/// Embree may read and write them in place.
template <int W>
constexpr bool packet_layout_matches() {
  using Ray = typename EmbreePacketTypes<W>::Ray;
  using RayHit = typename EmbreePacketTypes<W>::RayHit;
  using Hit = decltype(RayHit::hit);
  static_assert(offsetof(RayPacket<W>, org_x) == offsetof(Ray, org_x));
  static_assert(offsetof(RayPacket<W>, org_y) == offsetof(Ray, org_y));
  static_assert(offsetof(RayPacket<W>, org_z) == offsetof(Ray, org_z));
  static_assert(offsetof(RayPacket<W>, tnear) == offsetof(Ray, tnear));
  static_assert(offsetof(RayPacket<W>, dir_x) == offsetof(Ray, dir_x));
  static_assert(offsetof(RayPacket<W>, dir_y) == offsetof(Ray, dir_y));
  static_assert(offsetof(RayPacket<W>, dir_z) == offsetof(Ray, dir_z));
  static_assert(offsetof(RayPacket<W>, time) == offsetof(Ray, time));
  static_assert(offsetof(RayPacket<W>, tfar) == offsetof(Ray, tfar));
  static_assert(offsetof(RayPacket<W>, mask) == offsetof(Ray, mask));
  static_assert(offsetof(RayPacket<W>, id) == offsetof(Ray, id));
  static_assert(offsetof(RayPacket<W>, flags) == offsetof(Ray, flags));
  static_assert(sizeof(Ray) <= sizeof(RayPacket<W>) && alignof(Ray) <= alignof(RayPacket<W>));
  static_assert(offsetof(HitPacket<W>, Ng_x) == offsetof(Hit, Ng_x));
  static_assert(offsetof(HitPacket<W>, Ng_y) == offsetof(Hit, Ng_y));
  static_assert(offsetof(HitPacket<W>, Ng_z) == offsetof(Hit, Ng_z));
  static_assert(offsetof(HitPacket<W>, u) == offsetof(Hit, u));
  static_assert(offsetof(HitPacket<W>, v) == offsetof(Hit, v));
  static_assert(offsetof(HitPacket<W>, primID) == offsetof(Hit, primID));
  static_assert(offsetof(HitPacket<W>, geomID) == offsetof(Hit, geomID));
  static_assert(offsetof(HitPacket<W>, instID) == offsetof(Hit, instID));
  static_assert(sizeof(Hit) <= sizeof(HitPacket<W>));
  static_assert(RTC_MAX_INSTANCE_LEVEL_COUNT == 1, "HitPacket holds one instance level");
  static_assert(invalid_id == RTC_INVALID_GEOMETRY_ID);
  return true;
}

}  // namespace detail

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

  /// Flattening copies at most this many world-space triangles by default (about 1 GB of Embree
  /// data with vertices and BVH): beyond it, meshes with several instances stay Embree instances.
  static constexpr std::size_t default_flatten_limit = std::size_t(16) << 20;

  /// Builds the scene on a new Embree device made with `device_config` (Embree's rtcNewDevice
  /// string, e.g. "threads=1"), flattening up to `flatten_limit` triangles (0: only meshes with a
  /// single instance); throws std::invalid_argument on a malformed scene and EmbreeError when
  /// Embree reports a problem.
  explicit EmbreeBackend(const Scene& scene, const std::string& device_config = "",
                         std::size_t flatten_limit = default_flatten_limit)
      : state_(std::make_unique<State>()) {
    validate_for_tracing(scene, "igi::EmbreeBackend");
    state_->device = rtcNewDevice(device_config.c_str());
    if (state_->device == nullptr)
      throw EmbreeError(std::string("igi::EmbreeBackend: rtcNewDevice(\"") + device_config +
                        "\") failed: " + detail::embree_error_name(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(state_->device, &State::on_error, state_.get());

    for (const Mesh& mesh : scene.meshes) add_mesh(mesh);
    state_->top = rtcNewScene(state_->device);
    check("rtcNewScene (instances)");
    state_->flat = rtcNewScene(state_->device);
    rtcSetSceneFlags(state_->flat, RTC_SCENE_FLAG_ROBUST);  // watertight, as the mesh scenes
    check("rtcNewScene (flattened)");
    // The flattened scene is itself one instance of the top level, with the id after the instances'.
    state_->flat_id = unsigned(scene.instances.size());
    state_->flat_instance = rtcNewGeometry(state_->device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(state_->flat_instance, state_->flat);
    rtcSetGeometryTimeStepCount(state_->flat_instance, 1);
    const glm::mat4 identity(1.0f);
    rtcSetGeometryTransform(state_->flat_instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &identity[0][0]);
    rtcAttachGeometryByID(state_->top, state_->flat_instance, state_->flat_id);
    check("flattened scene instance");

    std::vector<std::size_t> users(scene.meshes.size(), 0);
    std::size_t world_triangles = 0;
    for (const Instance& instance : scene.instances) {
      ++users[std::size_t(instance.mesh)];
      world_triangles += scene.meshes[std::size_t(instance.mesh)].triangles.size();
    }
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      const Instance& instance = scene.instances[i];
      state_->instances.push_back(InstanceEntry{instance.name, std::size_t(instance.mesh), instance.transform});
      if (world_triangles <= flatten_limit || users[std::size_t(instance.mesh)] == 1)
        flatten(unsigned(i));
      else
        instantiate(unsigned(i));
    }
    state_->flat_dirty = state_->top_dirty = true;
    commit();
  }

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
    trace_closest<N>(state_->traced, rays, hits, Coherence::coherent, mask);
    remap_flattened(hits, mask);
  }

  /// intersect() with Embree's coherence flag chosen by the caller (incoherent for bounce rays).
  template <int N>
    requires(N == W || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, Coherence coherence, const vmask<N>& mask) const {
    trace_closest<N>(state_->traced, rays, hits, coherence, mask);
    remap_flattened(hits, mask);
  }

  /// Lanes of `mask` whose interval [tnear, tfar] is blocked; Embree sets their tfar to -inf.
  template <int N>
    requires(N == W || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, const vmask<N>& mask) const {
    return trace_any<N>(state_->traced, rays, Coherence::coherent, mask);
  }

  /// occluded() with Embree's coherence flag chosen by the caller.
  template <int N>
    requires(N == W || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, Coherence coherence, const vmask<N>& mask) const {
    return trace_any<N>(state_->traced, rays, coherence, mask);
  }

  /// Moves instance `index`; the top level is re-committed at commit().
  void set_instance_transform(int index, const glm::mat4& transform) {
    check_index(index, state_->instances.size(), "igi::EmbreeBackend", "instance");
    check_transform(transform, "igi::EmbreeBackend");
    const InstanceEntry& instance = state_->instances[std::size_t(index)];
    const MeshEntry& mesh = state_->meshes[instance.mesh];
    check_extent(transform, std::span(mesh.positions).first(mesh.vertex_count), instance.name, mesh.name,
                 "igi::EmbreeBackend");
    state_->pending_transforms.emplace_back(index, transform);
    state_->top_dirty = true;
  }

  /// Replaces the vertex positions of mesh `index` (same count); its BVH is refitted at commit().
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) {
    check_index(index, state_->meshes.size(), "igi::EmbreeBackend", "mesh");
    MeshEntry& mesh = state_->meshes[std::size_t(index)];
    if (positions.size() != mesh.vertex_count)
      throw std::invalid_argument("igi::EmbreeBackend: set_mesh_positions got " + std::to_string(positions.size()) +
                                  " positions for mesh '" + mesh.name + "' which has " +
                                  std::to_string(mesh.vertex_count));
    Mesh probe;
    probe.name = mesh.name;
    probe.positions.resize(mesh.vertex_count);
    check_positions(probe, positions, "igi::EmbreeBackend");
    for (std::size_t i = 0; i < state_->instances.size(); ++i)
      if (state_->instances[i].mesh == std::size_t(index))
        check_extent(latest_transform(i), positions, state_->instances[i].name, mesh.name, "igi::EmbreeBackend");
    std::copy(positions.begin(), positions.end(), mesh.positions.begin());
    mesh.changed = true;
    state_->top_dirty = true;
    if (mesh.geometry == nullptr) return;  // No triangles or no mesh scene yet: nothing to refit.
    rtcUpdateGeometryBuffer(mesh.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(mesh.geometry);
    check("set_mesh_positions");
    mesh.dirty = true;
    state_->top_dirty = true;  // The instances' bounds changed with the mesh.
  }

  /// Commits what changed: instances that moved or whose mesh changed leave the flattened scene
  /// (re-transforming a flattened copy would rebuild the whole flattened BVH at every change),
  /// changed meshes are refitted, then the flattened scene and the instance level re-committed.
  void commit() {
    for (const auto& [index, transform] : state_->pending_transforms) {
      state_->instances[std::size_t(index)].transform = transform;
      if (state_->instances[std::size_t(index)].instanced == nullptr) move_out_of_flattened(unsigned(index));
    }
    for (unsigned i = 0; i < unsigned(state_->instances.size()); ++i)
      if (state_->instances[i].flattened != nullptr && state_->meshes[state_->instances[i].mesh].changed)
        move_out_of_flattened(i);
    for (MeshEntry& mesh : state_->meshes) mesh.changed = false;
    for (MeshEntry& mesh : state_->meshes)
      if (mesh.dirty) {
        rtcCommitScene(mesh.scene);
        check("rtcCommitScene (mesh '" + mesh.name + "')");
      }
    // Embree rebuilds the instance level only over instances marked modified: those of a refitted
    // mesh must be, or the top level keeps their old bounds.
    for (const InstanceEntry& instance : state_->instances)
      if (instance.instanced != nullptr && state_->meshes[instance.mesh].dirty) rtcCommitGeometry(instance.instanced);
    for (MeshEntry& mesh : state_->meshes) mesh.dirty = false;
    if (state_->flat_dirty) {
      rtcCommitScene(state_->flat);
      check("rtcCommitScene (flattened)");
      rtcCommitGeometry(state_->flat_instance);
      state_->flat_dirty = false;
      state_->top_dirty = true;
    }
    if (state_->top_dirty) {
      for (const auto& [index, transform] : state_->pending_transforms) {
        RTCGeometry instance = state_->instances[std::size_t(index)].instanced;
        rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transform[0][0]);
        rtcCommitGeometry(instance);
      }
      state_->pending_transforms.clear();
      check("instance transforms");
      rtcCommitScene(state_->top);
      check("rtcCommitScene (instances)");
      state_->top_dirty = false;
    }
    // One level while nothing is instanced: Embree traces the flattened triangles directly, without
    // the identity instance around them (Cornell's camera rays 17% faster, Sponza's 6%). The rays
    // and hits are the same either way: the identity transform leaves every coordinate as it is.
    bool any_instanced = false;
    for (const InstanceEntry& instance : state_->instances) any_instanced |= instance.instanced != nullptr;
    state_->traced = any_instanced ? state_->top : state_->flat;
  }

  /// The Embree device, for callers who add their own Embree objects (errors still surface here).
  RTCDevice device() const noexcept { return state_->device; }
  /// The Embree scene rays are traced in: the flattened scene itself while no instance is an
  /// Embree instance, else the instance level above it.
  RTCScene embree_scene() const noexcept { return state_->traced; }

  /// Throws EmbreeError if Embree recorded an error on this device since the last check; `what`
  /// names the operation in the message.
  void check(const std::string& what) const { state_->check(what); }

 private:
  /// One mesh: its data and, once an instance of it is traced as an Embree instance, its scene.
  struct MeshEntry {
    std::string name;                 ///< For messages.
    std::vector<glm::vec3> positions; ///< Object-space vertices, one padding vertex at the end (Embree reads 16 bytes per vertex).
    std::vector<glm::uvec3> triangles;  ///< Vertex indices, shared by the mesh scene and every flattened copy.
    std::size_t vertex_count = 0;     ///< Vertices (without the padding).
    RTCScene scene = nullptr;         ///< Scene holding only this mesh (built on first use).
    RTCGeometry geometry = nullptr;   ///< Its triangle geometry (null for a mesh without triangles).
    bool dirty = false;               ///< Its scene needs a commit at commit().
    bool changed = false;             ///< Vertices changed since the last commit().
  };

  /// One instance: flattened into the world-space scene or an Embree instance of its mesh's scene.
  struct InstanceEntry {
    std::string name;                    ///< For messages.
    std::size_t mesh = 0;                ///< Mesh index.
    glm::mat4 transform{1.0f};           ///< Object to world.
    RTCGeometry flattened = nullptr;     ///< World-space triangles in the flattened scene, or null.
    RTCGeometry instanced = nullptr;     ///< Embree instance in the top scene, or null.
  };

  /// Everything Embree owns, kept at a stable address for the error callback.
  struct State {
    RTCDevice device = nullptr;             ///< The device.
    RTCScene top = nullptr;                 ///< Instance level: the flattened scene and the moved instances.
    RTCScene flat = nullptr;                ///< World-space triangles of the instances that never moved.
    RTCScene traced = nullptr;              ///< What rays are traced in: `flat` while nothing is instanced, else `top`.
    RTCGeometry flat_instance = nullptr;    ///< The flattened scene's instance in the top scene.
    unsigned flat_id = 0;                   ///< Its geometry id there (after every instance index).
    std::vector<MeshEntry> meshes;          ///< One per Scene mesh.
    std::vector<InstanceEntry> instances;   ///< One per Scene instance.
    std::vector<std::pair<int, glm::mat4>> pending_transforms;  ///< Instance moves waiting for commit().
    bool flat_dirty = false;                ///< The flattened scene needs a rebuild.
    bool top_dirty = false;                 ///< Needs a re-commit.
    mutable std::mutex error_mutex;         ///< Guards `error_message` (Embree may report from any thread).
    std::string error_message;              ///< First message since the last check.

    static void on_error(void* user, RTCError code, const char* message) {
      auto* state = static_cast<State*>(user);
      const std::lock_guard lock(state->error_mutex);
      if (state->error_message.empty())
        state->error_message = std::string(detail::embree_error_name(code)) + ": " + (message ? message : "");
    }

    void check(const std::string& what) {
      const RTCError code = rtcGetDeviceError(device);
      std::string message;
      {
        const std::lock_guard lock(error_mutex);
        message.swap(error_message);
      }
      if (code == RTC_ERROR_NONE && message.empty()) return;
      if (message.empty()) message = detail::embree_error_name(code);
      throw EmbreeError("igi::EmbreeBackend: " + what + ": " + message);
    }

    ~State() {
      for (InstanceEntry& instance : instances) {
        if (instance.instanced) rtcReleaseGeometry(instance.instanced);
        if (instance.flattened) rtcReleaseGeometry(instance.flattened);
      }
      if (flat_instance) rtcReleaseGeometry(flat_instance);
      if (flat) rtcReleaseScene(flat);
      if (top) rtcReleaseScene(top);
      for (MeshEntry& mesh : meshes) {
        if (mesh.geometry) rtcReleaseGeometry(mesh.geometry);
        if (mesh.scene) rtcReleaseScene(mesh.scene);
      }
      if (device) rtcReleaseDevice(device);
    }
  };

  /// Copies a mesh's data; its Embree scene is made when an instance first needs it.
  void add_mesh(const Mesh& source) {
    MeshEntry& mesh = state_->meshes.emplace_back();
    mesh.name = source.name;
    mesh.vertex_count = source.positions.size();
    mesh.positions.reserve(source.positions.size() + 1);
    mesh.positions.assign(source.positions.begin(), source.positions.end());
    mesh.positions.emplace_back(0.0f);
    mesh.triangles = source.triangles;
  }

  /// A triangle geometry over `mesh`'s shared indices with `vertices` as its vertex buffer.
  RTCGeometry new_triangles(const MeshEntry& mesh, const void* vertices, bool embree_owned_vertices) {
    RTCGeometry geometry = rtcNewGeometry(state_->device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (!embree_owned_vertices)
      rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, vertices, 0,
                                 sizeof(glm::vec3), mesh.vertex_count);
    rtcSetSharedGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, mesh.triangles.data(), 0,
                               sizeof(glm::uvec3), mesh.triangles.size());
    check("triangle buffers (mesh '" + mesh.name + "')");
    return geometry;
  }

  /// Makes mesh `index`'s own scene if it has none yet (geomID = mesh index inside it).
  void ensure_mesh_scene(std::size_t index) {
    MeshEntry& mesh = state_->meshes[index];
    if (mesh.scene != nullptr) return;
    mesh.scene = rtcNewScene(state_->device);
    // Robust traversal and the watertight triangle test: rays through shared edges never leak.
    rtcSetSceneFlags(mesh.scene, RTC_SCENE_FLAG_ROBUST);
    check("rtcNewScene (mesh '" + mesh.name + "')");
    mesh.dirty = true;
    if (mesh.triangles.empty()) return;
    mesh.geometry = new_triangles(mesh, mesh.positions.data(), false);
    // Vertex changes refit the existing hierarchy instead of rebuilding it.
    rtcSetGeometryBuildQuality(mesh.geometry, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(mesh.geometry);
    rtcAttachGeometryByID(mesh.scene, mesh.geometry, unsigned(index));
    check("rtcAttachGeometryByID (mesh '" + mesh.name + "')");
  }

  /// Copies instance `index`'s triangles into the flattened scene in world space (geomID = instance index).
  void flatten(unsigned index) {
    InstanceEntry& instance = state_->instances[index];
    const MeshEntry& mesh = state_->meshes[instance.mesh];
    if (mesh.triangles.empty()) return;
    RTCGeometry geometry = new_triangles(mesh, nullptr, true);
    auto* world = static_cast<glm::vec3*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 sizeof(glm::vec3), mesh.vertex_count));
    check("rtcSetNewGeometryBuffer (instance '" + instance.name + "')");
    for (std::size_t v = 0; v < mesh.vertex_count; ++v)
      world[v] = glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f));
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(state_->flat, geometry, index);
    check("flattened instance " + std::to_string(index) + " ('" + instance.name + "')");
    instance.flattened = geometry;
    state_->flat_dirty = true;
  }

  /// Instance `index`'s transform as of the next commit(): its last pending one, else its current one.
  const glm::mat4& latest_transform(std::size_t index) const noexcept {
    for (auto pending = state_->pending_transforms.rbegin(); pending != state_->pending_transforms.rend(); ++pending)
      if (std::size_t(pending->first) == index) return pending->second;
    return state_->instances[index].transform;
  }

  /// Removes instance `index`'s triangles (if any) from the flattened scene and traces it as an Embree instance.
  void move_out_of_flattened(unsigned index) {
    InstanceEntry& instance = state_->instances[index];
    if (instance.flattened == nullptr) return instantiate(index);  // a mesh without triangles
    rtcDetachGeometry(state_->flat, index);
    rtcReleaseGeometry(instance.flattened);
    instance.flattened = nullptr;
    check("detaching flattened instance " + std::to_string(index));
    state_->flat_dirty = true;
    instantiate(index);
  }

  /// Traces instance `index` as an Embree instance of its mesh's scene (instID = instance index).
  void instantiate(unsigned index) {
    InstanceEntry& entry = state_->instances[index];
    ensure_mesh_scene(entry.mesh);
    RTCGeometry instance = rtcNewGeometry(state_->device, RTC_GEOMETRY_TYPE_INSTANCE);
    entry.instanced = instance;
    rtcSetGeometryInstancedScene(instance, state_->meshes[entry.mesh].scene);
    rtcSetGeometryTimeStepCount(instance, 1);
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &entry.transform[0][0]);
    rtcCommitGeometry(instance);
    rtcAttachGeometryByID(state_->top, instance, index);
    check("instance " + std::to_string(index) + " ('" + entry.name + "')");
    state_->top_dirty = true;
  }

  /// Hits inside the flattened scene carry (geomID = instance, instID = flat_id), or no instID
  /// when it is traced alone: rewritten to (geomID = mesh, instID = instance) like hits through
  /// Embree instances.
  template <int N>
  void remap_flattened(HitPacket<N>& hits, const vmask<N>& mask) const noexcept {
    const bool alone = state_->traced == state_->flat;
    for (int lane = 0; lane < N; ++lane)
      if (mask[lane] && hits.geomID[lane] != invalid_id &&
          (hits.instID[lane] == state_->flat_id || (alone && hits.instID[lane] == invalid_id))) {
        const unsigned instance = hits.geomID[lane];
        hits.instID[lane] = instance;
        hits.geomID[lane] = unsigned(state_->instances[instance].mesh);
      }
  }

  /// Embree's valid[] array: -1 for lanes in `mask` with a non-empty interval, 0 elsewhere.
  template <int N>
  struct alignas(packet_alignment) ValidLanes {
    int lane[N];  ///< -1 = trace, 0 = leave alone; Embree loads it with aligned vector loads.
    const int* data() const noexcept { return lane; }
    int operator[](std::size_t i) const noexcept { return lane[i]; }
  };
  template <int N>
  static ValidLanes<N> valid_lanes(const RayPacket<N>& rays, const vmask<N>& mask) noexcept {
    ValidLanes<N> valid;
    for (int lane = 0; lane < N; ++lane) valid.lane[lane] = mask[lane] && rays.tnear[lane] <= rays.tfar[lane] ? -1 : 0;
    return valid;
  }

  template <int N>
  static RTCIntersectContext context(Coherence coherence) noexcept {
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    // Packets are coherent unless the caller says otherwise; a single ray has nothing to share.
    context.flags = N > 1 && coherence == Coherence::coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                              : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
    return context;
  }

  template <int N>
  static void trace_closest(RTCScene top, RayPacket<N>& rays, HitPacket<N>& hits, Coherence coherence,
                            const vmask<N>& mask) {
    using EmbreeRay = typename detail::EmbreePacketTypes<N>::Ray;
    using EmbreeRayHit = typename detail::EmbreePacketTypes<N>::RayHit;
    RTCIntersectContext ctx = context<N>(coherence);
    const ValidLanes<N> valid = valid_lanes(rays, mask);
    // Where the hits follow the rays in memory exactly as in Embree's RTCRayHitN (the pipeline's
    // stream packets are laid out so for W = 4, 8, 16), Embree traces them in place.
    if constexpr (offsetof(EmbreeRayHit, hit) == sizeof(RayPacket<N>)) {
      if (reinterpret_cast<const char*>(&hits) == reinterpret_cast<const char*>(&rays) + sizeof(RayPacket<N>)) {
        // Embree writes nothing on a miss: active lanes start as misses.
        for (int lane = 0; lane < N; ++lane)
          if (mask[lane]) hits.geomID[lane] = hits.primID[lane] = hits.instID[lane] = invalid_id;
        auto* in_place = reinterpret_cast<EmbreeRayHit*>(&rays);
        if constexpr (N == 4) {
          rtcIntersect4(valid.data(), top, &ctx, in_place);
        } else if constexpr (N == 8) {
          rtcIntersect8(valid.data(), top, &ctx, in_place);
        } else if constexpr (N == 16) {
          rtcIntersect16(valid.data(), top, &ctx, in_place);
        } else {
          if (valid[0]) rtcIntersect1(top, &ctx, in_place);
        }
        return;
      }
    }
    // Otherwise the ray block (laid out as Embree's, checked above) is copied next to a hit block
    // and the active lanes' results copied back.
    alignas(packet_alignment) EmbreeRayHit both;
    std::memcpy(&both.ray, &rays, sizeof(EmbreeRay));
    // Embree's hit block is laid out as HitPacket (checked above) but, in RTCRayHit (N = 1), only
    // 16-byte aligned: it is filled and read through aligned copies, never through a cast.
    static_assert(sizeof(both.hit) <= sizeof(HitPacket<N>));
    HitPacket<N> lanes_out;
    lanes_out.clear();
    std::memcpy(&both.hit, &lanes_out, sizeof(both.hit));
    if constexpr (N == 1) {
      if (valid[0]) rtcIntersect1(top, &ctx, &both);
    } else if constexpr (N == 4) {
      rtcIntersect4(valid.data(), top, &ctx, &both);
    } else if constexpr (N == 8) {
      rtcIntersect8(valid.data(), top, &ctx, &both);
    } else {
      rtcIntersect16(valid.data(), top, &ctx, &both);
    }
    std::memcpy(&lanes_out, &both.hit, sizeof(both.hit));
    const HitPacket<N>* hit_lanes = &lanes_out;
    const auto* traced = reinterpret_cast<const RayPacket<N>*>(&both.ray);
    for (int lane = 0; lane < N; ++lane) {
      if (!mask[lane]) continue;
      rays.tfar[lane] = traced->tfar[lane];
      hits.Ng_x[lane] = hit_lanes->Ng_x[lane];
      hits.Ng_y[lane] = hit_lanes->Ng_y[lane];
      hits.Ng_z[lane] = hit_lanes->Ng_z[lane];
      hits.u[lane] = hit_lanes->u[lane];
      hits.v[lane] = hit_lanes->v[lane];
      hits.primID[lane] = hit_lanes->primID[lane];
      hits.geomID[lane] = hit_lanes->geomID[lane];
      hits.instID[lane] = hit_lanes->instID[lane];
    }
  }

  template <int N>
  static vmask<N> trace_any(RTCScene top, RayPacket<N>& rays, Coherence coherence, const vmask<N>& mask) {
    using EmbreeRay = typename detail::EmbreePacketTypes<N>::Ray;
    // Never Embree's coherent 16-wide occlusion kernel where it can loop forever (see
    // detail::embree_coherent_occlusion16_may_loop): coherent packets go as two coherent 8-wide
    // halves. Of the ways around it (bench/backends/occlusion16_bench.cpp, bench/README.md),
    // the halves were fastest on Sponza (1.17x the incoherent flag) and a million-triangle
    // terrain (1.02x), the incoherent flag on the 36-triangle Cornell box (1.38x the halves); on
    // whole frames the halves make Sponza_lit 2-5% faster and Cornell 5% slower. A device made
    // with "isa=avx2" is no way out: it traces 16-wide packets as Embree's ray stream, which
    // ignores valid[] (rtcore.cpp, rtcOccluded16) and asserts that inactive lanes hold finite rays.
    constexpr bool split = N == 16 && detail::embree_coherent_occlusion16_may_loop;
    RTCIntersectContext ctx = context<N>(coherence);
    const ValidLanes<N> valid = valid_lanes(rays, mask);
    // Occlusion needs no hit record: Embree reads and writes the packet in place.
    auto* embree_rays = reinterpret_cast<EmbreeRay*>(&rays);
    if constexpr (N == 1) {
      if (valid[0]) rtcOccluded1(top, &ctx, embree_rays);
    } else if constexpr (N == 4) {
      rtcOccluded4(valid.data(), top, &ctx, embree_rays);
    } else if constexpr (N == 8) {
      rtcOccluded8(valid.data(), top, &ctx, embree_rays);
    } else if (split && coherence == Coherence::coherent) {
      detail::occluded16_as_halves(valid.data(), top, &ctx, *embree_rays);
    } else {
      rtcOccluded16(valid.data(), top, &ctx, embree_rays);
    }
    vmask<N> blocked;
    for (int lane = 0; lane < N; ++lane)
      blocked.set(lane, valid[std::size_t(lane)] != 0 && rays.tfar[lane] == -std::numeric_limits<float>::infinity());
    return blocked;
  }

  std::unique_ptr<State> state_;  ///< Embree objects.
};

static_assert(Backend<EmbreeBackend<1>> && Backend<EmbreeBackend<4>> && Backend<EmbreeBackend<8>> && Backend<EmbreeBackend<16>>);

}  // namespace igi
