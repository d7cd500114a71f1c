#pragma once
/// \file
/// The tile engine: everything between a scene and finished tiles. It owns the backend and the
/// pipeline, applies scene changes (so the backend follows), commits them, prepares each frame's
/// FrameState (VPLs, instance matrices, projection) and renders lists of tiles on oneTBB threads,
/// one tile per task, demand driven, each thread with its own workspace. `Renderer` (a whole
/// frame in one process) and the MPI `TileRenderer` (the tiles rank 0 hands out) are thin front
/// ends on it, so a tile is the same whichever renders it.

#include <atomic>
#include <chrono>
#include <cstdint>
#include <memory>
#include <numeric>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <oneapi/tbb/enumerable_thread_specific.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/parallel_for_each.h>
#include <oneapi/tbb/task_arena.h>

#include "igi/render/frame_state.hpp"
#include "igi/render/pipeline.hpp"
#include "igi/scene/scene_bounds.hpp"
#include "igi/scene/scene_changes.hpp"
#include "igi/simd/float_mode.hpp"

namespace igi {

/// What TileEngine::apply changed.
struct AppliedChanges {
  bool scene = false;   ///< Anything: a light, an instance or a mesh.
  bool lights = false;  ///< A light: a punctual one, or an instance or mesh of an emissive material.
};

/// Renders tiles of frames of a scene with the IGI pipeline. The scene and policies are borrowed
/// and must outlive the engine; the backend is built and owned here. Change the scene only through
/// the engine (so the backend follows) and only between frames.
template <class B, class Surface, class Brdf, class Sampler, class F>
  requires VplSampler<Sampler, B, Surface, Brdf>
class TileEngine {
 public:
  /// The pipeline type that renders the tiles.
  using PipelineType = Pipeline<B, Surface, Brdf, F>;

