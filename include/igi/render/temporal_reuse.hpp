#pragma once
/// \file
/// Temporal reuse of a Renderer's frames. Each frame uses VPL sets of its own (the frame index
/// seeds them), so averaging frames averages independent instant-radiosity estimates: each pixel
/// keeps a history of its demodulated irradiance, found in the previous frame by reprojecting the
/// pixel's first hit with the camera's motion (a camera that stayed finds the pixel itself) and
/// kept only where the previous pixel shows the same surface (normal and tangent plane agree). A
/// history of n frames takes the new frame with weight 1/n, n capped at
/// RenderSettings::temporal_frames while the camera stays (whether or not the scene changes) and
/// at moving_frames while it moves (an exponential moving average past the cap). Glossy and
/// mirror radiance depend on the view: they are averaged only while the camera and the scene
/// stay as they were. Beside the irradiance each history averages its luminance's square, so that
/// its variance over the frames is known (irradiance_variance: what guides DenoisedPathTracer's
/// filter).
///
/// After a change of the scene (lights, instances, meshes) each history is kept but first
/// clamped (AfterSceneChange::clamp; or dropped), channel by channel, into the range the new
/// frame shows around the pixel (its neighbourhood's lowest and highest irradiance): light that
/// moved away or arrived is followed at once, while the history still averages away the noise
/// wherever the change is smaller than that noise. A change within that range the clamp cannot
/// see; so each history also averages the frames since the last change apart, and where that
/// average parts from the whole history by more than their noise allows (stale), the history
/// becomes those frames alone. A single frame is the clamp's to judge (stale_recent_frames).
///
/// While the view stays still the primary rays move inside their pixels from frame to frame
/// (pixel_jitter), and the albedo, glossy and unfiltered radiance are averaged with the
/// irradiance, so a still image converges to the average over each pixel's area (textures and
/// edges anti-aliased) rather than to its centre. A ray that misses where its pixel's earlier
/// rays hit counts as black albedo and keeps the irradiance history of the surface they hit
/// (irradiance is averaged over the hits, albedo over every frame: a pixel half covered by a
/// surface gets half its albedo times its irradiance).
///
/// While the view stays still the clamp distance shrinks as c n^(-1/4) with the history length n
/// (capped as n is): the average of frames then converges towards the unclamped image instead of
/// freezing the clamp's bias. The exponent balances what is left: the bias the clamp leaves falls
/// with c (the light of the region within c of a contact), the average's variance grows as
/// 1/c^2 per frame and falls as 1/n, so c^2 ~ n^(-1/2) makes both fall as n^(-1/2).
///
/// A moving camera's frames that keep their VPLs cycle through a few draws of them
/// (RenderSettings::held_vpl_sets): there each history also averages each draw's frames apart
/// and shows the mean of those averages, so that a pixel holds the light paths of every draw
/// while its value changes from frame to frame only as one draw's frames differ (one average of
/// all frames would move an eighth of the way to each draw's light as it came round).
///
/// Each history also keeps its first hit's shadow answers towards the delta lights (ShadowBits),
/// which the next frame's pipeline reuses instead of tracing those rays again where its first hit
/// shows the same surface as all four previous pixels around its reprojection, which agree
/// (previous_shadows): in a scene that did not change, a surface point's view of a light that
/// stayed does not change either. Where the four disagree (a shadow's edge) or the scene changed,
/// the rays are traced.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/parallel_for.h>

#include "igi/io/image_types.hpp"
#include "igi/io/srgb.hpp"
#include "igi/render/interleaving.hpp"
#include "igi/render/pixel_layers.hpp"
#include "igi/render/settings.hpp"
#include "igi/render/shadow_reuse.hpp"
#include "igi/scene/camera.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {

/// Which of the draws of VPLs that a run of frames keeping theirs cycles through a frame used
/// (FrameState::held_set).
struct HeldVplDraw {
  int set = -1;  ///< The draw (0 .. sets - 1); -1: the frame's VPLs are not one of several held draws.
  int sets = 1;  ///< How many the run cycles through (RenderSettings::held_vpl_sets).
};

