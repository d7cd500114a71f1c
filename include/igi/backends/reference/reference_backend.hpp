#pragma once
/// \file
/// `ReferenceBackend<W>`: the plain, obviously correct backend every other one is checked
/// against. All instanced triangles are transformed to world space and put in a bounding volume
/// hierarchy split at the median centroid of the longest axis; rays are traced one at a time
/// with the watertight triangle test, looping over the lanes of a packet.

#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/backends/coherence.hpp"
#include "igi/backends/packet.hpp"
#include "igi/backends/world_triangles.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Single-ray median-split BVH over world-space triangles, looped over W lanes; the ground truth.
template <int W>
  requires PacketWidth<W>
class ReferenceBackend {
 public:
  /// Lanes per packet.
  static constexpr int width = W;
  /// Name for tables and messages.
  static constexpr const char* name() noexcept { return "reference"; }

  /// Builds the hierarchy over `scene`; throws std::invalid_argument if the scene is malformed.
  explicit ReferenceBackend(const Scene& scene) : geometry_(scene, "igi::ReferenceBackend"), cutouts_(scene) {
    build();
  }

  /// Closest hit of the rays in `mask`: hit lanes get tfar = distance and their ids, missing lanes
  /// get invalid ids; lanes outside `mask` are not touched. `N` is W or 1 (the single-ray call).
  template <int N>
    requires(N == W || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, const vmask<N>& mask) const noexcept {
    for (int lane = 0; lane < N; ++lane) {
      if (!mask[lane]) continue;
      Found found;
      if (closest_hit(ray_of(rays, lane), found)) {
        rays.tfar[lane] = found.hit.t;
        hits.Ng_x[lane] = found.hit.normal.x;
        hits.Ng_y[lane] = found.hit.normal.y;
        hits.Ng_z[lane] = found.hit.normal.z;
        hits.u[lane] = found.hit.u;
        hits.v[lane] = found.hit.v;
        hits.primID[lane] = found.triangle->primitive;
        hits.geomID[lane] = found.triangle->mesh;
        hits.instID[lane] = found.triangle->instance;
      } else {
        hits.Ng_x[lane] = hits.Ng_y[lane] = hits.Ng_z[lane] = hits.u[lane] = hits.v[lane] = 0.0f;
        hits.primID[lane] = hits.geomID[lane] = hits.instID[lane] = invalid_id;
      }
    }
  }

  /// Lanes of `mask` whose interval [tnear, tfar] is blocked; those get tfar = -inf.
  template <int N>
    requires(N == W || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, const vmask<N>& mask) const noexcept {
    vmask<N> blocked;
    for (int lane = 0; lane < N; ++lane) {
      if (!mask[lane] || !any_hit(ray_of(rays, lane))) continue;
      blocked.set(lane, true);
      rays.tfar[lane] = -std::numeric_limits<float>::infinity();
    }
    return blocked;
  }

  /// intersect() with a coherence hint, which this backend does not need (same result).
  template <int N>
    requires(N == W || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, Coherence, const vmask<N>& mask) const noexcept {
    intersect(rays, hits, mask);
  }

  /// occluded() with a coherence hint, which this backend does not need (same result).
  template <int N>
    requires(N == W || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, Coherence, const vmask<N>& mask) const noexcept {
    return occluded(rays, mask);
  }

  /// Moves instance `index`; takes effect at commit().
  void set_instance_transform(int index, const glm::mat4& transform) { geometry_.set_instance_transform(index, transform); }

