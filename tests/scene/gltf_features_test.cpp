// Every glTF feature the loader claims, on files the tests write themselves: node hierarchies,
// instancing, index and attribute types, strides, sparse accessors, triangle modes, computed
// normals, textures, materials, lights, cameras and .glb.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <nlohmann/json.hpp>
#include <stb_image_write.h>

#include "gltf_builder.hpp"
#include "gltf_checks.hpp"
#include "igi/scene/gltf.hpp"

namespace {

using igi::testing::GltfBuilder;
using igi::testing::load_clean;
using igi::testing::near;
using igi::testing::tolerance;
using igi::testing::scratch_dir;
using json = nlohmann::json;
namespace component = igi::testing;

/// `instance`'s mesh vertex `v` in world space.
glm::vec3 world_vertex(const igi::Scene& scene, const igi::Instance& instance, std::size_t v) {
  return glm::vec3(instance.transform * glm::vec4(scene.meshes[std::size_t(instance.mesh)].positions[v], 1.0f));
}

/// Loads `file`, its warnings one per line into `warnings`.
igi::Scene load_with_warnings(const std::filesystem::path& file, std::string& warnings) {
  std::vector<std::string> lines;
  igi::Scene scene = igi::load_gltf(file, &lines);
  for (const std::string& line : lines) warnings += line + "\n";
  return scene;
}

/// Geometric unit normal of triangle `t` of `mesh`.
glm::vec3 face_normal(const igi::Mesh& mesh, std::size_t t) {
  const glm::uvec3 tri = mesh.triangles[t];
  return glm::normalize(glm::cross(mesh.positions[tri.y] - mesh.positions[tri.x], mesh.positions[tri.z] - mesh.positions[tri.x]));
}

}  // namespace

TEST_CASE("glTF node hierarchy: nested TRS and matrix transforms compose parent x child", "[scene][gltf]") {
  GltfBuilder b;
  const int position = b.add_positions({{0, 1, 0}, {1, 1, 0}, {0, 2, 0}});
  const int mesh = b.add_mesh("tri", json::array({{{"attributes", {{"POSITION", position}}}}}));
  // The child moves +1 in x by a matrix (column-major, translation in the last column).
  const int child = b.add_node({{"name", "child"}, {"mesh", mesh},
                                {"matrix", {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 1, 0, 0, 1}}});
  // The parent scales by 2, then turns 90 degrees about +Z, then moves +10 in x.
  const float s = std::sqrt(0.5f);
  const int parent = b.add_node({{"name", "parent"}, {"children", {child}}, {"translation", {10, 0, 0}},
                                 {"rotation", {0, 0, s, s}}, {"scale", {2, 2, 2}}});
  b.set_roots({parent});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("hierarchy"), "hierarchy"));
  REQUIRE(scene.instances.size() == 1);
  CHECK(scene.instances[0].name == "child");
  // (0,1,0): child -> (1,1,0); scale -> (2,2,0); rotate (x,y) -> (-y,x) = (-2,2,0); translate -> (8,2,0).
  CHECK(near(world_vertex(scene, scene.instances[0], 0), {8, 2, 0}));
  // (1,1,0) -> (2,1,0) -> (4,2,0) -> (-2,4,0) -> (8,4,0).
  CHECK(near(world_vertex(scene, scene.instances[0], 1), {8, 4, 0}));
  // (0,2,0) -> (1,2,0) -> (2,4,0) -> (-4,2,0) -> (6,2,0).
  CHECK(near(world_vertex(scene, scene.instances[0], 2), {6, 2, 0}));
}

TEST_CASE("glTF instancing: a mesh placed by several nodes is stored once", "[scene][gltf]") {
  GltfBuilder b;
  const int first = b.add_quad_node("quad", {{"translation", {0, 0, 0}}});
  const int second = b.add_node({{"name", "copy"}, {"mesh", 0}, {"translation", {5, 0, 0}}});
  b.set_roots({first, second});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("instancing"), "instancing"));
  CHECK(scene.meshes.size() == 1);
  REQUIRE(scene.instances.size() == 2);
  CHECK(scene.instances[0].mesh == scene.instances[1].mesh);
  CHECK(scene.unique_triangle_count() == 2);
  CHECK(scene.triangle_count() == 4);
  CHECK(near(world_vertex(scene, scene.instances[1], 1), {6, 0, 0}));
}

TEST_CASE("glTF meshes with several primitives become one Mesh per primitive, each with its material", "[scene][gltf]") {
  GltfBuilder b;
  const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.doc["materials"] = json::array({{{"name", "a"}}, {{"name", "b"}}});
  b.add_mesh("two", json::array({{{"attributes", {{"POSITION", position}}}, {"material", 1}},
                                 {{"attributes", {{"POSITION", position}}}, {"material", 0}}}));
  b.add_node({{"name", "n"}, {"mesh", 0}});
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("primitives"), "primitives"));
  REQUIRE(scene.meshes.size() == 2);
  CHECK(scene.meshes[0].name == "two#0");
  CHECK(scene.meshes[0].material == 1);
  CHECK(scene.meshes[1].name == "two#1");
  CHECK(scene.meshes[1].material == 0);
  CHECK(scene.instances.size() == 2);
}

