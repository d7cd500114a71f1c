#pragma once
// The cross-check harness: the same seeded rays traced by a backend under test and by
// ReferenceBackend<1> (the ground truth), compared ray by ray. One harness for every backend and
// width. The scenes (a triangle soup, an instanced two-level scene, the Cornell box, the bunny)
// and ray kinds (coherent camera rays, shadow rays towards a light, random rays, rays with zero
// direction components, rays starting on surfaces) exercise what a backend can get wrong:
// watertightness at shared edges, instance transforms, rays parallel to an axis, and
// self-intersection at the surface a ray starts on.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/backends/backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/world_triangles.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/scene.hpp"


#include "scenes.hpp"

namespace igi::testing {

// ---------------------------------------------------------------------------------------------
// Scenes built in code.

/// A UV sphere of `rings` x `segments` quads: closed, its triangles sharing every vertex they meet
/// at (the seam's too: a repeated column of vertices at phi = 2 pi would round to a crack of about
/// 1e-7 of the radius), so shared edges and vertices are everywhere and no ray may pass between.
inline Mesh sphere_mesh(int rings, int segments, float radius) {
  Mesh mesh;
  mesh.name = "sphere";
  const float pi = 3.14159265358979f;
  for (int r = 0; r <= rings; ++r)
    for (int s = 0; s < segments; ++s) {
      const float theta = pi * float(r) / float(rings), phi = 2.0f * pi * float(s) / float(segments);
      // Exactly zero at both poles (sinf(pi) is 8.7e-8, which would make pole slivers), and the
      // bottom pole exactly at -radius, so every pole vertex is the same point.
      const float ring_radius = (r == 0 || r == rings) ? 0.0f : radius * std::sin(theta);
      const float height = r == rings ? -radius : radius * std::cos(theta);
      mesh.positions.emplace_back(ring_radius * std::cos(phi), height, ring_radius * std::sin(phi));
    }
  const auto vertex = [&](int r, int s) { return std::uint32_t(r * segments + s % segments); };
  for (int r = 0; r < rings; ++r)
    for (int s = 0; s < segments; ++s) {
      // At the poles one triangle of each quad has two vertices at the pole: it is left out
      // rather than kept as a zero-area sliver.
      if (r != rings - 1) mesh.triangles.emplace_back(vertex(r, s), vertex(r + 1, s), vertex(r + 1, s + 1));
      if (r != 0) mesh.triangles.emplace_back(vertex(r, s), vertex(r + 1, s + 1), vertex(r, s + 1));
    }
  return mesh;
}

/// A flat n x n grid of quads in the xz plane, [-1, 1]^2: axis-aligned shared edges.
inline Mesh grid_mesh(int n) {
  Mesh mesh;
  mesh.name = "grid";
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      mesh.positions.emplace_back(-1.0f + 2.0f * float(j) / float(n), 0.0f, -1.0f + 2.0f * float(i) / float(n));
  const auto vertex = [&](int i, int j) { return std::uint32_t(i * (n + 1) + j); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      mesh.triangles.emplace_back(vertex(i, j), vertex(i + 1, j), vertex(i + 1, j + 1));
      mesh.triangles.emplace_back(vertex(i, j), vertex(i + 1, j + 1), vertex(i, j + 1));
    }
  return mesh;
}

/// `count` random triangles of edge up to `size` in the unit cube, seeded.
inline Mesh soup_mesh(int count, float size, std::uint32_t seed) {
  Mesh mesh;
  mesh.name = "soup";
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f), offset(-size, size);
  for (int t = 0; t < count; ++t) {
    const glm::vec3 c(unit(rng), unit(rng), unit(rng));
    for (int k = 0; k < 3; ++k) mesh.positions.push_back(c + glm::vec3(offset(rng), offset(rng), offset(rng)));
    mesh.triangles.emplace_back(3 * t, 3 * t + 1, 3 * t + 2);
  }
  return mesh;
}

/// One instance of one mesh: a random triangle soup.
inline Scene soup_scene() {
  Scene scene;
  scene.name = "soup";
  scene.meshes.push_back(soup_mesh(3000, 0.08f, 7));
  scene.instances.push_back({"soup", 0, glm::mat4(1.0f)});
  return scene;
}

