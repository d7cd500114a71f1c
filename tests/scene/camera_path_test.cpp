// Camera paths: a walkthrough written as a glTF file by write_camera_path and played back by
// CameraPath gives back its keys, interpolates between them (positions linearly, rotations by
// the shortest arc), clamps or loops outside them, and a file that cannot be followed is refused
// with a message naming it.

#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>

#include "animated_gltf.hpp"
#include "gltf_builder.hpp"
#include "igi/io/camera_path_file.hpp"
#include "igi/scene/camera_path.hpp"

namespace {

using Catch::Contains;

/// A camera at `eye` looking at `target`, +Y up.
glm::mat4 looking(const glm::vec3& eye, const glm::vec3& target) {
  return glm::inverse(glm::lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f)));
}

/// Largest difference between two matrices' entries.
float difference(const glm::mat4& a, const glm::mat4& b) {
  float largest = 0.0f;
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) largest = std::max(largest, std::abs(a[c][r] - b[c][r]));
  return largest;
}

// The keys come back through a quaternion and the file's 9 digits: 1e-5 is a few float roundings
// of entries of size 1 (rotations) and 5 (positions), far below any visible change.
constexpr float key_tolerance = 1e-5f;

/// Three keys: along +X looking at the origin, then round to the other side (a turn of about 150
/// degrees, whose shortest arc differs from the long way round), then up.
std::vector<igi::CameraKey> three_keys() {
  return {{0.0f, looking({5.0f, 1.0f, 0.0f}, {0.0f, 0.0f, 0.0f})},
          {1.0f, looking({-4.0f, 1.0f, 2.5f}, {0.0f, 0.0f, 0.0f})},
          {2.5f, looking({-4.0f, 3.0f, 2.5f}, {0.0f, 1.0f, 0.0f})}};
}

}  // namespace

TEST_CASE("camera path: written keys play back, with linear positions and shortest-arc turns between them", "[scene]") {
  const std::filesystem::path dir = igi::testing::scratch_dir("camera-path");
  const std::vector<igi::CameraKey> keys = three_keys();
  igi::write_camera_path(dir / "walk.gltf", keys, 0.8f, "walk");
  const igi::CameraPath path(dir / "walk.gltf");
  CHECK(path.name() == "walk");
  CHECK(path.duration() == Approx(2.5f));
  for (const igi::CameraKey& key : keys) {
    INFO("key at " << key.seconds << " s");
    CHECK(difference(path.at(key.seconds).camera_to_world, key.camera_to_world) < key_tolerance);
  }
  CHECK(path.at(0.0).yfov == Approx(0.8f));
  // Halfway between the first two keys: the position halfway along the line, the orientation
  // halfway along the shorter arc (the turn from each key to it half the turn between the keys,
  // which is under 180 degrees).
  const glm::mat4 halfway = path.at(0.5).camera_to_world;
  const glm::vec3 expected = 0.5f * (glm::vec3(keys[0].camera_to_world[3]) + glm::vec3(keys[1].camera_to_world[3]));
  CHECK(glm::length(glm::vec3(halfway[3]) - expected) < key_tolerance);
  const glm::quat first = glm::quat_cast(glm::mat3(keys[0].camera_to_world));
  const glm::quat second = glm::quat_cast(glm::mat3(keys[1].camera_to_world));
  const glm::quat middle = glm::quat_cast(glm::mat3(halfway));
  /// The angle of the rotation from orientation `a` to `b`, in [0, pi].
  const auto turn = [](const glm::quat& a, const glm::quat& b) {
    return 2.0f * std::acos(std::min(1.0f, std::abs(glm::dot(a, b))));
  };
  const float whole = turn(first, second);
  REQUIRE(whole > 2.0f);  // the keys were chosen far apart: the long way round would be clearly different
  // 1e-3 rad: acos near its ends magnifies the float rounding of slerp and of the matrix round trips.
  CHECK(turn(first, middle) == Approx(0.5f * whole).margin(1e-3));
  CHECK(turn(middle, second) == Approx(0.5f * whole).margin(1e-3));
  // Outside the keys: held at the ends; with looping, time wraps around the 2.5 s.
  CHECK(difference(path.at(-1.0).camera_to_world, keys.front().camera_to_world) < key_tolerance);
  CHECK(difference(path.at(9.0).camera_to_world, keys.back().camera_to_world) < key_tolerance);
  const igi::CameraPath looped(dir / "walk.gltf", "walk", true);
  CHECK(difference(looped.at(2.5 + 1.0).camera_to_world, keys[1].camera_to_world) < key_tolerance);
}

TEST_CASE("camera path: files that cannot be followed and keys that cannot be written are named", "[scene]") {
  const std::filesystem::path dir = igi::testing::scratch_dir("camera-path-bad");
  // A scene whose animation bends a skin but leaves its camera where it is.
  const std::filesystem::path deforming = igi::testing::write_deforming_scene(dir, "deforming");
  CHECK_THROWS_WITH(igi::CameraPath(deforming), Contains("does not move camera") && Contains("deforming.gltf"));
  CHECK_THROWS_WITH(igi::CameraPath(dir / "missing.gltf"), Contains("missing.gltf"));
  // No camera at all.
  igi::testing::GltfBuilder empty;
  empty.add_node({{"name", "nothing"}});
  empty.set_roots({0});
  CHECK_THROWS_WITH(igi::CameraPath(empty.write_gltf(dir, "no-camera")), Contains("no camera node"));
  // An animation the file lacks.
  igi::write_camera_path(dir / "walk.gltf", three_keys(), 0.8f);
  CHECK_THROWS_WITH(igi::CameraPath(dir / "walk.gltf", "run"), Contains("no animation 'run'"));
  // Keys out of order, none, a bad field of view, a name that would break the file.
  std::vector<igi::CameraKey> backwards = three_keys();
  backwards[2].seconds = 0.5f;
  CHECK_THROWS_WITH(igi::write_camera_path(dir / "x.gltf", backwards, 0.8f), Contains("key 2") && Contains("not after"));
  CHECK_THROWS_WITH(igi::write_camera_path(dir / "x.gltf", std::vector<igi::CameraKey>{}, 0.8f), Contains("no keys"));
  CHECK_THROWS_WITH(igi::write_camera_path(dir / "x.gltf", three_keys(), 0.0f), Contains("field of view"));
  CHECK_THROWS_WITH(igi::write_camera_path(dir / "x.gltf", three_keys(), 0.8f, "say \"hi\""), Contains("quotes"));
}
