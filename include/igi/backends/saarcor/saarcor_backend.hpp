#pragma once
/// \file
/// `SaarcorBackend`: a scalar emulation of the SaarCOR ray-tracing hardware (Schmittler, Wald and
/// Slusallek, "SaarCOR - A Hardware Architecture for Ray Tracing", Graphics Hardware 2002).
/// Packets of 8x8 = 64 rays traverse an SAH kd-tree together: the packet descends into a node if
/// any of its active rays needs it, with one traversal stack per packet, and every triangle of a
/// visited leaf is fetched once and tested against all active rays. Plain scalar code on purpose:
/// the point is to count what the hardware would do (traversal steps, triangle tests, bytes of
/// kd-nodes and triangles fetched, packets, active-lane ratio), not to be fast. Instances are
/// flattened into world space at build time; commit() rebuilds.

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/backends/coherence.hpp"
#include "igi/backends/packet.hpp"
#include "igi/backends/world_triangles.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// What the SaarCOR emulation counted since the last reset (a plain snapshot).
struct SaarcorStats {
  std::uint64_t packets = 0;             ///< intersect/occluded calls (packets issued), partial ones included.
  std::uint64_t rays = 0;                ///< Active rays in those packets.
  std::uint64_t traversal_steps = 0;     ///< Inner kd-nodes visited by packets.
  std::uint64_t leaf_visits = 0;         ///< Leaves visited by packets.
  std::uint64_t triangle_tests = 0;      ///< Triangles fetched and tested by packets (one per packet and triangle).
  std::uint64_t ray_triangle_tests = 0;  ///< Individual ray-triangle tests of active rays.
  std::uint64_t kd_node_bytes = 0;       ///< Bytes of kd-nodes fetched.
  std::uint64_t triangle_bytes = 0;      ///< Bytes of triangle references and triangle records fetched.
  std::uint64_t active_lanes = 0;        ///< Sum over traversal steps and leaf visits of the active rays.
  std::uint64_t lane_slots = 0;          ///< Sum over the same visits of the packet width.

  /// Fraction of packet lanes doing useful work in traversal steps and leaf visits (0 if none).
  double active_lane_ratio() const noexcept { return lane_slots ? double(active_lanes) / double(lane_slots) : 0.0; }
};

/// SaarCOR's 8x8-ray packets over an SAH kd-tree, emulated in scalar code, with hardware counters.
class SaarcorBackend {
 public:
  /// Lanes per packet: SaarCOR's 8x8 rays.
  static constexpr int width = 64;
  /// Name for tables and messages.
  static constexpr const char* name() noexcept { return "saarcor"; }

  /// Flattens the instances of `scene` and builds the kd-tree; throws std::invalid_argument if
  /// the scene is malformed.
  explicit SaarcorBackend(const Scene& scene) : geometry_(scene, "igi::SaarcorBackend") {
    build();
  }

  /// Not copyable: the counters are atomics shared by tracing threads.
  SaarcorBackend(const SaarcorBackend&) = delete;
  /// Not copyable: the counters are atomics shared by tracing threads.
  SaarcorBackend& operator=(const SaarcorBackend&) = delete;

  /// Closest hit of the rays in `mask`: hit lanes get tfar = distance, world-space Ng and ids,
  /// missing lanes get invalid ids, lanes outside `mask` are untouched. N is 64 or 1.
  template <int N>
    requires(N == width || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, const vmask<N>& mask) const noexcept {
    trace<N, false>(rays, &hits, mask);
  }

  /// Lanes of `mask` whose interval [tnear, tfar] is blocked; those get tfar = -inf.
  template <int N>
    requires(N == width || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, const vmask<N>& mask) const noexcept {
    return trace<N, true>(rays, nullptr, mask);
  }

  /// intersect() with a coherence hint, which this backend does not need (same result).
  template <int N>
    requires(N == width || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, Coherence, const vmask<N>& mask) const noexcept {
    intersect(rays, hits, mask);
  }

