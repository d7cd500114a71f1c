// Malformed glTF input: each case gives a SceneError whose message names the file and the
// problem, or (missing or broken textures, zero-area triangles) a warning and a defined scene.
// The broken files are written by the tests into a scratch folder.

#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "gltf_builder.hpp"
#include "igi/scene/gltf.hpp"
#include "scenes.hpp"

namespace {

using igi::testing::GltfBuilder;
using igi::testing::scratch_dir;
using igi::testing::write_bytes;
using json = nlohmann::json;
using Catch::Contains;

/// A valid one-quad document to break.
GltfBuilder quad_document() {
  GltfBuilder b;
  b.add_quad_node("quad");
  b.set_roots({0});
  return b;
}

/// The message of the SceneError `load_gltf(file)` throws; fails the test if it throws nothing else.
std::string load_error(const std::filesystem::path& file) {
  try {
    igi::load_gltf(file);
  } catch (const igi::SceneError& error) {
    CHECK(error.file() == file);
    return error.what();
  }
  FAIL("no SceneError for " << file);
  return {};
}

}  // namespace

TEST_CASE("glTF error: missing file", "[scene][gltf][malformed]") {
  const auto file = scratch_dir("missing") / "nothing.gltf";
  CHECK_THAT(load_error(file), Contains("nothing.gltf") && Contains("file not found"));
}

TEST_CASE("glTF error: empty file", "[scene][gltf][malformed]") {
  const auto file = scratch_dir("empty") / "empty.gltf";
  write_bytes(file, "");
  CHECK_THAT(load_error(file), Contains("empty.gltf") && Contains("file is empty"));
}

TEST_CASE("glTF error: not a glTF (text, PNG bytes, JSON without asset)", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("not-gltf");
  write_bytes(dir / "notes.gltf", "hello, world\n");
  CHECK_THAT(load_error(dir / "notes.gltf"), Contains("notes.gltf") && Contains("not a glTF file"));
  write_bytes(dir / "picture.glb", std::string("\x89PNG\r\n\x1a\n\0\0\0\rIHDR", 16));
  CHECK_THAT(load_error(dir / "picture.glb"), Contains("picture.glb") && Contains("not a glTF file"));
  write_bytes(dir / "object.gltf", R"({"hello": [1, 2, 3]})");
  CHECK_THAT(load_error(dir / "object.gltf"), Contains("object.gltf") && Contains("asset"));
}

TEST_CASE("glTF error: bad JSON", "[scene][gltf][malformed]") {
  const auto file = scratch_dir("bad-json") / "bad.gltf";
  write_bytes(file, R"({"asset": {"version": "2.0"}, "nodes": [ {"name": "a",, } ]})");
  CHECK_THAT(load_error(file), Contains("bad.gltf") && Contains("invalid glTF") && Contains("parse error"));
}

TEST_CASE("glTF error: truncated .gltf and truncated .glb", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("truncated");
  GltfBuilder b = quad_document();
  const std::string text = igi::testing::read_bytes(b.write_gltf(dir, "whole"));
  write_bytes(dir / "half.gltf", text.substr(0, text.size() / 2));
  CHECK_THAT(load_error(dir / "half.gltf"), Contains("half.gltf") && Contains("invalid glTF"));
  const std::string glb = b.glb_bytes();
  for (const std::size_t keep : {std::size_t(8), std::size_t(30), glb.size() / 2, glb.size() - 4}) {
    write_bytes(dir / "cut.glb", glb.substr(0, keep));
    INFO("kept " << keep << " of " << glb.size() << " bytes");
    CHECK_THAT(load_error(dir / "cut.glb"), Contains("cut.glb") && Contains("binary glTF"));
  }
}