/// A floor grid, three rotated/scaled spheres sharing one mesh and a small soup: two-level scene.
inline Scene instanced_scene() {
  Scene scene;
  scene.name = "instanced";
  scene.meshes.push_back(grid_mesh(16));
  scene.meshes.push_back(sphere_mesh(12, 24, 0.5f));
  scene.meshes.push_back(soup_mesh(400, 0.15f, 11));
  scene.instances.push_back({"floor", 0, glm::scale(glm::mat4(1.0f), glm::vec3(3.0f, 1.0f, 3.0f))});
  glm::mat4 a = glm::translate(glm::mat4(1.0f), glm::vec3(-1.2f, 0.5f, 0.3f));
  glm::mat4 b = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.9f, 0.8f, -0.4f)), 0.7f, glm::vec3(1, 1, 0));
  b = glm::scale(b, glm::vec3(1.5f, 0.8f, 1.0f));
  glm::mat4 c = glm::translate(glm::mat4(1.0f), glm::vec3(0.2f, 1.6f, 1.1f));
  scene.instances.push_back({"sphere a", 1, a});
  scene.instances.push_back({"sphere b", 1, b});
  scene.instances.push_back({"sphere c", 1, c});
  scene.instances.push_back({"soup", 2, glm::translate(glm::mat4(1.0f), glm::vec3(-0.5f, 0.2f, -1.5f))});
  return scene;
}

/// Where instance 2 of instanced_scene() moves to in the "after a move" case.
inline glm::mat4 moved_transform() {
  return glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(-0.3f, 1.0f, -0.8f)), -1.1f, glm::vec3(0, 1, 1));
}

/// Mesh 1 (the sphere) of instanced_scene() squashed into a wobbly ellipsoid: the "changed vertices" case.
inline std::vector<glm::vec3> deformed_sphere_positions(const Scene& scene) {
  std::vector<glm::vec3> positions = scene.meshes[1].positions;
  for (glm::vec3& p : positions) p = glm::vec3(p.x * 1.3f, p.y * 0.6f + 0.1f * std::sin(8.0f * p.x), p.z);
  return positions;
}

// ---------------------------------------------------------------------------------------------
// Rays.

/// One ray of a test set; inactive rays are masked off and carry garbage.
struct TestRay {
  glm::vec3 origin{0.0f}, direction{0.0f};  // Origin and direction.
  float tnear = 0.0f, tfar = 0.0f;          // Interval.
  bool active = true;                       // In the packet mask?
};

/// A named set of rays, in packet order (consecutive W rays form a packet).
struct RaySet {
  std::string kind;            // For messages.
  std::vector<TestRay> rays;   // Multiple of 64 long.
};

/// Scene diameter: the length scale of every tolerance.
inline float diameter(const Scene& scene) { return glm::length(scene.bounds().extent()); }

/// Tolerance of origins placed on surfaces ("rays starting on a surface"): the caller's tnear.
/// 1e-4 of the scene diameter is ~1000 float ulps of the coordinates, well above the rounding of
/// a hit point, and far below any feature of the test scenes.
inline float surface_offset(const Scene& scene) { return 1e-4f * diameter(scene); }

/// x, y of the `index`-th pixel of an 8x8 tile in Morton order: any run of 4, 8, 16 or 64
/// consecutive indices is a compact 2x2, 4x2, 4x4 or 8x8 block (coherent packets at every width).
inline glm::ivec2 morton_pixel(int index) {
  glm::ivec2 p(0);
  for (int bit = 0; bit < 3; ++bit) {
    p.x |= ((index >> (2 * bit)) & 1) << bit;
    p.y |= ((index >> (2 * bit + 1)) & 1) << bit;
  }
  return p;
}