TEST_CASE("glTF index types UNSIGNED_BYTE, UNSIGNED_SHORT, UNSIGNED_INT and no indices give the same triangles", "[scene][gltf]") {
  GltfBuilder b;
  const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  const int i8 = b.add_data(std::vector<std::uint8_t>{0, 1, 2, 3, 4, 5}, component::u8, "SCALAR", 1);
  const int i16 = b.add_data(std::vector<std::uint16_t>{0, 1, 2, 3, 4, 5}, component::u16, "SCALAR", 1);
  const int i32 = b.add_indices({0, 1, 2, 3, 4, 5});
  const json attributes = {{"POSITION", position}};
  b.add_mesh("m", json::array({{{"attributes", attributes}, {"indices", i8}},
                               {{"attributes", attributes}, {"indices", i16}},
                               {{"attributes", attributes}, {"indices", i32}},
                               {{"attributes", attributes}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("indices"), "indices"));
  REQUIRE(scene.meshes.size() == 4);
  for (const igi::Mesh& mesh : scene.meshes) {
    REQUIRE(mesh.triangles.size() == 2);
    CHECK(mesh.triangles[0] == glm::uvec3(0, 1, 2));
    CHECK(mesh.triangles[1] == glm::uvec3(3, 4, 5));
  }
}

TEST_CASE("glTF attribute component types: normalized and integer texcoords, normals and positions", "[scene][gltf]") {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
  b.doc["extensionsRequired"] = {"KHR_mesh_quantization"};
  // Integer positions (KHR_mesh_quantization), not normalized: read as their values. 4 bytes per
  // element keep each 2-byte vec3 aligned as glTF requires.
  const std::vector<std::uint16_t> positions{0, 0, 0, 0, 3, 0, 0, 0, 0, 3, 0, 0};
  const int position = b.add_accessor(b.add_view(positions.data(), positions.size() * 2, 8), component::u16, "VEC3", 3);
  // Signed normalized normals: 127 -> 1, -128 clamps to -1 (glTF 2.0 section 3.11).
  const std::vector<std::int8_t> normals{0, 0, 127, 0, 0, 0, -128, 0, 0, 127, 0, 0};
  const int normal = b.add_accessor(b.add_view(normals.data(), normals.size(), 4), component::i8, "VEC3", 3, true);
  const int uv8 = b.add_data(std::vector<std::uint8_t>{0, 255, 128, 51, 255, 0}, component::u8, "VEC2", 2, true);
  const int uv16 = b.add_data(std::vector<std::uint16_t>{0, 65535, 32768, 13107, 65535, 0}, component::u16, "VEC2", 2, true);
  b.add_mesh("m", json::array({{{"attributes", {{"POSITION", position}, {"NORMAL", normal}, {"TEXCOORD_0", uv8}, {"TEXCOORD_1", uv16}}}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("components"), "components"));
  REQUIRE(scene.meshes.size() == 1);
  const igi::Mesh& mesh = scene.meshes[0];
  CHECK(mesh.positions[1] == glm::vec3(3, 0, 0));
  CHECK(mesh.positions[2] == glm::vec3(0, 3, 0));
  CHECK(mesh.normals[0] == glm::vec3(0, 0, 1));
  CHECK(mesh.normals[1] == glm::vec3(0, 0, -1));
  CHECK(mesh.normals[2] == glm::vec3(0, 1, 0));
  REQUIRE(mesh.uvs.size() == 3);
  CHECK(mesh.uvs[0] == glm::vec2(0.0f, 1.0f));
  CHECK(mesh.uvs[1].x == Approx(128.0f / 255.0f));
  CHECK(mesh.uvs[1].y == Approx(0.2f));  // 51 / 255
  REQUIRE(mesh.uvs1.size() == 3);
  CHECK(mesh.uvs1[0] == glm::vec2(0.0f, 1.0f));
  CHECK(mesh.uvs1[1].x == Approx(32768.0f / 65535.0f));
  CHECK(mesh.uvs1[1].y == Approx(0.2f));  // 13107 / 65535
}

TEST_CASE("glTF TANGENT: float and normalized short tangents, w reduced to its sign, unusable ones warn, wrong counts "
          "fail", "[scene][gltf][normal-map]") {
  const auto scene_with = [](bool quantized, int tangent_count, std::string& warnings) {
    GltfBuilder b;
    b.doc["extensionsUsed"] = {"KHR_mesh_quantization"};
    const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
    int tangent = 0;
    if (quantized) {
      // Normalized shorts: 32767 -> 1, -32768 clamps to -1; the third tangent is zero (unusable).
      tangent = b.add_data(std::vector<std::int16_t>{32767, 0, 0, 32767, 0, -32768, 0, -32768, 0, 0, 0, 32767},
                           component::i16, "VEC4", 4, true);
    } else {
      std::vector<float> values{2, 0, 0, 0.5f, 0, 0, 3, -0.25f, 0, 1, 0, 1};
      values.resize(std::size_t(tangent_count) * 4, 1.0f);
      tangent = b.add_data(values, component::f32, "VEC4", 4);
    }
    b.add_mesh("m", json::array({{{"attributes", {{"POSITION", position}, {"TANGENT", tangent}}}}}));
    b.add_node({{"mesh", 0}});
    b.set_roots({0});
    return load_with_warnings(b.write_gltf(scratch_dir("tangents"), quantized ? "quantized" : "float"), warnings);
  };
  std::string warnings;
  const igi::Scene floats = scene_with(false, 3, warnings);
  CHECK(warnings.empty());
  REQUIRE(floats.meshes[0].tangents.size() == 3);
  CHECK(floats.meshes[0].tangents[0] == glm::vec4(1, 0, 0, 1));
  CHECK(floats.meshes[0].tangents[1] == glm::vec4(0, 0, 1, -1));
  CHECK(floats.meshes[0].tangents[2] == glm::vec4(0, 1, 0, 1));
  const igi::Scene shorts = scene_with(true, 3, warnings);
  REQUIRE(shorts.meshes[0].tangents.size() == 3);
  CHECK(shorts.meshes[0].tangents[0] == glm::vec4(1, 0, 0, 1));
  CHECK(shorts.meshes[0].tangents[1] == glm::vec4(0, -1, 0, -1));
  CHECK(shorts.meshes[0].tangents[2] == glm::vec4(0.0f));
  CHECK_THAT(warnings, Catch::Contains("1 zero or non-finite tangents"));
  CHECK_THROWS_WITH(scene_with(false, 2, warnings), Catch::Contains("TANGENT has 2 elements for 3 positions"));
}

TEST_CASE("glTF byteStride: interleaved position, normal and uv as in Sponza", "[scene][gltf]") {
  GltfBuilder b;
  // Per vertex: position (12 bytes), normal (12), uv (8) = 32 bytes.
  const std::vector<float> interleaved{0, 0, 0, 0, 0, 1, 0.25f, 0.5f,  //
                                       2, 0, 0, 0, 0, 1, 0.75f, 0.5f,  //
                                       0, 2, 0, 0, 0, 1, 0.25f, 1.0f};
  const int view = b.add_view(interleaved.data(), interleaved.size() * 4, 32);
  const int position = b.add_accessor(view, component::f32, "VEC3", 3);
  const int normal = b.add_accessor(view, component::f32, "VEC3", 3, false, 12);
  const int uv = b.add_accessor(view, component::f32, "VEC2", 3, false, 24);
  b.add_mesh("m", json::array({{{"attributes", {{"POSITION", position}, {"NORMAL", normal}, {"TEXCOORD_0", uv}}}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("stride"), "stride"));
  const igi::Mesh& mesh = scene.meshes.at(0);
  CHECK(mesh.positions == std::vector<glm::vec3>{{0, 0, 0}, {2, 0, 0}, {0, 2, 0}});
  CHECK(mesh.normals == std::vector<glm::vec3>{{0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  CHECK(mesh.uvs == std::vector<glm::vec2>{{0.25f, 0.5f}, {0.75f, 0.5f}, {0.25f, 1.0f}});
}

TEST_CASE("glTF sparse accessors replace the listed elements, with and without a base bufferView", "[scene][gltf]") {
  GltfBuilder b;
  // Positions with no bufferView: all zeros, then sparse entries 1 -> (1,0,0) and 2 -> (0,1,0).
  const std::vector<std::uint8_t> targets{1, 2};
  const std::vector<float> values{1, 0, 0, 0, 1, 0};
  b.doc["accessors"].push_back({{"componentType", component::f32}, {"type", "VEC3"}, {"count", 3},
                                {"sparse", {{"count", 2},
                                            {"indices", {{"bufferView", b.add_view(targets.data(), 2)}, {"componentType", component::u8}}},
                                            {"values", {{"bufferView", b.add_view(values.data(), 24)}}}}}});
  const int position = int(b.doc["accessors"].size()) - 1;
  // Indices (0, 0, 2) in a bufferView with the sparse entry 1 -> 1. (tinygltf 2.7 rejects index
  // accessors without a bufferView, so that variant is tested on positions only.)
  const int indices = b.add_indices({0, 0, 2});
  const std::vector<std::uint16_t> index_targets{1};
  const std::vector<std::uint32_t> index_values{1};
  b.doc["accessors"][indices]["sparse"] = {{"count", 1},
                                           {"indices", {{"bufferView", b.add_view(index_targets.data(), 2)}, {"componentType", component::u16}}},
                                           {"values", {{"bufferView", b.add_view(index_values.data(), 4)}}}};
  b.add_mesh("m", json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("sparse"), "sparse"));
  const igi::Mesh& mesh = scene.meshes.at(0);
  CHECK(mesh.positions == std::vector<glm::vec3>{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  REQUIRE(mesh.triangles.size() == 1);
  CHECK(mesh.triangles[0] == glm::uvec3(0, 1, 2));
}

TEST_CASE("glTF triangle strips and fans keep one consistent winding", "[scene][gltf]") {
  GltfBuilder b;
  // A zig-zag strip of 5 vertices and a fan around vertex 0, all in the z = 0 plane.
  const int strip = b.add_positions({{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, {1, 1, 0}, {2, 0, 0}});
  const int fan = b.add_positions({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {-1, 1, 0}});
  b.add_mesh("strip", json::array({{{"attributes", {{"POSITION", strip}}}, {"mode", 5}}}));
  b.add_mesh("fan", json::array({{{"attributes", {{"POSITION", fan}}}, {"mode", 6}}}));
  b.add_node({{"mesh", 0}});
  b.add_node({{"mesh", 1}});
  b.set_roots({0, 1});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("strips"), "strips"));
  const igi::Mesh& strip_mesh = scene.meshes.at(0);
  // glTF 2.0 section 3.7.2.1: strip triangle i is (i, i+1, i+2) for even i, (i, i+2, i+1) for odd i.
  REQUIRE(strip_mesh.triangles.size() == 3);
  CHECK(strip_mesh.triangles[0] == glm::uvec3(0, 1, 2));
  CHECK(strip_mesh.triangles[1] == glm::uvec3(1, 3, 2));
  CHECK(strip_mesh.triangles[2] == glm::uvec3(2, 3, 4));
  for (std::size_t t = 0; t < 3; ++t) CHECK(near(face_normal(strip_mesh, t), face_normal(strip_mesh, 0)));
  // Fan triangle i is (i+1, i+2, 0).
  const igi::Mesh& fan_mesh = scene.meshes.at(1);
  REQUIRE(fan_mesh.triangles.size() == 3);
  CHECK(fan_mesh.triangles[0] == glm::uvec3(1, 2, 0));
  CHECK(fan_mesh.triangles[2] == glm::uvec3(3, 4, 0));
  for (std::size_t t = 0; t < 3; ++t) CHECK(near(face_normal(fan_mesh, t), {0, 0, 1}));
}

TEST_CASE("glTF points and lines are skipped with a warning, triangles of the same mesh stay", "[scene][gltf]") {
  GltfBuilder b;
  const int position = b.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  b.add_mesh("mixed", json::array({{{"attributes", {{"POSITION", position}}}, {"mode", 0}},
                                   {{"attributes", {{"POSITION", position}}}, {"mode", 1}},
                                   {{"attributes", {{"POSITION", position}}}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("modes"), "modes"), &warnings);
  REQUIRE(warnings.size() == 2);
  CHECK_THAT(warnings[0], Catch::Contains("modes.gltf") && Catch::Contains("mode 0") && Catch::Contains("skipped"));
  CHECK_THAT(warnings[1], Catch::Contains("mode 1"));
  CHECK(scene.meshes.size() == 1);
  CHECK(scene.triangle_count() == 1);
}

TEST_CASE("glTF missing normals are computed, weighted by triangle area", "[scene][gltf]") {
  GltfBuilder b;
  // Vertex 0 is shared by a triangle of area 2 facing +Z and one of area 0.5 facing +Y.
  const int position = b.add_positions({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0, 0, 1}, {1, 0, 0}});
  const int indices = b.add_indices({0, 1, 2, 0, 3, 4});
  b.add_mesh("m", json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
  b.add_node({{"mesh", 0}});
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("normals"), "normals"));
  const igi::Mesh& mesh = scene.meshes.at(0);
  REQUIRE(mesh.normals.size() == 5);
  // Areas 2 and 0.5 weight (0,0,1) and (0,1,0): (0, 0.5, 2) / |.| = (0, 1, 4) / sqrt(17).
  CHECK(near(mesh.normals[0], glm::vec3(0, 1, 4) / std::sqrt(17.0f)));
  CHECK(near(mesh.normals[1], {0, 0, 1}));
  CHECK(near(mesh.normals[3], {0, 1, 0}));
}

TEST_CASE("glTF textures are decoded once, shared by materials, sRGB, top row first", "[scene][gltf]") {
  const auto dir = scratch_dir("textures");
  // 2x2 RGBA: row 0 red, green; row 1 blue, white with alpha 128.
  const std::vector<std::uint8_t> texels{255, 0, 0, 255, 0, 255, 0, 255, 0, 0, 255, 255, 255, 255, 255, 128};
  REQUIRE(stbi_write_png((dir / "checker.png").string().c_str(), 2, 2, 4, texels.data(), 8) != 0);
  GltfBuilder b;
  b.doc["images"] = json::array({{{"uri", "checker.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 0}}});  // two textures, one image
  b.doc["materials"] = json::array({
      {{"name", "base"}, {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"texCoord", 1}}}}}},
      {{"name", "glow"}, {"emissiveFactor", {1, 1, 1}}, {"emissiveTexture", {{"index", 1}}}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(dir, "textures"), &warnings);
  // Shading reads every texture through TEXCOORD_0: the base colour's set 1 is named, not ignored silently.
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("'base': base colour texture uses TEXCOORD_1"));
  REQUIRE(scene.textures.size() == 1);
  const igi::Texture& texture = scene.textures[0];
  CHECK(texture.width == 2);
  CHECK(texture.height == 2);
  CHECK(texture.srgb);
  CHECK(texture.texels == texels);
  CHECK(texture.name == "checker.png");
  REQUIRE(scene.materials.size() == 2);
  CHECK(scene.materials[0].base_color_texture == 0);
  CHECK(scene.materials[0].base_color_uv_set == 1);
  CHECK(scene.materials[1].emissive_texture == 0);
}

TEST_CASE("glTF metallic-roughness textures are linear: an image also used as base colour becomes a second texture",
          "[scene][gltf]") {
  const auto dir = scratch_dir("metallic_roughness");
  const std::vector<std::uint8_t> texels{10, 20, 30, 255, 40, 50, 60, 255, 70, 80, 90, 255, 100, 110, 120, 255};
  REQUIRE(stbi_write_png((dir / "shared.png").string().c_str(), 2, 2, 4, texels.data(), 8) != 0);
  REQUIRE(stbi_write_png((dir / "rough.png").string().c_str(), 2, 2, 4, texels.data(), 8) != 0);
  GltfBuilder b;
  b.doc["images"] = json::array({{{"uri", "shared.png"}}, {{"uri", "rough.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
  b.doc["materials"] = json::array({
      // Image 0 as base colour (sRGB) and as metallic-roughness (linear) of one material.
      {{"name", "varnish"},
       {"pbrMetallicRoughness",
        {{"baseColorTexture", {{"index", 0}}}, {"metallicRoughnessTexture", {{"index", 0}}}, {"roughnessFactor", 0.5}}}},
      // Image 1 only as metallic-roughness, twice: one linear texture.
      {{"name", "steel"}, {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 1}}}}}},
      {{"name", "chrome"}, {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 1}}}}}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(dir, "metallic_roughness"));
  REQUIRE(scene.materials.size() == 3);
  REQUIRE(scene.textures.size() == 3);
  const igi::Material& varnish = scene.materials[0];
  REQUIRE(varnish.base_color_texture >= 0);
  REQUIRE(varnish.metallic_roughness_texture >= 0);
  CHECK(varnish.base_color_texture != varnish.metallic_roughness_texture);
  CHECK(scene.textures[std::size_t(varnish.base_color_texture)].srgb);
  CHECK_FALSE(scene.textures[std::size_t(varnish.metallic_roughness_texture)].srgb);
  CHECK(scene.textures[std::size_t(varnish.metallic_roughness_texture)].texels == texels);
  CHECK(varnish.roughness == 0.5f);
  CHECK(varnish.metallic == 1.0f);  // glTF's default factor, which the texture's blue channel scales
  const int rough = scene.materials[1].metallic_roughness_texture;
  CHECK(rough >= 0);
  CHECK(scene.materials[2].metallic_roughness_texture == rough);
  CHECK_FALSE(scene.textures[std::size_t(rough)].srgb);
  CHECK(scene.textures[std::size_t(rough)].name == "rough.png");
  CHECK(scene.materials[1].base_color_texture == -1);
}

TEST_CASE("glTF normal textures: linear, with their scale, other sets and lost images warn", "[scene][gltf]") {
  const auto dir = scratch_dir("normal_textures");
  const std::vector<std::uint8_t> texels{128, 128, 255, 255};
  REQUIRE(stbi_write_png((dir / "bumps.png").string().c_str(), 1, 1, 4, texels.data(), 4) != 0);
  GltfBuilder b;
  b.doc["images"] = json::array({{{"uri", "bumps.png"}}, {{"uri", "lost.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
  b.doc["materials"] = json::array({
      {{"name", "plaster"}, {"normalTexture", {{"index", 0}, {"scale", 0.5}}}},
      {{"name", "tiles"}, {"normalTexture", {{"index", 0}, {"texCoord", 1}}}},
      {{"name", "stone"}, {"normalTexture", {{"index", 1}}}},
      {{"name", "paint"}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  std::string all;
  const igi::Scene scene = load_with_warnings(b.write_gltf(dir, "normals"), all);
  INFO(all);
  REQUIRE(scene.materials.size() == 4);
  const int bumps = scene.materials[0].normal_texture;
  REQUIRE(bumps >= 0);
  CHECK_FALSE(scene.textures[std::size_t(bumps)].srgb);
  CHECK(scene.materials[0].normal_scale == 0.5f);
  CHECK(scene.materials[1].normal_texture == bumps);
  CHECK(scene.materials[1].normal_scale == 1.0f);  // glTF's default
  CHECK(scene.materials[2].normal_texture == -1);
  CHECK(scene.materials[3].normal_texture == -1);
  CHECK_THAT(all, Catch::Contains("'tiles': normal texture uses TEXCOORD_1"));
  CHECK_THAT(all, Catch::Contains("'stone'") && Catch::Contains("lost.png") &&
                      Catch::Contains("drops the texture and keeps its normals"));
}

TEST_CASE("glTF KHR_texture_transform: offset, rotation and scale per texture, required or not", "[scene][gltf]") {
  const auto dir = scratch_dir("texture_transform");
  const std::vector<std::uint8_t> texels{128, 128, 255, 255};
  REQUIRE(stbi_write_png((dir / "one.png").string().c_str(), 1, 1, 4, texels.data(), 4) != 0);
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_texture_transform"};
  b.doc["extensionsRequired"] = {"KHR_texture_transform"};
  b.doc["images"] = json::array({{{"uri", "one.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  const json quarter_turn = {{"KHR_texture_transform", {{"offset", {0.5, 0.25}}, {"rotation", 1.5707963267948966}, {"scale", {2, 3}}}}};
  b.doc["materials"] = json::array({
      {{"name", "floor"},
       {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}, {"extensions", quarter_turn}}},
                                 {"metallicRoughnessTexture", {{"index", 0}}}}},
       {"normalTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {4, 4}}}}}}}},
       {"emissiveTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"texCoord", 1}}}}}}}},
      {{"name", "odd"},
       {"pbrMetallicRoughness",
        {{"baseColorTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"offset", "far"}, {"rotation", "some"}}}}}}}}}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  std::string all;
  const igi::Scene scene = load_with_warnings(b.write_gltf(dir, "transform"), all);
  INFO(all);
  REQUIRE(scene.materials.size() == 2);
  const igi::Material& floor = scene.materials[0];
  // offset + rotation x scale: u' = 2 cos(r) u + 3 sin(r) v + 0.5, v' = -2 sin(r) u + 3 cos(r) v + 0.25.
  CHECK(near(glm::vec3(floor.base_color_transform.apply({0.0f, 0.0f}), 0.0f), {0.5f, 0.25f, 0.0f}));
  CHECK(near(glm::vec3(floor.base_color_transform.apply({1.0f, 0.0f}), 0.0f), {0.5f, -1.75f, 0.0f}));
  CHECK(near(glm::vec3(floor.base_color_transform.apply({0.0f, 1.0f}), 0.0f), {3.5f, 0.25f, 0.0f}));
  CHECK(floor.base_color_transform.footprint_scale() == Approx(std::sqrt(6.0f)));
  // No extension: the identity.
  CHECK(floor.metallic_roughness_transform.apply({0.3f, 0.7f}) == glm::vec2(0.3f, 0.7f));
  CHECK(floor.normal_transform.apply({0.25f, 0.5f}) == glm::vec2(1.0f, 2.0f));
  // The extension's texCoord replaces the texture's and is named like it.
  CHECK_THAT(all, Catch::Contains("'floor': emissive texture uses TEXCOORD_1"));
  // Fields that are not numbers are named and left at their defaults.
  CHECK_THAT(all, Catch::Contains("'odd': the base colour texture's KHR_texture_transform offset is not two numbers"));
  CHECK_THAT(all, Catch::Contains("'odd': the base colour texture's KHR_texture_transform rotation is not a number"));
  CHECK(scene.materials[1].base_color_transform.apply({0.3f, 0.7f}) == glm::vec2(0.3f, 0.7f));
  CHECK(all.find("ignores") == std::string::npos);  // the extension is known
}

TEST_CASE("glTF metallic-roughness texture problems are warnings that keep the factors", "[scene][gltf]") {
  const auto dir = scratch_dir("metallic_roughness_problems");
  const std::vector<std::uint8_t> texels{0, 255, 255, 255};
  REQUIRE(stbi_write_png((dir / "one.png").string().c_str(), 1, 1, 4, texels.data(), 4) != 0);
  GltfBuilder b;
  b.doc["images"] = json::array({{{"uri", "one.png"}}, {{"uri", "missing.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
  b.doc["materials"] = json::array({
      {{"name", "second set"}, {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 0}, {"texCoord", 1}}}}}},
      {{"name", "lost"}, {"pbrMetallicRoughness", {{"metallicRoughnessTexture", {{"index", 1}}}, {"metallicFactor", 0.25}}}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  std::string all;
  const igi::Scene scene = load_with_warnings(b.write_gltf(dir, "problems"), all);
  INFO(all);
  CHECK_THAT(all, Catch::Contains("'second set': metallic-roughness texture uses TEXCOORD_1"));
  CHECK_THAT(all, Catch::Contains("'lost'") && Catch::Contains("missing.png") &&
                      Catch::Contains("drops the texture; its metallic and roughness factor stays"));
  REQUIRE(scene.materials.size() == 2);
  CHECK(scene.materials[0].metallic_roughness_texture == 0);
  CHECK(scene.materials[1].metallic_roughness_texture == -1);
  CHECK(scene.materials[1].metallic == 0.25f);
}

TEST_CASE("glTF materials: factors, emissive strength, transmission, ior, alpha mode, double-sided", "[scene][gltf]") {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_materials_emissive_strength", "KHR_materials_transmission", "KHR_materials_ior"};
  b.doc["materials"] = json::array({
      {{"name", "glass"},
       {"pbrMetallicRoughness", {{"baseColorFactor", {0.5, 0.25, 1.0, 0.75}}, {"metallicFactor", 0.125}, {"roughnessFactor", 0.0625}}},
       {"emissiveFactor", {1.0, 0.5, 0.25}},
       {"extensions", {{"KHR_materials_emissive_strength", {{"emissiveStrength", 4.0}}},
                       {"KHR_materials_transmission", {{"transmissionFactor", 0.9}}},
                       {"KHR_materials_ior", {{"ior", 1.33}}}}},
       {"alphaMode", "MASK"},
       {"alphaCutoff", 0.25},
       {"doubleSided", true}},
      {{"name", "defaults"}, {"alphaMode", "BLEND"}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("materials"), "materials"));
  REQUIRE(scene.materials.size() == 2);
  const igi::Material& glass = scene.materials[0];
  CHECK(glass.base_color == glm::vec4(0.5f, 0.25f, 1.0f, 0.75f));
  CHECK(glass.metallic == 0.125f);
  CHECK(glass.roughness == 0.0625f);
  CHECK(glass.emission == glm::vec3(4.0f, 2.0f, 1.0f));
  CHECK(glass.transmission == Approx(0.9f));
  CHECK(glass.ior == Approx(1.33f));
  CHECK(glass.alpha_mode == igi::AlphaMode::mask);
  CHECK(glass.alpha_cutoff == 0.25f);
  CHECK(glass.double_sided);
  const igi::Material& defaults = scene.materials[1];  // glTF defaults
  CHECK(defaults.base_color == glm::vec4(1.0f));
  CHECK(defaults.metallic == 1.0f);
  CHECK(defaults.roughness == 1.0f);
  CHECK(defaults.emission == glm::vec3(0.0f));
  CHECK(defaults.transmission == 0.0f);
  CHECK(defaults.ior == 1.5f);
  CHECK(defaults.alpha_mode == igi::AlphaMode::blend);
  CHECK_FALSE(defaults.double_sided);
  CHECK(defaults.base_color_texture == -1);
  CHECK(defaults.specular == 1.0f);  // glTF's 4% dielectric layer
  CHECK(defaults.specular_color == glm::vec3(1.0f));
  CHECK(defaults.specular_texture == -1);
  CHECK(defaults.specular_color_texture == -1);
}

TEST_CASE("glTF KHR_materials_specular: factors, textures (alpha linear, colour sRGB) with their transforms, bad "
          "fields warn", "[scene][gltf][specular]") {
  const auto dir = scratch_dir("materials_specular");
  const std::vector<std::uint8_t> texels{255, 188, 64, 128};
  REQUIRE(stbi_write_png((dir / "tint.png").string().c_str(), 1, 1, 4, texels.data(), 4) != 0);
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_materials_specular", "KHR_texture_transform"};
  b.doc["extensionsRequired"] = {"KHR_materials_specular"};
  b.doc["images"] = json::array({{{"uri", "tint.png"}}, {{"uri", "missing.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}, {{"source", 1}}});
  b.doc["materials"] = json::array({
      {{"name", "varnish"},
       {"extensions",
        {{"KHR_materials_specular",
          {{"specularFactor", 0.5},
           {"specularColorFactor", {1.0, 0.5, 0.25}},
           {"specularTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {2.0, 4.0}}}}}}}},
           {"specularColorTexture", {{"index", 0}, {"texCoord", 1}}}}}}}},
      {{"name", "odd"},
       {"extensions",
        {{"KHR_materials_specular", {{"specularColorFactor", {1.0, 0.5}}, {"specularTexture", {{"index", 1}}}}}}}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  std::string all;
  const igi::Scene scene = load_with_warnings(b.write_gltf(dir, "specular"), all);
  INFO(all);
  REQUIRE(scene.materials.size() == 2);
  const igi::Material& varnish = scene.materials[0];
  CHECK(varnish.specular == 0.5f);
  CHECK(varnish.specular_color == glm::vec3(1.0f, 0.5f, 0.25f));
  // One image, two encodings: the specular weight is linear, the specular colour sRGB.
  REQUIRE(varnish.specular_texture >= 0);
  REQUIRE(varnish.specular_color_texture >= 0);
  CHECK(varnish.specular_texture != varnish.specular_color_texture);
  CHECK_FALSE(scene.textures[std::size_t(varnish.specular_texture)].srgb);
  CHECK(scene.textures[std::size_t(varnish.specular_color_texture)].srgb);
  CHECK(scene.textures[std::size_t(varnish.specular_texture)].texels == texels);
  CHECK(varnish.specular_transform.apply({0.25f, 0.5f}) == glm::vec2(0.5f, 2.0f));
  CHECK(varnish.specular_color_transform.apply({0.25f, 0.5f}) == glm::vec2(0.25f, 0.5f));
  CHECK_THAT(all, Catch::Contains("'varnish': specular colour texture uses TEXCOORD_1"));
  // A colour that is not three numbers and a lost image are warnings that keep the defaults.
  const igi::Material& odd = scene.materials[1];
  CHECK_THAT(all, Catch::Contains("'odd': KHR_materials_specular specularColorFactor is not three numbers"));
  CHECK_THAT(all, Catch::Contains("'odd'") && Catch::Contains("missing.png") && Catch::Contains("its specular factor stays"));
  CHECK(odd.specular_color == glm::vec3(1.0f));
  CHECK(odd.specular == 1.0f);
  CHECK(odd.specular_texture == -1);
  CHECK(all.find("ignores") == std::string::npos);  // the extension is known
}

TEST_CASE("glTF KHR_materials_clearcoat: factors and textures (linear: red weighs the coat, green its roughness) with "
          "their transforms, the coat's normal map warns", "[scene][gltf][clearcoat]") {
  const auto dir = scratch_dir("materials_clearcoat");
  const std::vector<std::uint8_t> texels{200, 100, 50, 255};
  REQUIRE(stbi_write_png((dir / "coat.png").string().c_str(), 1, 1, 4, texels.data(), 4) != 0);
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_materials_clearcoat", "KHR_texture_transform"};
  b.doc["extensionsRequired"] = {"KHR_materials_clearcoat"};
  b.doc["images"] = json::array({{{"uri", "coat.png"}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  b.doc["materials"] = json::array({
      {{"name", "lacquer"},
       {"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}},
       {"extensions",
        {{"KHR_materials_clearcoat",
          {{"clearcoatFactor", 0.75},
           {"clearcoatRoughnessFactor", 0.25},
           {"clearcoatTexture", {{"index", 0}, {"extensions", {{"KHR_texture_transform", {{"scale", {2.0, 4.0}}}}}}}},
           {"clearcoatRoughnessTexture", {{"index", 0}, {"texCoord", 1}}},
           {"clearcoatNormalTexture", {{"index", 0}}}}}}}},
      {{"name", "plain"}},
  });
  b.add_quad_node("quad");
  b.set_roots({0});
  std::string all;
  const igi::Scene scene = load_with_warnings(b.write_gltf(dir, "clearcoat"), all);
  INFO(all);
  REQUIRE(scene.materials.size() == 2);
  const igi::Material& lacquer = scene.materials[0];
  CHECK(lacquer.clearcoat == 0.75f);
  CHECK(lacquer.clearcoat_roughness == 0.25f);
  // The coat's textures are linear: the image used as base colour (sRGB) becomes a second texture.
  REQUIRE(lacquer.clearcoat_texture >= 0);
  CHECK(lacquer.clearcoat_texture == lacquer.clearcoat_roughness_texture);
  CHECK(lacquer.clearcoat_texture != lacquer.base_color_texture);
  CHECK_FALSE(scene.textures[std::size_t(lacquer.clearcoat_texture)].srgb);
  CHECK(scene.textures[std::size_t(lacquer.clearcoat_texture)].texels == texels);
  CHECK(lacquer.clearcoat_transform.apply({0.25f, 0.5f}) == glm::vec2(0.5f, 2.0f));
  CHECK(lacquer.clearcoat_roughness_transform.apply({0.25f, 0.5f}) == glm::vec2(0.25f, 0.5f));
  CHECK_THAT(all, Catch::Contains("'lacquer': clearcoat roughness texture uses TEXCOORD_1"));
  CHECK_THAT(all, Catch::Contains("'lacquer': KHR_materials_clearcoat clearcoatNormalTexture is ignored"));
  // Without the extension: no coat.
  const igi::Material& plain = scene.materials[1];
  CHECK(plain.clearcoat == 0.0f);
  CHECK(plain.clearcoat_texture == -1);
  CHECK(all.find("which igi ignores") == std::string::npos);  // the extension is known
}

TEST_CASE("glTF KHR_lights_punctual: point, spot and directional placed by their nodes", "[scene][gltf]") {
  GltfBuilder b;
  b.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  b.doc["extensions"]["KHR_lights_punctual"]["lights"] = json::array({
      {{"name", "bulb"}, {"type", "point"}, {"color", {1.0, 0.5, 0.25}}, {"intensity", 20.0}, {"range", 5.0}},
      {{"type", "spot"}, {"intensity", 3.0}, {"spot", {{"innerConeAngle", 0.25}, {"outerConeAngle", 0.5}}}},
      {{"name", "sun"}, {"type", "directional"}},
  });
  const float s = std::sqrt(0.5f);
  const int bulb = b.add_node({{"name", "bulb node"}, {"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  // +90 degrees about +X turns the light's -Z into +Y.
  const int spot = b.add_node({{"name", "spot node"}, {"translation", {0, 1, 0}}, {"rotation", {s, 0, 0, s}},
                               {"extensions", {{"KHR_lights_punctual", {{"light", 1}}}}}});
  // The sun hangs under a parent turned +90 degrees about +Y: -Z becomes -X.
  const int sun = b.add_node({{"name", "sun node"}, {"extensions", {{"KHR_lights_punctual", {{"light", 2}}}}}});
  const int parent = b.add_node({{"name", "rig"}, {"rotation", {0, s, 0, s}}, {"children", {sun}}});
  b.set_roots({parent, spot, bulb});
  const igi::Scene scene = load_clean(b.write_gltf(scratch_dir("lights"), "lights"));
  REQUIRE(scene.lights.size() == 3);  // in the order of the file's light array
  const igi::PunctualLight& point = scene.lights[0];
  CHECK(point.name == "bulb");
  CHECK(point.kind == igi::PunctualKind::point);
  CHECK(point.color == glm::vec3(1.0f, 0.5f, 0.25f));
  CHECK(point.intensity == 20.0f);
  CHECK(point.range == 5.0f);
  CHECK(near(point.position, {1, 2, 3}));
  const igi::PunctualLight& spot_light = scene.lights[1];
  CHECK(spot_light.name == "spot node");  // no light name: the node's
  CHECK(spot_light.kind == igi::PunctualKind::spot);
  CHECK(spot_light.inner_cone == 0.25f);
  CHECK(spot_light.outer_cone == 0.5f);
  CHECK(near(spot_light.position, {0, 1, 0}));
  CHECK(near(spot_light.direction, {0, 1, 0}));
  const igi::PunctualLight& sun_light = scene.lights[2];
  CHECK(sun_light.kind == igi::PunctualKind::directional);
  CHECK(sun_light.intensity == 1.0f);  // glTF default
  CHECK(near(sun_light.direction, {-1, 0, 0}));
}

TEST_CASE("glTF cameras: perspective parameters, named by camera or node, scale removed, orthographic skipped", "[scene][gltf]") {
  GltfBuilder b;
  b.doc["cameras"] = json::array({
      {{"name", "main"}, {"type", "perspective"}, {"perspective", {{"yfov", 0.5}, {"aspectRatio", 2.0}, {"znear", 0.1}}}},
      {{"type", "perspective"}, {"perspective", {{"yfov", 1.0}, {"znear", 0.01}}}},
      {{"name", "flat"}, {"type", "orthographic"}, {"orthographic", {{"xmag", 1.0}, {"ymag", 1.0}, {"znear", 0.1}, {"zfar", 10.0}}}},
  });
  b.add_node({{"name", "eye"}, {"camera", 1}, {"translation", {0, 0, 5}}, {"scale", {3, 3, 3}}});
  b.add_node({{"name", "main node"}, {"camera", 0}, {"translation", {1, 2, 3}}});
  b.add_node({{"name", "ortho"}, {"camera", 2}});
  b.set_roots({0, 1, 2});
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(b.write_gltf(scratch_dir("cameras"), "cameras"), &warnings);
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Catch::Contains("orthographic"));
  REQUIRE(scene.cameras.size() == 2);
  CHECK(scene.cameras[0].name == "main");
  CHECK(scene.cameras[0].yfov == 0.5f);
  CHECK(scene.cameras[0].aspect == 2.0f);
  CHECK(scene.cameras[0].znear == 0.1f);
  CHECK(near(scene.cameras[0].position(), {1, 2, 3}));
  CHECK(scene.cameras[1].name == "eye");
  CHECK(scene.cameras[1].aspect == 0.0f);  // absent: the image's
  CHECK(near(scene.cameras[1].position(), {0, 0, 5}));
  CHECK(near(glm::vec3(scene.cameras[1].camera_to_world[0]), {1, 0, 0}));  // unit axes despite scale 3
}

TEST_CASE("glTF .glb with its BIN chunk loads the same scene as .gltf + .bin", "[scene][gltf]") {
  GltfBuilder b;
  const float s = std::sqrt(0.5f);
  b.add_quad_node("quad", {{"rotation", {s, 0, 0, s}}, {"translation", {1, 2, 3}}});
  b.set_roots({0});
  const auto dir = scratch_dir("glb");
  const igi::Scene text = load_clean(b.write_gltf(dir, "scene"));
  const igi::Scene binary = load_clean(b.write_glb(dir, "scene"));
  CHECK(binary.name == "scene");
  REQUIRE(binary.meshes.size() == text.meshes.size());
  CHECK(binary.meshes[0].positions == text.meshes[0].positions);
  CHECK(binary.meshes[0].triangles == text.meshes[0].triangles);
  CHECK(binary.meshes[0].normals == text.meshes[0].normals);
  CHECK(binary.instances[0].transform == text.instances[0].transform);
}

TEST_CASE("glTF .glb images stored in a bufferView are decoded", "[scene][gltf]") {
  const auto dir = scratch_dir("glb-image");
  const std::vector<std::uint8_t> texels{10, 20, 30, 255};
  REQUIRE(stbi_write_png((dir / "pixel.png").string().c_str(), 1, 1, 4, texels.data(), 4) != 0);
  const std::string png = igi::testing::read_bytes(dir / "pixel.png");
  GltfBuilder b;
  const int view = b.add_view(png.data(), png.size());
  b.doc["images"] = json::array({{{"bufferView", view}, {"mimeType", "image/png"}, {"name", "embedded"}}});
  b.doc["textures"] = json::array({{{"source", 0}}});
  b.doc["materials"] = json::array({{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}}}}});
  b.add_quad_node("quad");
  b.set_roots({0});
  const igi::Scene scene = load_clean(b.write_glb(dir, "embedded"));
  REQUIRE(scene.textures.size() == 1);
  CHECK(scene.textures[0].texels == texels);
  CHECK(scene.textures[0].name == "embedded");
}

TEST_CASE("glTF files without scenes use every root node, loading is deterministic", "[scene][gltf]") {
  GltfBuilder b;
  const int quad = b.add_quad_node("quad");
  const int child = b.add_node({{"name", "child"}, {"mesh", 0}, {"translation", {0, 0, 1}}});
  b.doc["nodes"][quad]["children"] = {child};
  b.add_node({{"name", "second root"}, {"mesh", 0}, {"translation", {0, 0, 2}}});
  const auto file = b.write_gltf(scratch_dir("no-scenes"), "no-scenes");
  const igi::Scene first = load_clean(file);
  const igi::Scene second = load_clean(file);
  REQUIRE(first.instances.size() == 3);
  CHECK(first.instances[0].name == "quad");
  CHECK(first.instances[1].name == "child");
  CHECK(first.instances[2].name == "second root");
  REQUIRE(second.instances.size() == 3);
  for (std::size_t i = 0; i < 3; ++i) CHECK(first.instances[i].transform == second.instances[i].transform);
  CHECK(first.meshes[0].positions == second.meshes[0].positions);
  CHECK(first.meshes[0].normals == second.meshes[0].normals);
}