/// Averages a Renderer's frames over time (see the file comment).
class TemporalReuse {
 public:
  /// A previous pixel whose normal is further than acos(0.9) = 26 degrees from the new one's is
  /// another surface: wider than the shading normals' variation across one pixel of a curved
  /// mesh, narrower than any crease worth keeping.
  static constexpr float normal_agreement = 0.9f;
  /// A previous pixel whose first hit lies further off the new hit's tangent plane than this
  /// fraction of the new hit's depth is another surface: about three pixel footprints at 480 rows
  /// and a 40 degree field of view (0.0015 of the depth each). Flat facets lie on the plane up to
  /// rounding, a bumped shading normal tilts it by less over a pixel or two, and the step behind
  /// an object's edge is far more.
  static constexpr float plane_tolerance = 0.005f;
  /// Longest irradiance history while the camera moves: every moving frame resamples the history
  /// bilinearly, and 8 frames of that keep its blur near one pixel.
  static constexpr int moving_frames = 8;
  /// Half the side of the neighbourhood whose irradiance range bounds a history after a scene
  /// change: 3 x 3 pixels, the discontinuity buffer's window, whose filtered values differ by
  /// the sets each pixel does not share with its neighbours. Measured on the Cornell box
  /// (temporal_test): a 20 cm jump of its tall block is shown to 0.70 of the change in the first
  /// frame after it (0.81 without history), where 5 x 5 kept more of the old shadow (0.60);
  /// with the light sliding every frame, frames change a third as much as without history (a
  /// quarter with 5 x 5).
  static constexpr int clamp_radius = 1;
  /// A history that holds frames from before a scene change is stale where the average of the
  /// frames since the change differs from it by more than this many standard deviations of that
  /// difference (as the history's variance over its frames gives it): 3, beyond which unchanged
  /// light falls in fewer than one pixel of 300 with normal noise.
  static constexpr float stale_deviations = 3.0f;
  /// Frames a history needs before its variance over them tells staleness from noise: with 4,
  /// the estimate is within a factor of two or so of the variance most of the time.
  static constexpr int stale_test_frames = 4;
  /// Frames since a change before the test may find a history stale: the first frame after it
  /// is the clamp's (alone, its noise passes the test wherever the scene changes every frame:
  /// with 1, a block moving through the Cornell box doubled that walk's median relMSE).
  static constexpr int stale_recent_frames = 2;

  /// What a history does when the scene changed since its frame.
  enum class AfterSceneChange {
    clamp,  ///< Kept, clamped into the new frame's neighbourhood range (inputs already filtered, as IGI's).
    drop,   ///< Dropped (inputs of one sample each, whose neighbourhood range lies mostly below their mean).
  };

  /// Histories of at most `frames` frames (1 .. max_temporal_frames), treated after a scene change
  /// as `after_change` says; throws SettingsError otherwise.
  explicit TemporalReuse(int frames, AfterSceneChange after_change = AfterSceneChange::clamp)
      : frames_(frames), after_change_(after_change) {
    if (frames < 1 || frames > max_temporal_frames)
      throw SettingsError("temporal frames " + std::to_string(frames) + " is outside 1.." +
                          std::to_string(max_temporal_frames));
  }

  /// The clamp's scale for a frame after `still` frames of the same view, with histories of at most `frames`.
  static float clamp_scale(int still, int frames) noexcept {
    return std::pow(float(std::min(still + 1, frames)), -0.25f);
  }
  /// The camera rays' cone for a frame after `still` frames of the same view, with histories of
  /// at most `frames`: the n = min(still + 1, frames) frames averaged spread their rays over the
  /// pixel (pixel_jitter), each with 1/n of its area, so each reads textures over a side of
  /// 1/sqrt(n) (as N sub-samples do): a pixel-wide cone every frame blurred the average twice
  /// (Sponza_lit, 32 frames: relMSE 0.0128 against 0.0114 with point lookups).
  static float texture_cone_scale(int still, int frames) noexcept {
    return 1.0f / std::sqrt(float(std::min(still + 1, frames)));
  }
  /// Where the primary rays of a frame after `still` frames of the same view pass in their
  /// sub-sample cells: the centre first (a frame after a move is the frame without reuse), then
  /// the Halton points of bases 2 and 3 shifted by half a cell, so n still frames sample each
  /// pixel at n stratified points.
  static glm::vec2 pixel_jitter(int still) noexcept {
    const auto shifted = [](float u) { return u < 0.5f ? u + 0.5f : u - 0.5f; };
    return {shifted(radical_inverse(0, std::uint64_t(still))), shifted(radical_inverse(1, std::uint64_t(still)))};
  }

  /// What begin asks of the frame it starts.
  struct FrameRequest {
    float clamp_scale = 1.0f;       ///< Factor on the clamp distance (FrameOptions::clamp_scale).
    glm::vec2 pixel_jitter{0.5f};   ///< Where the primary rays pass (FrameOptions::pixel_jitter).
    float texture_cone_scale = 1.0f;  ///< Factor on the camera rays' cone (FrameOptions::texture_cone_scale).
  };