/// Primary rays of a `size` x `size` pinhole image from `eye` towards `target`, in tile order.
inline RaySet camera_rays(const glm::vec3& eye, const glm::vec3& target, float fov, int size) {
  RaySet set{"coherent camera rays", {}};
  const glm::vec3 forward = glm::normalize(target - eye);
  const glm::vec3 right = glm::normalize(glm::cross(forward, std::abs(forward.y) > 0.99f ? glm::vec3(1, 0, 0) : glm::vec3(0, 1, 0)));
  const glm::vec3 up = glm::cross(right, forward);
  const float scale = std::tan(0.5f * fov);
  for (int ty = 0; ty < size; ty += 8)
    for (int tx = 0; tx < size; tx += 8)
      for (int i = 0; i < 64; ++i) {
        const glm::ivec2 p = glm::ivec2(tx, ty) + morton_pixel(i);
        const float x = (2.0f * (float(p.x) + 0.5f) / float(size) - 1.0f) * scale;
        const float y = (1.0f - 2.0f * (float(p.y) + 0.5f) / float(size)) * scale;
        set.rays.push_back({eye, glm::normalize(forward + x * right + y * up), 0.0f, std::numeric_limits<float>::infinity()});
      }
  return set;
}

/// Uniform random unit vector.
inline glm::vec3 random_direction(std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(-1.0f, 1.0f);
  for (;;) {
    const glm::vec3 d(unit(rng), unit(rng), unit(rng));
    const float len2 = glm::dot(d, d);
    // Rejecting very short candidates keeps normalize() away from denormals.
    if (len2 > 1e-4f && len2 <= 1.0f) return d / std::sqrt(len2);
  }
}

/// Random origins in the (slightly grown) scene box, random directions; ~1 in 8 lanes masked off.
inline RaySet random_rays(const Scene& scene, int count, std::uint32_t seed) {
  RaySet set{"random rays", {}};
  std::mt19937 rng(seed);
  const Bounds b = scene.bounds();
  const glm::vec3 lower = b.lower - 0.1f * b.extent(), upper = b.upper + 0.1f * b.extent();
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (int i = 0; i < count; ++i) {
    TestRay ray;
    ray.origin = lower + glm::vec3(unit(rng), unit(rng), unit(rng)) * (upper - lower);
    ray.direction = random_direction(rng) * (0.5f + 2.0f * unit(rng));  // Not unit length on purpose.
    ray.tnear = 0.0f;
    ray.tfar = std::numeric_limits<float>::infinity();
    ray.active = unit(rng) > 0.125f;
    set.rays.push_back(ray);
  }
  return set;
}

/// Random rays whose direction has one or two components exactly zero (axis-parallel slabs).
inline RaySet zero_component_rays(const Scene& scene, int count, std::uint32_t seed) {
  RaySet set = random_rays(scene, count, seed);
  set.kind = "rays with a zero direction component";
  std::mt19937 rng(seed + 1);
  for (std::size_t i = 0; i < set.rays.size(); ++i) {
    glm::vec3& d = set.rays[i].direction;
    const int axis = int(rng() % 3);
    d[axis] = 0.0f;
    if (i % 3 == 0) d[(axis + 1) % 3] = 0.0f;
    if (glm::dot(d, d) == 0.0f) d[(axis + 2) % 3] = 1.0f;
  }
  return set;
}

/// A uniformly random point on a random world triangle, with its geometric normal.
inline std::pair<glm::vec3, glm::vec3> random_surface_point(const std::vector<WorldTriangle>& triangles, std::mt19937& rng) {
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (;;) {
    const WorldTriangle& t = triangles[rng() % triangles.size()];
    const glm::vec3 n = glm::cross(t.v1 - t.v0, t.v2 - t.v0);
    if (glm::dot(n, n) == 0.0f) continue;
    float a = unit(rng), b = unit(rng);
    if (a + b > 1.0f) a = 1.0f - a, b = 1.0f - b;
    return {t.v0 + a * (t.v1 - t.v0) + b * (t.v2 - t.v0), glm::normalize(n)};
  }
}

