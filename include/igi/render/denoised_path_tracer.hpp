#pragma once
/// \file
/// `DenoisedPathTracer`: what a user would build instead of IGI for interactive global
/// illumination: a path tracer at a sample or a few per pixel and frame, averaged over time and
/// filtered, in the manner of SVGF (Schied et al., "Spatiotemporal Variance-Guided Filtering",
/// HPG 2017), from igi's own parts. Per frame:
///
/// 1. The reference PathTracer traces `samples_per_pixel` paths per pixel, seeded by the frame
///    index, through the point of each pixel temporal reuse asks for (the centre while the camera
///    moves, stratified points while it stays); its first_hits give the G-buffer (albedo, normal,
///    depth) along the same rays.
/// 2. Demodulation: each hit pixel's radiance less its first hit's emission, over the hit's
///    albedo (floored, see albedo_floor), is its irradiance (as PixelLayers holds it, times pi),
///    so that the filters smooth lighting and not texture; the emission, and a miss's radiance,
///    stay unfiltered (PixelLayers::rest), as in an IGI frame (a light seen directly is no noisier
///    than its emission, and filtered it would bleed into the surfaces around it).
/// 3. TemporalReuse averages the irradiance over the pixel's history, found by reprojecting its
///    first hit into the previous frame and dropped where normal or tangent plane disagree (a
///    disocclusion) or where the scene changed (clamping to a neighbourhood's range, as IGI's
///    filtered frames do, darkened this method's single paths: frames of the window room under
///    a circling sun fell to 0.56 of the reference's mean); it also keeps the average of the
///    squared luminance.
/// 4. The variance of each pixel's average: from the history's moments (their variance over the
///    frames averaged) where the history is long enough, else the spread over the 3 x 3 window of
///    pixels on the same surface, whose same-surface mean then stands for the pixel (AtrousFilter's
///    first stage, as in an IGI frame with 3 x 3 interleaving).
/// 5. AtrousFilter's passes smooth the averaged irradiance, guided by normal, depth, albedo and
///    that variance; the result is remodulated with the averaged albedo.
///
/// A frame's image is a pure function of the scene, the cameras and scene changes of this frame
/// and the ones before it, the settings and the frame indices: the path tracer's samples depend
/// on the frame seed, pixel and sample index only, the averaging and remodulation pixel by pixel
/// on their inputs, and the filter runs on one thread. So any thread count gives the same frames.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "igi/filters/atrous_filter.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/renderer.hpp"
#include "igi/render/temporal_reuse.hpp"
#include "igi/scene/scene_changes.hpp"

namespace igi {

/// Settings of DenoisedPathTracer.
struct DenoisedPathTracerSettings {
  int width = 640;            ///< Pixels per row.
  int height = 480;           ///< Rows.
  int samples_per_pixel = 1;  ///< Paths traced per pixel and frame.
  /// Longest history a pixel averages (TemporalReuse; 1: none). 32 lets a still view converge
  /// over 4 seconds at 8 frames per second; a moving camera caps it at TemporalReuse::moving_frames.
  int temporal_frames = 32;
  /// The à-trous filter: the most passes (5, steps 1 to 16, 31 pixels each way), since one path
  /// per pixel leaves far more noise than an IGI frame, whose filter makes do with 3. On the
  /// walkthroughs (160 x 120) median relMSE fell with each pass: 0.0065, 0.0053, 0.0048 for 3, 4,
  /// 5 passes on the window walk, 0.0084, 0.0067, 0.0062 on the Cornell box's.
  AtrousSettings filter{.passes = AtrousFilter::max_passes};
  /// The path tracer: its seed is combined with each frame's index, its threads serve the whole
  /// frame; without jitter (here the default) its camera rays pass where temporal reuse asks.
  PathTracerSettings path_tracer{.jitter = false};
};

/// Most paths per pixel and frame: past 1024 a frame is a reference render, not an interactive one.
inline constexpr int max_denoised_samples_per_pixel = 1024;

/// Throws SettingsError naming the first setting out of range (the filter's are checked by AtrousFilter).
inline void validate(const DenoisedPathTracerSettings& s) {
  if (s.width < 1 || s.height < 1 || s.width > max_image_edge || s.height > max_image_edge)
    throw SettingsError("size " + std::to_string(s.width) + "x" + std::to_string(s.height) + " is outside 1.." +
                        std::to_string(max_image_edge) + " per side");
  if (s.samples_per_pixel < 1 || s.samples_per_pixel > max_denoised_samples_per_pixel)
    throw SettingsError("samples per pixel " + std::to_string(s.samples_per_pixel) + " is outside 1.." +
                        std::to_string(max_denoised_samples_per_pixel));
  if (s.temporal_frames < 1 || s.temporal_frames > max_temporal_frames)
    throw SettingsError("temporal frames " + std::to_string(s.temporal_frames) + " is outside 1.." +
                        std::to_string(max_temporal_frames));
  validate(s.path_tracer);
}

/// A path tracer whose frames are averaged over time and filtered (see the file comment), over
/// backend B (built and owned here), surface shader Surface and BRDF shader Brdf. The scene and
/// the shaders are borrowed and must outlive it; change the scene only through apply.
template <class B, class Surface, class Brdf>
  requires Backend<B> && SurfaceShader<Surface, 1> && BrdfShader<Brdf, 1>
class DenoisedPathTracer {
 public:
  /// Albedo below which a first hit is not demodulated by its own: 1% keeps the irradiance
  /// within 100 pi times its pixel's radiance on black paint, mirrors and glass (diffuse albedo
  /// 0), and the filter's albedo term keeps such pixels apart from brighter surfaces.
  static constexpr float albedo_floor = 0.01f;
  /// Shortest history whose moments give its variance: SVGF's 4; shorter ones take the spread
  /// over their 3 x 3 window instead, since two or three frames' spread says little. On the
  /// window walk (docs/interaction.md) the window's spread in every frame instead gave median
  /// relMSE 0.0065 against 0.0048.
  static constexpr int moment_frames = 4;
  /// The interleaving pattern AtrousFilter's first stage assumes: its S x S window (3 x 3) is the
  /// spatial estimate for short histories.
  static constexpr int window_interleave = 3;

