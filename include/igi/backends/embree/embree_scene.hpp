#pragma once
/// \file
/// `EmbreeScene`: an igi Scene built into Embree 3 and kept up to date, whatever the packet width
/// it is traced with (the tracing itself is igi/backends/embree/embree_tracing.hpp; EmbreeBackend,
/// igi/backends/embree/embree_backend.hpp, joins the two).
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
/// meshes used by several instances stay instanced from the start. Either way hits, once passed
/// through `remap_flattened`, report geomID = mesh index and instID = instance index. Embree
/// errors become igi::EmbreeError carrying Embree's message.

#include <algorithm>
#include <cstddef>
#include <mutex>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <embree3/rtcore.h>
#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/backends/packet.hpp"
#include "igi/backends/world_triangles.hpp"
#include "igi/scene/scene.hpp"
#include "igi/simd/simd.hpp"

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

}  // namespace detail

/// An igi Scene in Embree: the device, one scene per mesh that needs one, the flattened scene of
/// the instances that never moved and the instance level above them. Not copyable or movable
/// (Embree's error callback holds its address); EmbreeBackend keeps one on the heap.
class EmbreeScene {
 public:
  /// Flattening copies at most this many world-space triangles by default (about 1 GB of Embree
  /// data with vertices and BVH): beyond it, meshes with several instances stay Embree instances.
  static constexpr std::size_t default_flatten_limit = std::size_t(16) << 20;

  /// Builds the scene on a new Embree device made with `device_config` (Embree's rtcNewDevice
  /// string, e.g. "threads=1"), flattening up to `flatten_limit` triangles (0: only meshes with a
  /// single instance); throws std::invalid_argument on a malformed scene and EmbreeError when
  /// Embree reports a problem.
  explicit EmbreeScene(const Scene& scene, const std::string& device_config = "",
                       std::size_t flatten_limit = default_flatten_limit) {
    validate_for_tracing(scene, "igi::EmbreeBackend");
    state_.device = rtcNewDevice(device_config.c_str());
    if (state_.device == nullptr)
      throw EmbreeError(std::string("igi::EmbreeBackend: rtcNewDevice(\"") + device_config +
                        "\") failed: " + detail::embree_error_name(rtcGetDeviceError(nullptr)));
    rtcSetDeviceErrorFunction(state_.device, &State::on_error, &state_);

    state_.cutouts = CutoutMeshes(scene);
    for (const Mesh& mesh : scene.meshes) add_mesh(mesh);
    state_.top = rtcNewScene(state_.device);
    check("rtcNewScene (instances)");
    state_.flat = rtcNewScene(state_.device);
    rtcSetSceneFlags(state_.flat, RTC_SCENE_FLAG_ROBUST);  // watertight, as the mesh scenes
    check("rtcNewScene (flattened)");
    // The flattened scene is itself one instance of the top level, with the id after the instances'.
    state_.flat_id = unsigned(scene.instances.size());
    state_.flat_instance = rtcNewGeometry(state_.device, RTC_GEOMETRY_TYPE_INSTANCE);
    rtcSetGeometryInstancedScene(state_.flat_instance, state_.flat);
    rtcSetGeometryTimeStepCount(state_.flat_instance, 1);
    const glm::mat4 identity(1.0f);
    rtcSetGeometryTransform(state_.flat_instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &identity[0][0]);
    rtcAttachGeometryByID(state_.top, state_.flat_instance, state_.flat_id);
    check("flattened scene instance");

    std::vector<std::size_t> users(scene.meshes.size(), 0);
    std::size_t world_triangles = 0;
    for (const Instance& instance : scene.instances) {
      ++users[std::size_t(instance.mesh)];
      world_triangles += scene.meshes[std::size_t(instance.mesh)].triangles.size();
    }
    for (std::size_t i = 0; i < scene.instances.size(); ++i) {
      const Instance& instance = scene.instances[i];
      state_.instances.push_back(InstanceEntry{instance.name, std::size_t(instance.mesh), instance.transform});
      if (world_triangles <= flatten_limit || users[std::size_t(instance.mesh)] == 1)
        flatten(unsigned(i));
      else
        instantiate(unsigned(i));
    }
    state_.flat_dirty = state_.top_dirty = true;
    commit();
  }