  /// Starts a frame seen by `camera` at `width` x `height`; `scene_changed` says lights,
  /// instances or meshes changed since the previous frame (the histories are then clamped to
  /// the new frame's neighbourhoods). Returns the clamp scale, ray positions and texture cone the
  /// frame is to be rendered with.
  FrameRequest begin(const Camera& camera, int width, int height, bool scene_changed) {
    same_camera_ = has_history() && width == width_ && height == height_ &&
                   camera.camera_to_world == previous_camera_.camera_to_world && camera.yfov == previous_camera_.yfov;
    const bool same_view = same_camera_ && !scene_changed;
    if (width != width_ || height != height_ || (scene_changed && after_change_ == AfterSceneChange::drop))
      previous_projection_.reset();
    scene_changed_ = scene_changed;
    still_ = same_view ? still_ + 1 : 0;
    width_ = width;
    height_ = height;
    previous_camera_ = camera;
    return {clamp_scale(still_, frames_), pixel_jitter(still_), texture_cone_scale(still_, frames_)};
  }

  /// Averages the frame's `layers` (width x height of begin, row-major, seen through
  /// `projection` with `antialiasing` sub-samples) into the histories and writes the composed
  /// radiance into `hdr`. Rows run as a oneTBB loop (call it inside the renderer's arena); each
  /// pixel depends only on its inputs, so the result is the same on any number of threads.
  /// `shadow_keys` are the delta lights the layers' ShadowBits number (FrameState::delta_lights);
  /// `held` says which held draw of VPLs the frame used, if any.
  void accumulate(const PinholeProjection& projection, int antialiasing, std::span<const PixelLayers> layers,
                  Image& hdr, std::vector<DeltaLightKey> shadow_keys = {}, HeldVplDraw held = {}) {
    const std::size_t pixels = std::size_t(width_) * std::size_t(height_);
    if (layers.size() != pixels || hdr.width != width_ || hdr.height != height_ ||
        projection.width() != width_ || projection.height() != height_)
      throw std::invalid_argument("TemporalReuse::accumulate: the frame's sizes differ from begin's");
    glm::vec2 measured;  // where in each pixel its depth was measured: sub-sample 0's ray
    subsample_offset(0, antialiasing, measured.x, measured.y, pixel_jitter(still_));
    current_.resize(pixels);  // pixel() sets each entry whole
    current_view_.resize(pixels);
    const bool keep_shadows = !shadow_keys.empty();
    next_shadow_points_.resize(keep_shadows ? pixels : 0);
    const bool clamp = scene_changed_ && has_history();
    if (clamp) neighbourhood_ranges(layers);
    if (held.set < 0 || held.set >= held.sets) held = {};
    current_draws_.resize(held.set >= 0 ? pixels * std::size_t(held.sets) : 0);  // pixel() sets each entry
    tbb::parallel_for(0, height_, [&](int y) {
      for (int x = 0; x < width_; ++x) {
        const std::size_t at = std::size_t(y) * std::size_t(width_) + std::size_t(x);
        hdr.pixels[at] = pixel(projection, layers[at], x, y, measured, clamp ? &ranges_[at] : nullptr, held,
                               current_[at], current_view_[at],
                               held.set >= 0 ? &current_draws_[at * std::size_t(held.sets)] : nullptr);
        if (keep_shadows) {
          const Sample& kept = current_[at];
          next_shadow_points_[at] = {kept.position, kept.normal, kept.length > 0 ? layers[at].shadows : ShadowBits{}};
        }
      }
    });
    std::swap(previous_, current_);
    std::swap(previous_view_, current_view_);
    std::swap(shadow_points_, next_shadow_points_);
    std::swap(previous_draws_, current_draws_);
    previous_draw_sets_ = held.set >= 0 ? held.sets : 0;
    previous_keys_ = std::move(shadow_keys);
    previous_projection_.emplace(projection);
    previous_measured_ = measured;
  }

