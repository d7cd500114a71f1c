// Glass windows let light in. glTF transmission without a volume is thin-walled: light passes a
// pane straight on, weighted by its transmission, (1 - Fresnel) and base colour, for shadow
// rays, light particles and camera rays alike; alphaMode BLEND passes 1 - alpha. With a volume
// the glass is a solid that refracts. Before, every shadow ray stopped at a pane, so a room
// lit through a glazed window was black.

#include <cmath>
#include <cstdint>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/shading/cutout_occlusion.hpp"
#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

using OneLane = std::integral_constant<int, 1>;     ///< Packets of one lane.
using EightLanes = std::integral_constant<int, 8>;  ///< Packets of eight lanes.

/// Height of the room's roof, where its window is.
constexpr float roof_height = 1.0f;
/// The window: a square of this half-size in the roof around (window_x, 1, 0).
constexpr float window_half = 0.3f;
/// The window's centre's x.
constexpr float window_x = -0.5f;
/// The sun shines 45 degrees from the zenith towards +x, so the window's light falls on the
/// floor 1 further along x: over x in [0.2, 0.8], z in [-0.3, 0.3].
const glm::vec3 sun_direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
/// The sun's irradiance on a plane facing it.
constexpr float sun_irradiance = 2.0f;

/// A closed room over x, z in [-2, 2] and y in [0, 1]: a white floor (0.8) and black walls and
/// roof (which reflect nothing), the roof's only opening a window (window_half, window_x) under
/// the sun; the floor's own VPLs lie in its plane and add nothing to it, so its light is the
/// sun's alone, as the window lets it in. `pane`: the window's material, none for an open
/// window. The camera stands inside and looks down at the sunlit patch.
Scene room_with_window(const std::optional<Material>& pane) {
  Scene scene;
  scene.name = "room with a window";
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 2.0f, add_material(scene, glm::vec3(0.8f)));
  Mesh walls;
  walls.name = "walls and roof";
  const float h = roof_height, x0 = window_x - window_half, x1 = window_x + window_half, z = window_half;
  add_quad(walls, {-2, 0, -2}, {-2, h, -2}, {-2, h, 2}, {-2, 0, 2}, {1, 0, 0});
  add_quad(walls, {2, 0, -2}, {2, h, -2}, {2, h, 2}, {2, 0, 2}, {-1, 0, 0});
  add_quad(walls, {-2, 0, -2}, {2, 0, -2}, {2, h, -2}, {-2, h, -2}, {0, 0, 1});
  add_quad(walls, {-2, 0, 2}, {2, 0, 2}, {2, h, 2}, {-2, h, 2}, {0, 0, -1});
  // The roof around the window: strips left and right of it, and before and behind it.
  add_quad(walls, {-2, h, -2}, {x0, h, -2}, {x0, h, 2}, {-2, h, 2}, {0, -1, 0});
  add_quad(walls, {x1, h, -2}, {2, h, -2}, {2, h, 2}, {x1, h, 2}, {0, -1, 0});
  add_quad(walls, {x0, h, -2}, {x1, h, -2}, {x1, h, -z}, {x0, h, -z}, {0, -1, 0});
  add_quad(walls, {x0, h, z}, {x1, h, z}, {x1, h, 2}, {x0, h, 2}, {0, -1, 0});
  add_object(scene, std::move(walls), add_material(scene, glm::vec3(0.0f)));
  if (pane) {
    scene.materials.push_back(*pane);
    add_quad(scene, {window_x, h, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, window_half, int(scene.materials.size()) - 1);
  }
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .intensity = sun_irradiance, .direction = sun_direction});
  scene.cameras.push_back(look_at({0.5f, 0.9f, 0.8f}, {0.5f, 0.0f, 0.0f}, 0.8f));
  return scene;
}

/// A clear thin pane (no volume) of ior 1.5 tinted (1, 0.8, 0.5).
Material glass_pane() {
  return {.name = "pane", .base_color = {1.0f, 0.8f, 0.5f, 1.0f}, .metallic = 0.0f, .roughness = 0.0f, .transmission = 1.0f, .ior = 1.5f};
}

