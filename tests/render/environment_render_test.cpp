// Frames lit by an environment: camera rays that leave the scene see it, the furnace test (a
// closed diffuse object under a uniform sky) for the path tracer and for IGI's shared
// directional VPLs, IGI against the path tracer on a small outdoor scene under the neutral sky,
// and the default sky of a scene without lights.

#include <algorithm>
#include <memory>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/render/light_check.hpp"
#include "igi/render/path_tracer.hpp"
#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// Adds the axis-aligned box [lower, upper] with its faces' fronts outwards, in material `material`.
void add_solid_box(Scene& scene, const glm::vec3& lower, const glm::vec3& upper, int material) {
  Mesh mesh;
  mesh.name = "box";
  const glm::vec3 l = lower, u = upper;
  add_quad(mesh, {l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, l.y, u.z}, {l.x, l.y, u.z}, {0, -1, 0});
  add_quad(mesh, {l.x, u.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z}, {0, 1, 0});
  add_quad(mesh, {l.x, l.y, l.z}, {l.x, u.y, l.z}, {l.x, u.y, u.z}, {l.x, l.y, u.z}, {-1, 0, 0});
  add_quad(mesh, {u.x, l.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z}, {u.x, l.y, u.z}, {1, 0, 0});
  add_quad(mesh, {l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, u.y, l.z}, {l.x, u.y, l.z}, {0, 0, -1});
  add_quad(mesh, {l.x, l.y, u.z}, {u.x, l.y, u.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z}, {0, 0, 1});
  add_object(scene, std::move(mesh), material);
}

/// A white-ish diffuse cube of `albedo` under a uniform sky of radiance 1, seen from a corner so
/// three faces and the sky show. A convex object reflects no light onto itself, so every point
/// of it has radiance albedo x 1: the furnace test.
Scene furnace(float albedo) {
  Scene scene;
  scene.name = "furnace";
  add_solid_box(scene, glm::vec3(-0.5f), glm::vec3(0.5f), add_material(scene, glm::vec3(albedo)));
  scene.environment = std::make_shared<const Environment>("uniform", 16, 8, std::vector<glm::vec3>(128, glm::vec3(1.0f)));
  scene.cameras.push_back(look_at({1.6f, 1.3f, 1.9f}, {0.0f, 0.0f, 0.0f}, 0.9f));
  return scene;
}

/// A map with a gradient, a hue that turns with azimuth and a bright spot, for lookups.
std::shared_ptr<const Environment> colourful_map() {
  constexpr int width = 48, height = 24;
  std::vector<glm::vec3> texels;
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x)
      texels.emplace_back(1.0f + float(x) / 8.0f, 0.5f + float(y) / 6.0f, (x == 30 && y == 8) ? 50.0f : 0.25f);
  return std::make_shared<const Environment>("colourful", width, height, std::move(texels), 1.5f, 0.8f);
}

/// A small outdoor scene: a grey ground, a box standing on it and a slab raised on the box's side,
/// which throws a soft sky shadow and takes the ground's bounce light.
Scene yard() {
  Scene scene;
  scene.name = "yard";
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 4.0f, add_material(scene, glm::vec3(0.5f)));
  add_solid_box(scene, {-0.6f, 0.0f, -0.6f}, {0.6f, 1.0f, 0.6f}, add_material(scene, glm::vec3(0.7f, 0.6f, 0.5f)));
  add_solid_box(scene, {0.6f, 0.6f, -0.5f}, {1.6f, 0.7f, 0.5f}, add_material(scene, glm::vec3(0.6f)));
  scene.cameras.push_back(look_at({3.0f, 2.2f, 3.4f}, {0.3f, 0.3f, 0.0f}, 0.9f));
  return scene;
}

/// The path tracer's image of `scene` from its first camera.
Image path_traced(const Scene& scene, int width, int height, int spp, bool jitter = true) {
  const EmbreeBackend<1> backend(scene);
  const GltfMaterialShader surface(scene);
  const StandardBrdf brdf;
  PathTracer<EmbreeBackend<1>, GltfMaterialShader, StandardBrdf> tracer(scene, backend, surface, brdf,
                                                                      {.seed = 3, .threads = 0, .jitter = jitter});
  return tracer.render(scene.cameras.front(), width, height, spp);
}

