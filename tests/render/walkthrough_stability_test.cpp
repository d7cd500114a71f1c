// Stability under motion in a window-lit room: the camera walks slowly through the built-in
// window room under the sun and the sky while igi renders at its programs' defaults (portals,
// temporal reuse over 32 frames, VPLs held while the camera moves). Against the same frames
// rendered converged (256 VPLs, one sampling pattern for all frames, so they change only with
// the view), each frame's image mean must stay steady (no pulsing) and its pixels must not
// change from frame to frame much more than the converged frames' do (no crawling); with new
// VPLs every frame (--hold-vpls 0) and in the frame-independent mode of the paper (--temporal 0)
// they pulse and crawl more. The same holds while the sun moves and the view stays still. Over
// many frames, no frame may be lit by a few heavy light particles (a flash that temporal reuse
// only spreads).

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "render_support.hpp"
#include "igi/io/srgb.hpp"
#include "igi/scene/window_room.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// A frame's pixels' mean luminance.
double mean_luminance(const Frame& frame) {
  double sum = 0.0;
  for (const glm::vec3& p : frame.hdr.pixels) sum += double(luminance(p));
  return sum / double(frame.hdr.pixels.size());
}

/// Summed absolute change of each pixel's luminance from `before` to `after`.
double change(const Frame& before, const Frame& after) {
  double sum = 0.0;
  for (std::size_t i = 0; i < after.hdr.pixels.size(); ++i)
    sum += std::abs(double(luminance(after.hdr.pixels[i])) - double(luminance(before.hdr.pixels[i])));
  return sum;
}

/// Coefficient of variation of `values`: their standard deviation over their mean.
double variation(const std::vector<double>& values) {
  double mean = 0.0, square = 0.0;
  for (const double v : values) mean += v;
  mean /= double(values.size());
  for (const double v : values) square += (v - mean) * (v - mean);
  return std::sqrt(square / double(values.size())) / mean;
}

/// What a walk through the window room shows at some settings.
struct Walk {
  std::vector<double> mean_ratio;  ///< Each measured frame's image mean over the converged frame's.
  double flicker = 0.0;            ///< Pixels' frame-to-frame change beyond the converged frames', over their summed luminance.
};

/// The walk whose frame `index` `render(index)` renders, against `converged` (one frame per
/// index), measured from frame `first_measured` on (the first frames build the history up).
template <class Render>
Walk measure(const std::vector<Frame>& converged, std::uint32_t first_measured, Render&& render) {
  Walk result;
  Frame previous;
  double beyond = 0.0, total = 0.0;
  for (std::uint32_t index = 0; index < std::uint32_t(converged.size()); ++index) {
    Frame frame = render(index);
    if (index >= first_measured) {
      result.mean_ratio.push_back(mean_luminance(frame) / mean_luminance(converged[index]));
      beyond += std::max(0.0, change(previous, frame) - change(converged[index - 1], converged[index]));
      total += mean_luminance(converged[index]) * double(frame.hdr.pixels.size());
    }
    previous = std::move(frame);
  }
  result.flicker = beyond / total;
  return result;
}

/// The window room's camera `index` frames into a slow walk: 1 cm a frame sideways and a turn of
/// 0.1 degrees, about a tenth of a pixel at 96 x 64, as a user edging along.
Camera walked(const Camera& start, std::uint32_t index) { return walked_camera(start, index, 0.01f, 0.1f); }

}  // namespace

TEST_CASE("walkthrough: a window-lit room neither pulses nor crawls under a moving camera at the programs' defaults",
          "[render][temporal][stability]") {
  Scene scene = with_sky(window_room());
  RenderSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.threads = 2;
  RenderSettings converged_settings = settings;
  converged_settings.vpls_per_pixel = 256;
  const Camera start = scene.cameras.front();
  constexpr std::uint32_t frames = 16, first_measured = 4;

  std::vector<Frame> converged;
  {
    Scene copy = scene;
    RoomRenderer renderer(copy, converged_settings);
    for (std::uint32_t index = 0; index < frames; ++index) converged.push_back(renderer.render(walked(start, index), 0));
  }
  const auto walk = [&](int temporal_frames, int held_vpl_frames) {
    Scene copy = scene;
    RenderSettings s = settings;
    s.temporal_frames = temporal_frames;
    s.held_vpl_frames = held_vpl_frames;
    RoomRenderer renderer(copy, s);
    return measure(converged, first_measured, [&](std::uint32_t index) { return renderer.render(walked(start, index), index); });
  };
  const Walk defaults = walk(32, settings.held_vpl_frames), drawn = walk(32, 0), paper = walk(0, 0);
  INFO("image mean over the converged frame's: CV " << variation(defaults.mean_ratio) << " at the defaults, "
       << variation(drawn.mean_ratio) << " with new VPLs every frame, " << variation(paper.mean_ratio)
       << " frame by frame; flicker " << defaults.flicker << ", " << drawn.flicker << " and " << paper.flicker);
  // Measured (frames 4-15): the image mean varies by 2.6% at the defaults (VPLs held while the
  // camera moves), 3.9% with new VPLs every frame and 9.3% frame by frame; the pixels change by
  // 0%, 3.7% and 17% beyond the converged frames' change. The walkthrough benchmark's targets
  // are 2% and 5%; these bounds hold the defaults 2x above what was measured (new VPLs every
  // frame measured 3.8% and 6.3% before), so that a change that brings back pulsing or crawling
  // fails here.
  CHECK(variation(defaults.mean_ratio) < 0.06);
  CHECK(defaults.flicker < 0.10);
  // Holding the VPLs is what takes the frames' own VPL noise out of the walk: with new ones every
  // frame the image mean varies 1.5x as much and the pixels crawl.
  CHECK(variation(defaults.mean_ratio) < 0.8 * variation(drawn.mean_ratio));
  CHECK(defaults.flicker < 0.5 * drawn.flicker);
  // Temporal reuse is what steadies them: the paper's frame-independent mode pulses and crawls
  // at least twice as much.
  CHECK(variation(defaults.mean_ratio) < 0.5 * variation(paper.mean_ratio));
  CHECK(defaults.flicker < 0.5 * paper.flicker);
  // And no frame is far off its converged image's mean (at most 9% measured).
  for (const double ratio : defaults.mean_ratio) CHECK(std::abs(ratio - 1.0) < 0.15);
}

