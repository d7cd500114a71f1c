// The environment: its mapping, its importance sampling against its own density and integral,
// the directional VPLs that carry its direct light, its particles, the path tracer's light
// sampler, HDR files, the default sky and the warnings for dark images.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/io/environment_file.hpp"
#include "igi/io/image_files.hpp"
#include "igi/lighting/light_sampling.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/render/light_check.hpp"
#include "igi/simd/sampling.hpp"
#include "lighting/lighting_support.hpp"
#include "scene_builders.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// A map whose radiance varies in both directions (a gradient, a bright patch for a sun and a
/// black band), so that sampling and lookups are exercised off any symmetry.
Environment uneven_map(float scale = 1.0f, float rotation = 0.0f) {
  constexpr int width = 64, height = 32;
  std::vector<glm::vec3> texels(std::size_t(width * height));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      glm::vec3 value(0.2f + 0.8f * float(x) / width, 0.5f + 0.5f * float(y) / height, 0.3f);
      if (x >= 40 && x < 43 && y >= 6 && y < 8) value = glm::vec3(400.0f, 380.0f, 300.0f);  // a small, bright sun
      if (y >= 20 && y < 22) value = glm::vec3(0.0f);                                       // a black band
      texels[std::size_t(y * width + x)] = value;
    }
  return Environment("uneven", width, height, std::move(texels), scale, rotation);
}

/// A map of constant radiance `value`.
Environment uniform_map(float value, int width = 32, int height = 16) {
  return Environment("uniform", width, height, std::vector<glm::vec3>(std::size_t(width * height), glm::vec3(value)));
}

/// The integral over the sphere of `map`'s (bilinear) radiance, times max(0, cos) to `normal`
/// if one is given, by the midpoint rule on a grid far finer than the map's texels.
glm::dvec3 lookup_integral(const Environment& map, const glm::vec3* normal = nullptr) {
  glm::dvec3 sum(0.0);
  constexpr int n = 768;
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < 2 * n; ++x) {
      const glm::vec2 uv((float(x) + 0.5f) / float(2 * n), (float(y) + 0.5f) / float(n));
      const glm::vec3 direction = map.from_map(uv);
      double weight = 2.0 * std::numbers::pi / (2 * n) * std::numbers::pi / n * std::sin(double(uv.y) * std::numbers::pi);
      if (normal) weight *= std::max(0.0, double(glm::dot(*normal, direction)));
      sum += glm::dvec3(map.radiance(direction)) * weight;
    }
  return sum;
}

/// A temporary file's path, removed when it goes out of scope.
struct TemporaryFile {
  std::filesystem::path path;
  explicit TemporaryFile(const std::string& name) : path(std::filesystem::temp_directory_path() / name) {}
  ~TemporaryFile() {
    std::error_code ignored;
    std::filesystem::remove(path, ignored);
  }
};

}  // namespace

TEST_CASE("environment: the mapping puts the zenith on the top row, -Z at the left edge and +X a quarter across",
          "[lighting][environment]") {
  const Environment map = uniform_map(1.0f);
  CHECK(map.to_map({0, 1, 0}).y == Approx(0.0f).margin(1e-6));
  CHECK(map.to_map({0, -1, 0}).y == Approx(1.0f).margin(1e-6));
  CHECK(map.to_map({0, 0, -1}).x == Approx(0.0f).margin(1e-6));
  CHECK(map.to_map({1, 0, 0}).x == Approx(0.25f).margin(1e-6));
  CHECK(map.to_map({0, 0, 1}).x == Approx(0.5f).margin(1e-6));
  CHECK(map.to_map({-1, 0, 0}).x == Approx(0.75f).margin(1e-6));
  Rng rng(7);
  for (const float rotation : {0.0f, 0.7f, -2.5f}) {
    const Environment turned("turned", 4, 2, std::vector<glm::vec3>(8, glm::vec3(1.0f)), 1.0f, rotation);
    for (int i = 0; i < 200; ++i) {
      const glm::vec2 uv(rng.next(), 0.02f + 0.96f * rng.next());
      const glm::vec2 back = turned.to_map(turned.from_map(uv));
      // u wraps around: compare on the circle.
      CHECK(std::abs(std::remainder(back.x - uv.x, 1.0f)) < 1e-5f);
      CHECK(back.y == Approx(uv.y).margin(1e-5));
    }
  }
  // A rotation of a quarter turn about +Y brings the map's -Z column to world -X (turning -Z towards -X).
  const Environment quarter("quarter", 4, 2, std::vector<glm::vec3>(8, glm::vec3(1.0f)), 1.0f, pi / 2);
  const glm::vec3 left_edge = quarter.from_map({0.0f, 0.5f});
  CHECK(left_edge.x == Approx(-1.0f).margin(1e-5));
  CHECK(left_edge.z == Approx(0.0f).margin(1e-5));
}