/// A black, alpha-blended pane of alpha 0.25, which reflects nothing.
Material blended_pane(float alpha = 0.25f) {
  Material pane{.name = "blend", .base_color = {0.0f, 0.0f, 0.0f, alpha}, .metallic = 0.0f, .specular = 0.0f};
  pane.alpha_mode = AlphaMode::blend;
  return pane;
}

/// The Fresnel reflectance of light from air onto a dielectric of index `n` at `cos_i` to its
/// normal, by the textbook formulas (Snell's law, then s and p amplitudes with n1 = 1, n2 = n).
double fresnel_by_hand(double cos_i, double n) {
  const double sin_t = std::sqrt(1.0 - cos_i * cos_i) / n;
  const double cos_t = std::sqrt(1.0 - sin_t * sin_t);
  const double rs = (cos_i - n * cos_t) / (cos_i + n * cos_t);
  const double rp = (n * cos_i - cos_t) / (n * cos_i + cos_t);
  return 0.5 * (rs * rs + rp * rp);
}

/// What glass_pane() passes of light at `cos_i` to its normal: transmission x (1 - F) x tint.
glm::dvec3 pane_transmittance(double cos_i) {
  return (1.0 - fresnel_by_hand(cos_i, 1.5)) * glm::dvec3(1.0, 0.8, 0.5);
}

/// The frame settings of these tests: small, few VPLs (the floor's light is the sun's exact VPL alone).
RenderSettings glass_settings() { return {.width = 64, .height = 48, .vpls_per_pixel = 4, .threads = 2}; }

/// Calls `visit(i)` for each pixel of room_with_window's camera whose floor point lies inside the
/// sunlit patch, 0.1 from its edges (out of reach of the filter's neighbourhood across them).
template <class Visit>
int for_each_sunlit_pixel(const Scene& scene, const RenderSettings& settings, Visit&& visit) {
  int count = 0;
  for_each_floor_pixel(scene.cameras.front(), settings, [&](std::size_t i, const glm::vec3& floor) {
    const float patch_x = window_x + roof_height;  // the sun's 45 degrees shift the window's light by the roof's height
    if (std::abs(floor.x - patch_x) > window_half - 0.1f || std::abs(floor.z) > window_half - 0.1f) return;
    ++count;
    visit(i);
  });
  return count;
}

/// Checks that through `pane` the floor of room_with_window, rendered with backend B, gets the
/// open window's light times `expected` per channel, pixel by pixel; returns the glazed frame.
template <class B>
Frame check_window(const Material& pane, const glm::dvec3& expected) {
  const RenderSettings settings = glass_settings();
  Scene open = room_with_window(std::nullopt);
  Scene glazed = room_with_window(pane);
  const Frame open_frame = render_once<B>(open, settings);
  const Frame glazed_frame = render_once<B>(glazed, settings);
  int matching = 0;
  const int pixels = for_each_sunlit_pixel(glazed, settings, [&](std::size_t i) {
    const glm::vec3 lit = open_frame.hdr.pixels[i], through = glazed_frame.hdr.pixels[i];
    REQUIRE(lit.g > 0.0f);
    bool match = true;
    // 1e-4: float rounding of a few products; a Fresnel or tint off by 1% would be 100 times that.
    for (int c = 0; c < 3; ++c) match = match && double(through[c]) == Approx(double(lit[c]) * expected[c]).epsilon(1e-4);
    if (!match) UNSCOPED_INFO(B::name() << " pixel " << i << ": " << through.r << " " << through.g << " " << through.b << " through the pane, "
                                        << lit.r << " " << lit.g << " " << lit.b << " open");
    matching += match ? 1 : 0;
  });
  INFO(B::name() << ": " << matching << " of " << pixels << " sunlit pixels as the open window's times the pane's transmittance");
  CHECK(pixels > 100);  // the patch fills a few hundred of the 64 x 48 pixels: a check that it was found
  CHECK(matching == pixels);
  // The open window's floor has the sun's light, albedo / pi x irradiance x cos 45 degrees.
  const float sunlit = 0.8f / 3.14159265f * sun_irradiance * std::sqrt(0.5f);
  // 1e-3: float rounding, with room for the filter's sums; the VPLs' light would be 0 or far more.
  for_each_sunlit_pixel(open, settings, [&](std::size_t i) { CHECK(open_frame.hdr.pixels[i].g == Approx(sunlit).epsilon(1e-3)); });
  return glazed_frame;
}

}  // namespace