  /// Builds the backend for `scene`; throws SettingsError for unusable settings and
  /// std::invalid_argument for a scene without triangles.
  TileEngine(Scene& scene, const RenderSettings& settings, const Surface& surface, const Brdf& brdf,
             const Sampler& sampler, const F& filter)
      : scene_((require_geometry(scene), &scene)),
        settings_((validate(settings), settings)),
        backend_(std::make_unique<B>(scene)),
        bounds_(scene),
        surface_(&surface),
        brdf_(&brdf),
        sampler_(&sampler),
        pipeline_(*backend_, surface, brdf, filter),
        arena_(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic),
        tiles_(make_tiles(settings.width, settings.height, settings.tile_size)),
        all_tiles_(tiles_.size()) {
    std::iota(all_tiles_.begin(), all_tiles_.end(), 0);
    // Shadow rays pass alpha cut-outs inside the backend's traversal where it can (else the
    // pipeline traces blocked shadow rays again: igi::occluded_by_opaque).
    if constexpr (CutoutTestingBackend<B>) test_cutouts_with(*backend_, *scene_, surface);
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
  /// Replaces the vertices of mesh `vertices.mesh` (positions, and normals and tangents where
  /// given; same count; takes effect at the next frame, the mesh's BVH refitted, not rebuilt).
  void set_mesh_vertices(const MeshVertices& vertices) {
    set_mesh_positions(vertices.mesh, vertices.positions);
    Mesh& mesh = scene_->meshes[std::size_t(vertices.mesh)];
    if (!vertices.normals.empty()) mesh.normals.assign(vertices.normals.begin(), vertices.normals.end());
    if (!vertices.tangents.empty()) mesh.tangents.assign(vertices.tangents.begin(), vertices.tangents.end());
  }
  /// Replaces punctual light `light` (lights are read afresh every frame).
  void set_light(int light, const PunctualLight& value) { scene_->lights.at(std::size_t(light)) = value; }
  /// Applies `changes` (throws SceneError on an index the scene lacks, before changing anything);
  /// returns what changed. Only what differs is set, so an unchanged scene is not re-committed
  /// and the first frame of an animation renders exactly as a still frame.
  AppliedChanges apply(const SceneChanges& changes) {
    changes.check(*scene_);
    AppliedChanges changed;
    for (const auto& [index, light] : changes.lights)
      if (!(scene_->lights[std::size_t(index)] == light)) {
        set_light(index, light);
        changed.scene = changed.lights = true;
      }
    for (const auto& [index, transform] : changes.instances)
      if (scene_->instances[std::size_t(index)].transform != transform) {
        set_instance_transform(index, transform);
        changed.scene = true;
        changed.lights |= scene_->emits_light(scene_->instances[std::size_t(index)].mesh);
      }
    for (const MeshVertices& vertices : changes.meshes)
      if (scene_->meshes[std::size_t(vertices.mesh)].positions != vertices.positions) {
        set_mesh_vertices(vertices);
        changed.scene = true;
        changed.lights |= scene_->emits_light(vertices.mesh);
      }
    return changed;
  }

  /// Prepares frame `index` as seen by `camera`: commits the scene changes, generates the frame's
  /// VPLs and sets up the FrameState every tile reads, tone mapped with `tone_mapping`, with what
  /// `options` asks (stage timing, the tiles' PixelLayers, a scaled clamp, moved primary rays).
  void begin_frame(const Camera& camera, std::uint32_t index, const ToneMapping& tone_mapping,
                   const FrameOptions& options = {}) {
    commit_milliseconds_ = 0.0;
    if (dirty_) {
      const auto start = std::chrono::steady_clock::now();
      backend_->commit();
      commit_milliseconds_ = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
      dirty_ = false;
    }
    // In the engine's arena: a sampler's parallel loops (ImportanceVplSampler) use its threads.
    arena_.execute([&] {
      frame_.prepare(*scene_, bounds_.bounds(), *backend_, *surface_, *brdf_, *sampler_, settings_, camera, index,
                     tone_mapping, options.clamp_scale, options.keep_vpls, options.vpl_index);
    });
    frame_.profile = options.profile;
    frame_.keep_layers = options.keep_layers;
    frame_.pixel_jitter = options.pixel_jitter;
    frame_.texture_cone_scale = options.texture_cone_scale;
    frame_.use_shadow_history(options.shadow_history);
  }

  /// Runs `work` inside this engine's threads (its task arena), so oneTBB loops in it use the
  /// engine's thread count.
  template <class Work>
  void execute(Work&& work) {
    arena_.execute(std::forward<Work>(work));
  }

  /// Renders tile `tile` (an index into tiles()) of the current frame into `out` on the calling
  /// thread. Throws std::out_of_range for a tile outside the frame, std::logic_error before begin_frame.
  void render_tile(int tile, TileResult& out) {
    check_tile(tile);
    const FlushDenormals flush;  // as every tile task, so a tile is the same on any thread
    pipeline_.render_tile(frame_, tiles_[std::size_t(tile)], workspaces_.local().pipeline, out);
  }

  /// Renders the tiles `tiles` (indices into tiles()) of the current frame on this engine's
  /// threads, one tile per task, demand driven. `done(i, result, milliseconds)` runs on the
  /// rendering thread right after tile `tiles[i]`; `result` is that thread's buffer, reused for its
  /// next tile, so keep what you need (copy, or swap it with a TileResult of yours).
  template <class Done>
  void render_tiles(std::span<const int> tiles, Done&& done) {
    for (const int tile : tiles) check_tile(tile);
    arena_.execute([&] {
      // grainsize 1 + simple_partitioner: each idle thread takes the next single tile (demand driven).
      tbb::parallel_for(
          tbb::blocked_range<std::size_t>(0, tiles.size(), 1),
          [&](const tbb::blocked_range<std::size_t>& range) {
            const FlushDenormals flush;
            ThreadWork& work = workspaces_.local();
            for (std::size_t i = range.begin(); i != range.end(); ++i) {
              const auto start = std::chrono::steady_clock::now();
              pipeline_.render_tile(frame_, tiles_[std::size_t(tiles[i])], work.pipeline, work.result);
              const double milliseconds =
                  std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
              done(i, work.result, milliseconds);
            }
          },
          tbb::simple_partitioner());
    });
  }

  /// Renders every tile of the current frame on this engine's threads with tiles that share
  /// their borders: each tile's pixels are shaded once into its own G-buffer, and as soon as a
  /// tile and every tile its border reaches into are shaded, the tile's border is copied from
  /// theirs and the tile filtered and composed (so its G-buffer and its neighbours' are still in
  /// cache: waiting for the whole frame to be shaded first cost Cornell 640 x 480 3 ms of CPU a
  /// frame more). A StagedFilter runs the same way stage by stage, each stage of a tile once its
  /// neighbours' previous stage is done, over the tile's own pixels with its border copied from
  /// theirs. The pixels are render_tiles' (the filter reads the same G-buffer values, as a pixel's
  /// shading does not depend on the tile that holds it, and a stage's output at a pixel does not
  /// depend on the tile that computes it) without shading each tile's border again (8.5% more
  /// pixels for the 3 x 3 window on 48-pixel tiles, 78% for AtrousFilter's 8-pixel border) nor
  /// filtering it again (AtrousFilter's stages cover 1.36 to 1.67 times the tile's pixels with
  /// their borders). `done(tile, result, milliseconds)` as for render_tiles, after the tile is
  /// composed, with its rays and the time of all its steps. Throws std::logic_error before begin_frame.
  template <class Done>
  void render_frame(Done&& done) {
    if (!frame_.prepared()) throw std::logic_error("a frame was rendered before begin_frame");
    // A tile's levels: 0 shades it, 1 .. stage_count filter it (the last also composes it).
    const int stage_count = filter_stage_count();
    shaded_.resize(tiles_.size());
    // Level l > 0 of a tile waits for level l - 1 of the tiles its border reaches into and of itself.
    for (std::size_t i = 0; i < tiles_.size(); ++i) {
      int neighbours = 0;
      for_each_neighbour(i, [&](std::size_t) { ++neighbours; });
      if (shaded_[i].waiting.size() != std::size_t(stage_count))
        shaded_[i].waiting = std::vector<std::atomic<int>>(std::size_t(stage_count));
      for (auto& count : shaded_[i].waiting) count.store(neighbours, std::memory_order_relaxed);
    }
    using clock = std::chrono::steady_clock;
    const auto since = [](clock::time_point start) {
      return std::chrono::duration<double, std::milli>(clock::now() - start).count();
    };
    struct Step {
      std::size_t tile;  ///< Which tile.
      int level;         ///< What to do with it (see above).
    };
    std::vector<Step> shading(tiles_.size());
    for (std::size_t i = 0; i < tiles_.size(); ++i) shading[i] = {i, 0};
    arena_.execute([&] {
      tbb::parallel_for_each(shading.begin(), shading.end(), [&](const Step& step, tbb::feeder<Step>& feeder) {
        const FlushDenormals flush;
        ThreadWork& work = workspaces_.local();
        ShadedTile& shaded = shaded_[step.tile];
        const auto start = clock::now();
        // Level `step.level` of the tile is done: the neighbours whose last wait that was go next.
        // The tile itself is fed last, so that this thread (whose fed steps run last in, first
        // out) goes on with it while its buffers are in cache.
        const auto next = [&] {
          const auto release = [&](std::size_t j) {
            if (shaded_[j].waiting[std::size_t(step.level)].fetch_sub(1, std::memory_order_acq_rel) == 1)
              feeder.add(Step{j, step.level + 1});
          };
          for_each_neighbour(step.tile, [&](std::size_t j) {
            if (j != step.tile) release(j);
          });
          release(step.tile);
        };
        if (step.level == 0) {
          pipeline_.shade_tile(frame_, tiles_[step.tile], shaded.gbuffer, work.pipeline, shaded.rays, shaded.stages);
          shaded.milliseconds = since(start);
          next();
          return;
        }
        const int stage = step.level - 1;
        if (stage == 0) {
          const StageTimer timer(frame_.profile ? &shaded.stages.gbuffer : nullptr);
          gather_border(step.tile);
        }
        if constexpr (StagedFilter<F>) {
          if (stage > 0) {
            const StageTimer timer(frame_.profile ? &shaded.stages.filter : nullptr);
            gather_stage(step.tile, stage);
          }
          pipeline_.filter_stage(frame_, stage, shaded.gbuffer, shaded.filter_stages, shaded.stages);
          if (stage + 1 < stage_count) {
            shaded.milliseconds += since(start);
            next();
            return;
          }
          pipeline_.finish_staged_tile(frame_, tiles_[step.tile], shaded.gbuffer, shaded.filter_stages, work.pipeline,
                                       work.result);
        } else {
          pipeline_.finish_tile(frame_, tiles_[step.tile], shaded.gbuffer, work.pipeline, work.result);
        }
        work.result.rays = shaded.rays;
        work.result.stages.merge(shaded.stages);
        done(step.tile, work.result, shaded.milliseconds + since(start));
      });
    });
  }

  /// The frame's tiles, in make_tiles order.
  const std::vector<PixelRect>& tiles() const noexcept { return tiles_; }
  /// Every tile index, 0 .. tiles().size() - 1, for render_tiles.
  std::span<const int> all_tiles() const noexcept { return all_tiles_; }
  /// The current frame's shared state (after begin_frame).
  const FrameState& frame() const noexcept { return frame_; }
  /// The VPL sampler.
  const Sampler& sampler() const noexcept { return *sampler_; }
  /// The scene being rendered.
  const Scene& scene() const noexcept { return *scene_; }
  /// The backend (for statistics).
  const B& backend() const noexcept { return *backend_; }
  /// The settings.
  const RenderSettings& settings() const noexcept { return settings_; }
  /// How long the last begin_frame took to commit scene changes to the backend (instance moves,
  /// BVH refits and rebuilds); 0 when nothing changed.
  double commit_milliseconds() const noexcept { return commit_milliseconds_; }

 private:
  /// Throws unless `scene` has something to render.
  static void require_geometry(const Scene& scene) {
    if (scene.triangle_count() == 0)
      throw std::invalid_argument("scene '" + scene.name + "' has no geometry: no triangles to render");
  }
  /// Throws unless `tile` can be rendered now.
  void check_tile(int tile) const {
    if (tile < 0 || std::size_t(tile) >= tiles_.size())
      throw std::out_of_range("tile " + std::to_string(tile) + " is outside 0.." + std::to_string(tiles_.size() - 1));
    if (!frame_.prepared()) throw std::logic_error("a tile was rendered before begin_frame");
  }
  /// The part of tile `i` grown by the filter's border that lies inside the image.
  PixelRect reach(std::size_t i) const {
    const PixelRect& tile = tiles_[i];
    const int border = pipeline_.shared_border(frame_);
    return {std::max(tile.x0 - border, 0), std::max(tile.y0 - border, 0), std::min(tile.x1 + border, settings_.width),
            std::min(tile.y1 + border, settings_.height)};
  }
  /// Calls `visit(j)` for tile `i` and each tile j its border reaches into (tiles lie in
  /// make_tiles' grid; the relation is symmetric, as every tile has the same border).
  template <class Visit>
  void for_each_neighbour(std::size_t i, Visit&& visit) const {
    const PixelRect r = reach(i);
    const int size = settings_.tile_size;
    const int columns = (settings_.width + size - 1) / size;
    for (int row = r.y0 / size; row <= (r.y1 - 1) / size; ++row)
      for (int column = r.x0 / size; column <= (r.x1 - 1) / size; ++column)
        visit(std::size_t(row) * std::size_t(columns) + std::size_t(column));
  }
  /// The filter's stages (1 for a filter that runs whole).
  int filter_stage_count() const {
    if constexpr (StagedFilter<F>)
      return pipeline_.filter().stage_count();
    else
      return 1;
  }
  /// Calls `visit(j, block)` for each tile j other than `i` that holds pixels within `reach` of
  /// tile i: `block` copies them from j's tile buffer into i's (both laid out with the filter's border).
  template <class Visit>
  void for_each_border_block(std::size_t i, int reach, Visit&& visit) const {
    const PixelRect& tile = tiles_[i];
    const int border = pipeline_.shared_border(frame_);
    for_each_neighbour(i, [&](std::size_t j) {
      if (j == i) return;
      const PixelRect& other = tiles_[j];
      const int x0 = std::max(tile.x0 - reach, other.x0), y0 = std::max(tile.y0 - reach, other.y0);
      const int x1 = std::min(tile.x1 + reach, other.x1), y1 = std::min(tile.y1 + reach, other.y1);
      if (x1 <= x0 || y1 <= y0) return;
      visit(j, BlockCopy{.source_x = x0 - other.x0 + border,
                         .source_y = y0 - other.y0 + border,
                         .x = x0 - (tile.x0 - border),
                         .y = y0 - (tile.y0 - border),
                         .columns = x1 - x0,
                         .rows = y1 - y0});
    });
  }
  /// Copies into the border of tile `i`'s G-buffer the pixels its neighbours shaded (the border
  /// outside the image stays as sized: zero, "no hit"), all but their unfiltered `radiance`,
  /// which only the tile's own pixels compose.
  void gather_border(std::size_t i) {
    for_each_border_block(i, pipeline_.shared_border(frame_), [&](std::size_t j, const BlockCopy& block) {
      shaded_[i].gbuffer.copy_from(shaded_[j].gbuffer, block, false);
    });
  }
  /// Copies into the border of tile `i`'s filter stages what stage `stage` reads of its
  /// neighbours' stage `stage - 1` output (outside the image the filter keeps its own zeros).
  void gather_stage(std::size_t i, int stage)
    requires StagedFilter<F>
  {
    const F& filter = pipeline_.filter();
    for_each_border_block(i, filter.stage_reach(stage), [&](std::size_t j, const BlockCopy& block) {
      filter.copy_stage(stage - 1, shaded_[j].filter_stages, block, shaded_[i].filter_stages);
    });
  }

  /// What one thread keeps between tiles.
  struct ThreadWork {
    typename PipelineType::Workspace pipeline;  ///< Streams and G-buffer.
    TileResult result;                          ///< The tile being finished.
  };
  /// What render_frame keeps of a tile between its shading and its composition.
  struct ShadedTile {
    TileGBuffer gbuffer;          ///< The tile with the filter's border; shading writes its interior.
    RayCounts rays;               ///< Rays its shading traced.
    StageTimes stages;            ///< Its steps' stage times.
    typename FilterStages<F>::type filter_stages;  ///< A StagedFilter's stage outputs (its border filled from the neighbours').
    double milliseconds = 0.0;    ///< Time of its steps so far.
    /// Per level l > 0: tiles (itself among them) within its border not yet done with level l - 1.
    std::vector<std::atomic<int>> waiting;
  };

  Scene* scene_;
  RenderSettings settings_;
  std::unique_ptr<B> backend_;
  SceneBounds bounds_;  ///< The scene's world bounds, updated with each change.
  const Surface* surface_;
  const Brdf* brdf_;
  const Sampler* sampler_;
  PipelineType pipeline_;
  tbb::task_arena arena_;
  std::vector<PixelRect> tiles_;
  std::vector<int> all_tiles_;
  tbb::enumerable_thread_specific<ThreadWork> workspaces_;
  std::vector<ShadedTile> shaded_;  ///< Per tile, between its shading and composition (its G-buffer between frames too).
  FrameState frame_;
  bool dirty_ = false;
  double commit_milliseconds_ = 0.0;  ///< The last begin_frame's backend commit.
};

}  // namespace igi