TEST_CASE("environment: lookups are bilinear between texel centres, times the scale", "[lighting][environment]") {
  // Two columns: left 1, right 3; at a texel centre the texel itself, halfway between the centres the mean.
  const Environment map("two", 2, 1, {glm::vec3(1.0f), glm::vec3(3.0f)}, 2.0f);
  CHECK(map.radiance(map.from_map({0.25f, 0.5f})).x == Approx(2.0f).epsilon(1e-4));
  CHECK(map.radiance(map.from_map({0.75f, 0.5f})).x == Approx(6.0f).epsilon(1e-4));
  CHECK(map.radiance(map.from_map({0.5f, 0.5f})).x == Approx(4.0f).epsilon(1e-4));
  // Across the seam at u = 0 the map wraps: halfway between the right texel and the left one.
  CHECK(map.radiance(map.from_map({0.0f, 0.5f})).x == Approx(4.0f).epsilon(1e-4));
}

TEST_CASE("environment: a uniform map is sampled uniformly over the sphere", "[lighting][environment]") {
  const Environment map = uniform_map(2.0f);
  CHECK(map.integral().x == Approx(8.0f * pi).epsilon(1e-5));
  CHECK(map.mean_radiance().y == Approx(2.0f).epsilon(1e-5));
  const Halton halton(3);
  for (int i = 0; i < 500; ++i) {
    const EnvironmentSample s = map.sample(halton.sample(0, std::uint64_t(i)), halton.sample(1, std::uint64_t(i)));
    REQUIRE(s.pdf > 0.0f);
    CHECK(glm::length(s.direction) == Approx(1.0f).epsilon(1e-5));
    CHECK(s.pdf == Approx(1.0f / (4.0f * pi)).epsilon(1e-3));
    CHECK(s.radiance.z == Approx(2.0f).epsilon(1e-5));
  }
}

TEST_CASE("environment: sampling follows its density, and L / pdf integrates the map", "[lighting][environment]") {
  for (const float rotation : {0.0f, 1.3f}) {
    const Environment map = uneven_map(1.5f, rotation);
    const Halton halton(11);
    glm::dvec3 estimate(0.0);
    constexpr int samples = 1 << 16;
    int other_texel = 0;
    for (int i = 0; i < samples; ++i) {
      const EnvironmentSample s = map.sample(halton.sample(0, std::uint64_t(i)), halton.sample(1, std::uint64_t(i)));
      REQUIRE(s.pdf > 0.0f);
      // The density sample() reports is the one pdf() gives for its direction: both read the
      // texel's weight, but a sample on a texel's edge may round into its neighbour.
      if (std::abs(map.pdf(s.direction) - s.pdf) > 2e-3f * s.pdf) ++other_texel;
      estimate += glm::dvec3(s.radiance / s.pdf);
    }
    estimate /= double(samples);
    CHECK(other_texel <= samples / 1000);
    // Unbiased for the lookups' own integral; the texels' piecewise-constant one differs from
    // it by the blur of the sun's and the band's edges, within 2% on this map.
    const glm::dvec3 reference = lookup_integral(map);
    const glm::vec3 integral = map.integral();
    for (int c = 0; c < 3; ++c) {
      CHECK(estimate[c] == Approx(reference[c]).epsilon(0.003));
      CHECK(integral[c] == Approx(reference[c]).epsilon(0.02));
    }
  }
}