TEMPLATE_TEST_CASE("glass: the sun on the floor of a room whose only window is a thin glazed pane is the open window's "
                   "times the pane's transmission x (1 - Fresnel) x base colour, on every backend",
                   "[render][glass]", EmbreeBackend<8>, EmbreeBackend<16>, EmbreeBackend<1>, ReferenceBackend<8>, SaarcorBackend) {
  const glm::dvec3 expected = pane_transmittance(std::sqrt(0.5));  // the sun meets the pane at 45 degrees
  const Frame glazed = check_window<TestType>(glass_pane(), expected);
  // Every backend gives the same image (Embree's 8 wide as the yardstick).
  Scene scene = room_with_window(glass_pane());
  const Frame yardstick = render_once<EmbreeBackend<8>>(scene, glass_settings());
  CHECK(differing_pixels(yardstick, glazed, 1e-4f) == 0);  // up to the float rounding of hit points
}

TEMPLATE_TEST_CASE("glass: an alpha-blended pane of alpha 0.25 lets 0.75 of the sun in, on every backend", "[render][glass]",
                   EmbreeBackend<8>, ReferenceBackend<8>, SaarcorBackend) {
  check_window<TestType>(blended_pane(), glm::dvec3(0.75));
}

TEST_CASE("glass: two panes one behind the other pass the product of their transmittances", "[render][glass]") {
  const RenderSettings settings = glass_settings();
  Scene open = room_with_window(std::nullopt);
  Scene double_glazed = room_with_window(glass_pane());
  // A second, blended pane just below the first.
  double_glazed.materials.push_back(blended_pane(0.5f));
  add_quad(double_glazed, {window_x, roof_height - 0.05f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, window_half,
           int(double_glazed.materials.size()) - 1);
  const Frame open_frame = render_once<EmbreeBackend<8>>(open, settings);
  const Frame frame = render_once<EmbreeBackend<8>>(double_glazed, settings);
  const glm::dvec3 expected = pane_transmittance(std::sqrt(0.5)) * 0.5;
  int matching = 0;
  // The lower pane's shadow edge lies 0.05 closer to the window than the upper one's: the
  // patch's inner part is lit through both.
  const int pixels = for_each_sunlit_pixel(double_glazed, settings, [&](std::size_t i) {
    const glm::vec3 lit = open_frame.hdr.pixels[i], through = frame.hdr.pixels[i];
    bool match = true;
    for (int c = 0; c < 3; ++c) match = match && double(through[c]) == Approx(double(lit[c]) * expected[c]).epsilon(1e-4);
    matching += match ? 1 : 0;
  });
  CHECK(pixels > 100);
  CHECK(matching == pixels);
}

TEST_CASE("glass: camera rays see the sunlit floor through a pane from outside, dimmed by the pane once for the sun "
          "and once for the view", "[render][glass]") {
  RenderSettings settings = glass_settings();
  Scene open = room_with_window(std::nullopt);
  Scene glazed = room_with_window(glass_pane());
  // Above the roof, looking down through the window at the sunlit patch.
  const Camera outside = look_at({-1.3f, 2.0f, 0.0f}, {0.5f, 0.0f, 0.0f}, 0.5f);
  open.cameras.front() = outside;
  glazed.cameras.front() = outside;
  const Frame open_frame = render_once<EmbreeBackend<8>>(open, settings);
  const Frame glazed_frame = render_once<EmbreeBackend<8>>(glazed, settings);
  const PinholeProjection projection(outside, settings.width, settings.height);
  int pixels = 0, matching = 0;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const glm::vec3 direction = glm::normalize(projection.direction(float(x) + 0.5f, float(y) + 0.5f));
      const glm::vec3 eye = projection.origin();
      // Where the ray crosses the roof's plane and meets the floor.
      const glm::vec3 roof = eye + direction * ((eye.y - roof_height) / -direction.y);
      const glm::vec3 floor = eye + direction * (eye.y / -direction.y);
      const float margin = 0.1f;  // as for_each_sunlit_pixel: off the window's and the patch's edges
      if (std::abs(roof.x - window_x) > window_half - margin || std::abs(roof.z) > window_half - margin) continue;
      if (std::abs(floor.x - (window_x + roof_height)) > window_half - margin || std::abs(floor.z) > window_half - margin) continue;
      ++pixels;
      const std::size_t i = std::size_t(y) * std::size_t(settings.width) + std::size_t(x);
      const glm::dvec3 expected = pane_transmittance(std::sqrt(0.5)) * pane_transmittance(double(-direction.y));
      const glm::vec3 lit = open_frame.hdr.pixels[i], through = glazed_frame.hdr.pixels[i];
      bool match = lit.g > 0.0f;
      // 1e-3: the view's angle is recomputed here from the pixel centre, a few ulps off the renderer's ray.
      for (int c = 0; c < 3; ++c) match = match && double(through[c]) == Approx(double(lit[c]) * expected[c]).epsilon(1e-3);
      matching += match ? 1 : 0;
    }
  INFO(matching << " of " << pixels << " pixels seeing the sunlit floor through the window as expected");
  CHECK(pixels > 30);  // the window shows the patch in some dozens of pixels: a check that they were found
  CHECK(matching == pixels);
}

