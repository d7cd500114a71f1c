// The filters alone, one thread, on one 48 x 48 tile: what each costs per pixel, and what each of
// AtrousFilter's stages costs, without the rest of a frame around it.
//
//   filter/<name>[/glossy]   Filter::apply over a tile with the border its filter reads
//                            (`glossy`: with glossy radiance too, which the à-trous filter then
//                            filters beside irradiance)
//   atrous_stage/<k>         AtrousFilter::run_stage(k) on the tile's own pixels, as one process's
//                            tiles run it (stage 0 the S x S window, k > 0 pass k with step 2^(k-1))
//
//   filters_bench --benchmark_format=json
//
//   atrous_frame/tiles:35/stage_major:0|1
//                            all stages over 35 such tiles (a 320 x 240 frame's): tile after tile
//                            (in cache), or each stage over every tile before the next (its
//                            buffers have left the cache when the next stage comes)
//
// The tile is a view of a room traced analytically (a floor, a back wall and a box in front of
// it), so it has the depth, normal and albedo edges the filters stop at; its irradiance is smooth
// light times the 3 x 3 interleaving pattern times noise from a hash of the pixel, as VPL sets
// leave it. Counters: items_per_second = pixels of the tiles' interiors per CPU second,
// ns_per_pixel its inverse.

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>

#include "igi/filters/atrous_filter.hpp"
#include "igi/filters/tile_filters.hpp"

namespace {

using namespace igi;

/// The tile's interior side: the pipeline's default tile size.
constexpr int tile_size = 48;
/// The paper's S.
constexpr int interleave = 3;

/// A uniform number in [0, 1) from the pixel (a 32-bit integer hash: the same tile every run).
float hash(int x, int y) {
  std::uint32_t h = std::uint32_t(x) * 0x8da6b343u ^ std::uint32_t(y) * 0xd8163841u;
  h ^= h >> 16;
  h *= 0x7feb352du;
  h ^= h >> 15;
  h *= 0x846ca68bu;
  h ^= h >> 16;
  return float(h >> 8) * (1.0f / 16777216.0f);
}

/// The G-buffer of a `tile_size` tile with `border` pixels around it, cut from a 320 x 240 view
/// where the box's left edge and foot and the wall's foot meet (image pixels 140..187 x
/// 170..217): wall, floor and box front, so a depth step, two creases and albedo edges.
TileGBuffer room_tile(int border, bool glossy) {
  TileGBuffer g;
  g.border = border;
  g.resize(tile_size + 2 * border, tile_size + 2 * border);
  const glm::vec3 eye(0.0f, 1.2f, 3.0f);
  const float focal = 240.0f / (2.0f * std::tan(0.35f));  // 40 degrees over 240 rows
  // The interleaving pattern's factors (mean 1): what 3 x 3 different VPL sets leave on a flat wall.
  static const float pattern[9] = {0.4f, 1.7f, 0.8f, 1.3f, 0.6f, 1.1f, 1.5f, 0.5f, 1.1f};
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const int image_x = 140 + x - border, image_y = 170 + y - border;
      const glm::vec3 direction =
          glm::normalize(glm::vec3(float(image_x) - 160.0f, 120.0f - float(image_y), -focal));
      // Closest of: floor y = 0, back wall z = -4 (up to y = 3) and the box's front z = -1.5 (x in
      // [0.1, 1.5], y in [0, 1.4]; its top lies above the eye, out of sight).
      float t = INFINITY;
      glm::vec3 normal(0.0f), albedo(0.0f);
      const auto consider = [&](float candidate, glm::vec3 n, glm::vec3 a, bool inside) {
        if (inside && candidate > 0.0f && candidate < t) {
          t = candidate;
          normal = n;
          albedo = a;
        }
      };
      const float floor_t = -eye.y / direction.y;
      const glm::vec3 on_floor = eye + floor_t * direction;
      const bool check = (int(std::floor(on_floor.x * 4.0f)) + int(std::floor(on_floor.z * 4.0f))) % 2 == 0;
      consider(floor_t, {0, 1, 0}, glm::vec3(check ? 0.55f : 0.45f), direction.y < 0.0f);
      const float wall_t = (-4.0f - eye.z) / direction.z;
      consider(wall_t, {0, 0, 1}, glm::vec3(0.7f), (eye + wall_t * direction).y < 3.0f);
      const float front_t = (-1.5f - eye.z) / direction.z;
      const glm::vec3 on_front = eye + front_t * direction;
      consider(front_t, {0, 0, 1}, {0.6f, 0.1f, 0.1f}, on_front.x > 0.1f && on_front.x < 1.5f && on_front.y < 1.4f);
      const std::size_t i = g.index(x, y);
      if (!std::isfinite(t)) continue;  // above the wall: a miss, zeros (none in this tile)
      const glm::vec3 point = eye + t * direction;
      g.hit[i] = 1.0f;
      g.depth[i] = t;
      g.normal[i] = normal;
      g.albedo[i] = albedo;
      // Smooth light falling off from a lamp, times the set's pattern, times +-30% noise.
      const float light = 3.0f / (1.0f + glm::dot(point - glm::vec3(1, 2.5f, -1), point - glm::vec3(1, 2.5f, -1)));
      const float set = pattern[(image_y % 3) * 3 + image_x % 3];
      const float noise = 0.7f + 0.6f * hash(image_x, image_y);
      g.irradiance[i] = glm::vec3(1.0f, 0.9f, 0.8f) * (light * set * noise);
      if (glossy) g.glossy[i] = glm::vec3(0.2f * light * set * hash(image_y, image_x));
    }
  return g;
}

