#pragma once
/// \file
/// The frame loop: VPLs for the frame, tiles from a demand-driven queue on oneTBB threads, the
/// pipeline per tile, statistics combined into the next frame's tone mapping, and scene changes
/// (instances, vertices, lights, camera) between frames.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <memory>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "igi/render/float_mode.hpp"
#include "igi/render/pipeline.hpp"
#include "igi/scene/scene_bounds.hpp"

namespace igi {

/// Timings and counts of one frame.
struct FrameStatistics {
  double milliseconds = 0.0;      ///< Whole frame, VPL generation included.
  double vpl_milliseconds = 0.0;  ///< Frame set-up: VPL generation, instance matrices, projection.
  RayCounts rays;                 ///< Rays traced.
  int tiles = 0;                  ///< Tiles rendered.
  int vpls = 0;                   ///< VPLs in all sets.
  LuminanceStatistics luminance;  ///< Combined tile statistics.
  StageTimes stages;              ///< CPU time per pipeline stage, summed over tiles (with Renderer::set_profiling).
  /// Million rays per second over the whole frame time.
  double mrays_per_second() const noexcept {
    return milliseconds > 0.0 ? double(rays.total()) / (milliseconds * 1e3) : 0.0;
  }
};

/// One rendered frame.
struct Frame {
  int width = 0;                    ///< Pixels per row.
  int height = 0;                   ///< Rows.
  std::uint32_t index = 0;          ///< Frame index it was rendered with.
  Image hdr;                        ///< Linear radiance.
  Rgb8Image rgb8;                   ///< Tone-mapped sRGB.
  FrameStatistics statistics;       ///< What it cost.

  /// A black `width x height` frame for index `index`, its images allocated.
  static Frame blank(int width, int height, std::uint32_t index) {
    Frame frame;
    frame.width = width;
    frame.height = height;
    frame.index = index;
    frame.hdr = Image(width, height);
    frame.rgb8 = Rgb8Image(width, height);
    return frame;
  }
  /// Tone maps the whole HDR image into `rgb8` with `mapping` (the first frame, which has no
  /// previous frame's statistics, is mapped with its own).
  void tone_map(const ToneMapping& mapping);
};

/// Writes one 8-bit pixel.
inline void store_pixel(Rgb8Image& image, int x, int y, const glm::u8vec3& rgb) noexcept {
  std::uint8_t* p = image.pixel(x, y);
  p[0] = rgb.r;
  p[1] = rgb.g;
  p[2] = rgb.b;
}

inline void Frame::tone_map(const ToneMapping& mapping) {
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) store_pixel(rgb8, x, y, quantize_srgb(mapping.apply(hdr(x, y))));
}

/// Copies a finished tile's pixels into its place in the frame.
inline void place_tile(const TileResult& tile, Frame& frame) {
  std::size_t from = 0;
  for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
    for (int x = tile.rect.x0; x < tile.rect.x1; ++x, ++from) {
      frame.hdr(x, y) = tile.hdr[from];
      store_pixel(frame.rgb8, x, y, tile.rgb8[from]);
    }
}

/// Renders frames of a scene with the IGI pipeline. The scene and policies are borrowed and must
/// outlive the renderer; the backend is built and owned here. Change the scene only through the
/// renderer's methods (so the backend follows) and only between frames.
template <class B, class Surface, class Brdf, class Sampler, class F>
class Renderer {
 public:
  /// The pipeline type this renderer runs.
  using PipelineType = Pipeline<B, Surface, Brdf, Sampler, F>;

  /// Builds the backend for `scene`; throws SettingsError for unusable settings and
  /// std::invalid_argument for a scene without triangles.
  Renderer(Scene& scene, const RenderSettings& settings, const Surface& surface, const Brdf& brdf,
           const Sampler& sampler, const F& filter)
      : scene_((require_geometry(scene), &scene)),
        settings_((validate(settings), settings)),
        backend_(std::make_unique<B>(scene)),
        bounds_(scene),
        sampler_(&sampler),
        pipeline_(*backend_, surface, brdf, filter),
        arena_(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic) {}

  /// Renders frame `index` as seen by `camera`. The HDR image depends only on scene, camera,
  /// settings and index; the RGB8 image is tone mapped with the previous frame's statistics (the
  /// first frame, having none, is mapped with its own).
  Frame render(const Camera& camera, std::uint32_t index) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    if (dirty_) {
      backend_->commit();
      dirty_ = false;
    }
    Frame frame = Frame::blank(settings_.width, settings_.height, index);