TEST_CASE("glass: the path tracer agrees with IGI on the glazed room's floor", "[render][glass]") {
  const RenderSettings settings = glass_settings();
  Scene glazed = room_with_window(glass_pane());
  const Frame frame = render_once<EmbreeBackend<8>>(glazed, settings);
  const EmbreeBackend<1> backend(glazed);
  const GltfMaterialShader surface(glazed);
  const StandardBrdf brdf;
  PathTracerSettings path_settings;
  path_settings.threads = 2;
  PathTracer<EmbreeBackend<1>, GltfMaterialShader, StandardBrdf> tracer(glazed, backend, surface, brdf, path_settings);
  const Image image = tracer.render(glazed.cameras.front(), settings.width, settings.height, 16);
  glm::dvec3 igi_sum(0.0), path_sum(0.0);
  const int pixels = for_each_sunlit_pixel(glazed, settings, [&](std::size_t i) {
    igi_sum += glm::dvec3(frame.hdr.pixels[i]);
    path_sum += glm::dvec3(image.pixels[i]);
  });
  REQUIRE(pixels > 100);
  const glm::dvec3 expected = 0.8 / 3.14159265358979 * double(sun_irradiance) * std::sqrt(0.5) * pane_transmittance(std::sqrt(0.5));
  for (int c = 0; c < 3; ++c) {
    INFO("channel " << c);
    // IGI's floor has the sun's light alone; the path tracer's also a little the pane reflects
    // back down of the floor's light (its Fresnel 5% of a few percent of the floor's view).
    CHECK(igi_sum[c] / pixels == Approx(expected[c]).epsilon(1e-3));  // float rounding, as above
    // 1%: the pane's reflection of the floor's light (about 0.1%) and its noise at 16 samples.
    CHECK(path_sum[c] / pixels == Approx(expected[c]).epsilon(0.01));
  }
}