/// Rays leaving random surface points in random directions (both sides), tnear = surface_offset.
inline RaySet surface_rays(const Scene& scene, int count, std::uint32_t seed) {
  RaySet set{"rays starting on a surface", {}};
  std::mt19937 rng(seed);
  const std::vector<WorldTriangle> triangles = world_triangles(scene);
  for (int i = 0; i < count; ++i) {
    const auto [point, normal] = random_surface_point(triangles, rng);
    glm::vec3 d = random_direction(rng);
    // Half the rays leave along the normal's side, half go through the surface.
    if ((glm::dot(d, normal) > 0.0f) != (i % 2 == 0)) d = -d;
    set.rays.push_back({point, d, surface_offset(scene), std::numeric_limits<float>::infinity()});
  }
  return set;
}

/// Shadow rays from the surface points seen by `camera` to `light` (direction = light - point,
/// interval [offset, 1 - offset]); camera rays that missed give masked-off lanes.
template <class Reference>
RaySet shadow_rays(const Scene& scene, const Reference& reference, const RaySet& camera, const glm::vec3& light) {
  RaySet set{"coherent shadow rays to a point", {}};
  const float offset = surface_offset(scene);
  for (const TestRay& c : camera.rays) {
    RayPacket<1> ray;
    HitPacket<1> hit;
    ray.set(vec3<1>(c.origin), vec3<1>(c.direction), vfloat<1>(c.tnear), vfloat<1>(c.tfar), vmask<1>(true));
    hit.clear();
    reference.intersect(ray, hit, vmask<1>(true));
    TestRay shadow;
    shadow.active = hit.geomID[0] != invalid_id;
    const glm::vec3 point = c.origin + ray.tfar[0] * c.direction;
    shadow.origin = shadow.active ? point : glm::vec3(0.0f);
    shadow.direction = light - shadow.origin;
    const float length = glm::length(shadow.direction);
    shadow.tnear = offset / std::max(length, offset);
    shadow.tfar = 1.0f - offset / std::max(length, offset);
    set.rays.push_back(shadow);
  }
  return set;
}

// ---------------------------------------------------------------------------------------------
// Results and comparison.

/// What one backend reported for one ray.
struct Result {
  bool hit = false;                                                  // Closest-hit found something.
  float t = 0.0f, u = 0.0f, v = 0.0f;                                // Hit distance and barycentrics.
  std::uint32_t prim = invalid_id, geom = invalid_id, inst = invalid_id;  // Ids.
  std::string describe() const {
    std::ostringstream s;
    if (!hit) return "miss";
    s << "hit t=" << t << " u=" << u << " v=" << v << " prim=" << prim << " mesh=" << geom << " instance=" << inst;
    return s.str();
  }
};

/// Sentinels written to every lane before a call: masked-off lanes must still hold them after.
constexpr float sentinel_float = 12345.5f;
constexpr std::uint32_t sentinel_id = 0xdeadbeefu;

/// Fills `rays` lanes from `set` starting at `first`; inactive lanes get NaN garbage (never traced).
template <int W>
vmask<W> load_packet(const RaySet& set, std::size_t first, RayPacket<W>& rays, HitPacket<W>& hits) {
  vmask<W> mask;
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (int lane = 0; lane < W; ++lane) {
    const TestRay& r = set.rays[first + std::size_t(lane)];
    mask.set(lane, r.active);
    rays.org_x[lane] = r.active ? r.origin.x : nan;
    rays.org_y[lane] = r.active ? r.origin.y : nan;
    rays.org_z[lane] = r.active ? r.origin.z : nan;
    rays.dir_x[lane] = r.active ? r.direction.x : nan;
    rays.dir_y[lane] = r.active ? r.direction.y : nan;
    rays.dir_z[lane] = r.active ? r.direction.z : nan;
    rays.tnear[lane] = r.active ? r.tnear : sentinel_float;
    rays.tfar[lane] = r.active ? r.tfar : sentinel_float;
    rays.time[lane] = 0.0f;
    rays.mask[lane] = invalid_id;
    rays.id[lane] = std::uint32_t(lane);
    rays.flags[lane] = 0;
    hits.Ng_x[lane] = hits.Ng_y[lane] = hits.Ng_z[lane] = hits.u[lane] = hits.v[lane] = sentinel_float;
    hits.primID[lane] = hits.geomID[lane] = hits.instID[lane] = sentinel_id;
  }
  return mask;
}

