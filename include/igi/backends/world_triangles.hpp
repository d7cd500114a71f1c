#pragma once
/// \file
/// Geometry shared by the backends that flatten instances (reference and SaarCOR): scene
/// validation, world-space triangles with their ids, a watertight ray-triangle test (after Woop,
/// Benthin and Wald, "Watertight Ray/Triangle Intersection", JCGT 2013) and a ray-box slab test.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <span>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/packet.hpp"
#include "igi/scene/scene.hpp"
#include "igi/scene/validate.hpp"

namespace igi {

/// Throws std::invalid_argument naming the first problem that would make `scene` untraceable.
inline void validate_for_tracing(const Scene& scene, const char* backend) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(std::string(backend) + ": " + what); };
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    for (const glm::vec3& p : mesh.positions)
      if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
        fail("mesh " + std::to_string(m) + " ('" + mesh.name + "') has a non-finite vertex position");
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const glm::uvec3& tri = mesh.triangles[t];
      if (tri.x >= mesh.positions.size() || tri.y >= mesh.positions.size() || tri.z >= mesh.positions.size())
        fail("mesh " + std::to_string(m) + " ('" + mesh.name + "') triangle " + std::to_string(t) +
             " indexes a vertex beyond its " + std::to_string(mesh.positions.size()) + " positions");
    }
  }
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    if (instance.mesh < 0 || std::size_t(instance.mesh) >= scene.meshes.size())
      fail("instance " + std::to_string(i) + " ('" + instance.name + "') refers to mesh " +
           std::to_string(instance.mesh) + " but the scene has " + std::to_string(scene.meshes.size()));
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(instance.transform[c][r]))
          fail("instance " + std::to_string(i) + " ('" + instance.name + "') has a non-finite transform");
  }
  try {
    check_scene_extent(scene);
  } catch (const SceneError& error) {
    fail(error.what());
  }
}

/// Throws std::out_of_range unless `index` names one of `count` things of kind `what`.
inline void check_index(int index, std::size_t count, const char* backend, const char* what) {
  if (index < 0 || std::size_t(index) >= count)
    throw std::out_of_range(std::string(backend) + ": " + what + " index " + std::to_string(index) +
                            " is out of range (there are " + std::to_string(count) + ")");
}

/// Throws std::invalid_argument unless `transform` is finite.
inline void check_transform(const glm::mat4& transform, const char* backend) {
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r)
      if (!std::isfinite(transform[c][r]))
        throw std::invalid_argument(std::string(backend) + ": instance transform has a non-finite entry");
}

/// Throws std::invalid_argument unless `positions` can replace the vertices of `mesh`.
inline void check_positions(const Mesh& mesh, std::span<const glm::vec3> positions, const char* backend) {
  if (positions.size() != mesh.positions.size())
    throw std::invalid_argument(std::string(backend) + ": set_mesh_positions got " + std::to_string(positions.size()) +
                                " positions for mesh '" + mesh.name + "' which has " +
                                std::to_string(mesh.positions.size()));
  for (const glm::vec3& p : positions)
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      throw std::invalid_argument(std::string(backend) + ": set_mesh_positions got a non-finite position for mesh '" +
                                  mesh.name + "'");
}

/// Throws std::invalid_argument naming `backend` if `transform` places a vertex of `positions`
/// beyond +-max_scene_coordinate: the limit validate_scene sets, kept by every runtime update.
/// `box` bounds `positions`: if its placed corners are within the limit every vertex is (each
/// transformed coordinate, rounding included, is monotonic in each object-space coordinate), so
/// a move costs O(1) whatever the mesh's size; only a box beyond the limit walks the vertices.
inline void check_extent(const glm::mat4& transform, const Bounds& box, std::span<const glm::vec3> positions,
                         std::string_view instance, std::string_view mesh, const char* backend) {
  const Bounds world = placed(box, transform);
  const glm::vec3 limit(max_scene_coordinate);
  if (world.empty() || (glm::all(glm::lessThanEqual(glm::abs(world.lower), limit)) &&
                        glm::all(glm::lessThanEqual(glm::abs(world.upper), limit))))
    return;
  if (const auto vertex = first_vertex_beyond_limit(transform, positions))
    throw std::invalid_argument(std::string(backend) + ": " +
                                beyond_limit_message(transform, positions, *vertex, instance, mesh));
}

/// One triangle in world space with the ids a hit reports.
struct WorldTriangle {
  ///@{
  glm::vec3 v0, v1, v2;        ///< World-space vertices.
  ///@}
  std::uint32_t primitive;     ///< Triangle index within its mesh.
  std::uint32_t mesh;          ///< Mesh index.
  std::uint32_t instance;      ///< Instance index.
  /// World-space bounds.
  Bounds bounds() const noexcept {
    Bounds b;
    b.extend(v0);
    b.extend(v1);
    b.extend(v2);
    return b;
  }
};

