// glTF animations as the files describe them: every interpolation against hand-computed values
// (linear, shortest-path slerp, step, cubic spline with its tangents), clamping and looping,
// several animations chosen by name or index, a two-bone skin, a morph target from a sparse
// accessor, an animated camera and light, unsupported channels named once, and bad animation
// data refused with an error naming the problem.

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <nlohmann/json.hpp>

#include "animated_gltf.hpp"
#include "gltf_builder.hpp"
#include "gltf_checks.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/gltf.hpp"

namespace {

using Catch::Contains;
using igi::testing::add_animation;
using igi::testing::add_floats;
using igi::testing::GltfBuilder;
using igi::testing::load_clean;
using igi::testing::near;
using igi::testing::scratch_dir;

/// The message of the SceneError loading `file` throws ("" if it loads).
std::string load_error(const std::filesystem::path& file) {
  try {
    std::vector<std::string> warnings;
    static_cast<void>(igi::load_gltf(file, &warnings));
  } catch (const igi::SceneError& error) {
    return error.what();
  }
  return "";
}

/// The translation an animation gives the one instance it moves at `seconds`.
glm::vec3 translation_at(const igi::Scene& scene, int animation, double seconds, bool loop = false) {
  const igi::AnimationPlayer player(scene, animation, loop);
  const igi::SceneChanges changes = player(seconds, igi::Camera{});
  REQUIRE(changes.instances.size() == 1);
  return glm::vec3(changes.instances.front().second[3]);
}

/// A quad node moved by three animations of its translation over keys at t = 1, 2, 4: "linear"
/// (LINEAR), "step" (STEP) and "cubic" (CUBICSPLINE, with its own tangents).
std::filesystem::path write_keyframed_quad(const std::string& test) {
  GltfBuilder gltf;
  const int quad = gltf.add_quad_node("quad");
  const int times = add_floats(gltf, {1.0f, 2.0f, 4.0f}, "SCALAR", 1);
  const int values = add_floats(gltf, {0, 0, 0, 2, 0, 0, 2, 4, 0}, "VEC3", 3);
  add_animation(gltf, "linear", {{quad, "translation", "LINEAR", times, values}});
  add_animation(gltf, "step", {{quad, "translation", "STEP", times, values}});
  // Per key: in-tangent, value, out-tangent.
  const int cubic = add_floats(gltf, {0, 0, 0, 0, 0, 0, 3, 0, 0,   // key 0: value 0, out-tangent (3, 0, 0)
                                      1, 0, 0, 2, 0, 0, 0, 1, 0,   // key 1: in (1, 0, 0), value (2, 0, 0), out (0, 1, 0)
                                      0, 2, 0, 2, 4, 0, 0, 0, 0},  // key 2: in (0, 2, 0), value (2, 4, 0)
                               "VEC3", 3);
  add_animation(gltf, "cubic", {{quad, "translation", "CUBICSPLINE", times, cubic}});
  gltf.set_roots({quad});
  return gltf.write_gltf(scratch_dir(test), "keyframed");
}

TEST_CASE("LINEAR translation interpolates between keys and clamps outside them", "[animation]") {
  const igi::Scene scene = load_clean(write_keyframed_quad("linear"));
  REQUIRE(scene.animations.animations.size() == 3);
  CHECK(scene.animations.animations[0].duration == 4.0f);
  CHECK(near(translation_at(scene, 0, 1.5), {1, 0, 0}));     // halfway from (0,0,0) to (2,0,0)
  CHECK(near(translation_at(scene, 0, 3.0), {2, 2, 0}));     // halfway from (2,0,0) to (2,4,0)
  CHECK(near(translation_at(scene, 0, 0.25), {0, 0, 0}));    // before the first key: the first value
  CHECK(near(translation_at(scene, 0, -3.0), {0, 0, 0}));
  CHECK(near(translation_at(scene, 0, 100.0), {2, 4, 0}));   // after the last key: the last value
}

TEST_CASE("looping wraps time around the animation's duration", "[animation]") {
  const igi::Scene scene = load_clean(write_keyframed_quad("loop"));
  CHECK(near(translation_at(scene, 0, 5.5, true), {1, 0, 0}));   // 5.5 mod 4 = 1.5
  CHECK(near(translation_at(scene, 0, 7.0, true), {2, 2, 0}));   // 7 mod 4 = 3
  CHECK(near(translation_at(scene, 0, -2.5, true), {1, 0, 0}));  // -2.5 mod 4 = 1.5
  CHECK(near(translation_at(scene, 0, 7.0, false), {2, 4, 0}));  // without looping it holds
}

TEST_CASE("STEP holds each key until the next", "[animation]") {
  const igi::Scene scene = load_clean(write_keyframed_quad("step"));
  CHECK(near(translation_at(scene, 1, 1.99), {0, 0, 0}));
  CHECK(near(translation_at(scene, 1, 2.0), {2, 0, 0}));
  CHECK(near(translation_at(scene, 1, 3.9), {2, 0, 0}));
  CHECK(near(translation_at(scene, 1, 4.5), {2, 4, 0}));
}

TEST_CASE("CUBICSPLINE follows the Hermite spline of its values and tangents", "[animation]") {
  const igi::Scene scene = load_clean(write_keyframed_quad("cubic"));
  // Between keys 0 and 1 (span 1) at s = 0.5: h00 = 0.5, h10 = 0.125, h01 = 0.5, h11 = -0.125.
  // p = 0.5 * 0 + 0.125 * 1 * (3,0,0) + 0.5 * (2,0,0) - 0.125 * 1 * (1,0,0) = (1.25, 0, 0).
  CHECK(near(translation_at(scene, 2, 1.5), {1.25f, 0, 0}));
  // Between keys 1 and 2 (span 2) at t = 2.5, s = 0.25: h00 = 0.84375, h10 = 0.140625,
  // h01 = 0.15625, h11 = -0.046875. p = 0.84375 (2,0,0) + 0.28125 (0,1,0) + 0.15625 (2,4,0) - 0.09375 (0,2,0)
  //   = (2, 0.28125 + 0.625 - 0.1875, 0) = (2, 0.71875, 0).
  CHECK(near(translation_at(scene, 2, 2.5), {2.0f, 0.71875f, 0}));
  // At the keys the spline passes through the values.
  CHECK(near(translation_at(scene, 2, 2.0), {2, 0, 0}));
  CHECK(near(translation_at(scene, 2, 4.0), {2, 4, 0}));
}

TEST_CASE("animations are found by name or index", "[animation]") {
  const igi::Scene scene = load_clean(write_keyframed_quad("names"));
  CHECK(igi::find_animation(scene, "step") == 1);
  CHECK(igi::find_animation(scene, "cubic") == 2);
  CHECK(igi::find_animation(scene, "0") == 0);
  CHECK_THROWS_WITH(igi::find_animation(scene, "walk"), Contains("no animation 'walk'") && Contains("'linear', 'step', 'cubic'"));
  CHECK_THROWS_WITH(igi::find_animation(scene, "3"), Contains("no animation '3'"));
}

TEST_CASE("LINEAR rotation takes the shortest path between quaternions of opposite sign", "[animation]") {
  GltfBuilder gltf;
  const int quad = gltf.add_quad_node("quad");
  const int times = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const float half = 0.70710678f;  // cos and sin of 45 degrees
  // Key 1 is -q of 90 degrees about +Z: the same rotation, on the far hemisphere of the identity.
  const int rotations = add_floats(gltf, {0, 0, 0, 1, 0, 0, -half, -half}, "VEC4", 4);
  add_animation(gltf, "turn", {{quad, "rotation", "LINEAR", times, rotations}});
  gltf.set_roots({quad});
  const igi::Scene scene = load_clean(gltf.write_gltf(scratch_dir("slerp"), "slerp"));
  const igi::AnimationPlayer player(scene, 0);
  const auto x_axis_at = [&](double t) {
    const igi::SceneChanges changes = player(t, igi::Camera{});
    REQUIRE(changes.instances.size() == 1);
    return glm::vec3(changes.instances.front().second * glm::vec4(1, 0, 0, 0));
  };
  // Halfway the short way is 45 degrees about +Z (the long way would be -135 degrees: (-0.707, -0.707, 0)).
  CHECK(near(x_axis_at(0.5), {half, half, 0}));
  // A quarter of the way: 22.5 degrees.
  CHECK(near(x_axis_at(0.25), {std::cos(0.3926991f), std::sin(0.3926991f), 0}));
  CHECK(near(x_axis_at(1.0), {0, 1, 0}));
}

TEST_CASE("a two-bone skin moves its vertices as hand computation says, its node's transform ignored", "[animation][skin]") {
  GltfBuilder gltf;
  gltf.set_roots(igi::testing::add_two_bone_skin(gltf));
  const igi::Scene scene = load_clean(gltf.write_gltf(scratch_dir("skin"), "skin"));
  REQUIRE(scene.instances.size() == 1);
  REQUIRE(scene.animations.deformables.size() == 1);
  const igi::Mesh& rest = scene.meshes[std::size_t(scene.instances[0].mesh)];
  // At rest the joints are where they were bound: the vertices as in the file, the node's (5,0,0) ignored.
  CHECK(scene.instances[0].transform == glm::mat4(1.0f));
  for (std::size_t v = 0; v < 4; ++v) CHECK(near(rest.positions[v], igi::testing::skin_rest_vertices()[v]));

  const igi::AnimationPlayer player(scene, igi::find_animation(scene, "bend"));
  const igi::SceneChanges changes = player(1.0, igi::Camera{});
  CHECK(changes.instances.empty());  // a skinned mesh moves by its vertices, not its instance
  REQUIRE(changes.meshes.size() == 1);
  const igi::MeshVertices& bent = changes.meshes[0];
  // Bone 1 turned 90 degrees about +Z at (0,1,0): (x, y) -> (-(y - 1), x + 1) for its vertices.
  CHECK(near(bent.positions[0], {0.2f, 0.5f, 0}));     // A: bone 0 only, unmoved
  CHECK(near(bent.positions[1], {-0.5f, 1.2f, 0}));    // B: bone 1 only
  CHECK(near(bent.positions[2], {-0.1f, 0.9f, 0}));    // C: half of (-0.2,1,0) and half of (0,0.8,0)
  CHECK(near(bent.positions[3], {-0.35f, 1.15f, 0}));  // D: half of (-0.2,1.5,0) and half of (-0.5,0.8,0), the second half from JOINTS_1
  // Normals (0,0,1) are unchanged by a turn about +Z and stay unit.
  for (const glm::vec3& n : bent.normals) CHECK(near(n, {0, 0, 1}));
  // Halfway: 45 degrees. B = (0,1,0) + R45 (0.2, 0.5, 0).
  const float c = std::cos(0.7853982f), s = std::sin(0.7853982f);
  CHECK(near(player(0.5, igi::Camera{}).meshes[0].positions[1], {0.2f * c - 0.5f * s, 1.0f + 0.2f * s + 0.5f * c, 0}));
}

TEST_CASE("a morph target from a sparse accessor moves its vertex by the default and animated weights", "[animation][morph]") {
  GltfBuilder gltf;
  const int node = igi::testing::add_morphed_quad(gltf);
  gltf.set_roots({node});
  const std::filesystem::path dir = scratch_dir("morph");
  const igi::Scene scene = load_clean(gltf.write_gltf(dir, "morph"));
  const igi::Mesh& mesh = scene.meshes[std::size_t(scene.instances[0].mesh)];
  // The mesh's default weight 0.25 is applied at load.
  CHECK(near(mesh.positions[2], {1, 1, 0.25f}));
  CHECK(near(mesh.positions[0], {0, 0, 0}));
  CHECK(near(mesh.normals[2], glm::normalize(glm::vec3(0, 0.25f, 1))));
  const igi::AnimationPlayer player(scene, 0);
  const igi::SceneChanges half = player(0.5, igi::Camera{});
  REQUIRE(half.meshes.size() == 1);
  CHECK(near(half.meshes[0].positions[2], {1, 1, 0.5f}));
  CHECK(near(half.meshes[0].normals[2], glm::normalize(glm::vec3(0, 0.5f, 1))));
  REQUIRE(half.meshes[0].tangents.size() == 4);
  CHECK(near(glm::vec3(half.meshes[0].tangents[2]), glm::normalize(glm::vec3(1, 0, 0.5f))));
  CHECK(half.meshes[0].tangents[2].w == 1.0f);
  CHECK(near(glm::vec3(half.meshes[0].tangents[1]), {1, 0, 0}));
  CHECK(near(half.meshes[0].positions[1], {1, 0, 0}));
  CHECK(near(player(2.0, igi::Camera{}).meshes[0].positions[2], {1, 1, 1}));

  // node.weights overrides mesh.weights.
  gltf.doc["nodes"][std::size_t(node)]["weights"] = {0.75};
  const igi::Scene overridden = load_clean(gltf.write_gltf(dir, "node_weights"));
  CHECK(near(overridden.meshes[std::size_t(overridden.instances[0].mesh)].positions[2], {1, 1, 0.75f}));
}

TEST_CASE("a sparse accessor substitutes animation output values", "[animation][sparse]") {
  GltfBuilder gltf;
  const int quad = gltf.add_quad_node("quad");
  const int times = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const std::vector<float> base{0, 0, 0, 1, 0, 0};
  const int base_view = gltf.add_view(base.data(), base.size() * sizeof(float));
  const std::vector<std::uint16_t> index{1};
  const std::vector<float> value{0, 0, 3};
  const int index_view = gltf.add_view(index.data(), sizeof(std::uint16_t));
  const int value_view = gltf.add_view(value.data(), value.size() * sizeof(float));
  gltf.doc["accessors"].push_back({{"bufferView", base_view},
                                   {"componentType", igi::testing::f32},
                                   {"type", "VEC3"},
                                   {"count", 2},
                                   {"sparse",
                                    {{"count", 1},
                                     {"indices", {{"bufferView", index_view}, {"componentType", igi::testing::u16}}},
                                     {"values", {{"bufferView", value_view}}}}}});
  const int output = int(gltf.doc["accessors"].size()) - 1;
  add_animation(gltf, "slide", {{quad, "translation", "LINEAR", times, output}});
  gltf.set_roots({quad});
  const igi::Scene scene = load_clean(gltf.write_gltf(scratch_dir("sparse"), "sparse"));
  CHECK(near(translation_at(scene, 0, 1.0), {0, 0, 3}));  // the substituted key, not the base (1, 0, 0)
  CHECK(near(translation_at(scene, 0, 0.5), {0, 0, 1.5f}));
}

TEST_CASE("an animated camera and light follow their nodes", "[animation]") {
  GltfBuilder gltf;
  const int quad = gltf.add_quad_node("quad");
  gltf.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  gltf.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "spot"}, {"intensity", 5.0}, {"spot", {{"outerConeAngle", 0.7}}}}};
  gltf.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.8}, {"znear", 0.1}}}}};
  const int camera = gltf.add_node({{"name", "eye"}, {"camera", 0}, {"translation", {0, 0, 2}}});
  // The camera rides on a parent (a dolly) moving along +X; the light turns about +Y.
  const int dolly = gltf.add_node({{"name", "dolly"}, {"children", {camera}}});
  const int lamp = gltf.add_node({{"name", "lamp"}, {"translation", {1, 2, 3}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}});
  const int times = add_floats(gltf, {0.0f, 2.0f}, "SCALAR", 1);
  const int slide = add_floats(gltf, {0, 0, 0, 4, 0, 0}, "VEC3", 3);
  const float half = 0.70710678f;  // a quaternion of 90 degrees about +Y
  const int turn = add_floats(gltf, {0, 0, 0, 1, 0, half, 0, half}, "VEC4", 4);
  add_animation(gltf, "move", {{dolly, "translation", "LINEAR", times, slide}, {lamp, "rotation", "LINEAR", times, turn}});
  gltf.set_roots({quad, dolly, lamp});
  const igi::Scene scene = load_clean(gltf.write_gltf(scratch_dir("camera_light"), "camera_light"));
  REQUIRE(scene.cameras.size() == 1);
  REQUIRE(scene.lights.size() == 1);
  // Every instance, camera and light knows the node that places it.
  CHECK(scene.animations.instance_nodes == std::vector<int>{quad});
  CHECK(scene.animations.camera_nodes == std::vector<int>{camera});
  CHECK(scene.animations.light_nodes == std::vector<int>{lamp});
  CHECK(scene.animations.nodes[std::size_t(camera)].parent == dolly);
  const igi::AnimationPlayer player(scene, 0);
  const igi::SceneChanges changes = player(1.0, scene.cameras[0], 0);
  CHECK(near(changes.camera.position(), {2, 0, 2}));  // halfway along the dolly's slide
  CHECK(changes.camera.yfov == scene.cameras[0].yfov);
  REQUIRE(changes.lights.size() == 1);
  CHECK(changes.lights[0].first == 0);
  CHECK(near(changes.lights[0].second.position, {1, 2, 3}));
  // -Z turned 45 degrees about +Y: (-sin 45, 0, -cos 45).
  CHECK(near(changes.lights[0].second.direction, {-half, 0, -half}));
  CHECK(changes.lights[0].second.kind == igi::PunctualKind::spot);
  CHECK(changes.instances.empty());  // the quad does not move
  // A camera of one's own (index -1) is left as given.
  igi::Camera own;
  own.camera_to_world[3] = glm::vec4(7, 7, 7, 1);
  CHECK(near(player(1.0, own, -1).camera.position(), {7, 7, 7}));
}