  /// Builds the backend for `scene`; throws SettingsError for unusable settings,
  /// std::invalid_argument for a scene without geometry or a filter setting out of range.
  DenoisedPathTracer(Scene& scene, const Surface& surface, const Brdf& brdf, const DenoisedPathTracerSettings& settings = {})
      : scene_(&scene),
        surface_(&surface),
        brdf_(&brdf),
        settings_((validate(settings), settings)),
        backend_(scene),
        filter_(settings.filter),
        temporal_(settings.temporal_frames, TemporalReuse::AfterSceneChange::drop),
        arena_(settings.path_tracer.threads > 0 ? settings.path_tracer.threads : tbb::task_arena::automatic) {
    tracer_.emplace(*scene_, backend_, *surface_, *brdf_, settings_.path_tracer);
    guide_.resize(settings_.width, settings_.height);  // glossy and unfiltered radiance stay zero
    guide_.border = 0;
  }

  /// Applies an animation's `changes` (throws SceneError on an index the scene lacks, before
  /// changing anything) and returns their camera. A change of a light, an instance or a mesh
  /// drops every history at the next frame, so nothing lags behind it.
  Camera apply(const SceneChanges& changes) {
    changes.check(*scene_);
    if (!changes.alters(*scene_)) return changes.camera;
    changes.apply_to(*scene_);
    for (const auto& [index, transform] : changes.instances) backend_.set_instance_transform(index, transform);
    for (const MeshVertices& vertices : changes.meshes) backend_.set_mesh_positions(vertices.mesh, vertices.positions);
    backend_.commit();
    // The path tracer keeps the lights' sampling tables and the scene's geometry: built anew.
    tracer_.emplace(*scene_, backend_, *surface_, *brdf_, settings_.path_tracer);
    scene_changed_ = true;
    return changes.camera;
  }

