// glTF's dielectric specular layer in a rendered frame: a varnished floor (base colour 0.5,
// roughness 0.5, glTF's default 4% layer) under the sun, seen from where the sun's mirror image
// lies on the floor, takes on every pixel the Fresnel-weighted diffuse light plus the Phong
// lobe's highlight that the shader's parameters give, through the whole chain (the view-dependent
// Fresnel of the surface shader, the glossy buffer, the composition).

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// A floor (y = 0, half-size 3) of base colour 0.5, roughness 0.5 and KHR_materials_specular's
/// `specular` factor under a sun 45 degrees above the +x horizon; the camera stands over -x at
/// 45 degrees, where the sun's reflection in the floor comes back to it.
Scene varnished_floor(float specular) {
  Scene scene;
  scene.name = "varnished floor";
  const int varnish = add_material(scene, glm::vec3(0.5f));
  Material& material = scene.materials[std::size_t(varnish)];
  material.roughness = 0.5f;
  material.specular = specular;
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 3.0f, varnish);
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .intensity = 2.0f,
                          .direction = glm::normalize(glm::vec3(-1.0f, -1.0f, 0.0f))});
  scene.cameras.push_back(look_at({-2.5f, 2.5f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0f));
  return scene;
}

}  // namespace

TEST_CASE("glTF specular layer: a varnished floor under the sun takes the Fresnel-weighted diffuse light and the "
          "lobe's highlight on every pixel", "[render][specular]") {
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.vpls_per_pixel = 4;
  settings.threads = 2;
  Scene matte = varnished_floor(0.0f);
  Scene varnished = varnished_floor(1.0f);
  const Frame matte_frame = render_once<EmbreeBackend<8>>(matte, settings);
  const Frame varnished_frame = render_once<EmbreeBackend<8>>(varnished, settings);

  // The floor's own VPLs lie in its plane and light none of it: the matte frame holds the sun's
  // direct light, E cos / pi x 0.5, and the varnished one that times (1 - F) plus E cos x F x the
  // lobe (s + 2) / (2 pi) (r . wi)^s, with F Schlick's from 4% towards 1 - roughness = 0.5 at the
  // pixel's view angle, s = 2 / 0.25^2 - 2 = 30 and r the view mirrored about the normal.
  const glm::vec3 eye = PinholeProjection(varnished.cameras.front(), settings.width, settings.height).origin();
  const glm::vec3 towards_sun = glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f));
  const double shininess = 30.0;
  int pixels = 0, matches = 0, highlights = 0;
  for_each_floor_pixel(varnished.cameras.front(), settings, [&](std::size_t i, const glm::vec3& floor) {
    if (std::abs(floor.x) > 2.9f || std::abs(floor.z) > 2.9f) return;  // the floor's edge pixels see past it
    const double diffuse_light = matte_frame.hdr.pixels[i].g;
    REQUIRE(diffuse_light > 0.0);
    const glm::dvec3 wo = glm::normalize(glm::dvec3(eye - floor));
    const double fresnel = 0.04 + (0.5 - 0.04) * std::pow(1.0 - wo.y, 5.0);
    const glm::dvec3 mirrored(-wo.x, wo.y, -wo.z);
    const double lobe = (shininess + 2.0) / (2.0 * std::numbers::pi) *
                        std::pow(std::max(0.0, glm::dot(mirrored, glm::dvec3(towards_sun))), shininess);
    // diffuse_light / 0.5 x pi = E cos: the sun's irradiance on the floor.
    const double glossy_light = diffuse_light / 0.5 * std::numbers::pi * fresnel * lobe;
    const double expected = diffuse_light * (1.0 - fresnel) + glossy_light;
    ++pixels;
    // 1e-3: the lobe's exponential (pow_unit, 2e-6 x (1 + s |ln x|) relative, 6e-4 at s = 30 down
    // to x = e^-10, below which the lobe is invisible) and float rounding of the composition.
    matches += varnished_frame.hdr.pixels[i].g == Approx(expected).epsilon(1e-3) ? 1 : 0;
    highlights += glossy_light > diffuse_light ? 1 : 0;
  });
  INFO(matches << " of " << pixels << " floor pixels at the layer's light, " << highlights << " in the highlight");
  CHECK(pixels > 1000);
  CHECK(matches == pixels);
  CHECK(highlights > 20);            // the highlight is in view ...
  CHECK(highlights < pixels / 2);    // ... and a highlight, not the whole floor
}