  /// occluded() with a coherence hint, which this backend does not need (same result).
  template <int N>
    requires(N == width || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, Coherence, const vmask<N>& mask) const noexcept {
    return occluded(rays, mask);
  }

  /// Moves instance `index`; the tree is rebuilt at commit().
  void set_instance_transform(int index, const glm::mat4& transform) { geometry_.set_instance_transform(index, transform); }

  /// Replaces the vertex positions of mesh `index` (same count); the tree is rebuilt at commit().
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) { geometry_.set_mesh_positions(index, positions); }

  /// Rebuilds the kd-tree from the current transforms and positions (SaarCOR flattens instances).
  void commit() { build(); }

  /// The counters since the last reset_stats(); safe while other threads trace.
  SaarcorStats stats() const noexcept {
    SaarcorStats s;
    s.packets = counters_.packets.load(std::memory_order_relaxed);
    s.rays = counters_.rays.load(std::memory_order_relaxed);
    s.traversal_steps = counters_.traversal_steps.load(std::memory_order_relaxed);
    s.leaf_visits = counters_.leaf_visits.load(std::memory_order_relaxed);
    s.triangle_tests = counters_.triangle_tests.load(std::memory_order_relaxed);
    s.ray_triangle_tests = counters_.ray_triangle_tests.load(std::memory_order_relaxed);
    s.kd_node_bytes = counters_.kd_node_bytes.load(std::memory_order_relaxed);
    s.triangle_bytes = counters_.triangle_bytes.load(std::memory_order_relaxed);
    s.active_lanes = counters_.active_lanes.load(std::memory_order_relaxed);
    s.lane_slots = counters_.lane_slots.load(std::memory_order_relaxed);
    return s;
  }

  /// Sets every counter to zero (call between frames).
  void reset_stats() const noexcept {
    for (std::atomic<std::uint64_t>* c : counters_.all()) c->store(0, std::memory_order_relaxed);
  }

  /// Number of kd-tree nodes.
  std::size_t node_count() const noexcept { return nodes_.size(); }
  /// Triangle references held by all leaves (a triangle straddling a split is referenced twice).
  std::size_t reference_count() const noexcept { return references_.size(); }
  /// Depth of the deepest leaf.
  int depth() const noexcept { return depth_; }

 private:
  /// A kd-tree node in 8 bytes, as SaarCOR stores them. Inner: `word` = axis | (first child << 2)
  /// (children are adjacent), `value` = split position. Leaf: `word` = 3 | (first reference << 2),
  /// `value` holds the reference count as bits.
  struct KdNode {
    std::uint32_t word;  ///< Axis (or 3 for a leaf) in the low 2 bits, index above.
    float value;         ///< Split position, or the leaf's reference count (bit pattern).

    bool leaf() const noexcept { return (word & 3u) == 3u; }
    int axis() const noexcept { return int(word & 3u); }
    std::uint32_t index() const noexcept { return word >> 2; }
    std::uint32_t count() const noexcept { return std::bit_cast<std::uint32_t>(value); }
  };
  static_assert(sizeof(KdNode) == 8, "SaarCOR kd-nodes are 8 bytes");

  /// A leaf's triangle reference: a 32-bit index.
  using Reference = std::uint32_t;

  /// Per-frame counters, accumulated per call and added atomically.
  struct Counters {
    std::atomic<std::uint64_t> packets{0}, rays{0}, traversal_steps{0}, leaf_visits{0}, triangle_tests{0},
        ray_triangle_tests{0}, kd_node_bytes{0}, triangle_bytes{0}, active_lanes{0}, lane_slots{0};
    std::array<std::atomic<std::uint64_t>*, 10> all() noexcept {
      return {&packets, &rays, &traversal_steps, &leaf_visits, &triangle_tests, &ray_triangle_tests, &kd_node_bytes,
              &triangle_bytes, &active_lanes, &lane_slots};
    }
    void add(const SaarcorStats& s) noexcept {
      packets.fetch_add(s.packets, std::memory_order_relaxed);
      rays.fetch_add(s.rays, std::memory_order_relaxed);
      traversal_steps.fetch_add(s.traversal_steps, std::memory_order_relaxed);
      leaf_visits.fetch_add(s.leaf_visits, std::memory_order_relaxed);
      triangle_tests.fetch_add(s.triangle_tests, std::memory_order_relaxed);
      ray_triangle_tests.fetch_add(s.ray_triangle_tests, std::memory_order_relaxed);
      kd_node_bytes.fetch_add(s.kd_node_bytes, std::memory_order_relaxed);
      triangle_bytes.fetch_add(s.triangle_bytes, std::memory_order_relaxed);
      active_lanes.fetch_add(s.active_lanes, std::memory_order_relaxed);
      lane_slots.fetch_add(s.lane_slots, std::memory_order_relaxed);
    }
  };

  // --- Build: binned surface area heuristic over triangle bounds clipped to the node. ---

  /// SAH cost of one traversal step relative to one triangle test (SaarCOR's units are close).
  static constexpr float traversal_cost = 1.0f;
  /// SAH cost of one ray-triangle test.
  static constexpr float intersection_cost = 1.5f;
  /// Cost factor for a split that cuts off empty space, which is cheap to traverse (Havran's 0.8).
  static constexpr float empty_space_bonus = 0.8f;
  /// Candidate planes per axis and node: fine enough that binning costs little tree quality.
  static constexpr int bin_count = 64;
  /// Hard depth limit: kd-trees beyond ~60 levels gain nothing and the stack below must hold it.
  static constexpr int max_depth_limit = 60;

  struct BuildItem {
    Bounds bounds;   ///< The triangle's bounds clipped to the current node.
    Reference triangle;  ///< Index into triangles_.
  };

  static float area(const Bounds& b) noexcept {
    const glm::vec3 e = glm::max(b.extent(), glm::vec3(0.0f));
    return 2.0f * (e.x * e.y + e.y * e.z + e.z * e.x);
  }

  void build() {
    triangles_ = geometry_.triangles();
    nodes_.clear();
    references_.clear();
    depth_ = 0;
    scene_bounds_ = Bounds{};
    std::vector<BuildItem> items;
    items.reserve(triangles_.size());
    for (std::size_t i = 0; i < triangles_.size(); ++i) {
      const Bounds b = triangles_[i].bounds();
      scene_bounds_.extend(b);
      items.push_back({b, Reference(i)});
    }
    nodes_.push_back({});
    if (triangles_.empty()) {
      make_leaf(0, items);
      return;
    }
    // Havran's rule of thumb for kd-tree depth: 8 + 1.3 log2(n).
    const int max_depth = std::min(max_depth_limit, int(8.0 + 1.3 * std::log2(double(triangles_.size()))));
    build_node(0, scene_bounds_, std::move(items), 0, max_depth);
  }

  void make_leaf(std::size_t node, const std::vector<BuildItem>& items) {
    nodes_[node].word = (std::uint32_t(references_.size()) << 2) | 3u;
    nodes_[node].value = std::bit_cast<float>(std::uint32_t(items.size()));
    for (const BuildItem& item : items) references_.push_back(item.triangle);
  }

  void build_node(std::size_t node, const Bounds& box, std::vector<BuildItem> items, int depth, int max_depth) {
    depth_ = std::max(depth_, depth);
    const float leaf_cost = intersection_cost * float(items.size());
    const float box_area = area(box);
    if (items.size() <= 2 || depth >= max_depth || box_area <= 0.0f) return make_leaf(node, items);

    float best_cost = leaf_cost;
    int best_axis = -1;
    float best_split = 0.0f;
    for (int axis = 0; axis < 3; ++axis) {
      const float lower = box.lower[axis], extent = box.upper[axis] - box.lower[axis];
      if (!(extent > 0.0f)) continue;
      std::array<int, bin_count> starts{}, ends{};
      const auto bin = [&](float x) { return std::clamp(int(float(bin_count) * (x - lower) / extent), 0, bin_count - 1); };
      for (const BuildItem& item : items) {
        ++starts[std::size_t(bin(item.bounds.lower[axis]))];
        ++ends[std::size_t(bin(item.bounds.upper[axis]))];
      }
      // Plane k sits between bins k-1 and k; left holds what starts below it, right what ends at or above it.
      int left = 0, right = int(items.size());
      for (int k = 1; k < bin_count; ++k) {
        left += starts[std::size_t(k - 1)];
        right -= ends[std::size_t(k - 1)];
        const float split = lower + extent * float(k) / float(bin_count);
        Bounds below = box, above = box;
        below.upper[axis] = split;
        above.lower[axis] = split;
        float cost = traversal_cost + intersection_cost * (area(below) * float(left) + area(above) * float(right)) / box_area;
        if (left == 0 || right == 0) cost *= empty_space_bonus;
        if (cost < best_cost) {
          best_cost = cost;
          best_axis = axis;
          best_split = split;
        }
      }
    }
    if (best_axis < 0) return make_leaf(node, items);

    // Closed cells: a triangle touching the plane goes to both sides, so no ray can slip between.
    std::vector<BuildItem> below_items, above_items;
    Bounds below = box, above = box;
    below.upper[best_axis] = best_split;
    above.lower[best_axis] = best_split;
    for (const BuildItem& item : items) {
      if (item.bounds.lower[best_axis] <= best_split) {
        BuildItem clipped = item;
        clipped.bounds.upper[best_axis] = std::min(clipped.bounds.upper[best_axis], best_split);
        below_items.push_back(clipped);
      }
      if (item.bounds.upper[best_axis] >= best_split) {
        BuildItem clipped = item;
        clipped.bounds.lower[best_axis] = std::max(clipped.bounds.lower[best_axis], best_split);
        above_items.push_back(clipped);
      }
    }
    // A split that separates nothing would recurse forever.
    if (below_items.size() == items.size() && above_items.size() == items.size()) return make_leaf(node, items);
    items.clear();
    items.shrink_to_fit();

    const auto children = std::uint32_t(nodes_.size());
    nodes_[node].word = (children << 2) | std::uint32_t(best_axis);
    nodes_[node].value = best_split;
    nodes_.push_back({});
    nodes_.push_back({});
    build_node(children, below, std::move(below_items), depth + 1, max_depth);
    build_node(children + 1, above, std::move(above_items), depth + 1, max_depth);
  }

  // --- Traversal: one packet, one stack, per-ray parameter intervals. ---

  /// Lanes as bits of one word: SaarCOR's per-packet activity mask.
  using LaneBits = std::uint64_t;

  /// One traversal stack entry: a node still to visit and each ray's interval inside it.
  template <int N>
  struct StackEntry {
    std::uint32_t node;          ///< Node index.
    LaneBits active;             ///< Rays that need the node.
    std::array<float, N> t0, t1;  ///< Per-ray interval within the node.
  };

  /// Widening of the split-plane distance on both sides: the two children's intervals overlap by
  /// a few ulps (relative 2^-21 = 4.8e-7) so a hit on the plane itself is never lost to rounding.
  static constexpr float split_slack = 4.8e-7f;

  template <int N, bool any_hit>
  vmask<N> trace(RayPacket<N>& rays, HitPacket<N>* hits, const vmask<N>& mask) const noexcept {
    SaarcorStats count;
    count.packets = 1;
    std::array<glm::vec3, N> origin, direction;
    std::array<float, N> best{};     // tfar, shrinking to the closest hit so far (zero on inactive lanes, never read).
    std::array<TriangleHit, N> found;
    std::array<const WorldTriangle*, N> hit_triangle{};
    vmask<N> blocked;

    StackEntry<N> entry;
    entry.node = 0;
    entry.active = 0;
    for (int lane = 0; lane < N; ++lane) {
      if (!mask[lane]) continue;
      const Ray ray = ray_of(rays, lane);
      origin[std::size_t(lane)] = ray.origin;
      direction[std::size_t(lane)] = ray.direction;
      best[std::size_t(lane)] = ray.tfar;
      ++count.rays;
      if (!triangles_.empty() && clip_to_box(ray, scene_bounds_, entry.t0[std::size_t(lane)], entry.t1[std::size_t(lane)]))
        entry.active |= LaneBits(1) << lane;
    }
    std::array<ShearedRay, N> sheared = make_sheared<N>(origin, direction, entry.active);

    // The tree is at most max_depth_limit deep and each level pushes at most one sibling.
    std::array<StackEntry<N>, max_depth_limit + 2> stack;
    int top = 0;
    if (entry.active) stack[top++] = entry;
    while (top > 0) {
      StackEntry<N>& current = stack[--top];
      std::uint32_t node_index = current.node;
      LaneBits active = current.active;
      std::array<float, N> t0 = current.t0, t1 = current.t1;
      // Rays that have meanwhile found a closer hit (or were blocked) drop out.
      for (LaneBits bits = active; bits; bits &= bits - 1) {
        const int lane = std::countr_zero(bits);
        if (t0[std::size_t(lane)] > best[std::size_t(lane)] || (any_hit && blocked[lane])) active &= ~(LaneBits(1) << lane);
      }
      if (!active) continue;

      for (;;) {
        const KdNode node = nodes_[node_index];
        count.kd_node_bytes += sizeof(KdNode);
        count.active_lanes += std::uint64_t(std::popcount(active));
        count.lane_slots += N;
        if (node.leaf()) {
          ++count.leaf_visits;
          visit_leaf<N, any_hit>(node, active, sheared, rays, best, found, hit_triangle, blocked, count);
          break;
        }
        ++count.traversal_steps;
        const int axis = node.axis();
        const float split = node.value;
        LaneBits below = 0, above = 0;
        // Zeroed, not left indeterminate: only the lanes of `below` and `above` are written, but
        // the arrays are copied whole onto the stack and into t0 and t1.
        std::array<float, N> below_t0{}, below_t1{}, above_t0{}, above_t1{};
        bool first_ray = true, below_first = true;
        for (LaneBits bits = active; bits; bits &= bits - 1) {
          const int lane = std::countr_zero(bits);
          const std::size_t l = std::size_t(lane);
          const float o = origin[l][axis], d = direction[l][axis];
          const float end = std::min(t1[l], best[l]);
          float near_t0 = t0[l], near_t1 = end, far_t0 = t0[l], far_t1 = end;
          bool near_is_below;
          bool use_near = true, use_far = true;
          if (d == 0.0f) {
            // Parallel to the plane: the ray stays on its origin's side (both if on the plane).
            near_is_below = o <= split;
            use_far = o == split;
          } else {
            const float t = (split - o) / d;
            near_is_below = d > 0.0f;
            near_t1 = std::min(end, t + split_slack * std::abs(t));
            far_t0 = std::max(t0[l], t - split_slack * std::abs(t));
            use_near = t0[l] <= near_t1;
            use_far = far_t0 <= end;
          }
          if (first_ray) below_first = near_is_below, first_ray = false;
          const LaneBits bit = LaneBits(1) << lane;
          if (use_near) {
            (near_is_below ? below : above) |= bit;
            (near_is_below ? below_t0 : above_t0)[l] = near_t0;
            (near_is_below ? below_t1 : above_t1)[l] = near_t1;
          }
          if (use_far) {
            (near_is_below ? above : below) |= bit;
            (near_is_below ? above_t0 : below_t0)[l] = far_t0;
            (near_is_below ? above_t1 : below_t1)[l] = far_t1;
          }
        }
        // The packet goes to the first ray's near side first; the other side waits on the stack.
        const std::uint32_t below_child = node.index(), above_child = node.index() + 1;
        const LaneBits near_bits = below_first ? below : above, far_bits = below_first ? above : below;
        if (far_bits) {
          StackEntry<N>& pushed = stack[top++];
          pushed.node = below_first ? above_child : below_child;
          pushed.active = far_bits;
          pushed.t0 = below_first ? above_t0 : below_t0;
          pushed.t1 = below_first ? above_t1 : below_t1;
        }
        if (!near_bits) break;
        node_index = below_first ? below_child : above_child;
        active = near_bits;
        t0 = below_first ? below_t0 : above_t0;
        t1 = below_first ? below_t1 : above_t1;
      }
    }

    for (int lane = 0; lane < N; ++lane) {
      if (!mask[lane]) continue;
      const std::size_t l = std::size_t(lane);
      if constexpr (any_hit) {
        if (blocked[lane]) rays.tfar[lane] = -std::numeric_limits<float>::infinity();
      } else {
        HitPacket<N>& h = *hits;
        if (hit_triangle[l]) {
          rays.tfar[lane] = found[l].t;
          h.Ng_x[lane] = found[l].normal.x;
          h.Ng_y[lane] = found[l].normal.y;
          h.Ng_z[lane] = found[l].normal.z;
          h.u[lane] = found[l].u;
          h.v[lane] = found[l].v;
          h.primID[lane] = hit_triangle[l]->primitive;
          h.geomID[lane] = hit_triangle[l]->mesh;
          h.instID[lane] = hit_triangle[l]->instance;
        } else {
          h.Ng_x[lane] = h.Ng_y[lane] = h.Ng_z[lane] = h.u[lane] = h.v[lane] = 0.0f;
          h.primID[lane] = h.geomID[lane] = h.instID[lane] = invalid_id;
        }
      }
    }
    counters_.add(count);
    return blocked;
  }

  template <int N>
  static std::array<ShearedRay, N> make_sheared(const std::array<glm::vec3, N>& origin,
                                                const std::array<glm::vec3, N>& direction, LaneBits active) noexcept {
    std::array<ShearedRay, N> sheared;
    for (int lane = 0; lane < N; ++lane)
      if (active & (LaneBits(1) << lane))
        sheared[std::size_t(lane)] = ShearedRay(Ray{origin[std::size_t(lane)], direction[std::size_t(lane)], 0.0f, 0.0f});
    return sheared;
  }

  template <int N, bool any_hit>
  void visit_leaf(const KdNode& node, LaneBits active, const std::array<ShearedRay, N>& sheared, const RayPacket<N>& rays,
                  std::array<float, N>& best, std::array<TriangleHit, N>& found,
                  std::array<const WorldTriangle*, N>& hit_triangle, vmask<N>& blocked, SaarcorStats& count) const noexcept {
    const std::uint32_t first = node.index(), n = node.count();
    for (std::uint32_t r = first; r < first + n && active; ++r) {
      const WorldTriangle& triangle = triangles_[references_[r]];
      ++count.triangle_tests;
      count.triangle_bytes += sizeof(Reference) + sizeof(WorldTriangle);
      for (LaneBits bits = active; bits; bits &= bits - 1) {
        const int lane = std::countr_zero(bits);
        const std::size_t l = std::size_t(lane);
        ++count.ray_triangle_tests;
        TriangleHit hit;
        if (!intersect_triangle(sheared[l], rays.tnear[lane], best[l], triangle.v0, triangle.v1, triangle.v2, hit))
          continue;
        if constexpr (any_hit) {
          blocked.set(lane, true);
          active &= ~(LaneBits(1) << lane);
        } else if (hit_triangle[l] == nullptr || hit.t < found[l].t) {
          found[l] = hit;
          hit_triangle[l] = &triangle;
          best[l] = hit.t;
        }
      }
    }
  }

  FlattenedGeometry geometry_;  ///< What is traced, as of the last update.
  std::vector<WorldTriangle> triangles_;  ///< Flattened world triangles.
  std::vector<KdNode> nodes_;             ///< Node 0 is the root.
  std::vector<Reference> references_;     ///< Leaf triangle lists.
  Bounds scene_bounds_;                   ///< Bounds of all triangles.
  int depth_ = 0;                         ///< Deepest leaf.
  mutable Counters counters_;             ///< Hardware counters.
};

static_assert(Backend<SaarcorBackend>);

}  // namespace igi