TEST_CASE("channels igi cannot play are named once in a warning", "[animation]") {
  GltfBuilder gltf;
  const int quad = gltf.add_quad_node("quad");
  const int times = add_floats(gltf, {0.0f, 1.0f}, "SCALAR", 1);
  const int values = add_floats(gltf, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
  add_animation(gltf, "odd", {{quad, "pointer", "LINEAR", times, values}, {quad, "pointer", "LINEAR", times, values},
                              {quad, "translation", "LINEAR", times, values}});
  gltf.set_roots({quad});
  // tinygltf drops channels without a target node, as KHR_animation_pointer's are: the extension is named instead.
  gltf.doc["extensionsUsed"] = {"KHR_animation_pointer"};
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(gltf.write_gltf(scratch_dir("unsupported"), "unsupported"), &warnings);
  int named = 0, pointer = 0;
  for (const std::string& warning : warnings) {
    named += warning.find("target path 'pointer'") != std::string::npos;
    pointer += warning.find("KHR_animation_pointer channels") != std::string::npos;
  }
  CHECK(named == 1);
  CHECK(pointer == 1);
  REQUIRE(scene.animations.animations.size() == 1);
  CHECK(scene.animations.animations[0].channels.size() == 1);  // the translation channel plays
}

/// A keyframed quad whose one channel has `times` and `values` (VEC3, `interpolation`), written as `name`.
std::filesystem::path write_channel(const std::string& name, const std::vector<float>& times, const std::vector<float>& values,
                                    const std::string& interpolation = "LINEAR") {
  GltfBuilder gltf;
  const int quad = gltf.add_quad_node("quad");
  const int input = add_floats(gltf, times, "SCALAR", 1);
  const int output = add_floats(gltf, values, "VEC3", 3);
  add_animation(gltf, "broken", {{quad, "translation", interpolation, input, output}});
  gltf.set_roots({quad});
  return gltf.write_gltf(scratch_dir(name), name);
}

TEST_CASE("bad animation data is refused with an error naming the problem", "[animation][malformed]") {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  CHECK_THAT(load_error(write_channel("unordered", {0, 2, 1}, {0, 0, 0, 1, 0, 0, 2, 0, 0})),
             Contains("unordered.gltf") && Contains("animation 'broken' channel 0") && Contains("not strictly increasing"));
  CHECK_THAT(load_error(write_channel("repeated", {0, 1, 1}, {0, 0, 0, 1, 0, 0, 2, 0, 0})), Contains("not strictly increasing"));
  CHECK_THAT(load_error(write_channel("mismatched", {0, 1, 2}, {0, 0, 0, 1, 0, 0})),
             Contains("sampler output has 6 values for 3 keys (needs 9)"));
  CHECK_THAT(load_error(write_channel("nan_key", {0, nan}, {0, 0, 0, 1, 0, 0})), Contains("key time 1 is not a finite number"));
  CHECK_THAT(load_error(write_channel("nan_value", {0, 1}, {0, 0, 0, nan, 0, 0})), Contains("output value 3 is not a finite number"));
  CHECK_THAT(load_error(write_channel("short_cubic", {0, 1}, {0, 0, 0, 1, 0, 0}, "CUBICSPLINE")),
             Contains("CUBICSPLINE") && Contains("has 6 values for 2 keys (needs 18)"));
  CHECK_THAT(load_error(write_channel("interpolation", {0, 1}, {0, 0, 0, 1, 0, 0}, "BEZIER")),
             Contains("interpolation 'BEZIER' is not LINEAR, STEP or CUBICSPLINE"));

  // A joint index past the skin's two joints.
  GltfBuilder gltf;
  gltf.set_roots(igi::testing::add_two_bone_skin(gltf));
  const std::vector<std::uint8_t> joints{0, 0, 0, 0, 5, 0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
  const int bad_joints = gltf.add_data(joints, igi::testing::u8, "VEC4", 4);
  gltf.doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_0"] = bad_joints;
  CHECK_THAT(load_error(gltf.write_gltf(scratch_dir("joint"), "joint")),
             Contains("vertex 1 names joint 5 but skin 'arm' has 2 joints"));

  // A channel driving a node that does not exist.
  GltfBuilder missing;
  missing.set_roots({missing.add_quad_node("quad")});
  const int input = add_floats(missing, {0, 1}, "SCALAR", 1);
  const int output = add_floats(missing, {0, 0, 0, 1, 0, 0}, "VEC3", 3);
  add_animation(missing, "lost", {{9, "translation", "LINEAR", input, output}});
  CHECK_THAT(load_error(missing.write_gltf(scratch_dir("missing_node"), "missing_node")), Contains("target node 9 does not exist"));
}

TEST_CASE("sampling never produces NaN, whatever the time", "[animation]") {
  const igi::Scene scene = load_clean(write_keyframed_quad("times"));
  for (int a = 0; a < 3; ++a)
    for (const double t : {-1e30, -1.0, 0.0, 1.0, 1.0000001, 3.999999, 4.0, 1e30, double(std::numeric_limits<float>::quiet_NaN())}) {
      for (const bool loop : {false, true}) {
        const glm::vec3 p = translation_at(scene, a, t, loop);
        CHECK(std::isfinite(p.x));
        CHECK(std::isfinite(p.y));
        CHECK(std::isfinite(p.z));
      }
    }
}

}  // namespace