TEST_CASE("glass: a see-through surface that light fully passes renders bit for bit as none, and a scene without "
          "see-through meshes as before", "[render][glass]") {
  const RenderSettings settings = glass_settings();
  Scene open = room_with_window(std::nullopt);
  const Frame open_frame = render_once<EmbreeBackend<8>>(open, settings);
  // A blended pane of alpha 0: shadow rays take the attenuating path and multiply by exactly 1.
  Scene clear = room_with_window(blended_pane(0.0f));
  const Frame clear_frame = render_once<EmbreeBackend<8>>(clear, settings);
  CHECK(clear_frame.hdr.pixels == open_frame.hdr.pixels);
  // A glass material no mesh uses leaves the scene without see-through meshes: the image is
  // bit for bit the one without it.
  Scene unused = open;
  unused.materials.push_back(glass_pane());
  CHECK_FALSE(SeeThroughMeshes(unused).any());
  const Frame unused_frame = render_once<EmbreeBackend<8>>(unused, settings);
  CHECK(unused_frame.hdr.pixels == open_frame.hdr.pixels);
}

TEMPLATE_TEST_CASE("glass: glass with a volume (thickness) still refracts by Snell's law, without one it passes light "
                   "straight on", "[render][glass]", OneLane, EightLanes) {
  constexpr int W = TestType::value;
  Scene scene;
  Material water{.name = "water", .base_color = {0.9f, 0.95f, 1.0f, 1.0f}, .metallic = 0.0f, .roughness = 0.0f,
                 .transmission = 1.0f, .ior = 1.33f, .thickness = 0.1f};
  scene.materials.push_back(water);
  water.thickness = 0.0f;
  scene.materials.push_back(water);
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 1.0f, 0);
  const GltfMaterialShader shader(scene);
  // A ray from above at 40 degrees from the normal meets the surface's front face at the origin.
  const float angle = 40.0f * 3.14159265f / 180.0f;
  const glm::vec3 incoming(std::sin(angle), -std::cos(angle), 0.0f);
  SurfaceHit<W> hit;
  const vmask<W> mask(true);
  hit.geometric_normal = vec3<W>(glm::vec3(0, 1, 0));
  hit.shading_normal = hit.geometric_normal;
  hit.wo = vec3<W>(-incoming);
  hit.front_face = mask;
  for (int i = 0; i < W; ++i) hit.material.set(i, i % 2);  // even lanes the solid, odd lanes the thin wall
  const BrdfParameters<W> p = shader.shade(hit, mask);
  SecondaryRays<W> reflection, refraction;
  StandardBrdf{}.spawn(hit, p, reflection, refraction, mask);
  const double fresnel = fresnel_by_hand(std::cos(angle), 1.33);
  // Tolerances: float rounding of the shader's few operations (1e-4; exact directions to 1e-5).
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    REQUIRE(refraction.active[i]);
    const glm::vec3 direction = glm::normalize(refraction.direction[i]);
    CHECK(reflection.weight[i].g == Approx(fresnel).epsilon(1e-4));
    if (i % 2 == 0) {
      // Bent towards the normal: sin(theta_t) = sin(theta_i) / 1.33, untinted as before.
      CHECK(direction.x == Approx(std::sin(angle) / 1.33f).epsilon(1e-4));
      CHECK(direction.y < 0.0f);
      CHECK(refraction.weight[i].b == Approx(1.0 - fresnel).epsilon(1e-4));
    } else {
      CHECK(direction.x == Approx(incoming.x).epsilon(1e-5));
      CHECK(direction.y == Approx(incoming.y).epsilon(1e-5));
      CHECK(refraction.weight[i].r == Approx((1.0 - fresnel) * 0.9).epsilon(1e-4));
      CHECK(refraction.weight[i].b == Approx(1.0 - fresnel).epsilon(1e-4));
    }
  }
}

