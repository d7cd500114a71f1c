#pragma once
// Small analytic scenes for the lighting, shading and filter tests: closed boxes, single quads.

#include <array>
#include <string>

#include <glm/glm.hpp>

#include "igi/scene/scene.hpp"

namespace igi::testing {

/// Adds a material and returns its index.
inline int add_material(Scene& scene, const glm::vec3& albedo, const glm::vec3& emission = glm::vec3(0.0f)) {
  Material m;
  m.name = "m" + std::to_string(scene.materials.size());
  m.base_color = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.emission = emission;
  scene.materials.push_back(m);
  return int(scene.materials.size()) - 1;
}

/// Adds a square of half-size `half` around `center`, spanned by unit `u_axis`, `v_axis`, whose
/// winding (front face) points along `normal`, as its own mesh and instance.
inline void add_quad(Scene& scene, const glm::vec3& center, const glm::vec3& u_axis, const glm::vec3& v_axis,
                     const glm::vec3& normal, float half, int material, const glm::mat4& transform = glm::mat4(1.0f)) {
  Mesh mesh;
  mesh.name = "quad" + std::to_string(scene.meshes.size());
  glm::vec3 p[4] = {center - half * u_axis - half * v_axis, center + half * u_axis - half * v_axis,
                    center + half * u_axis + half * v_axis, center - half * u_axis + half * v_axis};
  glm::vec2 uv[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  if (glm::dot(glm::cross(p[1] - p[0], p[2] - p[0]), normal) < 0.0f) {
    std::swap(p[1], p[3]);
    std::swap(uv[1], uv[3]);
  }
  for (int i = 0; i < 4; ++i) {
    mesh.positions.push_back(p[i]);
    mesh.normals.push_back(glm::normalize(normal));
    mesh.uvs.push_back(uv[i]);
  }
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  mesh.material = material;
  scene.meshes.push_back(mesh);
  scene.instances.push_back({.name = mesh.name, .mesh = int(scene.meshes.size()) - 1, .transform = transform});
}

/// The unit cube [0,1]^3 seen from inside: six walls facing inwards with albedos `albedo[face]`
/// (faces -x, +x, -y, +y, -z, +z).
inline Scene closed_cube(const std::array<glm::vec3, 6>& albedo) {
  Scene scene;
  scene.name = "closed cube";
  const glm::vec3 x(1, 0, 0), y(0, 1, 0), z(0, 0, 1);
  const glm::vec3 c(0.5f);
  add_quad(scene, c - 0.5f * x, y, z, x, 0.5f, add_material(scene, albedo[0]));
  add_quad(scene, c + 0.5f * x, y, z, -x, 0.5f, add_material(scene, albedo[1]));
  add_quad(scene, c - 0.5f * y, x, z, y, 0.5f, add_material(scene, albedo[2]));
  add_quad(scene, c + 0.5f * y, x, z, -y, 0.5f, add_material(scene, albedo[3]));
  add_quad(scene, c - 0.5f * z, x, y, z, 0.5f, add_material(scene, albedo[4]));
  add_quad(scene, c + 0.5f * z, x, y, -z, 0.5f, add_material(scene, albedo[5]));
  return scene;
}

/// Height of the emitter in `closed_box_with_light`.
inline constexpr float box_light_height = 0.95f;
/// Half size of that emitter.
inline constexpr float box_light_half = 0.1f;

/// A closed unit cube of uniform albedo `rho` with a 0.2 x 0.2 emitter of radiance `radiance`
/// (albedo `rho` too) just under the ceiling, facing down.
inline Scene closed_box_with_light(float rho, const glm::vec3& radiance) {
  Scene scene = closed_cube({glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho)});
  add_quad(scene, {0.5f, box_light_height, 0.5f}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, box_light_half,
           add_material(scene, glm::vec3(rho), radiance));
  return scene;
}

}  // namespace igi::testing