  /// Frames averaged into pixel (x, y)'s irradiance by the last accumulate (0 where nothing was hit).
  int history_length(int x, int y) const {
    if (!has_history()) return 0;
    return previous_.at(std::size_t(y) * std::size_t(width_) + std::size_t(x)).length;
  }
  /// Whether the frame begun may reuse the shadow answers of the frame before: there is one, of
  /// the same size, and the scene has not changed since.
  bool shadows_reusable() const noexcept { return has_history() && !scene_changed_; }
  /// The delta lights the frame before's shadow answers number.
  const std::vector<DeltaLightKey>& shadow_keys() const noexcept { return previous_keys_; }
  /// The frame before's shadow answers for a first hit at `position` with shading `normal`,
  /// `depth` from the eye (in that frame's numbering, shadow_keys): a light's answer is known
  /// only where the four previous pixels around the hit's reprojection all show its surface, all
  /// know the answer and agree on it (so a shadow's edge is traced again); none is known unless
  /// shadows_reusable. Reads only the frame before's histories: safe from any thread while the
  /// frame renders.
  ShadowBits previous_shadows(const glm::vec3& position, const glm::vec3& normal, float depth) const noexcept {
    if (!shadows_reusable() || shadow_points_.empty()) return {};
    const std::optional<glm::vec2> seen = previous_projection_->project(position);
    if (!seen) return {};
    const float u = seen->x - previous_measured_.x, v = seen->y - previous_measured_.y;
    if (!(u >= 0.0f && v >= 0.0f && u < float(width_ - 1) && v < float(height_ - 1))) return {};  // NaN too
    const int x0 = int(u), y0 = int(v);
    ShadowBits all{~0u, ~0u};
    std::uint32_t any_visible = 0;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const ShadowPoint& old = shadow_points_[std::size_t(y0 + j) * std::size_t(width_) + std::size_t(x0 + i)];
        all.known &= old.shadows.known;  // none on a miss
        if (all.known == 0 || !same_surface(old.position, old.normal, position, normal, depth)) return {};
        all.visible &= old.shadows.visible;
        any_visible |= old.shadows.visible;
      }
    all.known &= ~(any_visible ^ all.visible);  // where some see the light and others do not: unknown
    all.visible &= all.known;
    return all;
  }
  /// Frames before the current one with the same view and scene.
  int still_frames() const noexcept { return still_; }
  /// Pixel (x, y)'s averages after the last accumulate, as it composed them into the pixel's
  /// radiance: irradiance, glossy, albedo and rest (normal, depth and hit stay zero). What a
  /// caller that filters the averaged irradiance further remodulates it with (DenoisedPathTracer).
  PixelLayers averages(int x, int y) const {
    if (!has_history()) return {};
    const std::size_t at = std::size_t(y) * std::size_t(width_) + std::size_t(x);
    const Sample& sample = previous_.at(at);
    const ViewSample& view = previous_view_[at];
    return {.irradiance = sample.irradiance, .glossy = view.glossy, .albedo = view.albedo, .rest = view.rest};
  }
  /// Variance of the luminance of pixel (x, y)'s irradiance over the frames averaged into it by
  /// the last accumulate (from the running mean of the squared luminance; 0 with one frame or none).
  float irradiance_variance(int x, int y) const {
    if (!has_history()) return 0.0f;
    const Sample& sample = previous_.at(std::size_t(y) * std::size_t(width_) + std::size_t(x));
    const float mean = luminance(sample.irradiance);
    return std::max(sample.luminance_square - mean * mean, 0.0f);
  }

 private:
  /// Whether previous_ holds the histories of a frame the next one may reuse.
  bool has_history() const noexcept { return previous_projection_.has_value(); }

  /// The lowest and highest irradiance, channel by channel, of the hit pixels of a neighbourhood.
  struct Range {
    glm::vec3 lowest{std::numeric_limits<float>::infinity()};
    glm::vec3 highest{-std::numeric_limits<float>::infinity()};
  };

  /// ranges_[pixel]: the Range of the (2 clamp_radius + 1)^2 pixels about it in `layers`, taken
  /// as a running minimum and maximum along the rows, then along the columns.
  void neighbourhood_ranges(std::span<const PixelLayers> layers) {
    const std::size_t pixels = layers.size();
    rows_.resize(pixels);  // every entry is set whole below
    ranges_.resize(pixels);
    tbb::parallel_for(0, height_, [&](int y) {
      for (int x = 0; x < width_; ++x) {
        Range range;
        for (int i = std::max(0, x - clamp_radius); i <= std::min(width_ - 1, x + clamp_radius); ++i) {
          const PixelLayers& near = layers[std::size_t(y) * std::size_t(width_) + std::size_t(i)];
          if (!near.hit) continue;
          range.lowest = glm::min(range.lowest, near.irradiance);
          range.highest = glm::max(range.highest, near.irradiance);
        }
        rows_[std::size_t(y) * std::size_t(width_) + std::size_t(x)] = range;
      }
    });
    tbb::parallel_for(0, height_, [&](int y) {
      for (int x = 0; x < width_; ++x) {
        Range range;
        for (int j = std::max(0, y - clamp_radius); j <= std::min(height_ - 1, y + clamp_radius); ++j) {
          const Range& row = rows_[std::size_t(j) * std::size_t(width_) + std::size_t(x)];
          range.lowest = glm::min(range.lowest, row.lowest);
          range.highest = glm::max(range.highest, row.highest);
        }
        ranges_[std::size_t(y) * std::size_t(width_) + std::size_t(x)] = range;
      }
    });
  }

  /// What a pixel's history keeps of its surface: what reproject reads of the four previous
  /// pixels around each hit, apart from the view's averages (ViewSample), which only a still
  /// view reads, so that each of those reads touches one cache line (64 bytes).
  struct alignas(64) Sample {
    glm::vec3 position{0.0f};    ///< World position of the first hit.
    glm::vec3 normal{0.0f};      ///< Its shading normal.
    glm::vec3 irradiance{0.0f};  ///< Average demodulated irradiance.
    glm::vec3 recent{0.0f};      ///< Average demodulated irradiance of the frames since the scene's last change.
    float luminance_square = 0.0f;  ///< Average of the irradiance's squared luminance (its variance's second moment).
    int length = 0;              ///< Frames in the irradiance average; 0: no hit.
    int recent_length = 0;       ///< Frames in that average (capped as length is); 0: no hit.
  };
  /// What a pixel's history keeps of its view: averaged only while the camera and the scene stay.
  struct ViewSample {
    glm::vec3 glossy{0.0f};  ///< Average glossy radiance (this view's; 0 in frames that missed).
    glm::vec3 albedo{0.0f};  ///< Average albedo (this view's; 0 in frames that missed).
    glm::vec3 rest{0.0f};    ///< Average unfiltered radiance (this view's).
  };

  /// A pixel's first hit and its delta lights' shadow answers, kept apart from its Sample so
  /// that previous_shadows, called for every first hit while the frame renders, reads little.
  struct ShadowPoint {
    glm::vec3 position{0.0f};  ///< World position of the first hit.
    glm::vec3 normal{0.0f};    ///< Its shading normal.
    ShadowBits shadows{};      ///< Its answers (none known on a miss).
  };

  /// Whether a first hit at `old_position` with `old_normal` shows the surface at `position` with `normal`, `depth` from the eye.
  static bool same_surface(const glm::vec3& old_position, const glm::vec3& old_normal, const glm::vec3& position,
                           const glm::vec3& normal, float depth) noexcept {
    return glm::dot(old_normal, normal) >= normal_agreement && std::abs(glm::dot(normal, old_position - position)) <= plane_tolerance * depth;
  }
  /// Whether previous sample `old` shows the surface at `position` with `normal`, `depth` from the eye.
  static bool same_surface(const Sample& old, const glm::vec3& position, const glm::vec3& normal, float depth) noexcept {
    return old.length > 0 && same_surface(old.position, old.normal, position, normal, depth);
  }

  /// The previous pixels a history was taken from and their weights (summing to 1).
  struct Footprint {
    std::array<std::size_t, 4> at{};
    std::array<float, 4> weight{};
    int count = 0;
  };

  /// The irradiance history of a hit at `position` found in the previous frame by reprojection:
  /// the bilinear mix of the neighbours that show the same surface (length 0 if none does), whose
  /// places and weights go to `footprint`.
  Sample reproject(const glm::vec3& position, const glm::vec3& normal, float depth, Footprint& footprint) const {
    Sample found;
    const std::optional<glm::vec2> seen = previous_projection_->project(position);
    if (!seen) return found;
    // The previous frame measured pixel (i, j)'s first hit at (i, j) + previous_measured_.
    const float u = seen->x - previous_measured_.x, v = seen->y - previous_measured_.y;
    if (!(std::abs(u) < float(width_) + 1.0f && std::abs(v) < float(height_) + 1.0f)) return found;  // NaN too
    const int x0 = int(std::floor(u)), y0 = int(std::floor(v));
    const float fx = u - float(x0), fy = v - float(y0);
    float weight_sum = 0.0f, length_sum = 0.0f, recent_length_sum = 0.0f;
    glm::vec3 irradiance(0.0f), recent(0.0f);
    float luminance_square = 0.0f;
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) {
        const int x = x0 + i, y = y0 + j;
        if (x < 0 || y < 0 || x >= width_ || y >= height_) continue;
        const std::size_t at = std::size_t(y) * std::size_t(width_) + std::size_t(x);
        const Sample& old = previous_[at];
        if (!same_surface(old, position, normal, depth)) continue;
        const float weight = (i ? fx : 1.0f - fx) * (j ? fy : 1.0f - fy);
        footprint.at[std::size_t(footprint.count)] = at;
        footprint.weight[std::size_t(footprint.count++)] = weight;
        weight_sum += weight;
        length_sum += weight * float(old.length);
        irradiance += weight * old.irradiance;
        luminance_square += weight * old.luminance_square;
        recent += weight * old.recent;
        recent_length_sum += weight * float(old.recent_length);
      }
    if (!(weight_sum > 0.0f)) {
      footprint.count = 0;
      return found;
    }
    const float inverse_weight = 1.0f / weight_sum;
    for (int k = 0; k < footprint.count; ++k) footprint.weight[std::size_t(k)] *= inverse_weight;
    found.irradiance = irradiance * inverse_weight;
    found.luminance_square = luminance_square * inverse_weight;
    found.length = std::max(1, int(length_sum * inverse_weight + 0.5f));
    found.recent = recent * inverse_weight;
    found.recent_length = std::max(1, int(recent_length_sum * inverse_weight + 0.5f));
    return found;
  }

  /// One held draw's averages at a pixel (FrameState::held_vpls).
  struct DrawAverage {
    glm::vec3 irradiance{0.0f};  ///< Average demodulated irradiance of the draw's frames.
    glm::vec3 glossy{0.0f};      ///< Average glossy radiance of the same frames, reprojected as the irradiance is.
    float frames = 0.0f;         ///< Frames in the averages; 0: the pixel holds none of this draw.
  };
  /// The light a pixel shows while its draws are averaged apart: the mean of its draws' averages.
  struct DrawMean {
    glm::vec3 irradiance{0.0f};  ///< Mean of the draws' irradiance.
    glm::vec3 glossy{0.0f};      ///< Mean of the draws' glossy radiance.
  };

  /// Writes into `draws` (held.sets entries) the histories of the previous pixels in `footprint`
  /// draw by draw, or, after a frame that used no held draw, `history`'s irradiance average (with
  /// this frame's `glossy`) as the first draw's (and the others' if it holds more than one frame),
  /// the irradiance clamped into `range` if given; then averages this frame's `irradiance` and
  /// `glossy` into draw held.set, at most `cap` frames of it, and returns the mean of the draws
  /// that hold a frame. The glossy light is averaged with the draws too: taken from the frame
  /// alone, as a moving view's other view-dependent terms are, it changes with each draw's VPLs
  /// (Sponza_lit's walk with 4 draws swung frame to frame, 3.7% image-mean variation; 2.6% so).
  DrawMean average_draws(const Footprint& footprint, const Sample& history, const glm::vec3& irradiance,
                         const glm::vec3& glossy, const Range* range, HeldVplDraw held, int cap,
                         DrawAverage* draws) const {
    const std::size_t sets = std::size_t(held.sets);
    const int draw_cap = std::max(1, cap / held.sets);  // the draws together hold what one history does
    for (std::size_t k = 0; k < sets; ++k) {
      draws[k] = DrawAverage{};
      if (previous_draw_sets_ == held.sets && footprint.count > 0) {
        DrawAverage sum;
        float weight_sum = 0.0f;
        for (int i = 0; i < footprint.count; ++i) {
          const DrawAverage& old = previous_draws_[footprint.at[std::size_t(i)] * sets + k];
          if (old.frames <= 0.0f) continue;  // that pixel holds no frame of this draw
          const float weight = footprint.weight[std::size_t(i)];
          sum.irradiance += weight * old.irradiance;
          sum.glossy += weight * old.glossy;
          sum.frames += weight * old.frames;
          weight_sum += weight;
        }
        if (weight_sum > 0.0f)
          draws[k] = {.irradiance = sum.irradiance / weight_sum, .glossy = sum.glossy / weight_sum,
                      .frames = std::max(1.0f, std::round(sum.frames / weight_sum))};
      } else if (history.length > 0 && (k == 0 || history.length > 1)) {
        // The run's first draw is the VPLs of the frame before it, whose light the history holds;
        // a history of several frames, drawn anew each (a still view's, or after a change), is
        // the better guess for the others too, until their own frames replace it. One frame is
        // the first draw's alone: the others start empty. The glossy light has no history
        // while the view moves: this frame's stands for it.
        draws[k] = {.irradiance = history.irradiance, .glossy = glossy, .frames = float(std::min(history.length, draw_cap))};
      }
      if (range && draws[k].frames > 0.0f) draws[k].irradiance = glm::clamp(draws[k].irradiance, range->lowest, range->highest);
    }
    DrawAverage& own = draws[std::size_t(held.set)];
    own.frames = std::min(own.frames + 1.0f, float(draw_cap));
    own.irradiance += (irradiance - own.irradiance) / own.frames;
    own.glossy += (glossy - own.glossy) / own.frames;
    DrawMean mean;
    float filled = 0.0f;
    for (std::size_t k = 0; k < sets; ++k)
      if (draws[k].frames > 0.0f) {
        mean.irradiance += draws[k].irradiance;
        mean.glossy += draws[k].glossy;
        filled += 1.0f;
      }
    return {.irradiance = mean.irradiance / filled, .glossy = mean.glossy / filled};  // the own draw holds a frame
  }

  /// Sets `sample`'s irradiance average to `irradiance`, its second moment moved with it so that
  /// the variance over its frames stays what it was.
  static void move_mean(Sample& sample, const glm::vec3& irradiance) noexcept {
    const float before = luminance(sample.irradiance), after = luminance(irradiance);
    sample.irradiance = irradiance;
    sample.luminance_square = std::max(sample.luminance_square + after * after - before * before, 0.0f);
  }

  /// Whether `history` (n frames, some from before the scene's last change) is stale: whether
  /// `recent`, the average of the last m frames (those since the change, the new one among them),
  /// differs from it by more than stale_deviations standard deviations. Frames of variance v
  /// give the difference the variance v (1/m + 1/n - 2 (m - 1) / (m n)): the m - 1 frames
  /// before the new one are in both.
  static bool stale(const Sample& history, const glm::vec3& recent, int recent_length) noexcept {
    const float mean = luminance(history.irradiance), n = float(history.length), m = float(recent_length);
    const float variance = std::max(history.luminance_square - mean * mean, 0.0f);
    const float expected = variance * (1.0f / m + 1.0f / n - 2.0f * (m - 1.0f) / (m * n));
    const float difference = luminance(recent) - mean;
    return difference * difference > stale_deviations * stale_deviations * expected;  // false on NaN
  }

  /// Pixel (x, y)'s new history `out` and `out_view` and its radiance; its first hit was measured
  /// at (x, y) + `measured`; with a `range` (after a scene change) the history is first clamped into
  /// it; with `held` draw's `out_draws` (held.sets of them) the pixel shows the mean of its draws' averages.
  glm::vec3 pixel(const PinholeProjection& projection, const PixelLayers& layers, int x, int y, glm::vec2 measured,
                  const Range* range, HeldVplDraw held, Sample& out, ViewSample& out_view, DrawAverage* out_draws) const {
    const std::size_t at = std::size_t(y) * std::size_t(width_) + std::size_t(x);
    out = Sample{};
    // The view-dependent terms keep a history only while the camera stays (then each pixel is its own previous pixel).
    const bool still = still_ > 0;  // the same view and scene as the previous frame
    const Sample* same_pixel = still ? &previous_[at] : nullptr;
    const ViewSample* same_view = still ? &previous_view_[at] : nullptr;
    const float view_weight = 1.0f / float(still ? std::min(still_ + 1, frames_) : 1);
    const auto view_average = [&](const glm::vec3& old, const glm::vec3& now) {
      return same_view ? old + (now - old) * view_weight : now;
    };
    const glm::vec3 black(0.0f);
    out_view.rest = view_average(same_view ? same_view->rest : black, layers.rest);
    out_view.albedo = view_average(same_view ? same_view->albedo : black, layers.hit ? layers.albedo : black);
    out_view.glossy = view_average(same_view ? same_view->glossy : black, layers.hit ? layers.glossy : black);
    if (layers.hit) {
      out.position = projection.origin() +
                     projection.direction(float(x) + measured.x, float(y) + measured.y) * layers.depth;
      out.normal = layers.normal;
      Sample history;
      Footprint footprint;
      if (same_pixel) {
        history = *same_pixel;
        footprint = {.at = {at}, .weight = {1.0f}, .count = 1};
      } else if (same_camera_ && has_history()) {
        // The camera stayed and the scene changed: the hit's previous pixel is its own, where it
        // still shows the same surface. Where something moved off that surface the pixel starts
        // afresh: its neighbours' histories of the surface hold the light from before the move
        // (taking them, a moved block's bounce light lagged: 0.85 of the change in the first two
        // frames, against 0.93 and 0.88 without).
        const Sample& own = previous_[at];
        if (same_surface(own, out.position, out.normal, layers.depth)) {
          history = own;
          footprint = {.at = {at}, .weight = {1.0f}, .count = 1};
        }
      } else if (has_history()) {
        history = reproject(out.position, out.normal, layers.depth, footprint);
      }
      if (range && history.length > 0) move_mean(history, glm::clamp(history.irradiance, range->lowest, range->highest));
      const int cap = same_camera_ ? frames_ : std::min(frames_, moving_frames);
      out.length = std::min(history.length + 1, cap);
      const float weight = 1.0f / float(out.length);
      const float brightness = luminance(layers.irradiance), square = brightness * brightness;
      // The frames since the scene's last change, averaged apart (the first frame after it starts them afresh).
      out.recent_length = scene_changed_ || history.recent_length == 0
                              ? 1
                              : std::min(history.recent_length + 1, cap);
      out.recent = out.recent_length == 1 ? layers.irradiance
                                          : history.recent + (layers.irradiance - history.recent) / float(out.recent_length);
      // Only a history holding frames from before the change (more than those since) can be
      // stale; one that is takes the frames since instead (the light's noise did not change
      // with the scene: its variance stays).
      if (out.recent_length >= stale_recent_frames && out.recent_length < out.length &&
          history.length >= stale_test_frames && stale(history, out.recent, out.recent_length)) {
        out.luminance_square = history.luminance_square;
        out.irradiance = history.irradiance;
        move_mean(out, out.recent);
        out.length = out.recent_length;
      } else {
        out.irradiance = history.length > 0 ? history.irradiance + (layers.irradiance - history.irradiance) * weight
                                            : layers.irradiance;
        out.luminance_square =
            history.length > 0 ? history.luminance_square + (square - history.luminance_square) * weight : square;
      }
      if (out_draws) {
        const DrawMean mean = average_draws(footprint, history, layers.irradiance, layers.glossy, range, held, cap, out_draws);
        move_mean(out, mean.irradiance);
        out_view.glossy = mean.glossy;
      }
    } else if (same_pixel && same_pixel->length > 0) {
      // A ray that missed where this pixel's earlier rays hit: their surface's history stays.
      out.irradiance = same_pixel->irradiance;
      out.luminance_square = same_pixel->luminance_square;
      out.length = same_pixel->length;
      out.recent = same_pixel->recent;
      out.recent_length = same_pixel->recent_length;
      out.position = same_pixel->position;
      out.normal = same_pixel->normal;
    }
    if (out_draws && !layers.hit) std::fill_n(out_draws, held.sets, DrawAverage{});
    // Composed as the pipeline composes (a miss without history has albedo and glossy 0).
    const PixelLayers averaged{.irradiance = out.irradiance, .glossy = out_view.glossy, .albedo = out_view.albedo,
                               .rest = out_view.rest, .hit = true};
    return averaged.radiance();
  }

  int frames_;
  AfterSceneChange after_change_;
  int width_ = 0;
  int height_ = 0;
  int still_ = 0;
  bool same_camera_ = false;  ///< Whether the frame begun sees through the previous frame's camera.
  bool scene_changed_ = false;  ///< Whether the frame begun follows a change of the scene.
  Camera previous_camera_;
  std::vector<Sample> previous_;  ///< The last frame's histories, row-major.
  std::vector<Sample> current_;   ///< The frame being accumulated (kept to reuse its memory).
  std::vector<ViewSample> previous_view_;  ///< The last frame's view averages, row-major.
  std::vector<ViewSample> current_view_;   ///< The frame being accumulated's (kept to reuse its memory).
  std::vector<Range> rows_;       ///< Each pixel's range along its row (neighbourhood_ranges' first pass).
  std::vector<Range> ranges_;     ///< Each pixel's neighbourhood range after a scene change.
  /// The last frame's held draws' histories (FrameState::held_vpls): previous_draw_sets_ a pixel,
  /// row-major; empty after a frame that used no held draw.
  std::vector<DrawAverage> previous_draws_;
  std::vector<DrawAverage> current_draws_;  ///< The frame being accumulated's (kept to reuse its memory).
  int previous_draw_sets_ = 0;            ///< Draws per pixel in previous_draws_ (0: it holds none).
  std::vector<ShadowPoint> shadow_points_;       ///< The last frame's first hits and shadow answers (empty: it kept none).
  std::vector<ShadowPoint> next_shadow_points_;  ///< The frame being accumulated's (kept to reuse its memory).
  std::vector<DeltaLightKey> previous_keys_;  ///< The delta lights previous_'s ShadowBits number.
  std::optional<PinholeProjection> previous_projection_;  ///< The last frame's camera; empty while there is no history.
  glm::vec2 previous_measured_{0.5f}; ///< Where in its pixel the previous frame measured each first hit.
};

}  // namespace igi