  /// Replaces the vertex positions of mesh `index` (same count); takes effect at commit().
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) { geometry_.set_mesh_positions(index, positions); }

  /// Rebuilds the hierarchy from the current transforms and positions.
  void commit() { build(); }

  /// Occlusion queries pass the alpha cut-outs' triangles where `test` finds them transparent
  /// (see CutoutTestingBackend). Only between frames.
  void set_cutout_test(CutoutTest test) { cutout_test_ = std::move(test); }
  /// Whether a cut-out test is set.
  bool cutout_test_set() const noexcept { return bool(cutout_test_); }

  /// Number of hierarchy nodes (for tests and statistics).
  std::size_t node_count() const noexcept { return nodes_.size(); }

 private:
  /// A hierarchy node: a leaf if `count` > 0, else an inner node with children `first`, `first + 1`.
  struct Node {
    Bounds bounds;        ///< Bounds of everything below.
    std::uint32_t first;  ///< First triangle (leaf) or first child (inner).
    std::uint32_t count;  ///< Triangles in a leaf, 0 for an inner node.
    std::uint32_t axis;   ///< Inner node: the axis its children were split along.
  };
  /// The closest hit found so far.
  struct Found {
    TriangleHit hit{};                         ///< Distance and barycentrics.
    const WorldTriangle* triangle = nullptr;   ///< Triangle hit.
  };

  /// Leaves hold at most this many triangles: small enough to keep traversal cheap, large
  /// enough that the tree is not mostly nodes.
  static constexpr std::uint32_t leaf_size = 4;
  /// Traversal stack entries: a median split halves the triangles per level, so depth stays
  /// below log2(2^32 / leaf_size) + 1 = 31 and each level leaves at most one sibling on the stack.
  static constexpr int stack_size = 64;

  void build() {
    triangles_ = geometry_.triangles();
    nodes_.clear();
    nodes_.reserve(2 * triangles_.size() / leaf_size + 1);
    nodes_.push_back({});
    build_node(0, 0, std::uint32_t(triangles_.size()));
  }

  void build_node(std::size_t node, std::uint32_t first, std::uint32_t count) {
    Bounds bounds, centroids;
    for (std::uint32_t i = first; i < first + count; ++i) {
      const Bounds b = triangles_[i].bounds();
      bounds.extend(b);
      centroids.extend(b.center());
    }
    nodes_[node].bounds = bounds;
    if (count <= leaf_size) {
      nodes_[node].first = first;
      nodes_[node].count = count;
      return;
    }
    const glm::vec3 extent = centroids.extent();
    const int axis = extent.x > extent.y ? (extent.x > extent.z ? 0 : 2) : (extent.y > extent.z ? 1 : 2);
    const std::uint32_t half = count / 2;
    const auto begin = triangles_.begin() + first;
    std::nth_element(begin, begin + half, begin + count, [axis](const WorldTriangle& a, const WorldTriangle& b) {
      return a.bounds().center()[axis] < b.bounds().center()[axis];
    });
    const auto children = std::uint32_t(nodes_.size());
    nodes_[node].first = children;
    nodes_[node].count = 0;
    nodes_[node].axis = std::uint32_t(axis);
    nodes_.push_back({});
    nodes_.push_back({});
    build_node(children, first, half);
    build_node(children + 1, first + half, count - half);
  }

  /// Visits every leaf whose box the ray enters before `limit()`, calling `test(triangle)` for its
  /// triangles; stops when `test` returns true (used by the any-hit query).
  template <class Limit, class Test>
  void traverse(const Ray& ray, Limit&& limit, Test&& test) const noexcept {
    if (triangles_.empty()) return;
    std::array<std::uint32_t, stack_size> stack;
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      float t0, t1;
      if (!clip_to_box({ray.origin, ray.direction, ray.tnear, limit()}, node.bounds, t0, t1)) continue;
      if (node.count > 0) {
        for (std::uint32_t i = node.first; i < node.first + node.count; ++i)
          if (test(triangles_[i])) return;
      } else {
        // The child on the lower side of the split is nearer for a ray going up that axis: visit
        // it first (push it last) so closest-hit searches shrink tfar early.
        const bool lower_first = ray.direction[int(node.axis)] >= 0.0f;
        stack[top++] = lower_first ? node.first + 1 : node.first;
        stack[top++] = lower_first ? node.first : node.first + 1;
      }
    }
  }

  bool closest_hit(const Ray& ray, Found& found) const noexcept {
    const ShearedRay sheared(ray);
    float tfar = ray.tfar;
    traverse(
        ray, [&] { return tfar; },
        [&](const WorldTriangle& triangle) {
          TriangleHit hit;
          if (intersect_triangle(sheared, ray.tnear, tfar, triangle.v0, triangle.v1, triangle.v2, hit) &&
              (found.triangle == nullptr || hit.t < found.hit.t)) {
            found = {hit, &triangle};
            tfar = hit.t;
          }
          return false;
        });
    return found.triangle != nullptr;
  }

  bool any_hit(const Ray& ray) const noexcept {
    const ShearedRay sheared(ray);
    bool blocked = false;
    traverse(
        ray, [&] { return ray.tfar; },
        [&](const WorldTriangle& triangle) {
          TriangleHit hit;
          if (!intersect_triangle(sheared, ray.tnear, ray.tfar, triangle.v0, triangle.v1, triangle.v2, hit)) return false;
          if (cutout_test_ && cutouts_.contains(triangle.mesh) &&
              !cutout_test_({.origin = ray.origin, .direction = ray.direction, .distance = hit.t, .u = hit.u, .v = hit.v,
                             .mesh = triangle.mesh, .instance = triangle.instance, .primitive = triangle.primitive}))
            return false;  // transparent there: the ray goes on
          blocked = true;
          return true;
        });
    return blocked;
  }

  FlattenedGeometry geometry_;  ///< What is traced, as of the last update.
  CutoutMeshes cutouts_;        ///< The alpha cut-out meshes, which block only where cutout_test_ says.
  CutoutTest cutout_test_;      ///< Empty: cut-outs block everywhere.
  std::vector<WorldTriangle> triangles_;  ///< World triangles in leaf order.
  std::vector<Node> nodes_;              ///< Node 0 is the root.
};

static_assert(Backend<ReferenceBackend<1>> && Backend<ReferenceBackend<8>> && Backend<ReferenceBackend<64>>);
static_assert(CutoutTestingBackend<ReferenceBackend<8>>);

}  // namespace igi
