#pragma once
/// \file
/// From traced packets to shading input: `make_surface_hit` turns a ray packet and its hit packet
/// into a world-space `SurfaceHit<W>`. `SceneGeometry` caches the per-instance matrices it needs
/// (rebuild it after instances move).
///
/// The hit position is interpolated from the world-space triangle with the hit's barycentrics
/// rather than computed as origin + t * direction: the barycentric point lies on the triangle's
/// plane to float precision whatever the ray length, so secondary and shadow rays offset from it
/// by a small epsilon do not re-hit the surface they start on.

#include <cmath>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/packet.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/surface_hit.hpp"

namespace igi {

/// Per-instance matrices shading needs, computed once per scene state.
class SceneGeometry {
 public:
  /// Empty cache; `update` fills it.
  SceneGeometry() = default;
  /// Cache for the current instance transforms of `scene`.
  explicit SceneGeometry(const Scene& scene) { update(scene); }

  /// Recomputes the matrices after instance transforms changed.
  void update(const Scene& scene) {
    object_to_world_.clear();
    normal_to_world_.clear();
    object_to_world_.reserve(scene.instances.size());
    normal_to_world_.reserve(scene.instances.size());
    for (const Instance& instance : scene.instances) {
      object_to_world_.push_back(instance.transform);
      normal_to_world_.push_back(glm::transpose(glm::inverse(glm::mat3(instance.transform))));
    }
  }
  /// Number of instances cached.
  std::size_t size() const noexcept { return object_to_world_.size(); }
  /// Object-to-world transform of instance `i`.
  const glm::mat4& object_to_world(std::size_t i) const noexcept { return object_to_world_[i]; }
  /// Inverse transpose of the linear part of instance `i`'s transform (maps normals).
  const glm::mat3& normal_to_world(std::size_t i) const noexcept { return normal_to_world_[i]; }

 private:
  std::vector<glm::mat4> object_to_world_;
  std::vector<glm::mat3> normal_to_world_;
};

namespace hit_detail {

/// Throws if lane data of a hit refers to meshes, instances or triangles the scene lacks.
inline void check_hit_ids(const Scene& scene, std::size_t cached_instances, std::uint32_t mesh, std::uint32_t instance,
                          std::uint32_t triangle) {
  if (instance >= scene.instances.size() || instance >= cached_instances)
    throw std::out_of_range("make_surface_hit: instance id " + std::to_string(instance) + " is not in the scene (" +
                            std::to_string(scene.instances.size()) + " instances; rebuild SceneGeometry after changes)");
  if (mesh >= scene.meshes.size())
    throw std::out_of_range("make_surface_hit: mesh id " + std::to_string(mesh) + " is not in the scene (" +
                            std::to_string(scene.meshes.size()) + " meshes)");
  if (triangle >= scene.meshes[mesh].triangles.size())
    throw std::out_of_range("make_surface_hit: triangle " + std::to_string(triangle) + " is not in mesh '" +
                            scene.meshes[mesh].name + "'");
}

/// Matrices of one instance, by value.
struct InstanceMatrices {
  glm::mat4 object_to_world;  ///< Instance transform.
  glm::mat3 normal_to_world;  ///< Inverse transpose of its linear part.
};

/// Per-lane instance matrices as packets of columns, for transforming whole packets at once.
template <int W>
struct PacketMatrices {
  vec3<W> column[4];         ///< Columns of the object-to-world transform (the 4th is the translation).
  vec3<W> normal_column[3];  ///< Columns of the normal matrix.

