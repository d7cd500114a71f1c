// Normal textures in a rendered frame: a floor whose normal map tilts its left half towards the
// sun and its right half away takes, pixel for pixel, the sun's light at the tilted normals'
// cosines, through the whole chain (make_surface_hit's uv derivatives, the shader's tangent
// frame, the BRDF's cosine).

#include <cmath>
#include <cstdint>
#include <vector>

#include <catch2/catch.hpp>

#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// Codes of a 16 x 1 normal texture: the left 8 texels tilted 30 degrees towards +x of the map
/// ((0.5, 0, 0.866) -> 191, 128, 238), the right 8 towards -x (64, 128, 238).
Texture tilted_halves() {
  Texture texture{.name = "tilted halves", .width = 16, .height = 1, .texels = {}, .srgb = false};
  for (int x = 0; x < 16; ++x) {
    const std::uint8_t red = x < 8 ? 191 : 64;
    texture.texels.insert(texture.texels.end(), {red, 128, 238, 255});
  }
  return texture;
}

/// The texel `red`, 128, 238's normal on the floor below: map x along +x (u grows with x), map
/// y along -z (against v, which grows with z), map z along +y.
glm::vec3 floor_normal(float red) {
  const auto decode = [](float code) { return 2.0f * code / 255.0f - 1.0f; };
  return glm::normalize(glm::vec3(decode(red), decode(238.0f), -decode(128.0f)));
}

/// A white floor (y = 0, half-size 3, u along +x and v along +z) with `normals` as its normal
/// texture, or none, under a sun 45 degrees above the +x horizon; the camera looks down on it.
/// `tangent_x` != 0 gives it TANGENTs along that sign of x, their bitangents along -z.
Scene floor_under_sun(bool normals, float tangent_x = 0.0f) {
  Scene scene;
  scene.name = "normal-mapped floor";
  const int white = add_material(scene, glm::vec3(0.8f));
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 3.0f, white);
  // cross(+y, (x, 0, 0)) w = -z needs w = x.
  if (tangent_x != 0.0f)
    scene.meshes.back().tangents.assign(scene.meshes.back().positions.size(), glm::vec4(tangent_x, 0.0f, 0.0f, tangent_x));
  if (normals) {
    scene.textures.push_back(tilted_halves());
    scene.materials[std::size_t(white)].normal_texture = 0;
  }
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .intensity = 2.0f,
                          .direction = glm::normalize(glm::vec3(-1.0f, -1.0f, 0.0f))});
  scene.cameras.push_back(look_at({0.0f, 4.0f, 2.0f}, {0.0f, 0.0f, 0.0f}, 1.2f));
  return scene;
}

}  // namespace

TEST_CASE("normal maps: a floor tilted towards the sun and away from it takes the light of the tilted normals",
          "[render][normal-map]") {
  // Without TANGENTs, with TANGENTs along the uv frame (the same image) and with TANGENTs turned
  // half round (the map's x then runs along -x: the halves' tilts swap).
  const float tangent_x = GENERATE(0.0f, 1.0f, -1.0f);
  INFO("TANGENT x " << tangent_x);
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.vpls_per_pixel = 4;
  settings.threads = 2;
  settings.filter_textures = false;  // the normals at each ray's point, not blended across the halves' seam
  Scene flat = floor_under_sun(false);
  Scene bumpy = floor_under_sun(true, tangent_x);
  const Frame flat_frame = render_once<EmbreeBackend<8>>(flat, settings);
  const Frame bumpy_frame = render_once<EmbreeBackend<8>>(bumpy, settings);

  // The floor's own VPLs lie in its plane and light none of it: each pixel holds the sun's
  // direct light, albedo / pi x irradiance x cos, so the two frames' ratio is the cosines' ratio.
  const glm::vec3 towards_sun = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
  const float flat_cosine = towards_sun.y;
  const bool swapped = tangent_x < 0.0f;
  const float left_ratio = glm::dot(floor_normal(swapped ? 64.0f : 191.0f), towards_sun) / flat_cosine;   // 1.37
  const float right_ratio = glm::dot(floor_normal(swapped ? 191.0f : 64.0f), towards_sun) / flat_cosine;  // 0.37
  int left = 0, right = 0, left_match = 0, right_match = 0;
  for_each_floor_pixel(flat.cameras.front(), settings, [&](std::size_t i, const glm::vec3& floor) {
    // Away from the halves' seam (x = 0) and from the floor's edges, where bilinear lookups
    // blend the two halves (the texture repeats): within a texel (6 / 16 = 0.375) of them.
    if (std::abs(floor.x) < 0.4f || std::abs(floor.x) > 2.6f || std::abs(floor.z) > 2.9f) return;
    const float flat_light = flat_frame.hdr.pixels[i].g, light = bumpy_frame.hdr.pixels[i].g;
    REQUIRE(flat_light > 0.0f);
    // 1e-4: float rounding of the cosines and the composition, far below the 8-bit texels' steps.
    if (floor.x < 0.0f) {
      ++left;
      left_match += light == Approx(flat_light * left_ratio).epsilon(1e-4) ? 1 : 0;
    } else {
      ++right;
      right_match += light == Approx(flat_light * right_ratio).epsilon(1e-4) ? 1 : 0;
    }
  });
  INFO(left_match << " of " << left << " pixels on the left half, " << right_match << " of " << right
                  << " on the right half, at the tilted normals' light");
  CHECK(left > 100);
  CHECK(right > 100);
  CHECK(left_match == left);
  CHECK(right_match == right);
}
