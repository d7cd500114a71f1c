#pragma once
// The scenes tests build in code, in one place: materials, quads (into a mesh, or as a mesh and
// instance of their own), boxes with walls facing inwards, and the analytic closed boxes of the
// lighting, rendering and accuracy tests.

#include <array>
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/scene/scene.hpp"

namespace igi::testing {

/// A camera at `eye` looking at `target` (+Y up) with vertical field of view `yfov` radians.
inline Camera look_at(const glm::vec3& eye, const glm::vec3& target, float yfov = 1.0f) {
  Camera camera;
  camera.name = "test";
  camera.camera_to_world = glm::inverse(glm::lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f)));
  camera.yfov = yfov;
  return camera;
}

/// The built-in Cornell box's corner of floor, back wall and the x = 0 wall seen from close by
/// (from the free space between the blocks): the view where the 1/d^2 clamp removes most light.
inline Camera cornell_corner_camera() { return look_at({0.15f, 0.3f, 0.3f}, {0.0f, 0.0f, 0.5592f}, 1.2f); }

/// Adds a Lambertian material (metallic 0, roughness 1, specular 0) of `albedo` emitting `emission`; returns its index.
inline int add_material(Scene& scene, const glm::vec3& albedo, const glm::vec3& emission = glm::vec3(0.0f)) {
  Material m;
  m.name = "m";  // appended, not "m" + ...: GCC 12 misreads that insert at 0 as an overlapping copy (-Wrestrict)
  m.name += std::to_string(scene.materials.size());
  m.base_color = glm::vec4(albedo, 1.0f);
  m.metallic = 0.0f;
  m.roughness = 1.0f;
  m.specular = 0.0f;
  m.emission = emission;
  scene.materials.push_back(m);
  return int(scene.materials.size()) - 1;
}

/// Adds quad (a, b, c, d) to `mesh` as two triangles whose winding (front face) points along
/// `normal`, with that normal at its vertices and uvs (0,0), (1,0), (1,1), (0,1) at a, b, c, d.
inline void add_quad(Mesh& mesh, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, const glm::vec3& normal) {
  glm::vec2 uv_b(1, 0), uv_d(0, 1);
  if (glm::dot(glm::cross(b - a, c - a), normal) < 0.0f) {
    std::swap(b, d);
    std::swap(uv_b, uv_d);
  }
  const auto base = std::uint32_t(mesh.positions.size());
  mesh.positions.insert(mesh.positions.end(), {a, b, c, d});
  mesh.normals.insert(mesh.normals.end(), 4, glm::normalize(normal));
  mesh.uvs.insert(mesh.uvs.end(), {glm::vec2(0, 0), uv_b, glm::vec2(1, 1), uv_d});
  mesh.triangles.push_back({base, base + 1, base + 2});
  mesh.triangles.push_back({base, base + 2, base + 3});
}

/// Adds `mesh` with material `material` as one instance placed by `transform`.
inline void add_object(Scene& scene, Mesh mesh, int material, const glm::mat4& transform = glm::mat4(1.0f)) {
  mesh.material = material;
  scene.instances.push_back({.name = mesh.name, .mesh = int(scene.meshes.size()), .transform = transform});
  scene.meshes.push_back(std::move(mesh));
}

/// Adds `mesh` with a new diffuse material of grey `albedo` (and `emission`) as one instance.
inline void add_object(Scene& scene, Mesh mesh, float albedo, const glm::vec3& emission = glm::vec3(0.0f)) {
  const int material = add_material(scene, glm::vec3(albedo), emission);
  add_object(scene, std::move(mesh), material);
}

/// Adds a square of half-size `half` around `center`, spanned by unit `u_axis`, `v_axis`, whose
/// winding (front face) points along `normal`, as its own mesh and instance.
inline void add_quad(Scene& scene, const glm::vec3& center, const glm::vec3& u_axis, const glm::vec3& v_axis,
                     const glm::vec3& normal, float half, int material, const glm::mat4& transform = glm::mat4(1.0f)) {
  Mesh mesh;
  mesh.name = "quad" + std::to_string(scene.meshes.size());
  add_quad(mesh, center - half * u_axis - half * v_axis, center + half * u_axis - half * v_axis,
           center + half * u_axis + half * v_axis, center - half * u_axis + half * v_axis, normal);
  add_object(scene, std::move(mesh), material, transform);
}