/// The world-space triangle with these ids in `scene`.
inline WorldTriangle triangle_of(const Scene& scene, std::uint32_t prim, std::uint32_t geom, std::uint32_t inst) {
  const Instance& instance = scene.instances.at(inst);
  REQUIRE(std::uint32_t(instance.mesh) == geom);
  const Mesh& mesh = scene.meshes.at(geom);
  const glm::uvec3 tri = mesh.triangles.at(prim);
  const auto world = [&](std::uint32_t v) { return glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f)); };
  return {world(tri.x), world(tri.y), world(tri.z), prim, geom, inst};
}

/// Barycentric coordinates of `p` projected on triangle `t` (double precision), and the
/// distance of `p` from the triangle's plane.
inline glm::dvec3 barycentrics(const WorldTriangle& t, const glm::vec3& p, double& plane_distance) {
  const glm::dvec3 a(t.v0), b(t.v1), c(t.v2), q(p);
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double area2 = glm::dot(n, n);
  if (area2 == 0.0) {
    plane_distance = std::numeric_limits<double>::infinity();
    return glm::dvec3(-1.0);
  }
  plane_distance = std::abs(glm::dot(q - a, n)) / std::sqrt(area2);
  const double w1 = glm::dot(glm::cross(q - a, c - a), n) / area2;
  const double w2 = glm::dot(glm::cross(b - a, q - a), n) / area2;
  return {1.0 - w1 - w2, w1, w2};
}

/// Agreement thresholds, all relative to the scene diameter D (the coordinates' magnitude).
struct Tolerances {
  /// Hit points may differ by this distance: float carries 2^-24 = 6e-8 of D; the shear, the
  /// division by the determinant and (Embree) the ray's transform into instance space add a few
  /// dozen ulps each, so 2e-5 D (~300 ulps) bounds honest rounding, yet is 1000x smaller than any
  /// triangle of the test scenes.
  double point;
  /// A point "lies on" a triangle if it is within `point` of its plane and its barycentrics
  /// exceed -edge: the same rounding allowance, in units of the triangle's own size.
  double edge;
};

inline Tolerances tolerances(const Scene& scene) { return {2e-5 * double(diameter(scene)), 1e-4}; }

/// True if `p` lies on triangle `t` within the tolerances; `near_edge` reports whether it is
/// within the tolerance of the triangle's boundary (a legitimately ambiguous grazing hit).
inline bool lies_on(const WorldTriangle& t, const glm::vec3& p, const Tolerances& tol, bool* near_edge = nullptr) {
  double plane_distance = 0.0;
  const glm::dvec3 w = barycentrics(t, p, plane_distance);
  const double edge_length = std::max({glm::length(glm::dvec3(t.v1 - t.v0)), glm::length(glm::dvec3(t.v2 - t.v0)),
                                       glm::length(glm::dvec3(t.v2 - t.v1))});
  // Edge tolerance in barycentric units: the absolute rounding allowance over the triangle's size.
  const double slack = tol.edge + tol.point / std::max(edge_length, 1e-30);
  if (near_edge) *near_edge = std::min({w.x, w.y, w.z}) < slack;
  return plane_distance <= tol.point && std::min({w.x, w.y, w.z}) >= -slack;
}

