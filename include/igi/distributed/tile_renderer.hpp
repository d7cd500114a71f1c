#pragma once
/// \file
/// One rank's renderer in the tile farm: owns the backend and the pipeline, applies broadcast scene
/// changes, builds the frame's VPLs itself from the frame index (VPL sets never cross the network)
/// and renders, filters and tone maps the tiles it is handed. Frame set-up follows Renderer::render
/// exactly, so a tile is the same here as in a single-process frame.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "igi/distributed/messages.hpp"
#include "igi/render/float_mode.hpp"
#include "igi/render/pipeline.hpp"
#include "igi/scene/scene_bounds.hpp"

namespace igi {

/// Renders single tiles of frames of a scene; the scene and policies are borrowed.
template <class B, class Surface, class Brdf, class Sampler, class F>
class TileRenderer {
 public:
  /// The pipeline type that renders the tiles.
  using PipelineType = Pipeline<B, Surface, Brdf, Sampler, F>;

  /// Builds the backend for `scene`; throws SettingsError for unusable settings.
  TileRenderer(Scene& scene, const RenderSettings& settings, const Surface& surface, const Brdf& brdf,
               const Sampler& sampler, const F& filter)
      : scene_(&scene),
        settings_((validate(settings), settings)),
        backend_(std::make_unique<B>(scene)),
        bounds_(scene),
        sampler_(&sampler),
        pipeline_(*backend_, surface, brdf, filter),
        arena_(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic),
        tiles_(make_tiles(settings.width, settings.height, settings.tile_size)) {}

  /// Applies broadcast scene changes (they take effect at the next begin_frame); throws SettingsError on bad indices.
  void apply(const SceneChanges& changes) {
    changes.check(*scene_);
    camera_ = changes.camera;
    for (const auto& [index, light] : changes.lights) scene_->lights[std::size_t(index)] = light;
    for (const auto& [index, transform] : changes.instances) {
      if (scene_->instances[std::size_t(index)].transform == transform) continue;
      backend_->set_instance_transform(index, transform);  // first: it checks, and the scene stays as it was if it throws
      scene_->instances[std::size_t(index)].transform = transform;
      bounds_.instance_moved(*scene_, index);
      dirty_ = true;
    }
  }

  /// Prepares frame `index` with the camera of the last apply(): commits scene changes, generates
  /// the frame's VPLs and sets up the shared frame context with `tone_mapping`.
  void begin_frame(std::uint32_t index, const ToneMapping& tone_mapping) {
    if (dirty_) {
      backend_->commit();
      dirty_ = false;
    }
    // The same frame set-up as Renderer::render, so tiles match single-process frames bit for bit.
    frame_.prepare(*scene_, bounds_.bounds(), *backend_, *sampler_, settings_, camera_, index, tone_mapping);
  }

  /// Renders tile `tile` of the current frame into `out` (any thread; each has its own workspace).
  void render(int tile, TileResult& out) {
    if (tile < 0 || std::size_t(tile) >= tiles_.size())
      throw DistributedError("tile " + std::to_string(tile) + " is outside 0.." + std::to_string(tiles_.size() - 1));
    if (!frame_.projection) throw DistributedError("TileRenderer::render called before begin_frame");
    const FlushDenormals flush;  // as Renderer's tile tasks do
    pipeline_.render_tile(frame_.context, tiles_[std::size_t(tile)], workspaces_.local(), out);
  }

  /// Renders the given tiles in parallel on this renderer's threads (one tile per task, demand
  /// driven); `after(i, result, milliseconds)` runs on the rendering thread after tile `tiles[i]`.
  template <class After>
  void render_all(std::span<const int> tiles, std::vector<TileResult>& results, After&& after) {
    results.resize(tiles.size());
    arena_.execute([&] {
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
              const auto start = std::chrono::steady_clock::now();
              render(tiles[i], results[i]);
              const double ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
              after(i, results[i], ms);
            }
          },
          tbb::simple_partitioner());
    });
  }

  /// The frame's tiles, in make_tiles order.
  const std::vector<PixelRect>& tiles() const noexcept { return tiles_; }
  /// The settings.
  const RenderSettings& settings() const noexcept { return settings_; }
  /// The scene as of the last apply().
  const Scene& scene() const noexcept { return *scene_; }
  /// VPLs in all sets of the current frame.
  int vpl_count() const noexcept { return frame_.vpl_count(); }

 private:
  Scene* scene_;
  RenderSettings settings_;
  std::unique_ptr<B> backend_;
  SceneBounds bounds_;  ///< The scene's world bounds, updated with each change.
  const Sampler* sampler_;
  PipelineType pipeline_;
  tbb::task_arena arena_;
  std::vector<PixelRect> tiles_;
  tbb::enumerable_thread_specific<typename PipelineType::Workspace> workspaces_;
  Camera camera_;
  FrameState frame_;
  bool dirty_ = false;
};

}  // namespace igi
