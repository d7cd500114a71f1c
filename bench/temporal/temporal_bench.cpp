// Temporal reuse alone, one thread, on a 640 x 480 frame: what TemporalReuse::accumulate costs
// per pixel in each of its modes, without the rest of a frame around it.
//
//   temporal/still      the view of the frame before: each pixel averages its own history
//   temporal/moving     the camera moved (2 cm and 0.6 degrees a frame): each hit is reprojected
//                       into the previous frame and its history read bilinearly from four pixels
//   temporal/moving_held  moving, the frames cycling through 4 held draws of VPLs
//                       (RenderSettings::held_vpl_sets): each history also reprojects and
//                       averages each draw's own
//   temporal/changed    the camera moved and the scene changed: the histories are also clamped
//                       into each pixel's 3 x 3 neighbourhood range and tested for staleness
//   temporal/still_changed  the camera stayed and the scene changed: each pixel's own history,
//                       clamped and tested
//
//   temporal_bench --benchmark_format=json
//
// The frame is a view from inside a box room traced analytically (walls, floor and ceiling), so
// every pixel hits and the reprojection finds the same surfaces; its irradiance varies smoothly
// with noise from a hash of the pixel and the frame. Each iteration accumulates the next frame
// of a sequence after 8 frames of warm-up (the moving histories' length). Counters:
// items_per_second = pixels per CPU second, ns_per_pixel its inverse.

#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <oneapi/tbb/global_control.h>

#include "igi/render/temporal_reuse.hpp"
#include "igi/simd/sampling.hpp"

namespace {

using namespace igi;

constexpr int width = 640;
constexpr int height = 480;

/// A uniform number in [0, 1) from the pixel and frame (hashed: the same frames every run).
float noise(int x, int y, int frame) {
  return to_unit_float(hash(hash(std::uint32_t(x), std::uint32_t(y)), std::uint32_t(frame)));
}

/// Frame `frame` of the sequence: the camera `moving` or not.
Camera camera_at(int frame, bool moving) {
  const float step = moving ? float(frame) : 0.0f;
  Camera camera;
  // 2 cm and 0.01 rad a frame: a walk at 0.5 m/s turning 14 degrees a second at 24 frames a second.
  camera.camera_to_world = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 1.5f, 2.0f + 0.02f * step)),
                                       0.01f * step, glm::vec3(0.0f, 1.0f, 0.0f));
  return camera;
}

/// The layers `camera` sees in a room 8 x 3 x 10 m around it, through pixel positions `jitter`.
void room_layers(const Camera& camera, int frame, glm::vec2 jitter, std::vector<PixelLayers>& layers) {
  const PinholeProjection projection(camera, width, height);
  const glm::vec3 lower(-4.0f, 0.0f, -5.0f), upper(4.0f, 3.0f, 5.0f);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      const glm::vec3 origin = projection.origin();
      const glm::vec3 direction = projection.direction(float(x) + jitter.x, float(y) + jitter.y);
      // The eye is inside the box: the first hit is where the ray leaves it.
      float depth = std::numeric_limits<float>::infinity();
      glm::vec3 normal(0.0f);
      for (int axis = 0; axis < 3; ++axis) {
        if (direction[axis] == 0.0f) continue;
        const float wall = direction[axis] > 0.0f ? upper[axis] : lower[axis];
        const float t = (wall - origin[axis]) / direction[axis];
        if (t < depth) {
          depth = t;
          normal = glm::vec3(0.0f);
          normal[axis] = direction[axis] > 0.0f ? -1.0f : 1.0f;
        }
      }
      const glm::vec3 hit = origin + direction * depth;
      PixelLayers& pixel = layers[std::size_t(y) * width + std::size_t(x)];
      pixel.hit = true;
      pixel.depth = depth;
      pixel.normal = normal;
      pixel.irradiance = (0.5f + noise(x, y, frame)) * glm::vec3(0.6f + 0.3f * std::sin(2.0f * hit.x), 0.5f, 0.4f + 0.2f * std::cos(hit.z));
      pixel.albedo = glm::vec3(0.6f, 0.55f, 0.5f);
      pixel.glossy = glm::vec3(0.01f);
      pixel.rest = glm::vec3(0.0f);
    }
}

/// Accumulates frames of the sequence, each timed after `warm_up` untimed ones.
void temporal_benchmark(benchmark::State& state, bool moving, bool changed, int held_draws = 1) {
  const tbb::global_control one_thread(tbb::global_control::max_allowed_parallelism, 1);
  constexpr int warm_up = 8;  // TemporalReuse::moving_frames: the moving histories full
  TemporalReuse reuse(32);
  std::vector<PixelLayers> layers(std::size_t(width) * height);
  Image hdr(width, height);
  int frame = 0;
  const auto next = [&](bool timed) {
    const Camera camera = camera_at(frame, moving);
    const TemporalReuse::FrameRequest request = reuse.begin(camera, width, height, changed && frame > 0);
    room_layers(camera, frame, request.pixel_jitter, layers);
    const PinholeProjection projection(camera, width, height);
    if (timed) state.ResumeTiming();
    const HeldVplDraw held = held_draws > 1 ? HeldVplDraw{.set = frame % held_draws, .sets = held_draws} : HeldVplDraw{};
    reuse.accumulate(projection, 1, layers, hdr, {}, held);
    if (timed) state.PauseTiming();
    ++frame;
  };
  for (int i = 0; i < warm_up; ++i) next(false);
  for (auto _ : state) {
    state.PauseTiming();
    next(true);
    state.ResumeTiming();
  }
  benchmark::DoNotOptimize(hdr.pixels.data());
  const double pixels = double(state.iterations()) * width * height;
  state.SetItemsProcessed(std::int64_t(pixels));
  state.counters["ns_per_pixel"] = benchmark::Counter(pixels * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

}  // namespace

BENCHMARK_CAPTURE(temporal_benchmark, still, false, false)->Name("temporal/still")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(temporal_benchmark, moving, true, false)->Name("temporal/moving")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(temporal_benchmark, moving_held, true, false, 4)->Name("temporal/moving_held")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(temporal_benchmark, changed, true, true)->Name("temporal/changed")->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(temporal_benchmark, still_changed, false, true)->Name("temporal/still_changed")->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