/// Compares one ray's closest hit: "" if they agree, else a message with both values.
inline std::string compare_hits(const Scene& scene, const TestRay& ray, const Result& truth, const Result& tested,
                                const Tolerances& tol) {
  const double dir_length = glm::length(glm::dvec3(ray.direction));
  const auto point = [&](const Result& r) { return ray.origin + r.t * ray.direction; };
  const auto on_edge = [&](const Result& r) {
    bool near_edge = false;
    return lies_on(triangle_of(scene, r.prim, r.geom, r.inst), point(r), tol, &near_edge) && near_edge;
  };
  if (!truth.hit && !tested.hit) return "";
  if (truth.hit != tested.hit) {
    // One backend grazed the silhouette edge of a triangle the other passed by.
    if (on_edge(truth.hit ? truth : tested)) return "";
    return "hit/miss differ";
  }
  if (std::abs(double(truth.t) - double(tested.t)) * dir_length > tol.point) {
    // The nearer hit grazed an edge the other backend passed by, and found what lies behind.
    if (on_edge(truth.t < tested.t ? truth : tested)) return "";
    return "distance differs";
  }
  if (truth.prim == tested.prim && truth.geom == tested.geom && truth.inst == tested.inst) {
    // Barycentrics: same rounding allowance as for the point, in the triangle's units.
    const WorldTriangle t = triangle_of(scene, truth.prim, truth.geom, truth.inst);
    const double size = std::max(glm::length(glm::dvec3(t.v1 - t.v0)), glm::length(glm::dvec3(t.v2 - t.v0)));
    const double slack = tol.edge + tol.point / std::max(size, 1e-30);
    if (std::abs(double(truth.u) - double(tested.u)) > slack || std::abs(double(truth.v) - double(tested.v)) > slack)
      return "barycentrics differ";
    return "";
  }
  // A tie on a shared edge (or overlapping surfaces): fine if the other triangle really holds the point.
  if (tested.inst >= scene.instances.size() || tested.geom >= scene.meshes.size() ||
      tested.prim >= scene.meshes[tested.geom].triangles.size() ||
      std::uint32_t(scene.instances[tested.inst].mesh) != tested.geom)
    return "ids are not a triangle of the scene";
  if (lies_on(triangle_of(scene, tested.prim, tested.geom, tested.inst), point(truth), tol)) return "";
  return "ids differ and the reported triangle does not contain the hit point";
}

/// Formats a ray for a mismatch message.
inline std::string describe(const TestRay& r) {
  std::ostringstream s;
  s.precision(9);
  s << "org=(" << r.origin.x << ", " << r.origin.y << ", " << r.origin.z << ") dir=(" << r.direction.x << ", "
    << r.direction.y << ", " << r.direction.z << ") tnear=" << r.tnear << " tfar=" << r.tfar;
  return s.str();
}

/// Reads lane `lane` of a traced packet into a Result.
template <int W>
Result result_of(const RayPacket<W>& rays, const HitPacket<W>& hits, int lane) {
  Result r;
  r.hit = hits.geomID[lane] != invalid_id;
  r.t = rays.tfar[lane];
  r.u = hits.u[lane];
  r.v = hits.v[lane];
  r.prim = hits.primID[lane];
  r.geom = hits.geomID[lane];
  r.inst = hits.instID[lane];
  return r;
}

/// Closest hits of every ray of `set` traced one at a time by `backend` (the ground truth path).
template <class B>
std::vector<Result> trace_singly(const B& backend, const RaySet& set) {
  std::vector<Result> results(set.rays.size());
  for (std::size_t i = 0; i < set.rays.size(); ++i) {
    if (!set.rays[i].active) continue;
    RayPacket<1> ray;
    HitPacket<1> hit;
    load_packet<1>(set, i, ray, hit);
    backend.intersect(ray, hit, vmask<1>(true));
    results[i] = result_of(ray, hit, 0);
  }
  return results;
}

/// Checks that masked-off lanes of a packet still hold what load_packet put there.
template <int W>
std::string untouched(const RayPacket<W>& before, const RayPacket<W>& rays, const HitPacket<W>& hits,
                      const vmask<W>& mask, bool check_hits) {
  for (int lane = 0; lane < W; ++lane) {
    if (mask[lane]) continue;
    const auto same = [](float a, float b) { return std::memcmp(&a, &b, sizeof a) == 0; };
    if (!same(rays.org_x[lane], before.org_x[lane]) || !same(rays.dir_z[lane], before.dir_z[lane]) ||
        !same(rays.tnear[lane], before.tnear[lane]) || !same(rays.tfar[lane], before.tfar[lane]))
      return "masked-off lane " + std::to_string(lane) + " ray was modified";
    if (check_hits && (hits.geomID[lane] != sentinel_id || hits.primID[lane] != sentinel_id ||
                       hits.instID[lane] != sentinel_id || hits.u[lane] != sentinel_float ||
                       hits.Ng_x[lane] != sentinel_float))
      return "masked-off lane " + std::to_string(lane) + " hit was modified";
  }
  return "";
}