  /// Not copyable or movable: it owns Embree objects, and Embree's error callback holds its address.
  EmbreeScene(const EmbreeScene&) = delete;
  /// Not copyable or movable: it owns Embree objects, and Embree's error callback holds its address.
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  /// Releases every Embree object.
  ~EmbreeScene() = default;

  /// Moves instance `index`; the top level is re-committed at commit().
  void set_instance_transform(int index, const glm::mat4& transform) {
    check_index(index, state_.instances.size(), "igi::EmbreeBackend", "instance");
    check_transform(transform, "igi::EmbreeBackend");
    const InstanceEntry& instance = state_.instances[std::size_t(index)];
    const MeshEntry& mesh = state_.meshes[instance.mesh];
    check_extent(transform, mesh.box, std::span(mesh.positions).first(mesh.vertex_count), instance.name, mesh.name,
                 "igi::EmbreeBackend");
    state_.pending_transforms.emplace_back(index, transform);
    state_.top_dirty = true;
  }

  /// Replaces the vertex positions of mesh `index` (same count); its BVH is refitted at commit().
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) {
    check_index(index, state_.meshes.size(), "igi::EmbreeBackend", "mesh");
    MeshEntry& mesh = state_.meshes[std::size_t(index)];
    if (positions.size() != mesh.vertex_count)
      throw std::invalid_argument("igi::EmbreeBackend: set_mesh_positions got " + std::to_string(positions.size()) +
                                  " positions for mesh '" + mesh.name + "' which has " +
                                  std::to_string(mesh.vertex_count));
    Mesh probe;
    probe.name = mesh.name;
    probe.positions.resize(mesh.vertex_count);
    check_positions(probe, positions, "igi::EmbreeBackend");
    const Bounds box = bounds_of(positions);
    for (std::size_t i = 0; i < state_.instances.size(); ++i)
      if (state_.instances[i].mesh == std::size_t(index))
        check_extent(latest_transform(i), box, positions, state_.instances[i].name, mesh.name, "igi::EmbreeBackend");
    std::copy(positions.begin(), positions.end(), mesh.positions.begin());
    mesh.box = box;
    mesh.changed = true;
    state_.top_dirty = true;
    if (mesh.geometry == nullptr) return;  // No triangles or no mesh scene yet: nothing to refit.
    rtcUpdateGeometryBuffer(mesh.geometry, RTC_BUFFER_TYPE_VERTEX, 0);
    rtcCommitGeometry(mesh.geometry);
    check("set_mesh_positions");
    mesh.dirty = true;
    state_.top_dirty = true;  // The instances' bounds changed with the mesh.
  }

  /// Commits what changed: instances that moved or whose mesh changed leave the flattened scene
  /// (re-transforming a flattened copy would rebuild the whole flattened BVH at every change),
  /// changed meshes are refitted, then the flattened scene and the instance level re-committed.
  void commit() {
    for (const auto& [index, transform] : state_.pending_transforms) {
      state_.instances[std::size_t(index)].transform = transform;
      if (state_.instances[std::size_t(index)].instanced == nullptr) move_out_of_flattened(unsigned(index));
    }
    for (unsigned i = 0; i < unsigned(state_.instances.size()); ++i)
      if (state_.instances[i].flattened != nullptr && state_.meshes[state_.instances[i].mesh].changed)
        move_out_of_flattened(i);
    for (MeshEntry& mesh : state_.meshes) mesh.changed = false;
    for (MeshEntry& mesh : state_.meshes)
      if (mesh.dirty) {
        rtcCommitScene(mesh.scene);
        check("rtcCommitScene (mesh '" + mesh.name + "')");
      }
    // Embree rebuilds the instance level only over instances marked modified: those of a refitted
    // mesh must be, or the top level keeps their old bounds.
    for (const InstanceEntry& instance : state_.instances)
      if (instance.instanced != nullptr && state_.meshes[instance.mesh].dirty) rtcCommitGeometry(instance.instanced);
    for (MeshEntry& mesh : state_.meshes) mesh.dirty = false;
    if (state_.flat_dirty) {
      rtcCommitScene(state_.flat);
      check("rtcCommitScene (flattened)");
      rtcCommitGeometry(state_.flat_instance);
      state_.flat_dirty = false;
      state_.top_dirty = true;
    }
    if (state_.top_dirty) {
      for (const auto& [index, transform] : state_.pending_transforms) {
        RTCGeometry instance = state_.instances[std::size_t(index)].instanced;
        rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &transform[0][0]);
        rtcCommitGeometry(instance);
      }
      state_.pending_transforms.clear();
      check("instance transforms");
      rtcCommitScene(state_.top);
      check("rtcCommitScene (instances)");
      state_.top_dirty = false;
    }
    // One level while nothing is instanced: Embree traces the flattened triangles directly, without
    // the identity instance around them (Cornell's camera rays 17% faster, Sponza's 6%). The rays
    // and hits are the same either way: the identity transform leaves every coordinate as it is.
    bool any_instanced = false;
    for (const InstanceEntry& instance : state_.instances) any_instanced |= instance.instanced != nullptr;
    state_.traced = any_instanced ? state_.top : state_.flat;
  }

  /// Lets occlusion and closest-hit queries pass the alpha cut-outs' triangles wherever `test` says they are
  /// transparent (see CutoutTestingBackend); an empty test makes them block everywhere again.
  /// Only between frames: the filter functions read it while rays are traced.
  void set_cutout_test(CutoutTest test) { state_.cutout_test = std::move(test); }
  /// Whether a cut-out test is set.
  bool cutout_test_set() const noexcept { return bool(state_.cutout_test); }

  /// The Embree device, for callers who add their own Embree objects (errors still surface here).
  RTCDevice device() const noexcept { return state_.device; }
  /// The Embree scene rays are traced in: the flattened scene itself while no instance is an
  /// Embree instance, else the instance level above it.
  RTCScene traced_scene() const noexcept { return state_.traced; }

  /// Throws EmbreeError if Embree recorded an error on this device since the last check; `what`
  /// names the operation in the message.
  void check(const std::string& what) { state_.check(what); }

  /// Hits of `mask` inside the flattened scene carry (geomID = instance, instID = flat_id), or no
  /// instID when it is traced alone: rewritten to (geomID = mesh, instID = instance) like hits
  /// through Embree instances.
  template <int N>
  void remap_flattened(HitPacket<N>& hits, const vmask<N>& mask) const noexcept {
    const bool alone = state_.traced == state_.flat;
    for (int lane = 0; lane < N; ++lane)
      if (mask[lane] && hits.geomID[lane] != invalid_id &&
          (hits.instID[lane] == state_.flat_id || (alone && hits.instID[lane] == invalid_id))) {
        const unsigned instance = hits.geomID[lane];
        hits.instID[lane] = instance;
        hits.geomID[lane] = unsigned(state_.instances[instance].mesh);
      }
  }

 private:
  /// One mesh: its data and, once an instance of it is traced as an Embree instance, its scene.
  struct MeshEntry {
    std::string name;                 ///< For messages.
    std::vector<glm::vec3> positions; ///< Object-space vertices, one padding vertex at the end (Embree reads 16 bytes per vertex).
    std::vector<glm::uvec3> triangles;  ///< Vertex indices, shared by the mesh scene and every flattened copy.
    std::size_t vertex_count = 0;     ///< Vertices (without the padding).
    Bounds box;                       ///< Object-space bounds of the vertices, for O(1) checks of a move.
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
    CutoutMeshes cutouts;                   ///< The alpha cut-out meshes, whose triangles carry the occlusion filter.
    CutoutTest cutout_test;                 ///< What the occlusion filter asks; empty: cut-outs block.
    mutable std::mutex error_mutex;         ///< Guards `error_message` (Embree may report from any thread).
    std::string error_message;              ///< First message since the last check.

    static void on_error(void* user, RTCError code, const char* message) {
      auto* state = static_cast<State*>(user);
      const std::lock_guard lock(state->error_mutex);
      if (state->error_message.empty())
        state->error_message = std::string(detail::embree_error_name(code)) + ": " + (message ? message : "");
    }

    /// Embree's occlusion and intersection filter on the cut-out meshes' triangles: rejects the
    /// hits `cutout_test` finds transparent, so the query goes on past them in the same traversal. Hits in the flattened
    /// scene carry geomID = instance in world space; hits through an Embree instance carry
    /// geomID = mesh, instID = instance, and the ray in the instance's object space, which the
    /// instance's transform takes back to world space.
    static void filter_cutouts(const RTCFilterFunctionNArguments* args) {
      const auto* state = static_cast<const State*>(args->geometryUserPtr);
      if (!state->cutout_test) return;
      const unsigned n = args->N;
      for (unsigned i = 0; i < n; ++i) {
        if (args->valid[i] == 0) continue;
        OcclusionCandidate candidate;
        const unsigned geometry = RTCHitN_geomID(args->hit, n, i), instance = RTCHitN_instID(args->hit, n, i, 0);
        candidate.origin = {RTCRayN_org_x(args->ray, n, i), RTCRayN_org_y(args->ray, n, i), RTCRayN_org_z(args->ray, n, i)};
        candidate.direction = {RTCRayN_dir_x(args->ray, n, i), RTCRayN_dir_y(args->ray, n, i), RTCRayN_dir_z(args->ray, n, i)};
        candidate.distance = RTCRayN_tfar(args->ray, n, i);
        candidate.u = RTCHitN_u(args->hit, n, i);
        candidate.v = RTCHitN_v(args->hit, n, i);
        candidate.primitive = RTCHitN_primID(args->hit, n, i);
        if (instance != RTC_INVALID_GEOMETRY_ID && instance != state->flat_id) {
          const glm::mat4& transform = state->instances[instance].transform;
          candidate.origin = glm::vec3(transform * glm::vec4(candidate.origin, 1.0f));
          candidate.direction = glm::mat3(transform) * candidate.direction;
          candidate.mesh = geometry;
          candidate.instance = instance;
        } else {
          candidate.mesh = unsigned(state->instances[geometry].mesh);
          candidate.instance = geometry;
        }
        if (!state->cutout_test(candidate)) args->valid[i] = 0;
      }
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
    MeshEntry& mesh = state_.meshes.emplace_back();
    mesh.name = source.name;
    mesh.vertex_count = source.positions.size();
    mesh.positions.reserve(source.positions.size() + 1);
    mesh.positions.assign(source.positions.begin(), source.positions.end());
    mesh.box = mesh_bounds(source);
    mesh.positions.emplace_back(0.0f);
    mesh.triangles = source.triangles;
  }

  /// A triangle geometry over mesh `index`'s shared indices with `vertices` as its vertex buffer,
  /// with the occlusion filter if the mesh is a cut-out (set here, before any commit: setting it
  /// later would need the scene rebuilt).
  RTCGeometry new_triangles(std::size_t index, const void* vertices, bool embree_owned_vertices) {
    const MeshEntry& mesh = state_.meshes[index];
    RTCGeometry geometry = rtcNewGeometry(state_.device, RTC_GEOMETRY_TYPE_TRIANGLE);
    if (state_.cutouts.contains(index)) {
      rtcSetGeometryUserData(geometry, &state_);
      rtcSetGeometryOccludedFilterFunction(geometry, &State::filter_cutouts);
      // Closest hits too: a camera ray through foliage found each leaf's transparent part and was
      // traced again behind it, a packet query per layer (Sponza_lit, 640 x 480: 22 of the
      // frame's 40 CPU-ms of surface shading for the 8% of camera rays that meet a cut-out).
      rtcSetGeometryIntersectFilterFunction(geometry, &State::filter_cutouts);
    }
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
    MeshEntry& mesh = state_.meshes[index];
    if (mesh.scene != nullptr) return;
    mesh.scene = rtcNewScene(state_.device);
    // Robust traversal and the watertight triangle test: rays through shared edges never leak.
    // Embree 3.13 refits the geometry's BVH (its REFIT quality, below) only in a dynamic scene of
    // low build quality (a two-level structure whose one geometry keeps its own BVH, built once by
    // SAH and then refitted); without both, every vertex change rebuilt it from scratch: a
    // 50k-triangle mesh took 8.5 ms of CPU per commit against 0.4 ms refitted (one thread).
    rtcSetSceneFlags(mesh.scene, RTC_SCENE_FLAG_ROBUST | RTC_SCENE_FLAG_DYNAMIC);
    rtcSetSceneBuildQuality(mesh.scene, RTC_BUILD_QUALITY_LOW);
    check("rtcNewScene (mesh '" + mesh.name + "')");
    mesh.dirty = true;
    if (mesh.triangles.empty()) return;
    mesh.geometry = new_triangles(index, mesh.positions.data(), false);
    // Vertex changes refit the existing hierarchy instead of rebuilding it.
    rtcSetGeometryBuildQuality(mesh.geometry, RTC_BUILD_QUALITY_REFIT);
    rtcCommitGeometry(mesh.geometry);
    rtcAttachGeometryByID(mesh.scene, mesh.geometry, unsigned(index));
    check("rtcAttachGeometryByID (mesh '" + mesh.name + "')");
  }

  /// Copies instance `index`'s triangles into the flattened scene in world space (geomID = instance index).
  void flatten(unsigned index) {
    InstanceEntry& instance = state_.instances[index];
    const MeshEntry& mesh = state_.meshes[instance.mesh];
    if (mesh.triangles.empty()) return;
    RTCGeometry geometry = new_triangles(instance.mesh, nullptr, true);
    auto* world = static_cast<glm::vec3*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                                 sizeof(glm::vec3), mesh.vertex_count));
    check("rtcSetNewGeometryBuffer (instance '" + instance.name + "')");
    for (std::size_t v = 0; v < mesh.vertex_count; ++v)
      world[v] = glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f));
    rtcCommitGeometry(geometry);
    rtcAttachGeometryByID(state_.flat, geometry, index);
    check("flattened instance " + std::to_string(index) + " ('" + instance.name + "')");
    instance.flattened = geometry;
    state_.flat_dirty = true;
  }

  /// Instance `index`'s transform as of the next commit(): its last pending one, else its current one.
  const glm::mat4& latest_transform(std::size_t index) const noexcept {
    for (auto pending = state_.pending_transforms.rbegin(); pending != state_.pending_transforms.rend(); ++pending)
      if (std::size_t(pending->first) == index) return pending->second;
    return state_.instances[index].transform;
  }

  /// Removes instance `index`'s triangles (if any) from the flattened scene and traces it as an Embree instance.
  void move_out_of_flattened(unsigned index) {
    InstanceEntry& instance = state_.instances[index];
    if (instance.flattened == nullptr) return instantiate(index);  // a mesh without triangles
    rtcDetachGeometry(state_.flat, index);
    rtcReleaseGeometry(instance.flattened);
    instance.flattened = nullptr;
    check("detaching flattened instance " + std::to_string(index));
    state_.flat_dirty = true;
    instantiate(index);
  }

  /// Traces instance `index` as an Embree instance of its mesh's scene (instID = instance index).
  void instantiate(unsigned index) {
    InstanceEntry& entry = state_.instances[index];
    ensure_mesh_scene(entry.mesh);
    RTCGeometry instance = rtcNewGeometry(state_.device, RTC_GEOMETRY_TYPE_INSTANCE);
    entry.instanced = instance;
    rtcSetGeometryInstancedScene(instance, state_.meshes[entry.mesh].scene);
    rtcSetGeometryTimeStepCount(instance, 1);
    rtcSetGeometryTransform(instance, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &entry.transform[0][0]);
    rtcCommitGeometry(instance);
    rtcAttachGeometryByID(state_.top, instance, index);
    check("instance " + std::to_string(index) + " ('" + entry.name + "')");
    state_.top_dirty = true;
  }

  State state_;  ///< Embree objects and the scene's copy of the igi scene.
};

}  // namespace igi