/// Pixels per second and ns per pixel of `state`'s loop over the interiors of `tiles` tiles.
void count_pixels(benchmark::State& state, std::size_t tiles = 1) {
  const double pixels = double(state.iterations()) * double(tiles) * tile_size * tile_size;
  state.SetItemsProcessed(std::int64_t(pixels));
  state.counters["ns_per_pixel"] = benchmark::Counter(pixels * 1e-9, benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}

template <class F>
void filter_apply(benchmark::State& state, bool glossy) {
  const F filter;
  const TileGBuffer g = room_tile(filter.border(interleave), glossy);
  FilteredTile out;
  for (auto _ : state) {
    filter.apply(g, interleave, out);
    benchmark::DoNotOptimize(out.irradiance.x.data());
    benchmark::ClobberMemory();
  }
  count_pixels(state);
}

void atrous_stage(benchmark::State& state) {
  const AtrousFilter filter;
  const int stage = int(state.range(0));
  const TileGBuffer g = room_tile(filter.border(interleave), false);
  AtrousFilter::TileStages stages;
  // The stages before this one, so that its input holds what it would in a frame (a lone tile:
  // its border keeps the filter's own zeros, as at the image's edge).
  for (int before = 0; before < stage; ++before) filter.run_stage(before, g, interleave, stages);
  for (auto _ : state) {
    filter.run_stage(stage, g, interleave, stages);
    benchmark::ClobberMemory();
  }
  count_pixels(state);
}

void discontinuity(benchmark::State& state) { filter_apply<DiscontinuityFilter>(state, false); }
void atrous(benchmark::State& state) { filter_apply<AtrousFilter>(state, false); }
void atrous_glossy(benchmark::State& state) { filter_apply<AtrousFilter>(state, true); }

/// All of AtrousFilter's stages over `tiles` tiles of a frame, each stage over every tile before
/// the next (so a tile's buffers have left the cache when its next stage comes: 35 tiles are a
/// 320 x 240 frame's), against the same stages tile after tile (in cache).
void atrous_frame(benchmark::State& state) {
  const AtrousFilter filter;
  const auto tiles = std::size_t(state.range(0));
  const bool stage_major = state.range(1) != 0;
  std::vector<TileGBuffer> gbuffers(tiles, room_tile(filter.border(interleave), false));
  std::vector<AtrousFilter::TileStages> stages(tiles);
  for (auto _ : state) {
    if (stage_major) {
      for (int stage = 0; stage < filter.stage_count(); ++stage)
        for (std::size_t t = 0; t < tiles; ++t) filter.run_stage(stage, gbuffers[t], interleave, stages[t]);
    } else {
      for (std::size_t t = 0; t < tiles; ++t)
        for (int stage = 0; stage < filter.stage_count(); ++stage) filter.run_stage(stage, gbuffers[t], interleave, stages[t]);
    }
    benchmark::ClobberMemory();
  }
  count_pixels(state, tiles);
}

BENCHMARK(discontinuity)->Name("filter/discontinuity");
BENCHMARK(atrous)->Name("filter/atrous");
BENCHMARK(atrous_glossy)->Name("filter/atrous/glossy");
BENCHMARK(atrous_stage)->Name("atrous_stage")->DenseRange(0, AtrousSettings{}.passes);
BENCHMARK(atrous_frame)->Name("atrous_frame")->ArgNames({"tiles", "stage_major"})->Args({35, 0})->Args({35, 1});

}  // namespace

BENCHMARK_MAIN();
