#pragma once
/// \file
/// The frame loop of one process: the TileEngine renders every tile of a frame (its two passes
/// whose tiles share their borders, TileEngine::render_frame), the tiles are
/// placed into the frame, and their statistics combined into the next frame's tone mapping.

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <mutex>
#include <optional>
#include <span>
#include <vector>

#include <oneapi/tbb/parallel_for.h>

#include "igi/render/pipeline.hpp"
#include "igi/render/temporal_reuse.hpp"
#include "igi/render/tile_engine.hpp"

namespace igi {

/// Timings and counts of one frame.
struct FrameStatistics {
  double milliseconds = 0.0;      ///< Whole frame, VPL generation included.
  double vpl_milliseconds = 0.0;  ///< Frame set-up: VPL generation, instance matrices, projection.
  double temporal_milliseconds = 0.0;  ///< Temporal reuse: reprojection, averaging, statistics and tone mapping anew (0 when off).
  RayCounts rays;                 ///< Rays traced.
  int tiles = 0;                  ///< Tiles rendered.
  int vpls = 0;                   ///< VPLs in all sets.
  bool vpls_kept = false;         ///< Whether the frame kept VPLs drawn before it (RenderSettings::held_vpl_frames).
  std::uint32_t vpl_index = 0;    ///< The frame index whose random numbers drew the frame's VPLs (its own, or an earlier frame's: RenderSettings::held_vpl_frames).
  LuminanceStatistics luminance;  ///< Combined tile statistics.
  StageTimes stages;              ///< CPU time per pipeline stage, summed over tiles (with Renderer::set_profiling).
  double commit_milliseconds = 0.0;  ///< Part of vpl_milliseconds: scene changes committed to the backend (BVH updates).
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

/// Copies a finished tile's pixels into its place in the frame, and its PixelLayers, if it has
/// them, into `layers` (the frame's, row-major).
inline void place_tile(const TileResult& tile, Frame& frame, std::span<PixelLayers> layers = {}) {
  std::size_t from = 0;
  for (int y = tile.rect.y0; y < tile.rect.y1; ++y)
    for (int x = tile.rect.x0; x < tile.rect.x1; ++x, ++from) {
      frame.hdr(x, y) = tile.hdr[from];
      store_pixel(frame.rgb8, x, y, tile.rgb8[from]);
      if (!tile.layers.empty()) layers[std::size_t(y) * std::size_t(frame.width) + std::size_t(x)] = tile.layers[from];
    }
}

/// Renders whole frames of a scene with the IGI pipeline in this process: a front end on the
/// TileEngine that renders every tile and assembles the frame. The scene and policies are borrowed
/// and must outlive the renderer; the backend is built and owned by the engine. Change the scene
/// only through the renderer's methods (so the backend follows) and only between frames.
template <class B, class Surface, class Brdf, class Sampler, class F>
class Renderer {
 public:
  /// The engine that renders the tiles.
  using Engine = TileEngine<B, Surface, Brdf, Sampler, F>;

  /// Builds the backend for `scene`; throws SettingsError for unusable settings and
  /// std::invalid_argument for a scene without triangles.
  Renderer(Scene& scene, const RenderSettings& settings, const Surface& surface, const Brdf& brdf,
           const Sampler& sampler, const F& filter)
      : engine_(scene, settings, surface, brdf, sampler, filter) {}

  // Defined after the class, so not inline: a program that declares the renderer's instantiation
  // extern (explicit instantiation declaration) does not compile the frame's pipeline again;
  // defined in the class, GCC compiled it in every such program to be able to inline it.
  /// Renders frame `index` as seen by `camera`. The HDR image depends only on scene, camera,
  /// settings and index (with RenderSettings::temporal_frames, on those of the frames before it
  /// too); the RGB8 image is tone mapped with the previous frame's statistics (the first frame,
  /// having none, is mapped with its own).
  Frame render(const Camera& camera, std::uint32_t index);