TEST_CASE("glTF error: index out of range", "[scene][gltf][malformed]") {
  GltfBuilder b;
  const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  const int indices = b.add_indices({0, 1, 7});
  b.add_mesh("broken", json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  CHECK_THAT(load_error(b.write_gltf(scratch_dir("index-range"), "index")),
             Contains("index.gltf") && Contains("mesh 'broken'") && Contains("index 7") && Contains("out of range"));
}

TEST_CASE("glTF error: accessor past its bufferView, bufferView past its buffer", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("accessor-range");
  {
    GltfBuilder b = quad_document();
    b.doc["accessors"][0]["count"] = 400;  // 4 positions stored
    CHECK_THAT(load_error(b.write_gltf(dir, "count")),
               Contains("count.gltf") && Contains("accessor 0") && Contains("past the end of bufferView"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["accessors"][0]["byteOffset"] = 40;
    CHECK_THAT(load_error(b.write_gltf(dir, "offset")), Contains("offset.gltf") && Contains("past the end of bufferView"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["bufferViews"][0]["byteLength"] = 4000;
    CHECK_THAT(load_error(b.write_gltf(dir, "view")), Contains("view.gltf") && Contains("past the end of buffer 0"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["accessors"][0]["count"] = std::numeric_limits<std::uint32_t>::max();
    CHECK_THAT(load_error(b.write_gltf(dir, "huge")), Contains("huge.gltf") && Contains("accessor 0"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["bufferViews"][0]["byteStride"] = 4;  // smaller than a float vec3
    CHECK_THAT(load_error(b.write_gltf(dir, "stride")), Contains("stride.gltf") && Contains("byteStride 4"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["accessors"][0]["bufferView"] = 9;
    CHECK_THAT(load_error(b.write_gltf(dir, "no-view")), Contains("no-view.gltf") && Contains("bufferView 9 does not exist"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["accessors"][0]["type"] = "VEC2";
    CHECK_THAT(load_error(b.write_gltf(dir, "type")), Contains("type.gltf") && Contains("POSITION") && Contains("needs 3"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["meshes"][0]["primitives"][0]["attributes"]["POSITION"] = 12;
    CHECK_THAT(load_error(b.write_gltf(dir, "no-accessor")),
               Contains("no-accessor.gltf") && Contains("accessor 12") && Contains("does not exist"));
  }
}

TEST_CASE("glTF error: sparse accessor index out of range", "[scene][gltf][malformed]") {
  GltfBuilder b = quad_document();
  const std::vector<std::uint8_t> targets{9};
  const std::vector<float> values{0, 0, 0};
  b.doc["accessors"][0]["sparse"] = {{"count", 1},
                                     {"indices", {{"bufferView", b.add_view(targets.data(), 1)}, {"componentType", 5121}}},
                                     {"values", {{"bufferView", b.add_view(values.data(), 12)}}}};
  CHECK_THAT(load_error(b.write_gltf(scratch_dir("sparse-range"), "sparse")),
             Contains("sparse.gltf") && Contains("sparse") && Contains("index 9"));
}

TEST_CASE("glTF error: missing buffer file", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("missing-buffer");
  GltfBuilder b = quad_document();
  const auto file = b.write_gltf(dir, "scene");
  std::filesystem::remove(dir / "scene.bin");
  CHECK_THAT(load_error(file), Contains("scene.gltf") && Contains("scene.bin"));
}

TEST_CASE("glTF warning: a missing texture file leaves the factor and drops the texture", "[scene][gltf][malformed]") {
  GltfBuilder b = quad_document();
  b.doc["images"] = json::array({{{"uri", "gone.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  b.doc["materials"] = json::array({{{"name", "painted"},
                                     {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}, {"baseColorTexture", {{"index", 0}}}}}}});
  b.doc["meshes"][0]["primitives"][0]["material"] = 0;
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("missing-texture"), "scene"), &warnings);
  REQUIRE(scene.materials.size() == 1);
  CHECK(scene.materials[0].base_color_texture == -1);
  CHECK(scene.materials[0].base_color == glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  CHECK(scene.textures.empty());
  CHECK(scene.triangle_count() == 2);
  bool named = false;
  for (const std::string& warning : warnings)
    named = named || (warning.find("scene.gltf") != std::string::npos && warning.find("painted") != std::string::npos &&
                      warning.find("gone.png") != std::string::npos && warning.find("drops the texture") != std::string::npos);
  CHECK(named);
}

TEST_CASE("glTF warning: an undecodable texture leaves the factor and drops the texture", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("corrupt-texture");
  write_bytes(dir / "noise.png", "definitely not a PNG");
  GltfBuilder b = quad_document();
  b.doc["images"] = json::array({{{"uri", "noise.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  b.doc["materials"] = json::array({{{"name", "glowing"}, {"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 0}}}}});
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(dir, "scene"), &warnings);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Contains("glowing") && Contains("noise.png") && Contains("could not be decoded"));
  CHECK(scene.materials.at(0).emissive_texture == -1);
  CHECK(scene.materials.at(0).emission == glm::vec3(1.0f));
}

TEST_CASE("glTF error: NaN and infinite positions name the mesh and vertex", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("nan");
  for (const float bad : {std::numeric_limits<float>::quiet_NaN(), std::numeric_limits<float>::infinity()}) {
    GltfBuilder b;
    const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {bad, 0, 0}});
    const int indices = b.add_indices({0, 1, 3});
    b.add_mesh("spiky", json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
    b.add_node({{"mesh", 0}});
    b.set_roots({0});
    CHECK_THAT(load_error(b.write_gltf(dir, "bad")),
               Contains("bad.gltf") && Contains("mesh 'spiky' vertex 3") && Contains("non-finite position"));
  }
}

TEST_CASE("glTF warning: zero-area triangles are dropped and counted", "[scene][gltf][malformed]") {
  GltfBuilder b;
  const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}});
  // A good triangle, a repeated index, and three collinear vertices.
  const int indices = b.add_indices({0, 1, 2, 0, 0, 2, 0, 1, 3});
  b.add_mesh("slivers", json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("zero-area"), "slivers"), &warnings);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Contains("slivers.gltf") && Contains("mesh 'slivers'") && Contains("dropped 2 zero-area triangles"));
  REQUIRE(scene.meshes.size() == 1);
  REQUIRE(scene.meshes[0].triangles.size() == 1);
  CHECK(scene.meshes[0].triangles[0] == glm::uvec3(0, 1, 2));
  CHECK(scene.meshes[0].normals[0] == glm::vec3(0, 0, 1));
}

TEST_CASE("glTF error: unknown required extension is named", "[scene][gltf][malformed]") {
  GltfBuilder b = quad_document();
  b.doc["extensionsUsed"] = {"KHR_draco_mesh_compression"};
  b.doc["extensionsRequired"] = {"KHR_draco_mesh_compression"};
  CHECK_THAT(load_error(b.write_gltf(scratch_dir("extension"), "draco")),
             Contains("draco.gltf") && Contains("KHR_draco_mesh_compression"));
}

TEST_CASE("glTF warning: an optional extension igi does not implement is named and ignored", "[scene][gltf][malformed]") {
  GltfBuilder b = quad_document();
  b.doc["extensionsUsed"] = {"KHR_materials_sheen"};
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("optional-extension"), "optional"), &warnings);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Contains("optional.gltf") && Contains("KHR_materials_sheen") && Contains("ignores"));
  CHECK(scene.triangle_count() == 2);
}

