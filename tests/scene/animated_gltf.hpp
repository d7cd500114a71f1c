#pragma once
// Small animated glTF files the tests write themselves: keyframed nodes, a two-bone skin, a
// morph target given by a sparse accessor, an animated camera and light. Shared by the scene
// tests (values against hand computation) and the render tests (every backend, one image).

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

#include "gltf_builder.hpp"

namespace igi::testing {

/// Float keys or values as a new accessor of `type` ("SCALAR", "VEC3", ...) with `components` per element.
inline int add_floats(GltfBuilder& gltf, const std::vector<float>& values, const char* type, int components) {
  return gltf.add_data(values, f32, type, components);
}

/// Adds an animation `name` with one sampler per channel: each channel is (node, path, interpolation, input, output).
struct ChannelSpec {
  int node;                  ///< Target node.
  std::string path;          ///< translation, rotation, scale or weights.
  std::string interpolation; ///< LINEAR, STEP or CUBICSPLINE.
  int input;                 ///< Accessor of key times.
  int output;                ///< Accessor of values.
};

/// Adds animation `name` of `channels`; returns its index.
inline int add_animation(GltfBuilder& gltf, const std::string& name, const std::vector<ChannelSpec>& channels) {
  nlohmann::json animation = {{"name", name}, {"channels", nlohmann::json::array()}, {"samplers", nlohmann::json::array()}};
  for (const ChannelSpec& channel : channels) {
    animation["samplers"].push_back({{"input", channel.input}, {"output", channel.output}, {"interpolation", channel.interpolation}});
    animation["channels"].push_back(
        {{"sampler", int(animation["samplers"].size()) - 1}, {"target", {{"node", channel.node}, {"path", channel.path}}}});
  }
  gltf.doc["animations"].push_back(animation);
  return int(gltf.doc["animations"].size()) - 1;
}

/// A floor quad (static, 4 x 4 at y = 0) so rendered images have something to receive light.
inline int add_floor(GltfBuilder& gltf) {
  const int position = gltf.add_positions({{-2, 0, 2}, {2, 0, 2}, {2, 0, -2}, {-2, 0, -2}});
  const int indices = gltf.add_indices({0, 1, 2, 0, 2, 3});
  const int mesh = gltf.add_mesh("floor", nlohmann::json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
  return gltf.add_node({{"name", "floor"}, {"mesh", mesh}});
}

/// The two-bone skin's rest vertices: A on bone 0 alone, B on bone 1 alone, C and D halfway
/// (D with its second half in JOINTS_1/WEIGHTS_1).
inline const std::vector<glm::vec3>& skin_rest_vertices() {
  static const std::vector<glm::vec3> vertices{{0.2f, 0.5f, 0.0f}, {0.2f, 1.5f, 0.0f}, {-0.2f, 1.0f, 0.0f}, {-0.2f, 1.5f, 0.0f}};
  return vertices;
}

/// Adds a two-bone skin: bone 0 at the origin, bone 1 at (0, 1, 0) its child, whose rotation
/// about +Z goes from none at t = 0 to 90 degrees at t = 1 (LINEAR); the skinned mesh's node is
/// translated by (5, 0, 0), which glTF says skinning ignores. Returns the root nodes (bone 0, mesh node).
inline std::vector<int> add_two_bone_skin(GltfBuilder& gltf) {
  const int position = gltf.add_positions(skin_rest_vertices());
  const int normal = gltf.add_positions({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int indices = gltf.add_indices({0, 1, 2, 2, 1, 3});
  const std::vector<std::uint8_t> joints0{0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
  const std::vector<float> weights0{1, 0, 0, 0, 1, 0, 0, 0, 0.5f, 0.5f, 0, 0, 0.5f, 0, 0, 0};
  const std::vector<std::uint8_t> joints1{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 1, 0, 0, 0};
  const std::vector<float> weights1{0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0.5f, 0, 0, 0};
  const int j0 = gltf.add_data(joints0, u8, "VEC4", 4);
  const int w0 = add_floats(gltf, weights0, "VEC4", 4);
  const int j1 = gltf.add_data(joints1, u8, "VEC4", 4);
  const int w1 = add_floats(gltf, weights1, "VEC4", 4);
  const int mesh = gltf.add_mesh("skinned", nlohmann::json::array({{{"attributes",
                                                                     {{"POSITION", position},
                                                                      {"NORMAL", normal},
                                                                      {"JOINTS_0", j0},
                                                                      {"WEIGHTS_0", w0},
                                                                      {"JOINTS_1", j1},
                                                                      {"WEIGHTS_1", w1}}},
                                                                    {"indices", indices}}}));
  const int bone1 = gltf.add_node({{"name", "bone1"}, {"translation", {0, 1, 0}}});
  const int bone0 = gltf.add_node({{"name", "bone0"}, {"children", {bone1}}});
  // Inverse bind matrices: bone 0 at the origin (identity), bone 1 at (0, 1, 0) (a translation by -1 in y).
  const std::vector<float> inverse_bind{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1,
                                        1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, -1, 0, 1};
  const int matrices = add_floats(gltf, inverse_bind, "MAT4", 16);
  gltf.doc["skins"].push_back({{"name", "arm"}, {"joints", {bone0, bone1}}, {"inverseBindMatrices", matrices}, {"skeleton", bone0}});
  const int skinned = gltf.add_node({{"name", "skinned"}, {"mesh", mesh}, {"skin", 0}, {"translation", {5, 0, 0}}});
  const float half = 0.70710678f;  // sin and cos of 45 degrees: a quaternion of 90 degrees about +Z
  const int times = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const int rotations = add_floats(gltf, {0, 0, 0, 1, 0, 0, half, half}, "VEC4", 4);
  add_animation(gltf, "bend", {{bone1, "rotation", "LINEAR", times, rotations}});
  return {bone0, skinned};
}

/// Adds a quad (x, y in [0, 1] at z = 0, normal +Z, tangent +X) with one morph target that lifts
/// vertex 2 by (0, 0, 1), tilts its normal by (0, 1, 0) and its tangent by (0, 0, 1), each given
/// as a sparse accessor without a bufferView;
/// the mesh's default weight is 0.25, and animation "morph" drives it from 0 at t = 0 to 1 at t = 1.
/// Returns the node.
inline int add_morphed_quad(GltfBuilder& gltf) {
  const int position = gltf.add_positions({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
  const int normal = gltf.add_positions({{0, 0, 1}, {0, 0, 1}, {0, 0, 1}, {0, 0, 1}});
  const int tangent = add_floats(gltf, {1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1, 1, 0, 0, 1}, "VEC4", 4);
  const int indices = gltf.add_indices({0, 1, 2, 0, 2, 3});
  const auto sparse_vec3 = [&](std::uint32_t vertex, const std::vector<float>& value) {
    const std::vector<std::uint32_t> index{vertex};
    const int index_view = gltf.add_view(index.data(), sizeof(std::uint32_t));
    const int value_view = gltf.add_view(value.data(), value.size() * sizeof(float));
    gltf.doc["accessors"].push_back({{"componentType", f32},
                                     {"type", "VEC3"},
                                     {"count", 4},
                                     {"sparse",
                                      {{"count", 1},
                                       {"indices", {{"bufferView", index_view}, {"componentType", u32}}},
                                       {"values", {{"bufferView", value_view}}}}}});
    return int(gltf.doc["accessors"].size()) - 1;
  };
  const int lift = sparse_vec3(2, {0, 0, 1});
  const int tilt = sparse_vec3(2, {0, 1, 0});
  const int twist = sparse_vec3(2, {0, 0, 1});
  const int mesh = gltf.add_mesh(
      "morphed", nlohmann::json::array({{{"attributes", {{"POSITION", position}, {"NORMAL", normal}, {"TANGENT", tangent}}},
                                         {"indices", indices},
                                         {"targets", {{{"POSITION", lift}, {"NORMAL", tilt}, {"TANGENT", twist}}}}}}));
  gltf.doc["meshes"][std::size_t(mesh)]["weights"] = {0.25};
  const int node = gltf.add_node({{"name", "morphed"}, {"mesh", mesh}});
  const int times = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const int weights = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  add_animation(gltf, "morph", {{node, "weights", "LINEAR", times, weights}});
  return node;
}

/// A scene of a floor, the two-bone skin, the morphed quad, a point light and a camera, one
/// animation "all" moving bone 1 and the morph weight together. Written as `name`.gltf in `dir`.
inline std::filesystem::path write_deforming_scene(const std::filesystem::path& dir, const std::string& name) {
  GltfBuilder gltf;
  const int floor = add_floor(gltf);
  const std::vector<int> skin = add_two_bone_skin(gltf);
  const int morphed = add_morphed_quad(gltf);
  gltf.doc["nodes"][std::size_t(morphed)]["translation"] = {-1.2, 0.2, 0.0};
  gltf.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  gltf.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 30.0}, {"color", {1, 1, 1}}}};
  const int light = gltf.add_node({{"name", "lamp"}, {"translation", {0.5, 2.5, 2.0}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  gltf.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.01}}}}};
  const int camera = gltf.add_node({{"name", "eye"}, {"camera", 0}, {"translation", {0.0, 1.0, 4.0}}});
  // "all": bone 1 bends and the quad morphs over one second, both LINEAR.
  const int times = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const float half = 0.70710678f;  // a quaternion of 90 degrees about +Z
  const int rotations = add_floats(gltf, {0, 0, 0, 1, 0, 0, half, half}, "VEC4", 4);
  const int weights = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const int bone1 = gltf.doc["nodes"][std::size_t(skin[0])]["children"][0];
  add_animation(gltf, "all", {{bone1, "rotation", "LINEAR", times, rotations}, {morphed, "weights", "LINEAR", times, weights}});
  // Coloured diffuse materials: a terracotta floor, a green skin, a blue quad (images with colour).
  gltf.doc["materials"] = {
      {{"name", "floor"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.35, 0.2, 1.0}}, {"metallicFactor", 0.0}}}},
      {{"name", "skin"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.7, 0.3, 1.0}}, {"metallicFactor", 0.0}}}},
      {{"name", "quad"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.2, 0.3, 0.8, 1.0}}, {"metallicFactor", 0.0}}}}};
  for (int m = 0; m < 3; ++m) gltf.doc["meshes"][std::size_t(m)]["primitives"][0]["material"] = m;
  gltf.set_roots({floor, skin[0], skin[1], morphed, light, camera});
  return gltf.write_gltf(dir, name);
}

}  // namespace igi::testing