  /// Moves instance `instance` (takes effect at the next frame).
  void set_instance_transform(int instance, const glm::mat4& transform) {
    engine_.set_instance_transform(instance, transform);
    note_change({.scene = true, .lights = scene().emits_light(scene().instances[std::size_t(instance)].mesh)});
  }
  /// Replaces the vertex positions of mesh `mesh` (same count; takes effect at the next frame).
  void set_mesh_positions(int mesh, std::span<const glm::vec3> positions) {
    engine_.set_mesh_positions(mesh, positions);
    note_change({.scene = true, .lights = scene().emits_light(mesh)});
  }
  /// Replaces the vertices of a mesh (see TileEngine::set_mesh_vertices).
  void set_mesh_vertices(const MeshVertices& vertices) {
    engine_.set_mesh_vertices(vertices);
    note_change({.scene = true, .lights = scene().emits_light(vertices.mesh)});
  }
  /// Replaces punctual light `light` (lights are read afresh every frame).
  void set_light(int light, const PunctualLight& value) {
    engine_.set_light(light, value);
    note_change({.scene = true, .lights = true});
  }
  /// Applies an animation's `changes` and returns their camera (see TileEngine::apply).
  Camera apply(const SceneChanges& changes) {
    note_change(engine_.apply(changes));
    return changes.camera;
  }
  /// Times every pipeline stage of the following frames into FrameStatistics::stages (off by
  /// default: the clock reads around each packet's queries made Cornell and Sponza_lit frames 2-9% slower).
  void set_profiling(bool on) noexcept { profiling_ = on; }
  /// Keeps each following frame's PixelLayers (the G-buffer: albedo, normal, depth and the
  /// shading terms) for layers(); off by default, since it keeps 68 bytes per pixel (sizeof(PixelLayers)).
  void set_keep_layers(bool on) noexcept { keep_layers_ = on; }
  /// The last frame's PixelLayers, row by row from the top (with set_keep_layers or
  /// RenderSettings::temporal_frames; else empty).
  std::span<const PixelLayers> layers() const noexcept { return layers_; }
  /// Forgets the tone-mapping history, as after a cut.
  void reset_tone_mapping() noexcept { tone_mapping_.reset(); }
  /// The temporal histories (with RenderSettings::temporal_frames; else null).
  const TemporalReuse* temporal() const noexcept { return temporal_ ? &*temporal_ : nullptr; }

  /// The scene being rendered.
  const Scene& scene() const noexcept { return engine_.scene(); }
  /// The backend (for statistics).
  const B& backend() const noexcept { return engine_.backend(); }
  /// The settings.
  const RenderSettings& settings() const noexcept { return engine_.settings(); }

 private:
  /// Replaces the frame's radiance by its average with the pixels' histories (TemporalReuse), and
  /// its luminance statistics and RGB8 image by the average's.
  void reuse_history(Frame& frame) {
    LuminanceStatistics& luminance = frame.statistics.luminance;
    std::vector<LuminanceAccumulator> rows(std::size_t(frame.height));
    engine_.execute([&] {
      temporal_->accumulate(*engine_.frame().projection, engine_.settings().antialiasing, layers_, frame.hdr,
                            engine_.frame().keeps_shadows ? engine_.frame().delta_lights : std::vector<DeltaLightKey>{},
                            {.set = settings().held_vpl_sets > 1 ? engine_.frame().held_set : -1,
                             .sets = settings().held_vpl_sets});
      tbb::parallel_for(0, frame.height, [&](int y) {
        for (int x = 0; x < frame.width; ++x) {
          rows[std::size_t(y)].add(frame.hdr(x, y));
          if (tone_mapping_) store_pixel(frame.rgb8, x, y, quantize_srgb(tone_mapping_->apply(frame.hdr(x, y))));
        }
      });
    });
    luminance = {};
    for (const LuminanceAccumulator& row : rows) luminance.merge(row.statistics());  // in row order: the same sums on any thread count
  }

  /// Remembers `changed` for the next frame.
  void note_change(const AppliedChanges& changed) noexcept {
    scene_changed_ |= changed.scene;
    lights_changed_ |= changed.lights;
  }