TEST_CASE("glTF error: unsupported glTF version", "[scene][gltf][malformed]") {
  GltfBuilder b = quad_document();
  b.doc["asset"]["version"] = "1.0";
  CHECK_THAT(load_error(b.write_gltf(scratch_dir("version"), "old")), Contains("old.gltf") && Contains("version 1.0"));
}

TEST_CASE("glTF error: broken references between nodes, meshes, materials, textures, cameras, lights", "[scene][gltf][malformed]") {
  const auto dir = scratch_dir("references");
  {
    GltfBuilder b = quad_document();
    b.doc["nodes"][0]["mesh"] = 5;
    CHECK_THAT(load_error(b.write_gltf(dir, "mesh")), Contains("mesh.gltf") && Contains("uses mesh 5"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["nodes"][0]["children"] = {3};
    CHECK_THAT(load_error(b.write_gltf(dir, "child")), Contains("child.gltf") && Contains("node 3 does not exist"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["nodes"][0]["children"] = {0};
    CHECK_THAT(load_error(b.write_gltf(dir, "cycle")), Contains("cycle.gltf") && Contains("cycle"));
  }
  {
    GltfBuilder b = quad_document();  // two parents share node 0: a DAG, not a tree
    b.add_node({{"name", "p1"}, {"children", {0}}});
    b.add_node({{"name", "p2"}, {"children", {0}}});
    b.set_roots({1, 2});
    CHECK_THAT(load_error(b.write_gltf(dir, "shared")), Contains("shared.gltf") && Contains("node 0 is reached twice"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["scenes"][0]["nodes"] = {4};
    CHECK_THAT(load_error(b.write_gltf(dir, "root")), Contains("root.gltf") && Contains("node 4 does not exist"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["meshes"][0]["primitives"][0]["material"] = 2;
    CHECK_THAT(load_error(b.write_gltf(dir, "material")), Contains("material.gltf") && Contains("material 2 does not exist"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["materials"] = json::array({{{"name", "m"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 3}}}}}}});
    CHECK_THAT(load_error(b.write_gltf(dir, "texture")), Contains("texture.gltf") && Contains("texture 3"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["nodes"][0]["camera"] = 1;
    CHECK_THAT(load_error(b.write_gltf(dir, "camera")), Contains("camera.gltf") && Contains("camera 1"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["nodes"][0]["extensions"] = {{"KHR_lights_punctual", {{"light", 0}}}};
    CHECK_THAT(load_error(b.write_gltf(dir, "light")), Contains("light.gltf") && Contains("light 0"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["extensions"]["KHR_lights_punctual"]["lights"] =
        json::array({{{"name", "narrow"}, {"type", "spot"}, {"spot", {{"innerConeAngle", 1.0}, {"outerConeAngle", 0.5}}}}});
    b.doc["nodes"][0]["extensions"] = {{"KHR_lights_punctual", {{"light", 0}}}};
    CHECK_THAT(load_error(b.write_gltf(dir, "cone")), Contains("cone.gltf") && Contains("narrow") && Contains("cone angles"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["nodes"][0]["rotation"] = {0, 0, 0, 0};
    CHECK_THAT(load_error(b.write_gltf(dir, "rotation")), Contains("rotation.gltf") && Contains("rotation"));
  }
  {
    GltfBuilder b = quad_document();
    b.doc["cameras"] = json::array({{{"type", "perspective"}, {"perspective", {{"yfov", 4.0}, {"znear", 0.1}}}}});
    b.doc["nodes"][0]["camera"] = 0;
    CHECK_THAT(load_error(b.write_gltf(dir, "fov")), Contains("fov.gltf") && Contains("yfov"));
  }
}

TEST_CASE("glTF error: .glb image bufferView past the end of its buffer", "[scene][gltf][malformed]") {
  GltfBuilder b = quad_document();
  b.doc["bufferViews"].push_back({{"buffer", 0}, {"byteOffset", 16}, {"byteLength", 100000}});
  b.doc["images"] = json::array({{{"bufferView", 2}, {"mimeType", "image/png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  b.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  CHECK_THAT(load_error(b.write_glb(scratch_dir("glb-image-range"), "image")),
             Contains("image.glb") && Contains("past the end of its buffer"));
}