/// True if the ray from `origin` along `direction` meets the box [lower, upper] (the slab test).
bool meets_box(const glm::vec3& origin, const glm::vec3& direction, const glm::vec3& lower, const glm::vec3& upper) {
  float near = 0.0f, far = 1e30f;
  for (int a = 0; a < 3; ++a) {
    const float t0 = (lower[a] - origin[a]) / direction[a], t1 = (upper[a] - origin[a]) / direction[a];
    near = std::max(near, std::min(t0, t1));
    far = std::min(far, std::max(t0, t1));
  }
  return near <= far;
}

/// Mean of all channels of `pixels` at the indices `which`.
double mean_at(const std::vector<glm::vec3>& pixels, const std::vector<std::size_t>& which) {
  double sum = 0.0;
  for (const std::size_t i : which) sum += (double(pixels[i].x) + double(pixels[i].y) + double(pixels[i].z)) / 3.0;
  return which.empty() ? 0.0 : sum / double(which.size());
}

}  // namespace

TEST_CASE("environment render: camera rays that leave the scene see the map, on every backend and in the path tracer",
          "[render][environment][determinism]") {
  Scene scene;
  scene.name = "sky only";
  // One small quad behind the camera, so the backends have geometry; every camera ray misses it.
  add_quad(scene, {0.0f, 0.0f, 5.0f}, {1, 0, 0}, {0, 1, 0}, {0, 0, -1}, 0.1f, add_material(scene, glm::vec3(0.5f)));
  scene.environment = colourful_map();
  scene.cameras.push_back(look_at({0.0f, 0.0f, 0.0f}, {0.3f, 0.4f, -1.0f}, 1.4f));
  RenderSettings settings;
  settings.width = 40;
  settings.height = 30;
  settings.vpls_per_pixel = 4;
  const PinholeProjection projection(scene.cameras.front(), settings.width, settings.height);
  std::vector<glm::vec3> expected;
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x)
      expected.push_back(scene.environment->radiance(glm::normalize(projection.direction(float(x) + 0.5f, float(y) + 0.5f))));
  const auto check = [&](const std::vector<glm::vec3>& pixels) {
    REQUIRE(pixels.size() == expected.size());
    for (std::size_t i = 0; i < pixels.size(); ++i)
      for (int c = 0; c < 3; ++c) REQUIRE(pixels[i][c] == Approx(expected[i][c]).epsilon(1e-5));
  };
  check(render_once<EmbreeBackend<8>>(scene, settings).hdr.pixels);
  check(render_once<EmbreeBackend<1>>(scene, settings).hdr.pixels);
  check(render_once<ReferenceBackend<4>>(scene, settings).hdr.pixels);
  check(path_traced(scene, settings.width, settings.height, 1, false).pixels);
}

TEST_CASE("environment render: the furnace, a diffuse cube under a uniform sky, has radiance albedo everywhere",
          "[render][environment][accuracy]") {
  for (const float albedo : {1.0f, 0.6f}) {
    Scene scene = furnace(albedo);
    RenderSettings settings;
    settings.width = 48;
    settings.height = 36;
    settings.vpls_per_pixel = 8;
    // Enough directions that each face's estimate of the sky's irradiance is within about 1%.
    settings.environment_directions = 512;
    std::vector<std::size_t> cube, sky;
    const Image reference = path_traced(scene, settings.width, settings.height, 64, false);
    const Frame frame = render_once<EmbreeBackend<8>>(scene, settings);
    REQUIRE(all_finite(frame));
    // Pixels split by what their centre ray sees, away from the cube's outline (whose pixels
    // the discontinuity buffer's window reads across).
    const PinholeProjection projection(scene.cameras.front(), settings.width, settings.height);
    for (int y = 0; y < settings.height; ++y)
      for (int x = 0; x < settings.width; ++x) {
        int inside = 0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx)
            inside += meets_box(projection.origin(), projection.direction(float(x + dx) + 0.5f, float(y + dy) + 0.5f),
                                glm::vec3(-0.5f), glm::vec3(0.5f));
        const std::size_t i = std::size_t(y) * std::size_t(settings.width) + std::size_t(x);
        if (inside == 9) cube.push_back(i);
        if (inside == 0) sky.push_back(i);
      }
    REQUIRE(cube.size() > 150);
    REQUIRE(sky.size() > 150);
    CHECK(mean_at(reference.pixels, sky) == Approx(1.0).epsilon(1e-6));
    CHECK(mean_at(frame.hdr.pixels, sky) == Approx(1.0).epsilon(1e-6));
    // The path tracer: unbiased, 64 samples of cosine-weighted light and BRDF sampling under MIS.
    CHECK(mean_at(reference.pixels, cube) == Approx(albedo).epsilon(0.01));
    // IGI: the shared directional VPLs of the sky (each face one estimate) and the walks' bounce
    // VPLs, of which a convex cube gets none.
    CHECK(mean_at(frame.hdr.pixels, cube) == Approx(albedo).epsilon(0.02));
    for (const std::size_t i : cube) CHECK(frame.hdr.pixels[i].y == Approx(albedo).epsilon(0.05));
  }
}