TEST_CASE("glass: a solid glass block with a volume displaces the floor seen through it, a thin one does not",
          "[render][glass]") {
  // A ray at 45 degrees through a glass slab 0.2 thick (ior 1.5) on a floor: refracted
  // at both faces, it comes out parallel but shifted, and meets the floor elsewhere.
  for (const bool solid : {true, false}) {
    Scene scene;
    Material glass = glass_pane();
    glass.base_color = glm::vec4(1.0f);
    glass.thickness = solid ? 0.2f : 0.0f;
    scene.materials.push_back(glass);
    add_object(scene, box_mesh("slab", {-1.0f, 0.4f, -1.0f}, {1.0f, 0.6f, 1.0f}), 0);
    // box_mesh's faces point inwards; the slab is seen from outside, so flip its winding.
    for (glm::uvec3& triangle : scene.meshes.back().triangles) std::swap(triangle.y, triangle.z);
    for (glm::vec3& normal : scene.meshes.back().normals) normal = -normal;
    const EmbreeBackend<1> backend(scene);
    const SceneGeometry geometry(scene);
    const GltfMaterialShader shader(scene);
    const vmask<1> one(true);
    RayPacket<1> ray;
    const glm::vec3 direction = glm::normalize(glm::vec3(1.0f, -1.0f, 0.0f));
    ray.set(vec3<1>(glm::vec3(-0.5f, 1.0f, 0.0f)), vec3<1>(direction), vfloat<1>(0.0f), vfloat<1>(100.0f), one);
    // Follow the refraction rays through both faces of the slab.
    glm::vec3 origin(-0.5f, 1.0f, 0.0f), along = direction;
    for (int face = 0; face < 2; ++face) {
      HitPacket<1> hit;
      hit.clear();
      backend.intersect(ray, hit, one);
      REQUIRE(hit.geomID[0] == 0u);
      const SurfaceHit<1> surface = make_surface_hit(scene, geometry, ray, hit, one);
      const BrdfParameters<1> p = shader.shade(surface, one);
      SecondaryRays<1> reflection, refraction;
      StandardBrdf{}.spawn(surface, p, reflection, refraction, one);
      REQUIRE(refraction.active[0]);
      along = glm::normalize(refraction.direction[0]);
      // 1e-4: off the face by far more than the float rounding of a unit-sized scene, far less than the slab.
      origin = leave_surface(surface.position, surface.geometric_normal, refraction.direction, 1e-4f)[0];
      ray.set(vec3<1>(origin), vec3<1>(along), vfloat<1>(0.0f), vfloat<1>(100.0f), one);
    }
    // Out of the slab at y = 0.4 along the incoming direction either way; it meets y = 0 at
    // x = 0.5 along the straight line, short of it after the solid's two refractions.
    // 1e-4: float rounding of two refractions; 1e-3 on the floor: of the hit points, against a shift of 0.09.
    CHECK(along.x == Approx(direction.x).epsilon(1e-4));
    CHECK(along.y == Approx(direction.y).epsilon(1e-4));
    const float floor_x = origin.x + along.x * (origin.y / -along.y);
    // Inside the slab the solid's ray runs at asin(sin 45 / 1.5) = 28.1 degrees: 0.2 x (1 - tan 28.1) = 0.093 shorter.
    const float shift = 0.2f * (1.0f - std::tan(std::asin(std::sqrt(0.5f) / 1.5f)));
    CHECK(floor_x == Approx(solid ? 0.5f - shift : 0.5f).margin(1e-3));
  }
}

TEST_CASE("glass: light particles pass a thin pane weighted by its transmittance: the floor's VPLs carry the open "
          "window's power times it", "[render][glass]") {
  // The sun's walks through the window leave their first bounce on the floor; the sum of the
  // floor VPLs' intensities estimates the power the window lets in (times albedo / pi).
  const auto floor_power = [](Scene scene) {
    const EmbreeBackend<8> backend(scene);
    // The walks that miss the window end on the black roof and leave no VPL, so the walk count
    // reaches its cap, 16 M = 6400 per set, a few hundred of all sets' through the window: the
    // same walks in both rooms up to the pane.
    const VplSettings settings{.sets = 9, .vpls_per_set = 400, .frame = 1, .seed = 3};
    const VplSets vpls = QmcVplSampler{}.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
    glm::dvec3 sum(0.0);
    for (const std::vector<Vpl>& set : vpls.sets)
      for (const Vpl& vpl : set)
        if (vpl.kind == VplKind::surface && std::abs(vpl.position.y) < 1e-3f) sum += glm::dvec3(vpl.intensity);  // on the floor
    return sum;
  };
  const glm::dvec3 open = floor_power(room_with_window(std::nullopt));
  const glm::dvec3 glazed = floor_power(room_with_window(glass_pane()));
  const glm::dvec3 expected = pane_transmittance(std::sqrt(0.5));
  for (int c = 0; c < 3; ++c) {
    INFO("channel " << c << ": " << glazed[c] << " through the pane, " << open[c] << " open");
    REQUIRE(open[c] > 0.0);
    // 3%: the walks' sampling error (the pane's 5% Fresnel reflection decides each walk's way
    // there), about 1% for a few hundred walks; a blocking pane gives 0, an ignored tint or
    // Fresnel 5-50% off.
    CHECK(glazed[c] / open[c] == Approx(expected[c]).epsilon(0.03));
  }
}

