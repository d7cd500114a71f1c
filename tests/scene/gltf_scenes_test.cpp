// The shared real scenes (../shared/scenes) load with the counts, lights, cameras and materials
// their README declares. A test whose scene is missing is reported skipped (scenes.hpp).

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>

#include "igi/scene/camera.hpp"
#include "igi/scene/gltf.hpp"
#include "scenes.hpp"

namespace {

using igi::testing::scene_path;

/// True if every normal of every mesh has unit length (to float rounding of a normalization).
bool unit_normals(const igi::Scene& scene) {
  for (const igi::Mesh& mesh : scene.meshes) {
    if (mesh.normals.size() != mesh.positions.size()) return false;
    for (const glm::vec3& n : mesh.normals)
      if (std::abs(glm::length(n) - 1.0f) > 1e-5f) return false;  // a few float ulps of a normalized vector
  }
  return true;
}

}  // namespace

TEST_CASE("Cornell box glTF: 36 triangles, 4 materials, emissive light, one camera (shared scene cornell_box.gltf)", "[scene][gltf][shared]") {
  const auto file = scene_path("cornell/cornell_box.gltf");
  IGI_REQUIRE_SCENE(file);
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(file, &warnings);
  CHECK(warnings.empty());
  CHECK(scene.name == "cornell_box");
  CHECK(scene.triangle_count() == 36);
  CHECK(scene.unique_triangle_count() == 36);
  CHECK(scene.meshes.size() == 8);
  CHECK(scene.instances.size() == 8);
  REQUIRE(scene.materials.size() == 4);
  CHECK(scene.textures.empty());
  CHECK(scene.lights.empty());
  REQUIRE(scene.cameras.size() == 1);
  CHECK(scene.cameras[0].name == "cornell_camera");
  CHECK(scene.cameras[0].aspect == 1.0f);
  int emissive = 0;
  for (const igi::Material& material : scene.materials) emissive += material.emissive() ? 1 : 0;
  CHECK(emissive == 1);
  const igi::Material& light = scene.materials[3];
  CHECK(light.name == "light");
  // Radiance (18.387, 13.987, 6.754) per the scenes README; 1e-3 is the README's rounding.
  CHECK(light.emission.x == Approx(18.387f).margin(1e-3));
  CHECK(light.emission.y == Approx(13.987f).margin(1e-3));
  CHECK(light.emission.z == Approx(6.754f).margin(1e-3));
  CHECK(unit_normals(scene));
}

TEST_CASE("Sponza: 262,087 triangles (115,580 unique), textures shared and sRGB, 4 named cameras (shared scene Sponza.gltf)", "[scene][gltf][shared]") {
  const auto file = scene_path("sponza/Sponza.gltf");
  IGI_REQUIRE_SCENE(file);
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(file, &warnings);
  for (const std::string& warning : warnings) UNSCOPED_INFO(warning);
  CHECK(warnings.empty());
  CHECK(scene.name == "Sponza");
  CHECK(scene.triangle_count() == 262087);
  CHECK(scene.unique_triangle_count() == 115580);
  CHECK(scene.meshes.size() == 44);
  CHECK(scene.instances.size() == 170);  // 174 nodes, 4 of which hold cameras
  CHECK(scene.materials.size() == 24);
  // 21 images, each decoded once however many materials use it.
  CHECK(scene.textures.size() == 21);
  std::set<std::string> texture_names;
  for (const igi::Texture& texture : scene.textures) {
    CHECK(texture.srgb);
    CHECK(texture.width > 0);
    CHECK(texture.texels.size() == std::size_t(texture.width) * std::size_t(texture.height) * 4);
    texture_names.insert(texture.name);
  }
  CHECK(texture_names.size() == scene.textures.size());
  CHECK(scene.lights.empty());
  REQUIRE(scene.cameras.size() == 4);
  for (const char* name : {"CameraMain", "CameraAlternate", "CameraBalcony", "CameraAlcove"}) {
    const igi::Camera* camera = igi::find_camera(scene, name);
    REQUIRE(camera != nullptr);
    CHECK(camera->yfov == Approx(0.7853981852531433f));
    CHECK(camera->aspect == Approx(1.7777777910232544f));
  }
  // CameraMain's node translation.
  const glm::vec3 eye = igi::find_camera(scene, "CameraMain")->position();
  CHECK(eye.x == Approx(15.46455192565918f));
  CHECK(eye.y == Approx(4.38787841796875f));
  CHECK(eye.z == Approx(0.45239686965942383f));
  // The README's bounding box, quoted to one decimal: 0.05 is half of its last digit.
  const igi::Bounds bounds = scene.bounds();
  CHECK(bounds.lower.x == Approx(-26.8f).margin(0.05));
  CHECK(bounds.upper.y == Approx(23.6f).margin(0.05));
  CHECK(unit_normals(scene));
}