TEST_CASE("environment: maps that cannot be used are refused with their problem named", "[lighting][environment]") {
  CHECK_THROWS_WITH(Environment("bad", 2, 2, std::vector<glm::vec3>(3)), Catch::Contains("2 x 2 map with 3 texels"));
  std::vector<glm::vec3> texels(4, glm::vec3(1.0f));
  texels[3].y = std::nanf("");
  CHECK_THROWS_WITH(Environment("nan", 2, 2, texels), Catch::Contains("texel (1, 1) is not finite"));
  texels[3].y = -1.0f;
  CHECK_THROWS_WITH(Environment("negative", 2, 2, texels), Catch::Contains("texel (1, 1) is negative"));
  CHECK_THROWS_WITH(Environment("scale", 1, 1, {glm::vec3(1.0f)}, -2.0f), Catch::Contains("scale"));
  // A black map is valid and emits nothing: no samples, no light.
  const Environment black = uniform_map(0.0f);
  CHECK_FALSE(black.emits());
  CHECK(black.sample(0.3f, 0.6f).pdf == 0.0f);
}

TEST_CASE("environment: its directional VPLs estimate the irradiance it gives", "[lighting][environment]") {
  Scene scene = testing::closed_cube({glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f),
                                      glm::vec3(0.5f)});
  SECTION("the neutral sky gives an open horizontal surface the irradiance pi") {
    const EnvironmentLight light(std::make_shared<const Environment>(neutral_sky()), scene.bounds());
    const glm::vec3 up(0.0f, 1.0f, 0.0f);
    const auto irradiance = [&](int count, std::uint32_t scramble) {
      double sum = 0.0;
      for (const Vpl& vpl : light.directional_vpls(count, scramble)) {
        CHECK(vpl.kind == VplKind::directional);
        sum += double(vpl.intensity.x) * std::max(0.0, double(glm::dot(up, -vpl.normal)));
      }
      return sum;
    };
    // With many directions the estimate converges to the sky's pi; with the default 32 it is
    // within a few percent on every frame's scrambling.
    CHECK(irradiance(4096, 1) == Approx(pi).epsilon(0.005));
    for (std::uint32_t scramble = 0; scramble < 8; ++scramble) CHECK(irradiance(32, scramble) == Approx(pi).epsilon(0.06));
  }
  SECTION("an uneven map's directions, summed over a tilted receiver's hemisphere, match the map's own integral") {
    const auto map = std::make_shared<const Environment>(uneven_map(1.0f, 0.4f));
    const EnvironmentLight light(map, scene.bounds());
    const glm::vec3 normal = glm::normalize(glm::vec3(0.3f, 0.8f, -0.5f));
    const double reference = lookup_integral(*map, &normal).x;
    double estimate = 0.0;
    for (const Vpl& vpl : light.directional_vpls(8192, 5))
      estimate += double(vpl.intensity.x) * std::max(0.0, double(glm::dot(normal, -vpl.normal)));
    CHECK(estimate == Approx(reference).epsilon(0.01));
  }
  SECTION("no directions without light") {
    const EnvironmentLight black(std::make_shared<const Environment>(uniform_map(0.0f)), scene.bounds());
    CHECK(black.directional_vpls(32, 1).empty());
  }
}

