// Scene checks for scenes built in code: errors name the mesh and vertex (or the broken
// reference); zero-area triangles are dropped with a warning.

#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "igi/scene/cornell.hpp"
#include "igi/scene/validate.hpp"

namespace {

using Catch::Contains;

/// A scene with one mesh of two triangles (a unit quad) and one instance.
igi::Scene quad_scene() {
  igi::Scene scene;
  scene.name = "quad";
  igi::Mesh mesh;
  mesh.name = "quad";
  mesh.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.meshes.push_back(mesh);
  scene.instances.push_back({.name = "quad", .mesh = 0});
  return scene;
}

/// The SceneError message of validate_scene(scene), or "" if it passes.
std::string validation_error(igi::Scene scene) {
  std::vector<std::string> warnings;
  try {
    igi::validate_scene(scene, &warnings);
  } catch (const igi::SceneError& error) {
    return error.what();
  }
  return {};
}

}  // namespace

TEST_CASE("zero_area: collinear and coincident vertices, but not thin slivers", "[scene][validate]") {
  CHECK(igi::zero_area({0, 0, 0}, {1, 1, 1}, {2, 2, 2}));
  CHECK(igi::zero_area({1, 2, 3}, {1, 2, 3}, {4, 5, 6}));
  CHECK_FALSE(igi::zero_area({0, 0, 0}, {1, 0, 0}, {0, 1, 0}));
  CHECK_FALSE(igi::zero_area({0, 0, 0}, {1, 0, 0}, {0.5f, 1e-6f, 0}));  // a sliver, but with area
}

TEST_CASE("validate: NaN or infinite positions name the mesh and vertex", "[scene][validate]") {
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), -std::numeric_limits<float>::infinity()}) {
    igi::Scene scene = quad_scene();
    scene.meshes[0].positions[2].y = bad;
    CHECK_THROWS_WITH(igi::check_positions_finite(scene.meshes[0]), Contains("mesh 'quad' vertex 2") && Contains("non-finite"));
    CHECK_THAT(validation_error(scene), Contains("scene 'quad'") && Contains("mesh 'quad' vertex 2"));
  }
}

TEST_CASE("validate: zero-area triangles are dropped with one warning giving their count", "[scene][validate]") {
  igi::Scene scene = quad_scene();
  scene.meshes[0].positions.push_back({2, 0, 0});
  scene.meshes[0].triangles.push_back({0, 1, 4});  // collinear along x
  scene.meshes[0].triangles.push_back({3, 3, 1});  // repeated vertex
  std::vector<std::string> warnings;
  igi::validate_scene(scene, &warnings);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Contains("scene 'quad'") && Contains("mesh 'quad'") && Contains("dropped 2 zero-area triangles"));
  CHECK(scene.meshes[0].triangles == std::vector<glm::uvec3>{{0, 1, 2}, {0, 2, 3}});
  warnings.clear();
  igi::validate_scene(scene, &warnings);  // nothing left to drop
  CHECK(warnings.empty());
}

TEST_CASE("validate: broken indices and references are errors naming what is broken", "[scene][validate]") {
  {
    igi::Scene scene = quad_scene();
    scene.meshes[0].triangles[1].z = 9;
    CHECK_THAT(validation_error(scene), Contains("mesh 'quad' triangle 1 uses vertex 9") && Contains("4 vertices"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.meshes[0].normals = {{0, 0, 1}};
    CHECK_THAT(validation_error(scene), Contains("1 normals for 4 vertices"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.instances[0].mesh = 3;
    CHECK_THAT(validation_error(scene), Contains("instance 'quad' uses mesh 3"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.instances[0].transform[3][0] = std::numeric_limits<float>::infinity();
    CHECK_THAT(validation_error(scene), Contains("instance 'quad' has a non-finite transform"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.meshes[0].material = 0;
    CHECK_THAT(validation_error(scene), Contains("mesh 'quad' uses material 0"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.materials.push_back({.name = "m", .base_color_texture = 2});
    CHECK_THAT(validation_error(scene), Contains("material 'm' uses texture 2"));
  }
  // KHR_materials_specular's and _clearcoat's factors, texture slots and transforms.
  struct Slot {
    const char* what;                           ///< For the message.
    float& (*number)(igi::Material&);           ///< The slot's factor (one channel of a colour).
    int igi::Material::*texture;                ///< Its texture.
    igi::UvTransform igi::Material::*transform;  ///< That texture's transform.
  };
  const Slot slots[] = {
      {"specular", [](igi::Material& m) -> float& { return m.specular; }, &igi::Material::specular_texture,
       &igi::Material::specular_transform},
      {"specular colour", [](igi::Material& m) -> float& { return m.specular_color.g; },
       &igi::Material::specular_color_texture, &igi::Material::specular_color_transform},
      {"clearcoat", [](igi::Material& m) -> float& { return m.clearcoat; }, &igi::Material::clearcoat_texture,
       &igi::Material::clearcoat_transform},
      {"clearcoat roughness", [](igi::Material& m) -> float& { return m.clearcoat_roughness; },
       &igi::Material::clearcoat_roughness_texture, &igi::Material::clearcoat_roughness_transform}};
  for (const Slot& slot : slots) {
    INFO(slot.what);
    igi::Scene scene = quad_scene();
    scene.materials.push_back({.name = "varnish"});
    slot.number(scene.materials[0]) = std::numeric_limits<float>::quiet_NaN();
    CHECK_THAT(validation_error(scene), Contains("material 'varnish' has a non-finite parameter"));
    scene.materials[0] = igi::Material{.name = "varnish"};
    scene.materials[0].*slot.texture = 4;
    CHECK_THAT(validation_error(scene), Contains("material 'varnish' uses texture 4"));
    scene.materials[0] = igi::Material{.name = "varnish"};
    (scene.materials[0].*slot.transform).matrix[2].x = std::numeric_limits<float>::infinity();
    CHECK_THAT(validation_error(scene), Contains("material 'varnish' has a non-finite texture transform"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.textures.push_back({.name = "t", .width = 2, .height = 2, .texels = std::vector<std::uint8_t>(15)});
    CHECK_THAT(validation_error(scene), Contains("texture 't' has 15 bytes for 2x2"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.lights.push_back({.name = "l", .intensity = -1.0f});
    CHECK_THAT(validation_error(scene), Contains("light 'l'"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.lights.push_back({.name = "cone", .kind = igi::PunctualKind::spot, .inner_cone = 0.5f, .outer_cone = 0.25f});
    CHECK_THAT(validation_error(scene), Contains("light 'cone'") && Contains("spot cone"));
  }
  {
    igi::Scene scene = quad_scene();
    scene.cameras.push_back({.name = "c", .yfov = 0.0f});
    CHECK_THAT(validation_error(scene), Contains("camera 'c'"));
  }
  CHECK(validation_error(quad_scene()).empty());
  CHECK(validation_error(igi::cornell_box()).empty());
}