  /// Renders frame `index` as seen by `camera`. Its HDR image depends on scene, camera, settings
  /// and index, and on those of the frames before it through the histories; the RGB8 image is
  /// tone mapped with the previous frame's statistics (the first frame's with its own).
  Frame render(const Camera& camera, std::uint32_t index) {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    const int width = settings_.width, height = settings_.height;
    const TemporalReuse::FrameRequest request = temporal_.begin(camera, width, height, scene_changed_);
    scene_changed_ = false;
    tracer_->set_seed(hash(settings_.path_tracer.seed, index));
    tracer_->set_pixel_position(request.pixel_jitter);
    tracer_->reset(camera, width, height);
    tracer_->add_samples(settings_.samples_per_pixel);
    const Image radiance = tracer_->image();
    layers_ = tracer_->first_hits();
    Frame frame = Frame::blank(width, height, index);
    FrameStatistics& statistics = frame.statistics;
    statistics.rays = tracer_->statistics().rays;
    statistics.rays.primary += std::uint64_t(width) * std::uint64_t(height);  // first_hits' rays
    const auto traced = clock::now();
    std::vector<LuminanceAccumulator> rows(static_cast<std::size_t>(height));
    arena_.execute([&] {
      tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) demodulate(radiance(x, y), layers_[std::size_t(y) * std::size_t(width) + std::size_t(x)]);
      });
      temporal_.accumulate(PinholeProjection(camera, width, height), 1, layers_, frame.hdr);
      tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) fill_guide(x, y);
      });
      filter();
      tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
          PixelLayers averaged = temporal_.averages(x, y);
          averaged.irradiance = filtered_.irradiance[std::size_t(y) * std::size_t(width) + std::size_t(x)];
          averaged.hit = true;  // composed as TemporalReuse composes: a miss without history has albedo 0
          frame.hdr(x, y) = averaged.radiance();
          rows[std::size_t(y)].add(frame.hdr(x, y));
        }
      });
    });
    for (const LuminanceAccumulator& row : rows) statistics.luminance.merge(row.statistics());  // in row order
    const ToneMapping next = ToneMapping::from(statistics.luminance);
    frame.tone_map(tone_mapping_ ? *tone_mapping_ : next);
    tone_mapping_ = next;
    const auto end = clock::now();
    statistics.milliseconds = std::chrono::duration<double, std::milli>(end - start).count();
    // All the frame adds to the path tracer's samples: averaging, filtering, tone mapping.
    statistics.temporal_milliseconds = std::chrono::duration<double, std::milli>(end - traced).count();
    return frame;
  }

  /// The last frame's G-buffer, row by row from the top: each pixel's first hit (albedo floored
  /// at albedo_floor, normal, depth, hit) and its demodulated radiance (irradiance, or rest on a miss).
  std::span<const PixelLayers> layers() const noexcept { return layers_; }
  /// The temporal histories.
  const TemporalReuse& temporal() const noexcept { return temporal_; }
  /// Forgets the tone-mapping history, as after a cut.
  void reset_tone_mapping() noexcept { tone_mapping_.reset(); }
  /// The scene being rendered.
  const Scene& scene() const noexcept { return *scene_; }
  /// The backend.
  const B& backend() const noexcept { return backend_; }
  /// The settings.
  const DenoisedPathTracerSettings& settings() const noexcept { return settings_; }

 private:
  /// Sets `pixel`'s irradiance to the demodulated `radiance` on a hit: less the hit's emission
  /// (in `rest`, from first_hits), over the floored albedo, times pi (as PixelLayers::radiance
  /// divides it); a miss's radiance goes to `rest`. Without jitter the samples' camera rays are
  /// first_hits' rays, so the emission they met is the one taken off; with jitter they may meet
  /// another surface, and the difference is kept from going negative.
  static void demodulate(const glm::vec3& radiance, PixelLayers& pixel) noexcept {
    if (!pixel.hit) {
      pixel.rest = radiance;
      return;
    }
    pixel.albedo = glm::max(pixel.albedo, glm::vec3(albedo_floor));
    pixel.irradiance = std::numbers::pi_v<float> * glm::max(radiance - pixel.rest, glm::vec3(0.0f)) / pixel.albedo;
  }

  /// Pixel (x, y) of the filter's G-buffer: the frame's first hit (albedo, normal, depth, hit)
  /// and the pixel's averaged irradiance.
  void fill_guide(int x, int y) {
    const std::size_t at = std::size_t(y) * std::size_t(settings_.width) + std::size_t(x);
    const PixelLayers& pixel = layers_[at];
    guide_.albedo[at] = pixel.albedo;
    guide_.normal[at] = pixel.normal;
    guide_.depth[at] = pixel.depth;
    guide_.hit[at] = pixel.hit ? 1.0f : 0.0f;
    guide_.irradiance[at] = temporal_.averages(x, y).irradiance;
  }

  /// The à-trous filter over the averaged irradiance into filtered_ (one tile: the whole image).
  void filter() {
    const int width = settings_.width;
    // Stage 0 (the 3 x 3 window) writes stages_.buffers[0]; its mean and variance stand where the
    // history is short, elsewhere the history's own average and the variance of it (the frames'
    // variance over their count; a miss keeps its own average: the passes leave it as it is).
    filter_.run_stage(0, guide_, window_interleave, stages_);
    filter_detail::AtrousStage& first = stages_.buffers[0];
    for (int y = 0; y < settings_.height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t at = std::size_t(y) * std::size_t(width) + std::size_t(x);
        const int length = temporal_.history_length(x, y);
        if (layers_[at].hit && length < moment_frames) continue;
        first.irradiance[at] = guide_.irradiance[at];
        first.irradiance_variance[at] = length > 0 ? temporal_.irradiance_variance(x, y) / float(length) : 0.0f;
      }
    for (int stage = 1; stage < filter_.stage_count(); ++stage) filter_.run_stage(stage, guide_, window_interleave, stages_);
    filter_.finish(guide_, stages_, filtered_);
  }

  Scene* scene_;
  const Surface* surface_;
  const Brdf* brdf_;
  DenoisedPathTracerSettings settings_;
  B backend_;
  AtrousFilter filter_;
  TemporalReuse temporal_;
  tbb::task_arena arena_;  ///< Runs the per-pixel loops on the path tracer's number of threads.
  std::optional<PathTracer<B, Surface, Brdf>> tracer_;  ///< Rebuilt when the scene changes (apply).
  std::optional<ToneMapping> tone_mapping_;
  bool scene_changed_ = false;       ///< Whether the scene changed since the last frame (every history is dropped).
  std::vector<PixelLayers> layers_;  ///< The last frame's G-buffer and demodulated radiance.
  TileGBuffer guide_;                ///< The filter's input: the whole image as one tile without border.
  AtrousTileStages stages_;          ///< The filter's stage outputs.
  FilteredTile filtered_;            ///< The filtered irradiance.
};

}  // namespace igi