  Engine engine_;
  std::optional<ToneMapping> tone_mapping_;
  bool profiling_ = false;
  bool keep_layers_ = false;         ///< Whether frames keep their PixelLayers without temporal reuse (set_keep_layers).
  std::optional<TemporalReuse> temporal_ =
      engine_.settings().temporal_frames > 0 ? std::optional<TemporalReuse>(engine_.settings().temporal_frames)
                                             : std::nullopt;
  bool scene_changed_ = false;       ///< Whether the scene changed since the last frame (temporal reuse clamps its histories).
  bool lights_changed_ = false;      ///< Whether a light changed since the last frame (AppliedChanges::lights).
  int held_vpl_frames_ = 0;          ///< Frames in a row that kept their VPLs or their random numbers (RenderSettings::held_vpl_frames).
  std::optional<std::uint32_t> vpl_index_;  ///< The frame index whose random numbers drew the current VPLs (none before the first frame).
  /// Frames rendered since the scene last changed, up to TemporalReuse::moving_frames (the first
  /// frame counts as unchanged: it has no history).
  int frames_since_change_ = TemporalReuse::moving_frames;
  std::vector<PixelLayers> layers_;  ///< The current frame's PixelLayers (with temporal reuse).
};

template <class B, class Surface, class Brdf, class Sampler, class F>
Frame Renderer<B, Surface, Brdf, Sampler, F>::render(const Camera& camera, std::uint32_t index) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  const RenderSettings& settings = engine_.settings();
  Frame frame = Frame::blank(settings.width, settings.height, index);
  FrameOptions options{.profile = profiling_};
  if (temporal_) {
    const TemporalReuse::FrameRequest request = temporal_->begin(camera, settings.width, settings.height, scene_changed_);
    options.clamp_scale = request.clamp_scale;
    options.pixel_jitter = request.pixel_jitter;
    options.texture_cone_scale = request.texture_cone_scale;
    options.shadow_history = &*temporal_;
    // A camera that moves through an unchanged scene keeps its VPLs (RenderSettings::held_vpl_frames),
    // once the moving histories hold no frame from before the scene's last change: until then
    // each frame's new VPLs add an independent sample of the changed light to the clamped histories.
    frames_since_change_ = scene_changed_ ? 0 : std::min(frames_since_change_ + 1, TemporalReuse::moving_frames);
    options.keep_vpls = frames_since_change_ >= TemporalReuse::moving_frames && temporal_->still_frames() == 0 &&
                        held_vpl_frames_ < settings.held_vpl_frames;
    // A light that changed (moved, turned, dimmed) draws its VPLs with the random numbers of
    // those it replaces: they move with the light instead of being replaced by other light
    // paths. Every VPL changes with it, so the histories, clamped everywhere, keep little, and
    // new numbers each frame would make the image pulse with each frame's few heavy paths. A
    // moved object changes only the paths that meet it: there the histories average new ones.
    if (lights_changed_ && vpl_index_ && held_vpl_frames_ < settings.held_vpl_frames) options.vpl_index = vpl_index_;
    // VPLs chosen for one view (ImportanceVplSampler's) are not kept for the next: the moving
    // frame draws them anew with the numbers of those it replaces, the same light paths chosen
    // for its own view. Kept, the choice fitted the run's first view alone, and the walks
    // through the forest and Sponza_lit had frames with a few heavy VPLs lighting what that
    // view had not shown (median relMSE 0.058 and 0.013 against 0.029 and 0.009 drawn anew,
    // seeds 1-4, docs/interaction.md).
    if (options.keep_vpls && vpl_index_ && chooses_for_view(engine_.sampler())) {
      options.keep_vpls = false;
      options.vpl_index = vpl_index_;
    }
  }
  if (temporal_ || keep_layers_) {
    options.keep_layers = true;
    layers_.resize(std::size_t(settings.width) * std::size_t(settings.height));
  }
  scene_changed_ = lights_changed_ = false;
  engine_.begin_frame(camera, index, tone_mapping_ ? *tone_mapping_ : ToneMapping{}, options);
  const auto vpls_done = clock::now();
  const bool same_numbers = engine_.frame().vpls_kept || options.vpl_index.has_value();
  held_vpl_frames_ = same_numbers ? held_vpl_frames_ + 1 : 0;
  vpl_index_ = engine_.frame().vpl_index;

  std::mutex merge_mutex;
  FrameStatistics& stats = frame.statistics;
  engine_.render_frame([&](std::size_t, const TileResult& result, double) {
    place_tile(result, frame, layers_);  // tiles are disjoint: no lock needed
    std::lock_guard lock(merge_mutex);
    stats.rays.merge(result.rays);
    stats.stages.merge(result.stages);
    stats.luminance.merge(result.luminance);
  });
  if (temporal_) {
    const auto reuse_start = clock::now();
    reuse_history(frame);
    stats.temporal_milliseconds = std::chrono::duration<double, std::milli>(clock::now() - reuse_start).count();
  }
  const ToneMapping next = ToneMapping::from(stats.luminance);
  if (!tone_mapping_) frame.tone_map(next);
  tone_mapping_ = next;
  stats.tiles = int(engine_.tiles().size());
  stats.vpls = engine_.frame().vpl_count();
  stats.vpls_kept = engine_.frame().vpls_kept;
  stats.vpl_index = *vpl_index_;
  const auto end = clock::now();
  stats.milliseconds = std::chrono::duration<double, std::milli>(end - start).count();
  stats.vpl_milliseconds = std::chrono::duration<double, std::milli>(vpls_done - start).count();
  stats.commit_milliseconds = engine_.commit_milliseconds();
  return frame;
}

}  // namespace igi