TEST_CASE("walkthrough: no frame of a window-lit room is lit by a few heavy light particles", "[render][portals][stability]") {
  // Frame by frame (the paper's mode, which shows each frame's own VPLs), 256 frames of the
  // still view: a particle that lands on the ground far outside carries the light of a large
  // part of the sun's disc, and where its bounce entered the room by chance it lit the frame.
  // Measured over frames 0-255 at 64 x 48, the brightest frame's image mean over the median
  // frame's: 3.4 in the window room and 2.1 behind the blinds, where it was 17.3 and 3.6 before
  // such bounces were aimed back in through the openings (BounceOpenings). The bounds hold
  // today's 1.5x above what was measured, so that a change that brings the flashes back fails.
  // Rarer ones are left: over frames 0-1023, 9.8 and 3.7 (17.3 and 8.6 before).
  struct Room {
    Scene scene;
    double brightest;  // most the brightest frame may have, over the median frame's image mean
  };
  for (Room room : {Room{window_room(), 5.0}, Room{window_room_with_blinds(), 3.0}}) {
    RenderSettings settings;
    settings.width = 64;
    settings.height = 48;
    settings.threads = 2;
    settings.temporal_frames = 0;
    RoomRenderer renderer(room.scene, settings);
    std::vector<double> means;
    for (std::uint32_t index = 0; index < 256; ++index)
      means.push_back(mean_luminance(renderer.render(room.scene.cameras.front(), index)));
    std::vector<double> sorted = means;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[sorted.size() / 2];
    REQUIRE(median > 0.0);
    INFO(room.scene.name << ": brightest frame " << std::max_element(means.begin(), means.end()) - means.begin() << " at "
                         << sorted.back() / median << "x the median frame's image mean");
    CHECK(sorted.back() / median < room.brightest);
  }
}

TEST_CASE("walkthrough: a window-lit room does not pulse while its sun moves", "[render][temporal][stability]") {
  // The view stays still while the sun turns 2 degrees a frame about the vertical (a user
  // dragging the sun, or a file's animation): every frame is a scene change, whose histories are
  // clamped to the new frame's neighbourhoods. Against the same frames rendered converged (256
  // VPLs, one sampling pattern), the defaults draw each changed frame's VPLs with the random
  // numbers of the frame before, so that its light paths move with the sun instead of being
  // replaced by other ones; with new VPLs every frame (--hold-vpls 0) each frame's few heavy
  // paths make the image mean pulse.
  Scene scene = with_sky(window_room());
  RenderSettings settings;
  settings.width = 96;
  settings.height = 64;
  settings.threads = 2;
  settings.temporal_frames = 32;
  RenderSettings converged_settings = settings;
  converged_settings.temporal_frames = 0;
  converged_settings.vpls_per_pixel = 256;
  const Camera camera = scene.cameras.front();
  const PunctualLight sun = scene.lights.front();
  REQUIRE(sun.kind == PunctualKind::directional);
  constexpr std::uint32_t frames = 16, first_measured = 4;
  const auto turned = [&](std::uint32_t index) {
    PunctualLight light = sun;
    light.direction = glm::mat3(glm::rotate(glm::mat4(1.0f), glm::radians(2.0f * float(index)), glm::vec3(0.0f, 1.0f, 0.0f))) *
                      sun.direction;
    return light;
  };
  std::vector<Frame> converged;
  {
    Scene copy = scene;
    RoomRenderer renderer(copy, converged_settings);
    for (std::uint32_t index = 0; index < frames; ++index) {
      renderer.renderer.set_light(0, turned(index));
      converged.push_back(renderer.render(camera, 0));
    }
  }
  const auto walk = [&](int held_vpl_frames) {
    Scene copy = scene;
    RenderSettings s = settings;
    s.held_vpl_frames = held_vpl_frames;
    RoomRenderer renderer(copy, s);
    return measure(converged, first_measured, [&](std::uint32_t index) {
      renderer.renderer.set_light(0, turned(index));
      return renderer.render(camera, index);
    });
  };
  const Walk defaults = walk(settings.held_vpl_frames), drawn = walk(0);
  INFO("image mean over the converged frame's: CV " << variation(defaults.mean_ratio) << " at the defaults, "
       << variation(drawn.mean_ratio) << " with new VPLs every frame; flicker " << defaults.flicker << " and "
       << drawn.flicker);
  // Measured (frames 4-15): the image mean varies by 3.1% at the defaults and 7.8% with new VPLs
  // every frame; the pixels change by 0.08% and 12% beyond the converged frames' change. The
  // bounds ask for the half of either that a return to new numbers at each change would miss.
  CHECK(variation(defaults.mean_ratio) < 0.5 * variation(drawn.mean_ratio));
  CHECK(defaults.flicker < 0.5 * drawn.flicker);
  for (const double ratio : defaults.mean_ratio) CHECK(std::abs(ratio - 1.0) < 0.15);
}