TEST_CASE("environment: its light particles carry its power into the scene's bounding sphere", "[lighting][environment]") {
  Scene scene = testing::closed_cube({glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f),
                                      glm::vec3(0.5f)});
  scene.environment = std::make_shared<const Environment>(uneven_map(2.0f));
  const LightSet lights(scene);
  // The cube's walls do not emit; the environment is the one emitter.
  REQUIRE(lights.size() == 1);
  const Emitter& emitter = lights.emitter(0);
  const EnvironmentLight light(scene.environment, scene.bounds());
  CHECK(emitter.power().x == Approx(light.power().x).epsilon(1e-6));
  const Bounds bounds = scene.bounds();
  const glm::vec3 centre = bounds.center();
  const float radius = 0.5f * glm::length(bounds.extent());
  const Halton halton(2);
  glm::dvec3 flux(0.0);
  constexpr int samples = 1 << 15;
  for (int i = 0; i < samples; ++i) {
    const auto k = std::uint64_t(i);
    const EmissionSample s = emitter.sample_emission(halton.sample(0, k), halton.sample(1, k), halton.sample(2, k), halton.sample(3, k));
    CHECK_FALSE(s.leaves_vpl);  // its direct light is the directional VPLs', not a VPL on the light
    // The particle heads into the bounding sphere: its line passes within the radius of the centre.
    const glm::vec3 to_centre = centre - s.origin;
    const glm::vec3 closest = s.origin + s.direction * glm::dot(to_centre, s.direction);
    CHECK(glm::length(closest - centre) <= radius * (1.0f + 1e-4f));
    flux += glm::dvec3(s.flux);
  }
  flux /= double(samples);
  // The particles' flux is unbiased for pi r^2 times the lookups' integral (power() uses the texels').
  const glm::dvec3 power = lookup_integral(*scene.environment) * double(std::numbers::pi_v<float> * radius * radius);
  CHECK(flux.x == Approx(power.x).epsilon(0.005));
  CHECK(flux.z == Approx(power.z).epsilon(0.005));
}

TEST_CASE("environment: the path tracer's light sampler draws it with the density it reports", "[lighting][environment]") {
  Scene scene = testing::closed_box_with_light(0.5f, {4.0f, 4.0f, 4.0f});
  scene.environment = std::make_shared<const Environment>(uneven_map());
  const LightSampler sampler(scene);
  REQUIRE(sampler.has_environment());
  const glm::vec3 receiver(0.5f, 0.2f, 0.5f);
  int environment_samples = 0;
  const Halton halton(4);
  for (int i = 0; i < 4000; ++i) {
    const auto k = std::uint64_t(i);
    const LightSample s = sampler.sample(receiver, halton.sample(0, k), halton.sample(1, k), halton.sample(2, k));
    if (!std::isinf(s.distance) || !s.usable()) continue;  // the area light's samples
    ++environment_samples;
    CHECK_FALSE(s.delta);
    CHECK(sampler.environment_pdf(s.wi) == Approx(s.pdf).epsilon(2e-3));
    CHECK(sampler.environment_radiance(s.wi).x == Approx(s.incident.x).epsilon(1e-5));
  }
  CHECK(environment_samples > 100);
  Scene dark = testing::closed_box_with_light(0.5f, {4.0f, 4.0f, 4.0f});
  const LightSampler none(dark);
  CHECK_FALSE(none.has_environment());
  CHECK(none.environment_pdf({0, 1, 0}) == 0.0f);
}

