// igi-view's window-free parts: the orbit / fly camera, progressive accumulation (and that it
// converges a real rendering), tone mapping of the mean, and the movable light and its orbit.
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "view_controls.hpp"

namespace {

// Positions go through atan2 / asin / cos / sin and a 4x4 inverse in float: a few ulps of
// coordinates near 1 m, so 1e-5 m is tight yet safe.
constexpr float position_tolerance = 1e-5f;

/// The view direction of a camera (its -Z axis).
glm::vec3 view_direction(const igi::Camera& camera) { return glm::normalize(-glm::vec3(camera.camera_to_world[2])); }

}  // namespace

TEST_CASE("orbit camera starts where the scene camera is and looks where it looks") {
  const igi::Camera cornell = igi::cornell_box().cameras.front();
  const igi_view::OrbitCamera orbit(cornell, 1.0f);
  const igi::Camera camera = orbit.camera();
  for (int c = 0; c < 3; ++c) {
    CHECK(camera.position()[c] == Approx(cornell.position()[c]).margin(position_tolerance));
    CHECK(view_direction(camera)[c] == Approx(view_direction(cornell)[c]).margin(position_tolerance));
  }
  CHECK(camera.yfov == cornell.yfov);
  CHECK(camera.aspect == 0.0f);  // follows the window
  CHECK(glm::length(orbit.target() - orbit.eye()) == Approx(1.0f));
}

TEST_CASE("orbiting keeps the target and distance, a full turn comes back") {
  igi_view::OrbitCamera orbit(igi::cornell_box().cameras.front(), 0.8f);
  const glm::vec3 target = orbit.target(), eye = orbit.eye();
  orbit.orbit(0.7f, 0.3f);
  CHECK(glm::length(orbit.target() - target) == 0.0f);
  CHECK(glm::length(orbit.eye() - target) == Approx(0.8f));
  CHECK(glm::length(orbit.eye() - eye) > 0.1f);  // it did move
  orbit.orbit(glm::two_pi<float>() - 0.7f, -0.3f);
  CHECK(glm::length(orbit.eye() - eye) < position_tolerance);
}

TEST_CASE("flying moves eye and target together, pitch stops short of the pole") {
  igi_view::OrbitCamera orbit(igi::cornell_box().cameras.front(), 0.8f);
  const glm::vec3 eye = orbit.eye(), forward = orbit.forward(), right = orbit.right();
  orbit.fly(0.1f, 0.2f, 0.05f);
  const glm::vec3 moved = orbit.eye() - eye;
  const glm::vec3 expected = 0.1f * forward + 0.2f * right + glm::vec3(0.0f, 0.05f, 0.0f);
  CHECK(glm::length(moved - expected) < position_tolerance);
  orbit.orbit(0.0f, 10.0f);
  CHECK(orbit.forward().y == Approx(std::sin(1.5f)));
  const igi::Camera camera = orbit.camera();
  for (int c = 0; c < 4; ++c)
    for (int r = 0; r < 4; ++r) CHECK(std::isfinite(camera.camera_to_world[c][r]));
  orbit.zoom(0.5f);
  CHECK(glm::length(orbit.eye() - orbit.target()) == Approx(0.4f));
  orbit.zoom(-1.0f);  // ignored
  CHECK(glm::length(orbit.eye() - orbit.target()) == Approx(0.4f));
  CHECK_THROWS_WITH(igi_view::OrbitCamera(igi::cornell_box().cameras.front(), 0.0f), Catch::Contains("target distance"));
}

TEST_CASE("the accumulator's mean is the mean of the frames since the last reset") {
  igi_view::ProgressiveAccumulator accumulator;
  CHECK(accumulator.count() == 0);
  CHECK(accumulator.mean().empty());
  accumulator.add(igi::Image(3, 2, glm::vec3(1.0f, 2.0f, 3.0f)));
  accumulator.add(igi::Image(3, 2, glm::vec3(3.0f, 0.0f, 1.0f)));
  CHECK(accumulator.count() == 2);
  igi::Image mean = accumulator.mean();
  REQUIRE(mean.width == 3);
  REQUIRE(mean.height == 2);
  for (const glm::vec3& p : mean.pixels) CHECK(p == glm::vec3(2.0f, 1.0f, 2.0f));
  accumulator.reset();
  accumulator.add(igi::Image(3, 2, glm::vec3(5.0f)));
  CHECK(accumulator.count() == 1);
  CHECK(accumulator.mean()(2, 1) == glm::vec3(5.0f));
  accumulator.add(igi::Image(4, 4, glm::vec3(7.0f)));  // another size starts again
  CHECK(accumulator.count() == 1);
  CHECK(accumulator.mean()(3, 3) == glm::vec3(7.0f));
}

