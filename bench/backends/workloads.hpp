#pragma once
// The ray sets of the backend benchmarks: coherent primary rays, coherent shadow rays to a point
// and incoherent bounce rays, in packet order, on the Cornell box, Sponza (if present) and a
// million-triangle terrain.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include <glm/gtc/matrix_transform.hpp>

#include "igi/backends/reference/reference_backend.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"

namespace igi::bench {

/// Image side for the ray sets: 256 x 256 = 65536 rays per set, 1024 SaarCOR packets.
inline constexpr int image_size = 256;

/// A ray list in packet order (8x8 tiles, Morton order inside: every width gets compact blocks).
struct RaySet {
  std::vector<glm::vec3> origin, direction;  // Per ray.
  std::vector<float> tnear, tfar;            // Per ray.
  std::vector<char> active;                  // Masked-off lanes (e.g. shadow rays of missed pixels).
  std::int64_t active_count = 0;             // Rays actually traced per pass.
};

/// The three workloads of one scene.
struct Workload {
  std::string name;     // "cornell" or "sponza".
  igi::Scene scene;     // Geometry.
  RaySet primary, shadow, bounce;  // Coherent primary, coherent shadow to a point, incoherent bounce.
};

inline glm::ivec2 morton_pixel(int index) {
  glm::ivec2 p(0);
  for (int bit = 0; bit < 3; ++bit) {
    p.x |= ((index >> (2 * bit)) & 1) << bit;
    p.y |= ((index >> (2 * bit + 1)) & 1) << bit;
  }
  return p;
}

inline void push(RaySet& set, const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar, bool active) {
  set.origin.push_back(origin);
  set.direction.push_back(direction);
  set.tnear.push_back(tnear);
  set.tfar.push_back(tfar);
  set.active.push_back(active);
  set.active_count += active;
}

inline Workload make_workload(const std::string& name, igi::Scene scene) {
  Workload w{name, std::move(scene), {}, {}, {}};
  const igi::Camera camera = w.scene.cameras.empty() ? igi::default_camera(w.scene) : w.scene.cameras.front();
  const igi::PinholeProjection projection(camera, image_size, image_size);
  for (int ty = 0; ty < image_size; ty += 8)
    for (int tx = 0; tx < image_size; tx += 8)
      for (int i = 0; i < 64; ++i) {
        const glm::ivec2 p = glm::ivec2(tx, ty) + morton_pixel(i);
        push(w.primary, projection.origin(), projection.direction(float(p.x) + 0.5f, float(p.y) + 0.5f), 0.0f,
             std::numeric_limits<float>::infinity(), true);
      }

  // Hit points from the reference; shadow rays go to one point light, bounce rays leave in
  // cosine-distributed random directions (seeded) about the normal facing the viewer.
  const igi::ReferenceBackend<1> reference(w.scene);
  const igi::Bounds bounds = w.scene.bounds();
  const glm::vec3 light = bounds.center() + glm::vec3(0.0f, 0.4f * bounds.extent().y, 0.0f);
  // Offset of secondary rays from their surface: 1e-4 of the scene size, well above the rounding
  // of a hit point and below any feature of the scenes.
  const float offset = 1e-4f * glm::length(bounds.extent());
  std::mt19937 rng(2003);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (std::size_t i = 0; i < w.primary.origin.size(); ++i) {
    igi::RayPacket<1> ray;
    igi::HitPacket<1> hit;
    ray.set(igi::vec3<1>(w.primary.origin[i]), igi::vec3<1>(w.primary.direction[i]), igi::vfloat<1>(0.0f),
            igi::vfloat<1>(std::numeric_limits<float>::infinity()), igi::vmask<1>(true));
    hit.clear();
    reference.intersect(ray, hit, igi::vmask<1>(true));
    const bool found = hit.geomID[0] != igi::invalid_id;
    const glm::vec3 point = w.primary.origin[i] + ray.tfar[0] * w.primary.direction[i];
    glm::vec3 normal(hit.Ng_x[0], hit.Ng_y[0], hit.Ng_z[0]);
    normal = found && glm::dot(normal, normal) > 0.0f ? glm::normalize(normal) : glm::vec3(0.0f, 1.0f, 0.0f);
    if (glm::dot(normal, w.primary.direction[i]) > 0.0f) normal = -normal;
    const glm::vec3 to_light = light - point;
    const float distance = glm::length(to_light);
    push(w.shadow, point, to_light, offset / std::max(distance, offset), 1.0f - offset / std::max(distance, offset), found);
    const glm::vec3 tangent = glm::normalize(std::abs(normal.x) > 0.5f ? glm::cross(normal, glm::vec3(0, 1, 0))
                                                                      : glm::cross(normal, glm::vec3(1, 0, 0)));
    const glm::vec3 bitangent = glm::cross(normal, tangent);
    const float r = std::sqrt(unit(rng)), phi = 6.2831853f * unit(rng);
    const glm::vec3 direction = r * std::cos(phi) * tangent + r * std::sin(phi) * bitangent +
                                std::sqrt(std::max(0.0f, 1.0f - r * r)) * normal;
    push(w.bounce, point, direction, offset, std::numeric_limits<float>::infinity(), found);
  }
  return w;
}

/// Packet `packet` of `set` (rays packet*W ... packet*W+W-1) in igi's packet layout; returns the
/// active lanes.
template <int W>
igi::vmask<W> load_packet(const RaySet& set, std::size_t packet, igi::RayPacket<W>& rays) {
  igi::vmask<W> active;
  for (int lane = 0; lane < W; ++lane) {
    const std::size_t i = packet * W + std::size_t(lane);
    rays.org_x[lane] = set.origin[i].x;
    rays.org_y[lane] = set.origin[i].y;
    rays.org_z[lane] = set.origin[i].z;
    rays.dir_x[lane] = set.direction[i].x;
    rays.dir_y[lane] = set.direction[i].y;
    rays.dir_z[lane] = set.direction[i].z;
    rays.tnear[lane] = set.tnear[i];
    rays.tfar[lane] = set.tfar[i];
    rays.time[lane] = 0.0f;
    rays.mask[lane] = igi::invalid_id;
    rays.id[lane] = std::uint32_t(lane);
    rays.flags[lane] = 0;
    active.set(lane, set.active[i] != 0);
  }
  return active;
}

/// Cornell and (if present) Sponza, loaded once.
inline const std::vector<Workload>& workloads() {
  static const std::vector<Workload> all = [] {
    std::vector<Workload> list;
    list.push_back(make_workload("cornell", igi::cornell_box()));
    const std::filesystem::path sponza = std::filesystem::path(IGI_SCENES_DIR) / "sponza" / "Sponza.gltf";
    if (std::filesystem::exists(sponza)) list.push_back(make_workload("sponza", igi::load_gltf(sponza)));
    return list;
  }();
  return all;
}

/// A terrain of rolling hills over a (side x side)-quad grid (2 side^2 triangles) inside a box of
/// walls: a large scene whose shadow rays to make_workload's light are often blocked by hills.
inline igi::Scene terrain(int side) {
  igi::Scene scene;
  scene.name = "terrain";
  scene.materials.push_back(igi::Material{});
  igi::Mesh& mesh = scene.meshes.emplace_back();
  mesh.name = "hills";
  mesh.material = 0;
  const int vertices = side + 1;
  for (int z = 0; z < vertices; ++z)
    for (int x = 0; x < vertices; ++x) {
      const float u = float(x) / float(side), v = float(z) / float(side);
      // Hills of three wavelengths, up to 0.15 high on the unit square: enough relief for
      // shadows, small enough for the light of make_workload to stay above most of them.
      const float height = 0.08f * std::sin(9.0f * u) * std::cos(7.0f * v) + 0.05f * std::sin(31.0f * u + 17.0f * v) +
                           0.02f * std::cos(83.0f * v - 47.0f * u);
      mesh.positions.emplace_back(u, height, v);
      mesh.normals.emplace_back(0.0f, 1.0f, 0.0f);
    }
  for (int z = 0; z < side; ++z)
    for (int x = 0; x < side; ++x) {
      const auto i = unsigned(z * vertices + x);
      mesh.triangles.emplace_back(i, i + unsigned(vertices), i + 1);
      mesh.triangles.emplace_back(i + 1, i + unsigned(vertices), i + unsigned(vertices) + 1);
    }
  scene.instances.push_back(igi::Instance{"hills", 0, glm::mat4(1.0f)});
  // A view from above one edge down across the hills, so that every pixel sees terrain.
  igi::Camera camera;
  camera.name = "overview";
  camera.camera_to_world = glm::inverse(glm::lookAt(glm::vec3(0.5f, 0.45f, -0.15f), glm::vec3(0.5f, 0.0f, 0.45f),
                                                    glm::vec3(0.0f, 1.0f, 0.0f)));
  scene.cameras.push_back(camera);
  return scene;
}

/// The terrain of about a million triangles (708^2 quads), loaded once: Embree's large-scene case.
inline const Workload& million_triangles() {
  static const Workload workload = make_workload("terrain", terrain(708));
  return workload;
}

}  // namespace igi::bench
