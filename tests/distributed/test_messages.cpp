// The tile farm's wire format and the deterministic animations, without MPI.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>

#include "igi/render/animation.hpp"
#include "igi/distributed/messages.hpp"
#include "igi/scene/cornell.hpp"

namespace {

igi::FrameHeader sample_header() {
  igi::FrameHeader header;
  header.index = 7;
  header.has_tone_mapping = true;
  header.tone_mapping.scale = 0.25f;
  header.tone_mapping.white = 3.5f;
  header.send_hdr = true;
  header.changes.camera.name = "cam";
  header.changes.camera.camera_to_world[3] = glm::vec4(1.0f, 2.0f, 3.0f, 1.0f);
  header.changes.camera.yfov = 0.9f;
  igi::PunctualLight light;
  light.name = "spot";
  light.kind = igi::PunctualKind::spot;
  light.position = {4.0f, 5.0f, 6.0f};
  light.outer_cone = 0.5f;
  header.changes.lights.emplace_back(2, light);
  header.changes.instances.emplace_back(3, glm::mat4(2.0f));
  header.changes.meshes.push_back({.mesh = 4,
                                   .positions = {{1.0f, 2.0f, 3.0f}, {4.0f, 5.0f, 6.0f}},
                                   .normals = {{0.0f, 1.0f, 0.0f}, {1.0f, 0.0f, 0.0f}},
                                   .tangents = {}});
  return header;
}

igi::TileMessage sample_tile() {
  igi::TileMessage tile;
  tile.tile = 11;
  tile.frame = 4;
  tile.rays.primary = 100;
  tile.rays.shadow = 2000;
  tile.rays.secondary = 30;
  tile.luminance.log_sum = -12.5;
  tile.luminance.count = 6;
  tile.luminance.max_luminance = 9.0f;
  tile.milliseconds = 1.5;
  for (int i = 0; i < 6; ++i) tile.rgb8.push_back(glm::u8vec3(std::uint8_t(i), std::uint8_t(10 * i), 255));
  return tile;
}

}  // namespace

TEST_CASE("frame header survives encoding", "[distributed]") {
  const igi::FrameHeader header = sample_header();
  const igi::FrameHeader back = igi::decode_frame_header(igi::encode(header));
  CHECK(back.quit == false);
  CHECK(back.index == 7);
  CHECK(back.has_tone_mapping);
  CHECK(back.tone_mapping.scale == 0.25f);
  CHECK(back.tone_mapping.white == 3.5f);
  CHECK(back.send_hdr);
  CHECK(back.changes.camera.name == "cam");
  CHECK(back.changes.camera.camera_to_world == header.changes.camera.camera_to_world);
  CHECK(back.changes.camera.yfov == 0.9f);
  REQUIRE(back.changes.lights.size() == 1);
  CHECK(back.changes.lights[0].first == 2);
  CHECK(back.changes.lights[0].second.name == "spot");
  CHECK(back.changes.lights[0].second.kind == igi::PunctualKind::spot);
  CHECK(back.changes.lights[0].second.position == glm::vec3(4.0f, 5.0f, 6.0f));
  CHECK(back.changes.lights[0].second.outer_cone == 0.5f);
  REQUIRE(back.changes.instances.size() == 1);
  CHECK(back.changes.instances[0].first == 3);
  CHECK(back.changes.instances[0].second == glm::mat4(2.0f));
  REQUIRE(back.changes.meshes.size() == 1);
  CHECK(back.changes.meshes[0].mesh == 4);
  CHECK(back.changes.meshes[0].positions == header.changes.meshes[0].positions);
  CHECK(back.changes.meshes[0].normals == header.changes.meshes[0].normals);
  CHECK(back.changes.meshes[0].tangents.empty());
}

TEST_CASE("tile message survives encoding and costs 3 bytes per pixel plus a fixed header", "[distributed]") {
  const igi::TileMessage tile = sample_tile();
  const std::vector<std::uint8_t> bytes = igi::encode(tile);
  // Fixed part: tile, frame (4 + 4), three ray counts (24), log sum, count, max (8 + 8 + 4), time (8),
  // two array lengths (16) = 76 bytes; then 3 bytes per RGB8 pixel.
  CHECK(bytes.size() == 76 + 3 * tile.rgb8.size());
  const igi::TileMessage back = igi::decode_tile_message(bytes);
  CHECK(back.tile == 11);
  CHECK(back.frame == 4);
  CHECK(back.rays.total() == 2130);
  CHECK(back.luminance.log_sum == -12.5);
  CHECK(back.luminance.count == 6);
  CHECK(back.luminance.max_luminance == 9.0f);
  CHECK(back.milliseconds == 1.5);
  CHECK(back.rgb8 == tile.rgb8);
  CHECK(back.hdr.empty());
}