/// Traces `set` with `backend` (packets of B::width) and the reference, and compares closest hits,
/// then occlusion on the same intervals, then occlusion stopping at 0.99 and 1.01 of the
/// reference hit distance. Fails on the first mismatch, printing both values.
template <class B, class Reference>
void cross_check(const Scene& scene, const B& backend, const Reference& reference, const RaySet& set) {
  constexpr int W = B::width;
  INFO("backend " << B::name() << " width " << W << ", scene '" << scene.name << "', " << set.kind);
  REQUIRE(set.rays.size() % W == 0);
  const Tolerances tol = tolerances(scene);
  const std::vector<Result> truth = trace_singly(reference, set);
  int hits = 0, occluded_count = 0;

  // Closest hit.
  for (std::size_t first = 0; first < set.rays.size(); first += W) {
    RayPacket<W> rays, before;
    HitPacket<W> hit_packet;
    const vmask<W> mask = load_packet<W>(set, first, rays, hit_packet);
    before = rays;
    backend.intersect(rays, hit_packet, mask);
    const std::string damage = untouched(before, rays, hit_packet, mask, true);
    if (!damage.empty()) FAIL(damage << " (packet at ray " << first << ")");
    // The same packet as one RayHitPacket, as the pipeline's stream packets are (Embree traces
    // those in place): the same results, and masked-off lanes left alone there too.
    RayHitPacket<W> joined;
    load_packet<W>(set, first, joined.rays, joined.hits);
    backend.intersect(joined.rays, joined.hits, mask);
    const std::string joined_damage = untouched(before, joined.rays, joined.hits, mask, true);
    if (!joined_damage.empty()) FAIL(joined_damage << " (RayHitPacket at ray " << first << ")");
    for (int lane = 0; lane < W; ++lane) {
      const std::size_t i = first + std::size_t(lane);
      if (!mask[lane]) continue;
      const Result tested = result_of(rays, hit_packet, lane);
      const Result joined_result = result_of(joined.rays, joined.hits, lane);
      if (joined_result.hit != tested.hit || joined_result.prim != tested.prim || joined_result.t != tested.t)
        FAIL("closest hit at ray " << i << " differs traced as a RayHitPacket: " << joined_result.describe()
                                   << " against " << tested.describe());
      hits += tested.hit;
      const std::string problem = compare_hits(scene, set.rays[i], truth[i], tested, tol);
      if (!problem.empty())
        FAIL("closest hit: " << problem << " at ray " << i << " " << describe(set.rays[i]) << "\n  reference: "
                             << truth[i].describe() << "\n  " << B::name() << ": " << tested.describe());
    }
  }

  // Occlusion on the same intervals, then at 0.99 (must be free: nothing is nearer than the
  // closest hit) and 1.01 (must be blocked: the closest hit is inside) of the reference distance.
  // Grazing-edge hits are ambiguous for any-hit queries too and are excluded from the last two.
  for (const double stop : {0.0, 0.99, 1.01}) {
    RaySet stopped = set;
    for (std::size_t i = 0; i < stopped.rays.size(); ++i) {
      if (stop == 0.0) continue;
      TestRay& r = stopped.rays[i];
      bool near_edge = false;
      const bool graze = truth[i].hit && lies_on(triangle_of(scene, truth[i].prim, truth[i].geom, truth[i].inst),
                                                 r.origin + truth[i].t * r.direction, tol, &near_edge) && near_edge;
      // 0.99 / 1.01 of a distance within tnear's reach would move the end across tnear itself.
      const bool too_close = truth[i].hit && float(stop) * truth[i].t <= r.tnear * 1.02f;
      r.active = r.active && truth[i].hit && !graze && !too_close;
      if (r.active) r.tfar = float(stop) * truth[i].t;
    }
    const std::vector<Result> expected_hits = stop == 0.0 ? truth : trace_singly(reference, stopped);
    for (std::size_t first = 0; first < stopped.rays.size(); first += W) {
      RayPacket<W> rays, before;
      HitPacket<W> unused;
      const vmask<W> mask = load_packet<W>(stopped, first, rays, unused);
      before = rays;
      const vmask<W> blocked = backend.occluded(rays, mask);
      const std::string damage = untouched(before, rays, unused, mask, false);
      if (!damage.empty()) FAIL("occluded: " << damage << " (packet at ray " << first << ")");
      for (int lane = 0; lane < W; ++lane) {
        const std::size_t i = first + std::size_t(lane);
        if (!mask[lane]) {
          if (blocked[lane]) FAIL("occluded: masked-off lane " << lane << " reported as occluded");
          continue;
        }
        const TestRay& r = stopped.rays[i];
        occluded_count += blocked[lane];
        if (blocked[lane] && rays.tfar[lane] != -std::numeric_limits<float>::infinity())
          FAIL("occluded: occluded lane " << lane << " has tfar " << rays.tfar[lane] << ", not -inf");
        if (!blocked[lane] && rays.tfar[lane] != r.tfar)
          FAIL("occluded: free lane " << lane << " had its tfar changed to " << rays.tfar[lane]);
        bool expected = expected_hits[i].hit;
        if (stop == 0.99) expected = false;
        if (stop == 1.01) expected = true;
        if (blocked[lane] == expected) continue;
        // The any-hit query may legitimately disagree only where the reference's nearest blocker
        // grazes an edge or sits at an end of the interval.
        const double dir_length = glm::length(glm::dvec3(r.direction));
        if (stop == 0.0 && expected_hits[i].hit) {
          // The reference's blocker grazes an edge, or sits at an end of the interval.
          const Result& e = expected_hits[i];
          bool near_edge = false;
          if (lies_on(triangle_of(scene, e.prim, e.geom, e.inst), r.origin + e.t * r.direction, tol, &near_edge) &&
              near_edge)
            continue;
          if ((double(r.tfar) - double(e.t)) * dir_length <= tol.point ||
              (double(e.t) - double(r.tnear)) * dir_length <= tol.point)
            continue;
        }
        if (stop == 0.0 && !expected_hits[i].hit) {
          // Blocked by something the reference sees just outside the interval?
          TestRay longer = r;
          longer.tfar = float(double(r.tfar) + tol.point / dir_length);
          longer.tnear = float(std::max(0.0, double(r.tnear) - tol.point / dir_length));
          if (trace_singly(reference, RaySet{"", {longer}})[0].hit) continue;
        }
        FAIL("occluded (tfar = " << (stop == 0.0 ? std::string("as given") : std::to_string(stop) + " x hit distance")
                                 << "): at ray " << i << " " << describe(r) << "\n  reference: "
                                 << (expected ? "occluded" : "free") << " (" << expected_hits[i].describe() << ")\n  "
                                 << B::name() << ": " << (blocked[lane] ? "occluded" : "free"));
      }
    }
  }
  // The sets are built to exercise both outcomes; a set where nothing hits checks nothing.
  INFO("hits " << hits << ", occluded " << occluded_count);
  CHECK(hits > 0);
  CHECK(occluded_count > 0);
}

/// Every ray kind above on `scene`, seeded; the camera looks from outside the bounds.
template <class B>
void cross_check_all_kinds(const Scene& scene, const B& backend) {
  const ReferenceBackend<1> reference(scene);
  const Bounds b = scene.bounds();
  const glm::vec3 eye = b.center() + glm::vec3(0.3f, 0.4f, 1.2f) * glm::length(b.extent());
  const RaySet camera = camera_rays(eye, b.center(), 0.8f, 64);
  const glm::vec3 light = b.center() + glm::vec3(0.1f, 0.45f, 0.05f) * b.extent();
  cross_check(scene, backend, reference, camera);
  cross_check(scene, backend, reference, shadow_rays(scene, reference, camera, light));
  cross_check(scene, backend, reference, random_rays(scene, 4096, 1234));
  cross_check(scene, backend, reference, zero_component_rays(scene, 2048, 99));
  cross_check(scene, backend, reference, surface_rays(scene, 2048, 4321));
}

}  // namespace igi::testing