    FrameState state;
    state.prepare(*scene_, bounds_.bounds(), *backend_, *sampler_, settings_, camera, index,
                  tone_mapping_ ? *tone_mapping_ : ToneMapping{});
    state.context.profile = profiling_;
    const FrameContext& context = state.context;
    const auto vpls_done = clock::now();

    const std::vector<PixelRect> tiles = make_tiles(settings_.width, settings_.height, settings_.tile_size);
    std::mutex merge_mutex;
    FrameStatistics& stats = frame.statistics;
    arena_.execute([&] {
      // grainsize 1 + simple_partitioner: each idle thread takes the next single tile (demand driven).
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            const FlushDenormals flush;
            auto& work = workspaces_.local();
            for (std::size_t t = range.begin(); t != range.end(); ++t) {
              TileResult& result = work.result;
              pipeline_.render_tile(context, tiles[t], work.pipeline, result);
              place_tile(result, frame);  // tiles are disjoint: no lock needed
              std::lock_guard lock(merge_mutex);
              stats.rays.merge(result.rays);
              stats.stages.merge(result.stages);
              stats.luminance.merge(result.luminance);
            }
          },
          tbb::simple_partitioner());
    });
    const ToneMapping next = ToneMapping::from(stats.luminance);
    if (!tone_mapping_) frame.tone_map(next);
    tone_mapping_ = next;
    stats.tiles = int(tiles.size());
    stats.vpls = state.vpl_count();
    const auto end = clock::now();
    stats.milliseconds = std::chrono::duration<double, std::milli>(end - start).count();
    stats.vpl_milliseconds = std::chrono::duration<double, std::milli>(vpls_done - start).count();
    return frame;
  }

  /// Moves instance `instance` (takes effect at the next frame).
  void set_instance_transform(int instance, const glm::mat4& transform) {
    Instance& entry = scene_->instances.at(std::size_t(instance));
    backend_->set_instance_transform(instance, transform);  // first: it checks, and the scene stays as it was if it throws
    entry.transform = transform;
    bounds_.instance_moved(*scene_, instance);
    dirty_ = true;
  }
  /// Replaces the vertex positions of mesh `mesh` (same count; takes effect at the next frame).
  void set_mesh_positions(int mesh, std::span<const glm::vec3> positions) {
    Mesh& m = scene_->meshes.at(std::size_t(mesh));
    if (positions.size() != m.positions.size())
      throw SettingsError("mesh " + std::to_string(mesh) + " has " + std::to_string(m.positions.size()) +
                          " vertices, not " + std::to_string(positions.size()));
    backend_->set_mesh_positions(mesh, positions);  // first: it checks, and the scene stays as it was if it throws
    m.positions.assign(positions.begin(), positions.end());
    bounds_.mesh_changed(*scene_, mesh);
    dirty_ = true;
  }
  /// Replaces punctual light `light` (lights are read afresh every frame).
  void set_light(int light, const PunctualLight& value) { scene_->lights.at(std::size_t(light)) = value; }
  /// Times every pipeline stage of the following frames into FrameStatistics::stages (off by
  /// default: the clock reads around each packet's queries made Cornell and Sponza_lit frames 2-9% slower).
  void set_profiling(bool on) noexcept { profiling_ = on; }
  /// Forgets the tone-mapping history, as after a cut.
  void reset_tone_mapping() noexcept { tone_mapping_.reset(); }

  /// The scene being rendered.
  const Scene& scene() const noexcept { return *scene_; }
  /// The backend (for statistics).
  const B& backend() const noexcept { return *backend_; }
  /// The settings.
  const RenderSettings& settings() const noexcept { return settings_; }

 private:
  /// Throws unless `scene` has something to render.
  static void require_geometry(const Scene& scene) {
    if (scene.triangle_count() == 0)
      throw std::invalid_argument("scene '" + scene.name + "' has no geometry: no triangles to render");
  }
  /// What one thread keeps between tiles.
  struct ThreadWork {
    typename PipelineType::Workspace pipeline;  ///< Streams and G-buffer.
    TileResult result;                          ///< The tile being finished.
  };

  Scene* scene_;
  RenderSettings settings_;
  std::unique_ptr<B> backend_;
  SceneBounds bounds_;  ///< The scene's world bounds, updated with each change.
  const Sampler* sampler_;
  PipelineType pipeline_;
  tbb::task_arena arena_;
  tbb::enumerable_thread_specific<ThreadWork> workspaces_;
  std::optional<ToneMapping> tone_mapping_;
  bool dirty_ = false;
  bool profiling_ = false;
};

}  // namespace igi