/// Adds a black alpha cut-out (alphaMode MASK) sheet facing up at height `y` over x, z in
/// [-2, 2], as its own mesh and instance: transparent where x < 0, opaque where x > 0. Its
/// texture is 16 texels across, alpha 0 in the left 8 and 255 in the right 8, so bilinear
/// lookups blend neighbours only within a texel of u = 0.5 and (repeat wrapping) of the edges.
inline void add_stencil_sheet(Scene& scene, float y) {
  Texture stencil{.name = "stencil", .width = 16, .height = 1, .texels = std::vector<std::uint8_t>(16 * 4, 255)};
  for (int x = 0; x < 8; ++x) stencil.texels[std::size_t(x) * 4 + 3] = 0;
  scene.textures.push_back(stencil);
  const int sheet = add_material(scene, glm::vec3(0.0f));
  scene.materials[std::size_t(sheet)].base_color_texture = int(scene.textures.size()) - 1;
  scene.materials[std::size_t(sheet)].alpha_mode = AlphaMode::mask;
  add_quad(scene, {0.0f, y, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 2.0f, sheet);
}

/// Faces of box_mesh, in the order it adds them.
enum BoxFace { box_floor, box_ceiling, box_x_lower, box_x_upper, box_z_lower, box_z_upper, box_no_face };

/// The faces of the axis-aligned box [lower, upper] but `missing`, normals pointing inwards.
inline Mesh box_mesh(const std::string& name, const glm::vec3& lower, const glm::vec3& upper,
                     BoxFace missing = box_no_face) {
  Mesh mesh;
  mesh.name = name;
  const glm::vec3 l = lower, u = upper;
  const auto face = [&](BoxFace which, glm::vec3 a, glm::vec3 b, glm::vec3 c, glm::vec3 d, glm::vec3 n) {
    if (which != missing) add_quad(mesh, a, b, c, d, n);
  };
  face(box_floor, {l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, l.y, u.z}, {l.x, l.y, u.z}, {0, 1, 0});
  face(box_ceiling, {l.x, u.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z}, {0, -1, 0});
  face(box_x_lower, {l.x, l.y, l.z}, {l.x, u.y, l.z}, {l.x, u.y, u.z}, {l.x, l.y, u.z}, {1, 0, 0});
  face(box_x_upper, {u.x, l.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z}, {u.x, l.y, u.z}, {-1, 0, 0});
  face(box_z_lower, {l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, u.y, l.z}, {l.x, u.y, l.z}, {0, 0, 1});
  face(box_z_upper, {l.x, l.y, u.z}, {u.x, l.y, u.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z}, {0, 0, -1});
  return mesh;
}

/// The unit cube [0,1]^3 seen from inside: six walls facing inwards, each its own mesh, with
/// albedos `albedo[face]` (faces -x, +x, -y, +y, -z, +z).
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

/// closed_cube() of uniform albedo `rho` with a 0.2 x 0.2 emitter of radiance `radiance`
/// (albedo `rho` too) just under the ceiling, facing down.
inline Scene closed_box_with_light(float rho, const glm::vec3& radiance) {
  Scene scene = closed_cube({glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho)});
  add_quad(scene, {0.5f, box_light_height, 0.5f}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, box_light_half,
           add_material(scene, glm::vec3(rho), radiance));
  return scene;
}

/// The unit cube around the origin seen from inside, one mesh whose every face emits `emission`
/// and reflects `albedo` diffusely, so radiance is emission / (1 - albedo) everywhere; its
/// camera sits at the centre looking down -z with a wide view of walls, edges and corners.
inline Scene closed_box(float albedo, float emission) {
  Scene scene;
  scene.name = "closed box";
  add_object(scene, box_mesh("box", glm::vec3(-0.5f), glm::vec3(0.5f)), albedo, glm::vec3(emission));
  Camera camera;
  camera.name = "inside";
  camera.yfov = 1.2f;  // wide: sees walls, edges and corners
  scene.cameras.push_back(camera);
  return scene;
}

}  // namespace igi::testing