TEST_CASE("environment render: IGI under the neutral sky agrees with the path tracer on a yard", "[render][environment][accuracy]") {
  Scene scene = yard();
  REQUIRE(light_with_default_sky(scene));
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.vpls_per_pixel = 32;
  settings.environment_directions = 128;
  const Image reference = path_traced(scene, settings.width, settings.height, 256, false);
  std::vector<std::size_t> all(reference.pixels.size());
  for (std::size_t i = 0; i < all.size(); ++i) all[i] = i;
  // Over frames: each frame draws its own directions and walks, so their average converges.
  double igi = 0.0;
  constexpr int frames = 4;
  for (int f = 0; f < frames; ++f) {
    const Frame frame = render_once<EmbreeBackend<8>>(scene, settings, std::uint32_t(f));
    REQUIRE(all_finite(frame));
    igi += mean_at(frame.hdr.pixels, all) / frames;
  }
  // The clamp takes a little of the box's contact light; 3% bounds that and the frames' noise.
  CHECK(igi == Approx(mean_at(reference.pixels, all)).epsilon(0.03));
  CHECK(light_warning(scene, reference).empty());
}

TEST_CASE("environment render: a scene without lights is not black under the default sky", "[render][environment]") {
  Scene scene = yard();
  RenderSettings settings;
  settings.width = 32;
  settings.height = 24;
  settings.vpls_per_pixel = 4;
  const Frame unlit = render_once<EmbreeBackend<8>>(scene, settings);
  CHECK(mean_radiance(unlit) == 0.0);
  CHECK_THAT(light_warning(scene, unlit.hdr), Catch::Contains("has no lights"));
  REQUIRE(light_with_default_sky(scene));
  const Frame lit = render_once<EmbreeBackend<8>>(scene, settings);
  CHECK(mean_radiance(lit) > 0.1);
  CHECK(light_warning(scene, lit.hdr).empty());
}

TEST_CASE("environment render: walks aimed through portals converge to the unaimed image", "[render][environment][portals]") {
  // The yard under the neutral sky and a low sun: the view sees a part of the ground, the box and
  // the slab, whose bounce light the aimed walks bring with fewer, lighter particles.
  Scene scene = yard();
  REQUIRE(light_with_default_sky(scene));
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .intensity = 2.0f,
                          .direction = glm::normalize(glm::vec3(-0.6f, -0.5f, -0.4f))});
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.vpls_per_pixel = 32;
  settings.environment_directions = 16;
  const auto average = [&](float share) {
    settings.portal_share = share;
    std::vector<glm::dvec3> sum(std::size_t(settings.width * settings.height), glm::dvec3(0.0));
    constexpr int frames = 8;
    for (int f = 0; f < frames; ++f) {
      const Frame frame = render_once<EmbreeBackend<8>>(scene, settings, std::uint32_t(f));
      REQUIRE(all_finite(frame));
      for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += glm::dvec3(frame.hdr.pixels[i]) / double(frames);
    }
    return sum;
  };
  const std::vector<glm::dvec3> plain = average(0.0f), aimed = average(0.7f);
  double plain_mean = 0.0, aimed_mean = 0.0;
  for (std::size_t i = 0; i < plain.size(); ++i) {
    plain_mean += (plain[i].x + plain[i].y + plain[i].z) / (3.0 * double(plain.size()));
    aimed_mean += (aimed[i].x + aimed[i].y + aimed[i].z) / (3.0 * double(plain.size()));
  }
  // The direct light is the same exact VPLs in both; the bounce light differs by the walks'
  // noise, about 1% of the image over 8 frames here.
  CHECK(aimed_mean == Approx(plain_mean).epsilon(0.02));
}
