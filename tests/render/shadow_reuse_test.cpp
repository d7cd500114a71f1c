// Temporal reuse of the delta lights' shadow answers: while the camera moves through a sunlit
// room, first hits that show the surface the previous frame showed around them take its answers
// instead of tracing the sun's shadow rays again, the images staying those that trace every ray
// up to shadows finer than a pixel; after a scene change every ray is traced; and the sequence is
// the same on every thread count.

#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "render_support.hpp"
#include "igi/scene/window_room.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// The room's camera `index` frames into a walk: 2 cm a frame sideways and a turn of 0.3
/// degrees, a few tenths of a pixel at 96 x 64.
Camera walked(const Camera& start, std::uint32_t index) { return walked_camera(start, index, 0.02f, 0.3f); }

RenderSettings room_settings(bool reuse) {
  RenderSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.vpls_per_pixel = 1;
  settings.temporal_frames = 16;
  settings.threads = 1;
  settings.reuse_shadows = reuse;
  return settings;
}

/// Pixels whose luminance differs by more than 1% (of the larger, at least 1e-3) between two frames.
std::size_t pixels_apart(const Frame& a, const Frame& b) {
  std::size_t apart = 0;
  for (std::size_t i = 0; i < a.hdr.pixels.size(); ++i) {
    const float x = luminance(a.hdr.pixels[i]), y = luminance(b.hdr.pixels[i]);
    apart += std::abs(x - y) > 0.01f * std::max({x, y, 0.1f});
  }
  return apart;
}

}  // namespace

TEST_CASE("shadow reuse: a moving camera traces fewer shadow rays for the same images", "[render][temporal][shadows]") {
  Scene scene = window_room();
  REQUIRE(std::any_of(scene.lights.begin(), scene.lights.end(),
                      [](const PunctualLight& light) { return light.kind == PunctualKind::directional; }));
  RoomRenderer reusing(scene, room_settings(true)), tracing(scene, room_settings(false));
  const Camera start = scene.cameras.front();
  std::uint64_t reused_rays = 0, traced_rays = 0;
  for (std::uint32_t index = 0; index < 8; ++index) {
    const Frame with = reusing.renderer.render(walked(start, index), index);
    const Frame without = tracing.renderer.render(walked(start, index), index);
    REQUIRE(all_finite(with));
    if (index == 0) {
      // No history yet: every ray traced, the same image.
      CHECK(with.statistics.rays.shadow == without.statistics.rays.shadow);
      CHECK(with.hdr.pixels == without.hdr.pixels);
      continue;
    }
    reused_rays += with.statistics.rays.shadow;
    traced_rays += without.statistics.rays.shadow;
    INFO("frame " << index);
    // Answers differ from the traced ones only on shadows finer than the four pixels they came
    // from: a handful of the 6,144 pixels, against every sunlit pixel of the room changing were
    // the answers wrong or numbered against the wrong light.
    CHECK(pixels_apart(with, without) <= with.hdr.pixels.size() / 100);
    CHECK(mean_radiance(with) == Approx(mean_radiance(without)).epsilon(2e-3));
  }
  INFO(reused_rays << " shadow rays reusing the sun's answers, " << traced_rays << " tracing them all");
  // At one VPL a pixel the sun's rays are about a quarter of the room's (the sky panel's walks
  // leave the rest); most of them are answered from the history, not those of the pixels whose
  // turn it is to trace nor a shadow's edges: measured 0.80 of the rays, against 1 were none reused.
  CHECK(double(reused_rays) < 0.85 * double(traced_rays));
}

TEST_CASE("shadow reuse: after the sun moves every shadow ray is traced", "[render][temporal][shadows]") {
  Scene scene = window_room();
  RoomRenderer reusing(scene, room_settings(true)), tracing(scene, room_settings(false));
  const Camera start = scene.cameras.front();
  for (std::uint32_t index = 0; index < 3; ++index) {
    reusing.renderer.render(walked(start, index), index);
    tracing.renderer.render(walked(start, index), index);
  }
  const auto sun = std::size_t(std::find_if(scene.lights.begin(), scene.lights.end(),
                                            [](const PunctualLight& light) { return light.kind == PunctualKind::directional; }) -
                               scene.lights.begin());
  PunctualLight turned = scene.lights[sun];
  turned.direction = glm::normalize(turned.direction + glm::vec3(0.2f, 0.0f, 0.1f));
  reusing.renderer.set_light(int(sun), turned);
  tracing.renderer.set_light(int(sun), turned);
  const Frame with = reusing.renderer.render(walked(start, 3), 3);
  const Frame without = tracing.renderer.render(walked(start, 3), 3);
  CHECK(with.statistics.rays.shadow == without.statistics.rays.shadow);
  CHECK(with.hdr.pixels == without.hdr.pixels);
}

TEST_CASE("shadow reuse: one and two threads render the same sequence", "[render][temporal][shadows][determinism]") {
  Scene scene = window_room();
  RenderSettings two = room_settings(true);
  two.threads = 2;
  RoomRenderer one_thread(scene, room_settings(true)), two_threads(scene, two);
  const Camera start = scene.cameras.front();
  for (std::uint32_t index = 0; index < 5; ++index) {
    const Frame a = one_thread.renderer.render(walked(start, index), index);
    const Frame b = two_threads.renderer.render(walked(start, index), index);
    INFO("frame " << index);
    CHECK(a.statistics.rays.shadow == b.statistics.rays.shadow);
    CHECK(a.hdr.pixels == b.hdr.pixels);
  }
}