TEST_CASE("environment: HDR files round-trip, and bad or missing maps name the file", "[lighting][environment][io]") {
  Image image(8, 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 8; ++x) image(x, y) = glm::vec3(0.1f + float(x), 2.0f * float(y) + 0.5f, 1000.0f * float(x + y) + 0.01f);
  for (const char* name : {"igi_environment_test.hdr", "igi_environment_test.exr", "igi_environment_test.pfm"}) {
    const TemporaryFile file(name);
    write_image(file.path, image);
    const Image back = read_image(file.path);
    REQUIRE(back.width == 8);
    REQUIRE(back.height == 4);
    // RGBE keeps an 8-bit mantissa shared by the channels: 1/128 of the largest channel.
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      for (int c = 0; c < 3; ++c)
        CHECK(std::abs(back.pixels[i][c] - image.pixels[i][c]) <= std::max(image.pixels[i].x, std::max(image.pixels[i].y, image.pixels[i].z)) / 128.0f);
    const auto map = read_environment(file.path, 2.0f, 90.0f);
    CHECK(map->width() == 8);
    CHECK(map->scale() == 2.0f);
    CHECK(map->rotation() == Approx(pi / 2));
  }
  CHECK_THROWS_WITH(read_environment("/nonexistent/sky.hdr"), Catch::Contains("/nonexistent/sky.hdr") && Catch::Contains("does not exist"));
  const TemporaryFile text("igi_environment_test_text.hdr");
  { std::ofstream(text.path) << "this is not an image"; }
  CHECK_THROWS_WITH(read_environment(text.path), Catch::Contains("igi_environment_test_text.hdr") && Catch::Contains("not a Radiance HDR"));
  const TemporaryFile negative("igi_environment_test_negative.pfm");
  Image bad(2, 1, glm::vec3(1.0f));
  bad(1, 0).y = -3.0f;
  write_image(negative.path, bad);
  CHECK_THROWS_WITH(read_environment(negative.path), Catch::Contains("igi_environment_test_negative.pfm") && Catch::Contains("negative"));
  CHECK_THROWS_AS(read_environment("sky.jpg"), ImageError);
}

TEST_CASE("environment: a scene without light gets the neutral sky, one with light keeps its own", "[lighting][environment]") {
  Scene dark = testing::closed_cube({glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f),
                                     glm::vec3(0.5f)});
  CHECK_FALSE(dark.has_lights());
  CHECK(light_with_default_sky(dark, 2.0f));
  REQUIRE(dark.environment);
  CHECK(dark.environment->name() == "neutral sky");
  CHECK(dark.environment->scale() == 2.0f);
  CHECK(dark.has_lights());
  CHECK_FALSE(light_with_default_sky(dark));  // once lit, left alone

  Scene lamp = testing::closed_box_with_light(0.5f, glm::vec3(1.0f));
  CHECK(lamp.has_lights());
  CHECK_FALSE(light_with_default_sky(lamp));
  CHECK_FALSE(lamp.environment);
  Scene sun = dark;
  sun.environment = nullptr;
  sun.lights.push_back({.name = "sun", .kind = PunctualKind::directional});
  CHECK_FALSE(light_with_default_sky(sun));
  // A black environment is no light.
  Scene black = sun;
  black.lights.clear();
  black.environment = std::make_shared<const Environment>(uniform_map(0.0f));
  CHECK_FALSE(black.has_lights());
}

TEST_CASE("environment: black images and images far darker than the scene's lights are named in a warning",
          "[lighting][environment]") {
  Scene scene = testing::closed_box_with_light(0.5f, glm::vec3(10.0f));
  const double scale = light_check_scale(scene);
  // The light (0.2 x 0.2, radiance 10) spreads 0.04 x 10 x pi over the cube's 6 + 0.04 m^2 of surface.
  CHECK(scale == Approx(0.04 * 10.0 * std::numbers::pi / (std::numbers::pi * 6.04)).epsilon(1e-3));
  Image image(4, 4, glm::vec3(float(scale)));
  CHECK(light_warning(scene, image).empty());
  Image black(4, 4);
  CHECK_THAT(light_warning(scene, black), Catch::Contains("the image is black") && Catch::Contains("closed cube"));
  Image dim(4, 4, glm::vec3(float(scale) * 1e-4f));
  CHECK_THAT(light_warning(scene, dim), Catch::Contains("below a thousandth"));
  Scene unlit = testing::closed_cube({glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f),
                                      glm::vec3(0.5f)});
  CHECK_THAT(light_warning(unlit, black), Catch::Contains("has no lights"));
}
