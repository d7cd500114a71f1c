// The built-in Cornell box (no file) matches ../shared/scenes/cornell/cornell_box.gltf: geometry
// after transforms, normals, albedos, emission and the camera.

#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/validate.hpp"
#include "scenes.hpp"

namespace {

/// True if `a` and `b` differ by at most `within` in every component.
template <class V>
bool near(const V& a, const V& b, float within) {
  for (int i = 0; i < V::length(); ++i)
    if (!(std::abs(a[i] - b[i]) <= within)) return false;
  return true;
}

}  // namespace

TEST_CASE("Built-in Cornell box: 36 triangles, walls, boxes, one emissive light, the Cornell camera", "[scene][cornell]") {
  igi::Scene scene = igi::cornell_box();
  CHECK(scene.name == "cornell");
  CHECK(scene.triangle_count() == 36);
  CHECK(scene.meshes.size() == 8);
  CHECK(scene.instances.size() == 8);
  REQUIRE(scene.materials.size() == 4);
  CHECK(scene.materials[1].base_color.r > 10.0f * scene.materials[1].base_color.g);  // red wall
  CHECK(scene.materials[2].base_color.g > 3.0f * scene.materials[2].base_color.r);   // green wall
  int emissive = 0;
  for (const igi::Mesh& mesh : scene.meshes) emissive += scene.material_of(int(&mesh - scene.meshes.data())).emissive() ? 1 : 0;
  CHECK(emissive == 1);
  REQUIRE(scene.cameras.size() == 1);
  CHECK(scene.cameras[0].position() == glm::vec3(0.278f, 0.273f, -0.8f));
  // The camera looks along +Z (its -Z axis flipped by the 180 degree turn) into the box.
  CHECK(-glm::vec3(scene.cameras[0].camera_to_world[2]) == glm::vec3(0.0f, 0.0f, 1.0f));
  // Every vertex normal faces the same side as its triangle's winding (front faces counter-clockwise).
  for (const igi::Mesh& mesh : scene.meshes)
    for (const glm::uvec3& t : mesh.triangles) {
      const glm::vec3 geometric = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
      CHECK(glm::dot(geometric, mesh.normals[t.x]) > 0.0f);
    }
  std::vector<std::string> warnings;
  igi::validate_scene(scene, &warnings);
  CHECK(warnings.empty());
  CHECK(scene.triangle_count() == 36);
}

TEST_CASE("Built-in Cornell box agrees with cornell_box.gltf (shared scene cornell_box.gltf)", "[scene][cornell][shared]") {
  const auto file = igi::testing::scene_path("cornell/cornell_box.gltf");
  IGI_REQUIRE_SCENE(file);
  const igi::Scene loaded = igi::load_gltf(file);
  const igi::Scene built = igi::cornell_box();
  // Positions and normals in cornell.hpp are the file's float32 values written so they read back
  // exactly, and every transform is the identity: a micrometre (1e-6) only absorbs float rounding
  // of the transform products, far below the model's millimetre precision.
  constexpr float geometry_tolerance = 1e-6f;
  REQUIRE(built.instances.size() == loaded.instances.size());
  for (std::size_t i = 0; i < built.instances.size(); ++i) {
    const igi::Instance& a = built.instances[i];
    const igi::Instance& b = loaded.instances[i];
    INFO("instance " << a.name);
    CHECK(a.name == b.name);
    const igi::Mesh& mesh_a = built.meshes[std::size_t(a.mesh)];
    const igi::Mesh& mesh_b = loaded.meshes[std::size_t(b.mesh)];
    CHECK(mesh_a.name == mesh_b.name);
    CHECK(mesh_a.material == mesh_b.material);
    REQUIRE(mesh_a.triangles.size() == mesh_b.triangles.size());
    for (std::size_t t = 0; t < mesh_a.triangles.size(); ++t)
      for (int corner = 0; corner < 3; ++corner) {
        const glm::vec3 pa(a.transform * glm::vec4(mesh_a.positions[mesh_a.triangles[t][corner]], 1.0f));
        const glm::vec3 pb(b.transform * glm::vec4(mesh_b.positions[mesh_b.triangles[t][corner]], 1.0f));
        CHECK(near(pa, pb, geometry_tolerance));
        CHECK(near(mesh_a.normals[mesh_a.triangles[t][corner]], mesh_b.normals[mesh_b.triangles[t][corner]], geometry_tolerance));
      }
  }
  // Albedos and emission: the same decimals, read as float directly or through double: one float
  // ulp at most (1e-6 relative); the radiance is a product of two such values (1e-5 relative).
  REQUIRE(built.materials.size() == loaded.materials.size());
  for (std::size_t m = 0; m < built.materials.size(); ++m) {
    const igi::Material& a = built.materials[m];
    const igi::Material& b = loaded.materials[m];
    INFO("material " << a.name);
    CHECK(a.name == b.name);
    CHECK(near(a.base_color, b.base_color, 1e-6f));
    CHECK(near(a.emission, b.emission, 1e-5f * 20.0f));  // radiance up to ~20
    CHECK(a.metallic == b.metallic);
    CHECK(a.roughness == b.roughness);
    CHECK(a.double_sided == b.double_sided);
    // The one intended difference: the built-in box's measured paints are Lambertian, while the
    // file, without KHR_materials_specular, has glTF's default 4% specular layer.
    CHECK(a.specular == 0.0f);
    CHECK(b.specular == 1.0f);
  }
  // Camera: a 180 degree turn and a translation, exact in float up to the quaternion's rounding.
  REQUIRE(loaded.cameras.size() == 1);
  const igi::Camera& a = built.cameras[0];
  const igi::Camera& b = loaded.cameras[0];
  CHECK(a.name == b.name);
  for (int c = 0; c < 4; ++c) CHECK(near(a.camera_to_world[c], b.camera_to_world[c], 1e-6f));
  CHECK(a.yfov == b.yfov);  // both the float nearest the file's double
  CHECK(a.aspect == b.aspect);
  CHECK(a.znear == b.znear);
}