TEST_CASE("glTF clear coat: a lacquered black floor mirrors an emissive wall by Schlick's Fresnel on every pixel",
          "[render][clearcoat]") {
  // A black floor (y = 0, half-size 3) under a smooth KHR_materials_clearcoat, and a wall at x =
  // 3.5 (y up to 4.5, z within +-3) emitting E towards it; nothing else. The floor has no diffuse
  // or glossy part, so each floor pixel shows the coat's mirror image alone: F E where its mirror
  // ray meets the wall, 0 where it passes above it, with F = 0.04 + 0.96 (1 - cos)^5 at the view's
  // angle (the wall is black, so it shows E and nothing it receives).
  Scene scene;
  scene.name = "lacquered floor";
  const int lacquer = add_material(scene, glm::vec3(0.0f));
  scene.materials[std::size_t(lacquer)].clearcoat = 1.0f;
  const glm::vec3 emission(2.0f);
  const int wall = add_material(scene, glm::vec3(0.0f), emission);
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 3.0f, lacquer);
  add_quad(scene, {3.5f, 1.5f, 0.0f}, {0, 1, 0}, {0, 0, 1}, {-1, 0, 0}, 3.0f, wall);
  scene.cameras.push_back(look_at({-2.5f, 2.5f, 0.0f}, {0.0f, 0.0f, 0.0f}, 1.0f));
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.vpls_per_pixel = 4;
  settings.threads = 2;
  const Frame frame = render_once<EmbreeBackend<8>>(scene, settings);

  const glm::vec3 eye = PinholeProjection(scene.cameras.front(), settings.width, settings.height).origin();
  int pixels = 0, matches = 0, mirrored = 0, dark = 0;
  for_each_floor_pixel(scene.cameras.front(), settings, [&](std::size_t i, const glm::vec3& floor) {
    if (std::abs(floor.x) > 2.9f || std::abs(floor.z) > 2.9f) return;  // the floor's edge pixels see past it
    const glm::dvec3 wo = glm::normalize(glm::dvec3(eye - floor));
    const glm::dvec3 reflected(-wo.x, wo.y, -wo.z);
    // Where the mirror ray reaches the wall's plane; pixels within 0.05 of its top or sides are
    // left out, where the pixel centre's float rounding decides hit or miss.
    const double distance = (3.5 - floor.x) / reflected.x;
    const glm::dvec3 at = glm::dvec3(floor) + distance * reflected;
    if (std::abs(at.y - 4.5) < 0.05 || std::abs(std::abs(at.z) - 3.0) < 0.05) return;
    const bool sees_wall = reflected.x > 0.0 && at.y < 4.5 && std::abs(at.z) < 3.0;
    const double fresnel = 0.04 + 0.96 * std::pow(1.0 - wo.y, 5.0);
    const double expected = sees_wall ? fresnel * emission.g : 0.0;
    ++pixels;
    // 1e-4: float rounding of the view direction in the shader's Fresnel (x^5 amplifies it 5x).
    matches += frame.hdr.pixels[i].g == Approx(expected).epsilon(1e-4).margin(1e-6) ? 1 : 0;
    mirrored += sees_wall ? 1 : 0;
    dark += sees_wall ? 0 : 1;
  });
  INFO(matches << " of " << pixels << " floor pixels at the coat's mirror image, " << mirrored << " showing the wall");
  CHECK(pixels > 1000);
  CHECK(matches == pixels);
  CHECK(mirrored > 100);  // the wall is in the mirror ...
  CHECK(dark > 100);      // ... and the sky above it is black
}