TEST_CASE("Sponza_lit: the sun and the atrium lamp placed by their nodes (shared scene Sponza_lit.gltf)", "[scene][gltf][shared]") {
  const auto file = scene_path("sponza/Sponza_lit.gltf");
  IGI_REQUIRE_SCENE(file);
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(file, &warnings);
  CHECK(warnings.empty());
  CHECK(scene.triangle_count() == 262087);
  CHECK(scene.unique_triangle_count() == 115580);
  REQUIRE(scene.lights.size() == 2);
  const igi::PunctualLight& sun = scene.lights[0];
  CHECK(sun.name == "Sun");
  CHECK(sun.kind == igi::PunctualKind::directional);
  CHECK(sun.intensity == 8.0f);
  CHECK(sun.color.y == Approx(0.95f));
  // The sun shines along its node's -Z: rotation quaternion (x, y, z, w) of SunNode applied to (0, 0, -1).
  const double x = -0.5189915681571986, y = 0.21828576865292545, z = 0.13906337156628334, w = 0.8146535791819436;
  const glm::vec3 expected(float(-2.0 * (x * z + w * y)), float(-2.0 * (y * z - w * x)), float(-(1.0 - 2.0 * (x * x + y * y))));
  CHECK(sun.direction.x == Approx(expected.x).margin(1e-6));  // float rounding of a unit vector
  CHECK(sun.direction.y == Approx(expected.y).margin(1e-6));
  CHECK(sun.direction.z == Approx(expected.z).margin(1e-6));
  CHECK(sun.direction.y < 0.0f);  // through the open roof, downwards
  const igi::PunctualLight& lamp = scene.lights[1];
  CHECK(lamp.name == "AtriumLamp");
  CHECK(lamp.kind == igi::PunctualKind::point);
  CHECK(lamp.intensity == 300.0f);
  CHECK(lamp.position == glm::vec3(0.0f, 9.0f, 0.0f));
  CHECK(scene.cameras.size() == 4);
}

TEST_CASE("Stanford bunny .glb: 69,451 triangles, computed unit normals, no material, camera or light (shared scene stanford-bunny.glb)", "[scene][gltf][shared]") {
  const auto file = scene_path("bunny/stanford-bunny.glb");
  IGI_REQUIRE_SCENE(file);
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(file, &warnings);
  CHECK(warnings.empty());
  CHECK(scene.name == "stanford-bunny");
  CHECK(scene.triangle_count() == 69451);
  REQUIRE(scene.meshes.size() == 1);
  CHECK(scene.meshes[0].material == -1);
  CHECK(scene.material_of(0).base_color.x == Approx(0.8f));
  CHECK(scene.cameras.empty());
  CHECK(scene.lights.empty());
  CHECK(unit_normals(scene));
  // Computed normals face outwards: on average they point away from the centre.
  const igi::Mesh& mesh = scene.meshes[0];
  const glm::vec3 center = scene.bounds().center();
  double outward = 0.0;
  for (std::size_t v = 0; v < mesh.positions.size(); ++v) outward += glm::dot(mesh.normals[v], glm::normalize(mesh.positions[v] - center));
  CHECK(outward / double(mesh.positions.size()) > 0.5);  // a closed, roughly convex shape: most normals point out
  // With no camera in the file, the default camera sees the whole bunny.
  const igi::Camera camera = igi::default_camera(scene);
  CHECK(camera.position().z > scene.bounds().upper.z);
}