TEST_CASE("accumulating new VPL sets converges a still Cornell box") {
  igi::Scene scene = igi::cornell_box();
  const igi::Camera camera = scene.cameras.front();
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::QmcVplSampler sampler;
  const igi::NoFilter filter;  // unfiltered, so each frame's VPL noise is plain to see
  using CornellRenderer = igi::Renderer<igi::EmbreeBackend<8>, igi::GltfMaterialShader, igi::StandardBrdf,
                                        igi::QmcVplSampler, igi::NoFilter>;
  igi::RenderSettings settings;
  settings.width = settings.height = 32;
  settings.vpls_per_pixel = 4;
  CornellRenderer renderer(scene, settings, surface, brdf, sampler, filter);
  // The reference: the same estimator with 256 times the VPLs, from a frame the test never accumulates.
  igi::RenderSettings many = settings;
  many.vpls_per_pixel = 1024;
  CornellRenderer reference_renderer(scene, many, surface, brdf, sampler, filter);
  const igi::Image reference = reference_renderer.render(camera, 1000).hdr;

  const auto mean_squared_error = [&](const igi::Image& image) {
    double sum = 0.0;
    for (std::size_t i = 0; i < image.pixels.size(); ++i) {
      const glm::vec3 d = image.pixels[i] - reference.pixels[i];
      sum += double(glm::dot(d, d));
    }
    return sum / double(image.pixels.size());
  };
  // A few VPLs light all pixels of one set alike, so one frame's error is itself noisy: the
  // single-frame error is averaged over all the frames that go into the accumulation.
  constexpr int frames = 16;
  igi_view::ProgressiveAccumulator accumulator;
  double single_frame = 0.0;
  for (std::uint32_t frame = 0; frame < frames; ++frame) {
    const igi::Image image = renderer.render(camera, frame).hdr;
    single_frame += mean_squared_error(image) / frames;
    accumulator.add(image);
  }
  CHECK(accumulator.count() == frames);
  const double accumulated = mean_squared_error(accumulator.mean());
  INFO("RMS error of one frame " << std::sqrt(single_frame) << ", of the mean of 16 " << std::sqrt(accumulated));
  CHECK(single_frame > 0.0);
  // Independent frames shrink the RMS error as 1/sqrt(16) = 1/4 (plus the reference's own, 1/16
  // of one frame's); 1/2 leaves room for the frames' sets sharing a Halton sequence.
  CHECK(std::sqrt(accumulated) < 0.5 * std::sqrt(single_frame));
}

TEST_CASE("tone mapping the mean gives a lit image and black for black") {
  igi::Image image(4, 1);
  image(0, 0) = glm::vec3(0.1f);
  image(1, 0) = glm::vec3(1.0f);
  image(2, 0) = glm::vec3(10.0f, 0.0f, 0.0f);
  const igi::Rgb8Image mapped = igi_view::tone_map(image);
  CHECK(mapped.pixel(0, 0)[0] > 0);
  CHECK(mapped.pixel(1, 0)[0] > mapped.pixel(0, 0)[0]);  // brighter stays brighter
  CHECK(mapped.pixel(2, 0)[0] > mapped.pixel(2, 0)[1]);  // red stays red
  CHECK(mapped.pixel(3, 0)[0] == 0);
  const igi::Rgb8Image black = igi_view::tone_map(igi::Image(2, 2));
  for (std::uint8_t byte : black.bytes) CHECK(byte == 0);
}

TEST_CASE("the movable light is the first punctual light, else the first emissive instance") {
  igi::Scene scene = igi::cornell_box();
  std::optional<igi_view::MovableLight> light = igi_view::find_movable_light(scene);
  REQUIRE(light);
  CHECK(light->kind == igi_view::MovableLight::Kind::instance);
  CHECK(scene.instances[std::size_t(light->index)].name == "luminaire");

  scene.lights.push_back({.name = "sun", .kind = igi::PunctualKind::directional});
  scene.lights.push_back({.name = "bulb", .kind = igi::PunctualKind::point, .position = {0.2f, 0.3f, 0.4f}});
  light = igi_view::find_movable_light(scene);
  REQUIRE(light);
  CHECK(light->kind == igi_view::MovableLight::Kind::punctual);
  CHECK(light->index == 1);
  CHECK(light->moved_light({0.1f, 0.0f, 0.0f}).position == glm::vec3(0.2f, 0.3f, 0.4f) + glm::vec3(0.1f, 0.0f, 0.0f));

  igi::Scene dark;
  igi::Mesh triangle;
  triangle.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  triangle.triangles = {{0, 1, 2}};
  dark.meshes.push_back(triangle);
  dark.instances.push_back({.name = "one", .mesh = 0});
  dark.lights.push_back({.name = "sun", .kind = igi::PunctualKind::directional});
  CHECK_FALSE(igi_view::find_movable_light(dark));
}

TEST_CASE("the scripted light orbit is periodic and keeps the Cornell luminaire inside the box") {
  const igi::Scene scene = igi::cornell_box();
  const igi::Bounds box = scene.bounds();
  const float radius = igi_view::light_orbit_radius(box);
  REQUIRE(radius > 0.0f);
  CHECK(igi_view::light_orbit_offset(0, radius, 60) == glm::vec3(radius, 0.0f, 0.0f));
  CHECK(glm::length(igi_view::light_orbit_offset(60, radius, 60) - igi_view::light_orbit_offset(0, radius, 60)) == 0.0f);
  const igi_view::MovableLight light = *igi_view::find_movable_light(scene);
  const igi::Mesh& luminaire = scene.meshes[std::size_t(scene.instances[std::size_t(light.index)].mesh)];
  for (std::uint32_t frame = 0; frame < 60; ++frame) {
    const glm::vec3 offset = igi_view::light_orbit_offset(frame, radius, 60);
    CHECK(glm::length(offset) == Approx(radius));
    const glm::mat4 moved = light.moved_transform(offset);
    for (const glm::vec3& p : luminaire.positions) {
      const glm::vec3 world(moved * glm::vec4(p, 1.0f));
      CHECK(world.x > box.lower.x);
      CHECK(world.x < box.upper.x);
      CHECK(world.z > box.lower.z);
      CHECK(world.z < box.upper.z);
    }
  }
  CHECK_THROWS_WITH(igi_view::light_orbit_offset(0, radius, 0), Catch::Contains("period"));
}