TEST_CASE("truncated or padded messages are rejected with a message", "[distributed]") {
  std::vector<std::uint8_t> bytes = igi::encode(sample_tile());
  std::vector<std::uint8_t> cut(bytes.begin(), bytes.end() - 1);
  CHECK_THROWS_WITH(igi::decode_tile_message(cut), Catch::Contains("tile message"));
  std::vector<std::uint8_t> padded = bytes;
  padded.push_back(0);
  CHECK_THROWS_WITH(igi::decode_tile_message(padded), Catch::Contains("trailing"));
  std::vector<std::uint8_t> header = igi::encode(sample_header());
  header.resize(header.size() / 2);
  CHECK_THROWS_AS(igi::decode_frame_header(header), igi::DistributedError);
  CHECK_THROWS_AS(igi::decode_frame_header({}), igi::DistributedError);
  // A huge pixel count must be refused before any allocation.
  std::vector<std::uint8_t> huge = bytes;
  const std::uint64_t lie = std::uint64_t(1) << 60;
  std::memcpy(huge.data() + 60, &lie, sizeof lie);  // the RGB8 array length sits after 60 fixed bytes
  CHECK_THROWS_WITH(igi::decode_tile_message(huge), Catch::Contains("runs past the end"));
}

TEST_CASE("scene changes naming missing lights or instances are refused", "[distributed]") {
  const igi::Scene scene = igi::cornell_box();
  igi::SceneChanges changes;
  changes.lights.emplace_back(0, igi::PunctualLight{});
  CHECK_THROWS_WITH(changes.check(scene), Catch::Contains("punctual light 0"));
  changes.lights.clear();
  changes.instances.emplace_back(int(scene.instances.size()), glm::mat4(1.0f));
  CHECK_THROWS_WITH(changes.check(scene), Catch::Contains("instance"));
  changes.instances.clear();
  changes.meshes.push_back({.mesh = int(scene.meshes.size()), .positions = {}, .normals = {}, .tangents = {}});
  CHECK_THROWS_WITH(changes.check(scene), Catch::Contains("mesh " + std::to_string(scene.meshes.size())));
  // Vertices must match the mesh's count: a skinned mesh keeps its topology.
  changes.meshes.back().mesh = 0;
  changes.meshes.back().positions.resize(scene.meshes[0].positions.size() + 1);
  CHECK_THROWS_WITH(changes.check(scene), Catch::Contains("positions") && Catch::Contains("vertices"));
}

TEST_CASE("animations start at the initial scene, move afterwards and are pure functions of the frame", "[distributed]") {
  const igi::Scene scene = igi::cornell_box();
  const igi::Camera camera = scene.cameras.front();
  CHECK(igi::parse_animation("object") == igi::Animation::object);
  CHECK_THROWS_AS(igi::parse_animation("wobble"), igi::SettingsError);
  for (const igi::Animation kind : {igi::Animation::light, igi::Animation::camera, igi::Animation::object}) {
    const igi::SceneChanges first = igi::animate(scene, camera, kind, 0);
    CHECK(first.camera.camera_to_world == camera.camera_to_world);
    for (const auto& [index, transform] : first.instances) CHECK(transform == scene.instances[std::size_t(index)].transform);
    const igi::SceneChanges later = igi::animate(scene, camera, kind, 3);
    const igi::SceneChanges again = igi::animate(scene, camera, kind, 3);
    CHECK(later.camera.camera_to_world == again.camera.camera_to_world);
    REQUIRE(later.instances.size() == again.instances.size());
    bool moved = later.camera.camera_to_world != camera.camera_to_world;
    for (std::size_t i = 0; i < later.instances.size(); ++i) {
      CHECK(later.instances[i].second == again.instances[i].second);
      moved = moved || later.instances[i].second != scene.instances[std::size_t(later.instances[i].first)].transform;
    }
    CHECK(moved);
  }
  // The Cornell box has no punctual lights: "light" slides its emissive luminaire.
  const igi::SceneChanges light = igi::animate(scene, camera, igi::Animation::light, 2);
  REQUIRE(light.instances.size() == 1);
  CHECK(scene.material_of(scene.instances[std::size_t(light.instances[0].first)].mesh).emissive());
  // "object" moves the smallest non-emissive instance: the short box.
  CHECK(scene.instances[std::size_t(igi::animated_instance(scene))].name == "smallbox");
}

TEST_CASE("animating a scene with nothing to move is an error that says so", "[distributed]") {
  igi::Scene empty;
  empty.name = "empty";
  CHECK_THROWS_WITH(igi::animate(empty, igi::Camera{}, igi::Animation::light, 1), Catch::Contains("no punctual or emissive light"));
  CHECK_THROWS_WITH(igi::animate(empty, igi::Camera{}, igi::Animation::object, 1), Catch::Contains("no non-emissive instance"));
}