  /// Every lane gets `m`.
  void broadcast(const InstanceMatrices& m) noexcept {
    for (int c = 0; c < 4; ++c) column[c] = vec3<W>(glm::vec3(m.object_to_world[c]));
    for (int c = 0; c < 3; ++c) normal_column[c] = vec3<W>(m.normal_to_world[c]);
  }
  /// Lane `i` gets `m`.
  void set(int i, const InstanceMatrices& m) noexcept {
    for (int c = 0; c < 4; ++c) column[c].set(i, glm::vec3(m.object_to_world[c]));
    for (int c = 0; c < 3; ++c) normal_column[c].set(i, m.normal_to_world[c]);
  }
  /// Object-space points to world space.
  vec3<W> point(const vec3<W>& p) const noexcept { return column[0] * p.x + column[1] * p.y + column[2] * p.z + column[3]; }
  /// Object-space directions (tangents) to world space: the linear part alone.
  vec3<W> direction(const vec3<W>& v) const noexcept { return column[0] * v.x + column[1] * v.y + column[2] * v.z; }
  /// -1 where the transform mirrors (negative determinant), else 1.
  vfloat<W> handedness() const noexcept {
    return select(dot(column[0], cross(column[1], column[2])) < vfloat<W>(0.0f), vfloat<W>(-1.0f), vfloat<W>(1.0f));
  }
  /// Object-space normals to world space (not normalised).
  vec3<W> normal(const vec3<W>& n) const noexcept {
    return normal_column[0] * n.x + normal_column[1] * n.y + normal_column[2] * n.z;
  }
};

/// The body of both make_surface_hit overloads; `matrices(instance)` yields the instance's
/// object-to-world and normal matrices, `instance_count` how many instances it knows.
template <int W, class Matrices>
SurfaceHit<W> build_surface_hit(const Scene& scene, std::size_t instance_count, const Matrices& matrices,
                                const RayPacket<W>& rays, const HitPacket<W>& hits, const vmask<W>& mask,
                                float cone_spread) {
  SurfaceHit<W> hit;
  const vmask<W> active = mask & hits.valid();
  if (none(active)) return hit;

  // Gather the object-space triangle, its vertex normals and uvs lane by lane (scalar: the data
  // are scattered over meshes), then transform and do the vector algebra on packets. A packet
  // nearly always hits one instance, whose matrices are then broadcast instead of gathered.
  vec3<W> p0, p1, p2, interpolated_normal, interpolated_tangent;
  vfloat<W> tex_u, tex_v, tangent_sign;
  vmask<W> tangent_lanes;  // lanes whose triangle has three usable TANGENTs
  vfloat<W> du1, dv1, du2, dv2;  // the triangle's edges p1 - p0 and p2 - p0 in texture coordinates
  const int first_lane = [&] {
    for (int i = 0; i < W; ++i)
      if (active[i]) return i;
    return 0;
  }();
  const std::uint32_t first_instance = hits.instID[first_lane];
  bool one_instance = true;
  for (int i = 0; i < W; ++i) {
    if (!active[i]) continue;
    const std::uint32_t mesh_id = hits.geomID[i], instance_id = hits.instID[i], triangle_id = hits.primID[i];
    check_hit_ids(scene, instance_count, mesh_id, instance_id, triangle_id);
    one_instance = one_instance && instance_id == first_instance;
    const Mesh& mesh = scene.meshes[mesh_id];
    const glm::uvec3 triangle = mesh.triangles[triangle_id];
    if (triangle.x >= mesh.positions.size() || triangle.y >= mesh.positions.size() || triangle.z >= mesh.positions.size())
      throw std::out_of_range("make_surface_hit: triangle " + std::to_string(triangle_id) + " of mesh '" + mesh.name +
                              "' indexes a vertex beyond its " + std::to_string(mesh.positions.size()) + " positions");
    const float b1 = hits.u[i], b2 = hits.v[i], b0 = 1.0f - b1 - b2;
    p0.set(i, mesh.positions[triangle.x]);
    p1.set(i, mesh.positions[triangle.y]);
    p2.set(i, mesh.positions[triangle.z]);
    if (mesh.normals.size() == mesh.positions.size())
      interpolated_normal.set(i, b0 * mesh.normals[triangle.x] + b1 * mesh.normals[triangle.y] + b2 * mesh.normals[triangle.z]);
    if (mesh.uvs.size() == mesh.positions.size()) {
      const glm::vec2 uv = b0 * mesh.uvs[triangle.x] + b1 * mesh.uvs[triangle.y] + b2 * mesh.uvs[triangle.z];
      tex_u.set(i, uv.x);
      tex_v.set(i, uv.y);
      const glm::vec2 e1 = mesh.uvs[triangle.y] - mesh.uvs[triangle.x], e2 = mesh.uvs[triangle.z] - mesh.uvs[triangle.x];
      du1.set(i, e1.x);
      dv1.set(i, e1.y);
      du2.set(i, e2.x);
      dv2.set(i, e2.y);
    }
    if (mesh.tangents.size() == mesh.positions.size()) {
      const glm::vec4 t0 = mesh.tangents[triangle.x], t1 = mesh.tangents[triangle.y], t2 = mesh.tangents[triangle.z];
      if (t0.w != 0.0f && t1.w != 0.0f && t2.w != 0.0f) {  // w is 0 only for a tangent the loader found unusable
        interpolated_tangent.set(i, b0 * glm::vec3(t0) + b1 * glm::vec3(t1) + b2 * glm::vec3(t2));
        tangent_sign.set(i, t0.w);
        tangent_lanes.set(i, true);
      }
    }
    hit.material.set(i, mesh.material);
    hit.mesh.set(i, std::int32_t(mesh_id));
    hit.instance.set(i, std::int32_t(instance_id));
    hit.triangle.set(i, std::int32_t(triangle_id));
  }
  PacketMatrices<W> to_world;
  if (one_instance) {
    to_world.broadcast(matrices(first_instance));
  } else {
    for (int i = 0; i < W; ++i)
      if (active[i]) to_world.set(i, matrices(hits.instID[i]));
  }
  p0 = to_world.point(p0);
  p1 = to_world.point(p1);
  p2 = to_world.point(p2);
  interpolated_normal = to_world.normal(interpolated_normal);

  const vfloat<W> b1 = vfloat<W>::load(hits.u), b2 = vfloat<W>::load(hits.v);
  const vfloat<W> b0 = vfloat<W>(1.0f) - b1 - b2;
  hit.position = keep(p0 * b0 + p1 * b1 + p2 * b2, active);

  const vec3<W> direction = rays.direction();
  const vfloat<W> direction_length = length(direction);
  hit.wo = keep(-normalize(direction), active);
  hit.distance = keep(vfloat<W>::load(rays.tfar) * direction_length, active);

  // Geometric normal of the world-space triangle; the winding decides the front face.
  const vec3<W> edge_cross = cross(p1 - p0, p2 - p0);
  const vec3<W> winding_normal = normalize(edge_cross);
  const vfloat<W> facing = dot(winding_normal, hit.wo);
  hit.front_face = active & (facing > vfloat<W>(0.0f));
  vec3<W> geometric = select(facing < vfloat<W>(0.0f), -winding_normal, winding_normal);
  // A degenerate (zero-area) triangle has no normal; the direction back to the eye is the only
  // safe choice that keeps every later cosine finite and the surface facing the ray.
  const vmask<W> degenerate = length_squared(geometric) == vfloat<W>(0.0f);
  geometric = select(degenerate, hit.wo, geometric);
  hit.geometric_normal = keep(geometric, active);

  // Shading normal: interpolated, flipped into the geometric hemisphere; missing or zero
  // vertex normals fall back to the geometric normal.
  vec3<W> shading = normalize(interpolated_normal);
  shading = select(dot(shading, geometric) < vfloat<W>(0.0f), -shading, shading);
  shading = select(length_squared(shading) == vfloat<W>(0.0f), geometric, shading);
  hit.shading_normal = keep(shading, active);

  hit.u = keep(tex_u, active);
  hit.v = keep(tex_v, active);
  // The position's derivatives along u and v: p = p0 + a edge1 + b edge2 where (u, v) = uv0 +
  // a e1 + b e2, solved for (a, b). A triangle whose uvs span no area (or none) has none: zero.
  const vec3<W> edge1 = p1 - p0, edge2 = p2 - p0;
  const vfloat<W> uv_determinant = du1 * dv2 - dv1 * du2;
  const vmask<W> mapped = active & (abs(uv_determinant) > vfloat<W>(0.0f)) & isfinite(uv_determinant);
  const vfloat<W> inverse_determinant = keep(vfloat<W>(1.0f) / select(mapped, uv_determinant, vfloat<W>(1.0f)), mapped);
  hit.dpdu = keep((edge1 * dv2 - edge2 * dv1) * inverse_determinant, mapped);
  hit.dpdv = keep((edge2 * du1 - edge1 * du2) * inverse_determinant, mapped);
  // Where the mesh has TANGENTs, they are the normal maps' frame (glTF: bitangent = w cross(n, t),
  // turned by a mirroring instance): dpdu along the tangent, dpdv against the bitangent (the map's
  // +y, which normal_mapped takes against dpdv), each as long as the uv derivative it replaces (1
  // where the uvs give none), so that a texture transform mixes them as it mixes the derivatives.
  if (any(tangent_lanes & active)) {
    const vec3<W> tangent = normalize(to_world.direction(interpolated_tangent));
    const vec3<W> vertex_normal = normalize(interpolated_normal);
    const vmask<W> framed = tangent_lanes & active & (length_squared(tangent) > vfloat<W>(0.0f)) &
                            (length_squared(vertex_normal) > vfloat<W>(0.0f));
    const vec3<W> bitangent = cross(vertex_normal, tangent) * (tangent_sign * to_world.handedness());
    const vfloat<W> one(1.0f);
    hit.dpdu = select(framed, tangent * select(mapped, length(hit.dpdu), one), hit.dpdu);
    hit.dpdv = select(framed, -bitangent * select(mapped, length(hit.dpdv), one), hit.dpdv);
  }
  if (cone_spread > 0.0f) {
    const vfloat<W> uv_area = abs(uv_determinant);  // twice the triangle's area in texture coordinates
    // The cone's width at the hit, over the surface: its cross-section's area grows by 1 / cos
    // on a slanted surface, so the side of the same area by 1 / sqrt(cos). Cosines below 1/64
    // (within a degree of grazing) count as 1/64: at most 8x the width, three mip levels, where
    // an exact factor would blur a grazing floor to one texel.
    const vfloat<W> cosine = max(abs(facing), vfloat<W>(1.0f / 64.0f));
    const vfloat<W> world_width = vfloat<W>(cone_spread) * hit.distance / sqrt(cosine);
    // Texture coordinates per unit of length: the square root of the ratio of the triangle's
    // areas in texture and world space (0 for a degenerate triangle: read at full resolution).
    const vfloat<W> world_area = length(edge_cross);
    const vmask<W> spanned = world_area > vfloat<W>(0.0f);
    const vfloat<W> density = keep(sqrt(uv_area / select(spanned, world_area, vfloat<W>(1.0f))), spanned);
    hit.texture_footprint = keep(density * world_width, active);  // not finite: sample_filtered reads level 0
  }
  return hit;
}

}  // namespace hit_detail

/// Builds the world-space hits of the lanes of `mask` that hit something, using the cached
/// instance matrices; other lanes are zero. Throws std::out_of_range on ids the scene lacks.
/// `cone_spread` > 0 gives the rays a cone that widens by that much per unit of distance (a
/// camera's pixel_spread) and sets each hit's texture_footprint; 0 leaves it zero.
template <int W>
SurfaceHit<W> make_surface_hit(const Scene& scene, const SceneGeometry& geometry, const RayPacket<W>& rays,
                               const HitPacket<W>& hits, const vmask<W>& mask, float cone_spread = 0.0f) {
  return hit_detail::build_surface_hit(
      scene, geometry.size(),
      [&](std::uint32_t i) { return hit_detail::InstanceMatrices{geometry.object_to_world(i), geometry.normal_to_world(i)}; },
      rays, hits, mask, cone_spread);
}

/// Builds world-space hits without a cache: each lane inverts its instance's 3x3 matrix
/// (cheap next to tracing; use the SceneGeometry overload to skip even that).
template <int W>
SurfaceHit<W> make_surface_hit(const Scene& scene, const RayPacket<W>& rays, const HitPacket<W>& hits,
                               const vmask<W>& mask) {
  return hit_detail::build_surface_hit(
      scene, scene.instances.size(),
      [&](std::uint32_t i) {
        const glm::mat4& transform = scene.instances[i].transform;
        return hit_detail::InstanceMatrices{transform, glm::transpose(glm::inverse(glm::mat3(transform)))};
      },
      rays, hits, mask, 0.0f);
}

}  // namespace igi
