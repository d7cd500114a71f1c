// The procedural room of examples/procedural: a valid scene whose lamp stays inside while it
// moves, and RoomShader, which must give each lane its own material's shader.
#include <catch2/catch.hpp>

#include "igi/scene/validate.hpp"
#include "procedural_room.hpp"

using igi_procedural::RoomShader;

namespace {

/// Width of the test packets: one lane per room material plus one more.
constexpr int W = 8;

/// A packet of hits on the back wall, lane i on material i (lane 7 on marble again).
igi::SurfaceHit<W> hits_on_every_material() {
  // All face +Z at different points of the z = 0 plane.
  igi::SurfaceHit<W> hit;
  for (int i = 0; i < W; ++i) {
    hit.position.set(i, glm::vec3(0.37f * float(i) + 0.1f, 0.23f * float(i) + 0.2f, 0.0f));
    hit.geometric_normal.set(i, glm::vec3(0.0f, 0.0f, 1.0f));
    hit.shading_normal.set(i, glm::vec3(0.0f, 0.0f, 1.0f));
    hit.wo.set(i, glm::vec3(0.0f, 0.0f, 1.0f));
    hit.distance.set(i, 3.0f);
    hit.material.set(i, i < igi_procedural::material_count ? i : int(igi_procedural::marble));
    hit.front_face.set(i, true);
  }
  return hit;
}

}  // namespace

TEST_CASE("the procedural room is a valid closed room with a lamp") {
  igi::Scene scene = igi_procedural::procedural_room();
  REQUIRE_NOTHROW(igi::validate_scene(scene));
  CHECK(scene.materials.size() == std::size_t(igi_procedural::material_count));
  CHECK(scene.materials[igi_procedural::lamp].emissive());
  REQUIRE(scene.cameras.size() == 1);
  const igi::Bounds bounds = scene.bounds();
  const glm::vec3 eye = scene.cameras.front().position();
  for (int c = 0; c < 3; ++c) {
    CHECK(eye[c] > bounds.lower[c]);
    CHECK(eye[c] < bounds.upper[c]);
  }
  CHECK(scene.instances[std::size_t(igi_procedural::lamp_instance(scene))].name == "lamp");
}

TEST_CASE("the lamp's orbit stays under the ceiling and inside the walls") {
  const igi::Scene scene = igi_procedural::procedural_room();
  const igi::Instance& lamp = scene.instances[std::size_t(igi_procedural::lamp_instance(scene))];
  const igi::Mesh& mesh = scene.meshes[std::size_t(lamp.mesh)];
  const glm::vec3 room = igi_procedural::room_size;
  for (std::uint32_t frame = 0; frame < 60; ++frame) {
    const glm::mat4 moved = igi_procedural::lamp_transform(frame) * lamp.transform;
    for (const glm::vec3& p : mesh.positions) {
      const glm::vec3 world(moved * glm::vec4(p, 1.0f));
      CHECK(world.x > 0.0f);
      CHECK(world.x < room.x);
      CHECK(world.z > 0.0f);
      CHECK(world.z < room.z);
      CHECK(world.y < room.y);
    }
  }
  // It moves: a quarter turn later the lamp is elsewhere.
  CHECK(glm::length(glm::vec3(igi_procedural::lamp_transform(15)[3] - igi_procedural::lamp_transform(0)[3])) > 0.5f);
}

TEST_CASE("RoomShader gives every lane its own material's shader") {
  const igi::Scene scene = igi_procedural::procedural_room();
  const RoomShader procedural(scene, RoomShader::Mode::procedural);
  const RoomShader constant(scene, RoomShader::Mode::constant);
  const igi::SurfaceHit<W> hit = hits_on_every_material();
  igi::vmask<W> mask(true);
  mask.set(6, false);  // the lamp lane is left out: it must come back all zeros
  const igi::BrdfParameters<W> p = procedural.shade(hit, mask);
  const igi::BrdfParameters<W> c = constant.shade(hit, mask);

  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    if (i == 6) {
      CHECK(p.albedo[i] == glm::vec3(0.0f));
      CHECK(p.normal[i] == glm::vec3(0.0f));
      CHECK(p.emission[i] == glm::vec3(0.0f));
      CHECK_FALSE(p.opaque[i]);
      continue;
    }
    CHECK(p.opaque[i]);
    CHECK(c.opaque[i]);
    // Constant mode: exactly the material's base colour.
    const int material = hit.material[i];
    CHECK(c.albedo[i] == glm::vec3(scene.materials[std::size_t(material)].base_color));
    CHECK(glm::length(p.normal[i]) == Approx(1.0f));
    for (int k = 0; k < 3; ++k) {
      CHECK(p.albedo[i][k] >= 0.0f);
      CHECK(p.albedo[i][k] <= 1.0f);
    }
    const bool patterned = material == igi_procedural::wood_floor || material == igi_procedural::wood_box ||
                           material == igi_procedural::brick_wall || material == igi_procedural::marble;
    if (patterned)
      CHECK(p.albedo[i] != c.albedo[i]);  // a pattern, not the flat colour
    else
      CHECK(p.albedo[i] == c.albedo[i]);
  }
  // The lamp emits when it is shaded.
  const igi::BrdfParameters<W> lamp = procedural.shade(hit, igi::vmask<W>(true));
  CHECK(lamp.emission[6] == scene.materials[igi_procedural::lamp].emission);
  CHECK(lamp.emission[4] == glm::vec3(0.0f));
  // The two marble lanes sit at different points of the pattern.
  CHECK(p.albedo[4] != p.albedo[7]);
}

TEST_CASE("RoomShader rejects a scene that is not the room") {
  igi::Scene other;
  other.name = "other";
  CHECK_THROWS_WITH(RoomShader(other, RoomShader::Mode::procedural), Catch::Contains("materials"));
}