/// Every triangle of every instance, transformed to world space, in instance order.
inline std::vector<WorldTriangle> world_triangles(const Scene& scene) {
  std::vector<WorldTriangle> triangles;
  triangles.reserve(scene.triangle_count());
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const Instance& instance = scene.instances[i];
    const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
    const auto world = [&](std::uint32_t v) { return glm::vec3(instance.transform * glm::vec4(mesh.positions[v], 1.0f)); };
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const glm::uvec3& tri = mesh.triangles[t];
      triangles.push_back({world(tri.x), world(tri.y), world(tri.z), std::uint32_t(t), std::uint32_t(instance.mesh),
                           std::uint32_t(i)});
    }
  }
  return triangles;
}

/// The geometry a flattening backend keeps between frames (mesh positions and triangles, and the
/// instances), with the checked updates ReferenceBackend and SaarcorBackend both take.
class FlattenedGeometry {
 public:
  /// Copies the geometry of `scene`; throws std::invalid_argument naming `backend` if it is malformed.
  FlattenedGeometry(const Scene& scene, const char* backend) : backend_(backend) {
    validate_for_tracing(scene, backend);
    geometry_.meshes.reserve(scene.meshes.size());
    for (const Mesh& mesh : scene.meshes) {
      Mesh copy;
      copy.name = mesh.name;
      copy.positions = mesh.positions;
      copy.triangles = mesh.triangles;
      geometry_.meshes.push_back(std::move(copy));
      boxes_.push_back(mesh_bounds(mesh));
    }
    geometry_.instances = scene.instances;
  }
  /// Moves instance `index`.
  void set_instance_transform(int index, const glm::mat4& transform) {
    check_index(index, geometry_.instances.size(), backend_, "instance");
    check_transform(transform, backend_);
    Instance& instance = geometry_.instances[std::size_t(index)];
    const Mesh& mesh = geometry_.meshes[std::size_t(instance.mesh)];
    check_extent(transform, boxes_[std::size_t(instance.mesh)], mesh.positions, instance.name, mesh.name, backend_);
    instance.transform = transform;
  }
  /// Replaces the vertex positions of mesh `index` (same count).
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) {
    check_index(index, geometry_.meshes.size(), backend_, "mesh");
    Mesh& mesh = geometry_.meshes[std::size_t(index)];
    check_positions(mesh, positions, backend_);
    const Bounds box = bounds_of(positions);
    for (const Instance& instance : geometry_.instances)
      if (instance.mesh == index) check_extent(instance.transform, box, positions, instance.name, mesh.name, backend_);
    mesh.positions.assign(positions.begin(), positions.end());
    boxes_[std::size_t(index)] = box;
  }
  /// The current triangles in world space.
  std::vector<WorldTriangle> triangles() const { return world_triangles(geometry_); }

 private:
  Scene geometry_;             ///< Meshes (positions, triangles) and instances only.
  std::vector<Bounds> boxes_;  ///< Each mesh's object-space bounds, for O(1) checks of a move.
  const char* backend_;        ///< Name in messages.
};

/// One ray, read from lane `lane` of a packet.
struct Ray {
  glm::vec3 origin;     ///< Origin.
  glm::vec3 direction;  ///< Direction, any length.
  float tnear;          ///< Start of the interval.
  float tfar;           ///< End of the interval.
};

/// Lane `lane` of `rays` as a single ray.
template <int W>
Ray ray_of(const RayPacket<W>& rays, int lane) noexcept {
  return {{rays.org_x[lane], rays.org_y[lane], rays.org_z[lane]},
          {rays.dir_x[lane], rays.dir_y[lane], rays.dir_z[lane]},
          rays.tnear[lane],
          rays.tfar[lane]};
}

/// The result of one ray-triangle test.
struct TriangleHit {
  float t;        ///< Distance along the ray (in units of its direction's length).
  ///@{
  float u, v;     ///< Barycentric weights of v1 and v2.
  ///@}
  glm::vec3 normal;  ///< Unnormalized geometric normal (v1 - v0) x (v2 - v0).
};

/// Precomputed shear of one ray, which makes the triangle test watertight: the ray becomes the
/// +z axis, so neighbouring triangles evaluate their shared edge with the same arithmetic.
struct ShearedRay {
  glm::vec3 origin{0.0f};  ///< Ray origin.
  ///@{
  int kx = 0, ky = 1, kz = 2;  ///< Axis permutation: kz is the largest direction component.
  ///@}
  ///@{
  float sx = 0, sy = 0, sz = 0;  ///< Shear constants.
  ///@}
  bool usable = false;  ///< False for a zero or non-finite direction, which hits nothing.