namespace {

/// Shadow rays of `B` straight up from y = 0.01 (length 2) through a cut-out sheet at y = 0.5,
/// transparent over x < 0 and opaque over x > 0, and then a glass_pane() at y = 1 over all of
/// it: shadow_transmittance gives the pane's transmittance at normal incidence where the
/// cut-out lets the ray on, 0 where it stops it; with `test` the backend's cut-out test is set.
template <class B>
void check_cutout_and_pane(bool test) {
  Scene scene;
  add_stencil_sheet(scene, 0.5f);
  scene.materials.push_back(glass_pane());
  add_quad(scene, {0.0f, 1.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, 2.0f, int(scene.materials.size()) - 1);
  const GltfMaterialShader surface(scene);
  B backend(scene);
  if constexpr (CutoutTestingBackend<B>)
    if (test) test_cutouts_with(backend, scene, surface);
  const SceneGeometry geometry(scene);
  constexpr int W = B::width;
  const glm::dvec3 pane = pane_transmittance(1.0);
  int checked = 0;
  for (int row = 0; row < 4; ++row) {
    RayPacket<W> rays;
    vec3<W> origin;
    float xs[W];
    for (int lane = 0; lane < W; ++lane) {
      xs[lane] = W == 1 ? -1.5f + 1.0f * float(row) : -1.8f + 3.6f * float(lane) / float(W - 1);
      origin.set(lane, glm::vec3(xs[lane], 0.01f, -0.6f + 0.4f * float(row)));
    }
    vmask<W> mask(true);
    if (W > 1) mask.set(0, false);  // an inactive lane gets nothing
    rays.set(origin, vec3<W>(glm::vec3(0.0f, 1.0f, 0.0f)), vfloat<W>(0.0f), vfloat<W>(2.0f), mask);
    const vec3<W> light = shadow_transmittance(backend, surface, scene, geometry, CutoutMeshes(scene), SeeThroughMeshes(scene),
                                               1e-4f, rays, Coherence::coherent, mask);
    for (int lane = 0; lane < W; ++lane) {
      INFO(B::name() << (test ? " with" : " without") << " its cut-out test: lane " << lane << ", x = " << xs[lane]);
      if (!mask[lane]) {
        CHECK(light[lane] == glm::vec3(0.0f));
        continue;
      }
      CHECK(rays.tfar[lane] == 2.0f);  // the rays are left as they came
      // Within 0.1 of the cut-out's edge its bilinear alpha blends: left out.
      if (std::abs(xs[lane]) < 0.1f) continue;
      ++checked;
      for (int c = 0; c < 3; ++c)
        CHECK(double(light[lane][c]) == Approx(xs[lane] < 0.0f ? pane[c] : 0.0).margin(1e-5));  // float rounding
    }
  }
  CHECK(checked >= (W == 1 ? 2 : W));
}

}  // namespace

TEMPLATE_TEST_CASE("glass: shadow rays through a cut-out and a pane: the pane's transmittance where the cut-out is "
                   "transparent, none where it is opaque, with the backend's cut-out test and without it",
                   "[render][glass]", EmbreeBackend<8>, EmbreeBackend<1>, ReferenceBackend<8>, SaarcorBackend) {
  check_cutout_and_pane<TestType>(true);
  check_cutout_and_pane<TestType>(false);
}
