// KHR_materials_volume: the loader reads thicknessFactor, attenuationDistance and
// attenuationColor, lists the extension as supported (a file may require it), and a material's
// transmission is thin-walled exactly where it has no thickness (or is alpha-blended).

#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "gltf_builder.hpp"
#include "igi/scene/error.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/validate.hpp"

namespace {

using igi::testing::GltfBuilder;
using igi::testing::scratch_dir;
using json = nlohmann::json;

/// A one-quad file whose materials are `materials`, requiring KHR_materials_volume.
GltfBuilder volume_file(const json& materials) {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_materials_transmission", "KHR_materials_volume"};
  b.doc["extensionsRequired"] = {"KHR_materials_volume"};
  b.doc["materials"] = materials;
  b.add_quad_node("quad");
  b.set_roots({0});
  return b;
}

}  // namespace

TEST_CASE("glTF KHR_materials_volume: thickness and attenuation are read, and a file may require the extension",
          "[scene][gltf][glass]") {
  GltfBuilder b = volume_file(json::array({
      {{"name", "water"},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                       {"KHR_materials_volume",
                        {{"thicknessFactor", 0.25}, {"attenuationDistance", 2.0}, {"attenuationColor", {0.5, 0.75, 1.0}}}}}}},
      {{"name", "pane"}, {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 0.8}}}}}},
      {{"name", "flat volume"},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}}, {"KHR_materials_volume", json::object()}}}},
  }));
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("volume"), "volume"), &warnings);
  for (const std::string& warning : warnings) UNSCOPED_INFO(warning);
  CHECK(warnings.empty());
  REQUIRE(scene.materials.size() == 3);
  const igi::Material& water = scene.materials[0];
  CHECK(water.thickness == 0.25f);
  CHECK(water.attenuation_distance == 2.0f);
  CHECK(water.attenuation_color == glm::vec3(0.5f, 0.75f, 1.0f));
  CHECK_FALSE(water.thin_walled());
  CHECK_FALSE(water.see_through());
  const igi::Material& pane = scene.materials[1];  // no volume: glTF's thin wall
  CHECK(pane.thickness == 0.0f);
  CHECK(pane.attenuation_distance == std::numeric_limits<float>::infinity());
  CHECK(pane.attenuation_color == glm::vec3(1.0f));
  CHECK(pane.thin_walled());
  CHECK(pane.see_through());
  CHECK(scene.materials[2].thin_walled());  // the extension's default thickness is 0
}

TEST_CASE("glTF KHR_materials_volume: a negative thickness or non-positive attenuation distance is named and left at "
          "its default, validation rejects them in a scene built in code",
          "[scene][gltf][glass]") {
  GltfBuilder b = volume_file(json::array({
      {{"name", "odd"},
       {"extensions", {{"KHR_materials_transmission", {{"transmissionFactor", 1.0}}},
                       {"KHR_materials_volume", {{"thicknessFactor", -1.0}, {"attenuationDistance", 0.0}}}}}},
  }));
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("volume_odd"), "volume_odd"), &warnings);
  REQUIRE(warnings.size() == 2);
  CHECK(warnings[0].find("thicknessFactor") != std::string::npos);
  CHECK(warnings[1].find("attenuationDistance") != std::string::npos);
  CHECK(scene.materials[0].thickness == 0.0f);
  CHECK(scene.materials[0].attenuation_distance == std::numeric_limits<float>::infinity());

  igi::Scene built = scene;
  built.materials[0].thickness = -0.5f;
  CHECK_THROWS_AS(igi::validate_scene(built), igi::SceneError);
  built.materials[0].thickness = 0.5f;
  built.materials[0].attenuation_distance = -1.0f;
  CHECK_THROWS_AS(igi::validate_scene(built), igi::SceneError);
}

TEST_CASE("glTF materials: alpha blending makes a surface see-through, and blended transmission thin-walled",
          "[scene][glass]") {
  igi::Material blended{.alpha_mode = igi::AlphaMode::blend};
  CHECK(blended.see_through());
  CHECK_FALSE(blended.thin_walled());
  blended.transmission = 1.0f;
  blended.thickness = 1.0f;
  CHECK(blended.thin_walled());
  const igi::Material solid{.transmission = 1.0f, .thickness = 1.0f};
  CHECK_FALSE(solid.see_through());
  const igi::Material opaque;
  CHECK_FALSE(opaque.see_through());
}