  /// A ray that hits nothing (what unused lanes carry).
  ShearedRay() = default;
  /// Prepares `ray` for triangle tests.
  explicit ShearedRay(const Ray& ray) noexcept : origin(ray.origin) {
    const glm::vec3 d = ray.direction;
    const glm::vec3 a = glm::abs(d);
    kz = a.x > a.y ? (a.x > a.z ? 0 : 2) : (a.y > a.z ? 1 : 2);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    // Keep the triangle's winding: a negative z axis would mirror the sheared frame.
    if (d[kz] < 0.0f) std::swap(kx, ky);
    usable = d[kz] != 0.0f && std::isfinite(d.x) && std::isfinite(d.y) && std::isfinite(d.z);
    if (!usable) return;
    sx = d[kx] / d[kz];
    sy = d[ky] / d[kz];
    sz = 1.0f / d[kz];
  }
};

/// Watertight test of `ray` against triangle (v0, v1, v2) on the closed interval [tnear, tfar].
/// Both faces count; degenerate triangles and rays with a zero direction never hit.
inline bool intersect_triangle(const ShearedRay& ray, float tnear, float tfar, const glm::vec3& v0, const glm::vec3& v1,
                               const glm::vec3& v2, TriangleHit& hit) noexcept {
  if (!ray.usable) return false;
  const glm::vec3 a = v0 - ray.origin, b = v1 - ray.origin, c = v2 - ray.origin;
  const float ax = a[ray.kx] - ray.sx * a[ray.kz], ay = a[ray.ky] - ray.sy * a[ray.kz];
  const float bx = b[ray.kx] - ray.sx * b[ray.kz], by = b[ray.ky] - ray.sy * b[ray.kz];
  const float cx = c[ray.kx] - ray.sx * c[ray.kz], cy = c[ray.ky] - ray.sy * c[ray.kz];
  // Edge functions: the weight of each vertex is the signed area opposite to it. Watertightness
  // needs the two triangles of a shared edge to compute exactly opposite values for it. In float,
  // a compiler that contracts p*q - r*s into fma(p, q, -r*s) (GCC does by default in C++) breaks
  // that symmetry and lets rays through shared edges; in double the products of two floats are
  // exact (48 of 53 bits), so contracted or not the difference is rounded once and stays exactly
  // antisymmetric, and its sign (all the test needs) survives the conversion to float.
  const float w0 = float(double(cx) * double(by) - double(cy) * double(bx));
  const float w1 = float(double(ax) * double(cy) - double(ay) * double(cx));
  const float w2 = float(double(bx) * double(ay) - double(by) * double(ax));
  if ((w0 < 0.0f || w1 < 0.0f || w2 < 0.0f) && (w0 > 0.0f || w1 > 0.0f || w2 > 0.0f)) return false;
  const float determinant = w0 + w1 + w2;
  if (determinant == 0.0f) return false;
  const float az = ray.sz * a[ray.kz], bz = ray.sz * b[ray.kz], cz = ray.sz * c[ray.kz];
  const float scaled_t = w0 * az + w1 * bz + w2 * cz;
  const float t = scaled_t / determinant;
  if (!(t >= tnear && t <= tfar)) return false;
  hit.t = t;
  hit.u = w1 / determinant;
  hit.v = w2 / determinant;
  hit.normal = glm::cross(v1 - v0, v2 - v0);
  return true;
}

/// Parameter interval [t0, t1] where `ray` is inside `box`, clipped to [tnear, tfar]; false if empty.
/// Axes with a zero direction component are handled explicitly (no 0 * inf = NaN).
inline bool clip_to_box(const Ray& ray, const Bounds& box, float& t0, float& t1) noexcept {
  t0 = ray.tnear;
  t1 = ray.tfar;
  for (int axis = 0; axis < 3; ++axis) {
    const float o = ray.origin[axis], d = ray.direction[axis];
    if (d == 0.0f) {
      if (o < box.lower[axis] || o > box.upper[axis]) return false;
      continue;
    }
    const float inverse = 1.0f / d;
    float near = (box.lower[axis] - o) * inverse, far = (box.upper[axis] - o) * inverse;
    if (near > far) std::swap(near, far);
    // Rounding of the two products may shave the last ulp off a box the ray touches: 2 ulps
    // of slack (relative 2^-22) keeps grazing rays inside without admitting any real miss.
    constexpr float slack = 2.4e-7f;
    far += slack * std::abs(far);
    near -= slack * std::abs(near);
    t0 = std::max(t0, near);
    t1 = std::min(t1, far);
    if (t0 > t1) return false;
  }
  return true;
}

}  // namespace igi
