#pragma once
/// \file
/// What every tile of one frame shares: the frame's VPL sets, instance matrices, primary-ray
/// projection, resolved clamp and ray offsets, and the tone mapping of the previous frame. Built
/// once per frame by `FrameState::prepare`, read by every tile (on any thread or process).

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>
#include <optional>
#include <tuple>
#include <utility>

#include <glm/glm.hpp>

#include "igi/lighting/vpl_sampler.hpp"
#include "igi/lighting/vpl_spread.hpp"
#include "igi/render/settings.hpp"
#include "igi/render/shadow_reuse.hpp"
#include "igi/render/temporal_reuse.hpp"
#include "igi/render/tone_mapping.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/scene_bounds.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/cutout_occlusion.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/simd/float_mode.hpp"

namespace igi {

/// The VPL settings of frame `index` rendered with `settings` in a scene of world `bounds`: S^2
/// sets of M VPLs, the frame's seed and bounce limit, and the `view` (projection and clamp; borrowed) if given.
inline VplSettings vpl_settings_for(const RenderSettings& settings, std::uint32_t index, const Bounds& bounds = {},
                                    const VplView* view = nullptr) {
  VplSettings vpl_settings;
  vpl_settings.sets = settings.interleave * settings.interleave;
  vpl_settings.vpls_per_set = settings.vpls_per_pixel;
  vpl_settings.frame = index;
  vpl_settings.seed = settings.seed;
  vpl_settings.max_bounces = settings.max_bounces;
  vpl_settings.environment_directions = settings.environment_directions;
  vpl_settings.portal_share = settings.portal_share;
  vpl_settings.scene_bounds = bounds;
  vpl_settings.view = view;
  return vpl_settings;
}

/// Gives each set of `draw` the direct light of `first`: its VPLs that are not surface VPLs (the
/// delta lights' exact ones, the same in every draw, and the environment's directions, which each
/// draw samples anew) replace `draw`'s, in order, where a set has as many of them. The held draws
/// of a run then differ only in their light walks: the direct light, composed per pixel without
/// a history while the camera moves, does not change from frame to frame as they come round, and
/// the shadow answers towards it stay reusable (shadow_reuse.hpp).
inline void share_direct_light(const VplSets& first, VplSets& draw) {
  const auto is_direct = [](const Vpl& vpl) { return vpl.kind != VplKind::surface; };
  for (std::size_t s = 0; s < std::min(first.sets.size(), draw.sets.size()); ++s) {
    const std::vector<Vpl>& from = first.sets[s];
    std::vector<Vpl>& to = draw.sets[s];
    if (std::count_if(from.begin(), from.end(), is_direct) != std::count_if(to.begin(), to.end(), is_direct)) continue;
    auto source = from.begin();
    for (Vpl& vpl : to) {
      if (!is_direct(vpl)) continue;
      source = std::find_if(source, from.end(), is_direct);
      vpl = *source++;
    }
  }
}

/// What a frame asks of the tile engine beyond scene, camera, settings and index.
struct FrameOptions {
  bool profile = false;      ///< Time each pipeline stage into the tiles' results.
  bool keep_layers = false;  ///< Tiles return their pixels' PixelLayers (what temporal reuse reads).
  float clamp_scale = 1.0f;  ///< Factor on the resolved clamp distance (temporal reuse shrinks it while the view stays still).
  /// Keep the previous frame's VPLs instead of drawing new ones (the camera moves through an
  /// unchanged scene: RenderSettings::held_vpl_frames); the first frame draws them anyway.
  bool keep_vpls = false;
  /// The frame index whose random numbers draw the VPLs when they are not kept; empty: the
  /// frame's own. A scene that changes under the same numbers moves its VPLs with the change
  /// instead of replacing them (RenderSettings::held_vpl_frames).
  std::optional<std::uint32_t> vpl_index = std::nullopt;
  /// Where in its cell each sub-sample's primary ray passes (subsample_offset; the centre by
  /// default; temporal reuse moves it from one still frame to the next, so they cover the pixel).
  glm::vec2 pixel_jitter{0.5f};
  /// Factor on the camera rays' cone (RenderSettings::filter_textures): temporal reuse of a still
  /// view spreads n frames' rays over each pixel, each with 1/n of its area.
  float texture_cone_scale = 1.0f;
  /// Temporal reuse's histories, whose shadow answers the frame's first hits may take
  /// (RenderSettings::reuse_shadows); borrowed for the frame; null: every shadow ray traced.
  const TemporalReuse* shadow_history = nullptr;
};

/// A pixel traces its delta lights' shadow rays again, whatever its history knows, in every
/// 8th frame (staggered by pixel): a shadow finer than a pixel that the four previous pixels
/// around a hit all missed is found within 8 frames, for an eighth of the rays.
inline constexpr std::uint32_t shadow_refresh_frames = 8;

/// One frame's shared, read-only inputs of the pipeline.
struct FrameState {
  const Scene* scene = nullptr;                ///< The scene as of this frame.
  SceneGeometry geometry;                      ///< The scene's instance matrices as of this frame.
  CutoutMeshes cutouts;                        ///< The scene's alpha cut-out meshes, which shadow rays pass where transparent.
  SeeThroughMeshes see_through;                ///< The scene's thin-walled glass and alpha-blended meshes, which shadow rays pass attenuated.
  std::optional<PinholeProjection> projection; ///< Primary-ray generator; empty before prepare.
  VplSets vpls;                                ///< This frame's VPL sets (S^2 of them).
  bool vpls_kept = false;                      ///< Whether vpls are a held draw (FrameOptions::keep_vpls).
  /// The draws of VPLs that the current run of frames keeping theirs cycles through
  /// (RenderSettings::held_vpl_sets): the first is the VPLs of the frame before the run, each
  /// other is drawn by the first frame that uses it, with that frame's random numbers. Empty while no run goes on.
  std::vector<std::pair<VplSets, std::uint32_t>> held_vpls;  ///< Each draw and the frame index whose random numbers drew it.
  int held_set = -1;  ///< Which of held_vpls the frame uses (-1: none, its VPLs are its own).
  std::uint32_t vpl_index = 0;  ///< The frame index whose random numbers drew vpls.
  /// The view whose openings aimed the particles of vpls (VplSettings::portal_view): the view of
  /// the first frame that drew with vpl_index's numbers; empty before the first frame.
  std::optional<PinholeProjection> portal_projection;
  RenderSettings settings;                     ///< Resolution, S, M, N, ...
  float clamp_distance = 0.0f;                 ///< Resolved minimum VPL distance.
  float ray_epsilon = 1e-4f;                   ///< ray_offset of the scene: how far rays start off surfaces.
  ToneMapping tone_mapping;                    ///< Parameters from the previous frame.
  std::uint32_t index = 0;                     ///< Frame index: what randomises the frame's samples.
  bool profile = false;                        ///< Time each stage into TileResult::stages (2-9% slower frames).
  bool keep_layers = false;                    ///< Tiles return their pixels' PixelLayers (TileResult::layers), for temporal reuse.
  glm::vec2 pixel_jitter{0.5f};                ///< Where in its cell each sub-sample's primary ray passes (FrameOptions::pixel_jitter).
  float texture_cone_scale = 1.0f;             ///< Factor on the camera rays' cone (FrameOptions::texture_cone_scale).
  std::vector<DeltaLightKey> delta_lights;     ///< This frame's delta lights, numbered as ShadowBits' bits.
  /// Whether first hits keep their delta lights' shadow answers for the next frame (with temporal
  /// reuse and RenderSettings::reuse_shadows; not with shadow-ray roulette or see-through surfaces,
  /// whose answers are not a plain yes or no).
  bool keeps_shadows = false;
  const TemporalReuse* shadow_history = nullptr;  ///< Where the previous frame's answers are (use_shadow_history); null: none.
  /// For each of delta_lights, its bit in shadow_history's answers (-1: that frame had no such light).
  std::array<std::int8_t, most_reused_shadow_lights> previous_shadow_bit{};

  /// Builds frame `index` of `scene` (committed in `backend`) seen by `camera`, to be tone mapped
  /// with `tone_mapping`: VPLs from `sampler`, whose walks shade their hits with the frame's own
  /// `surface` and `brdf` shaders, spread for glossy receivers by assign_vpl_radii, and clamp and ray offsets from the scene's world `bounds`
  /// (SceneBounds keeps them without walking every vertex each frame), the clamp times `clamp_scale`.
  /// With `keep_vpls` the frame takes the next of its run's held draws (held_vpls; if the frame
  /// prepared before has no VPLs, it draws anew); else they are drawn with the random numbers of
  /// frame `drawing_index` (empty: `index`).
  template <class B, class Surface, class Brdf, class Sampler>
    requires VplSampler<Sampler, B, Surface, Brdf>
  void prepare(const Scene& scene, const Bounds& bounds, const B& backend, const Surface& surface, const Brdf& brdf,
               const Sampler& sampler, const RenderSettings& frame_settings, const Camera& camera, std::uint32_t index,
               const ToneMapping& frame_tone_mapping, float clamp_scale = 1.0f, bool keep_vpls = false,
               std::optional<std::uint32_t> drawing_index = std::nullopt) {
    const PinholeProjection frame_projection(camera, frame_settings.width, frame_settings.height);
    const float diagonal = bounds.empty() ? 1.0f : glm::length(bounds.extent());
    const float frame_clamp = resolve_clamp(frame_settings, diagonal) * clamp_scale;
    const bool keep = keep_vpls && vpls.sets.size() == std::size_t(frame_settings.interleave * frame_settings.interleave);
    if (!keep) {
      held_vpls.clear();
      held_set = -1;
    } else {
      if (held_vpls.empty()) {
        held_vpls.emplace_back(vpls, vpl_index);  // the run's first draw: the frame before's
        held_set = 0;
      }
      held_set = (held_set + 1) % std::max(frame_settings.held_vpl_sets, 1);  // the first new draw first
    }
    vpls_kept = keep && std::size_t(held_set) < held_vpls.size();
    // With one draw the frame's VPLs already are that draw (nothing else drew since): no copy.
    if (vpls_kept && held_vpls.size() > 1) std::tie(vpls, vpl_index) = held_vpls[std::size_t(held_set)];
    if (!vpls_kept) {
      const FlushDenormals flush;  // as the tile tasks: VPLs are the same on every thread and process
      const VplView view{.projection = frame_projection, .clamp_distance = frame_clamp};
      // Drawing again with the numbers of the VPLs it replaces, a frame aims through the openings
      // those were aimed through: the same light walks, which a sampler choosing VPLs for the
      // view then chooses among for this frame's view.
      const bool same_numbers = drawing_index && *drawing_index == vpl_index && portal_projection;
      if (!same_numbers) portal_projection.emplace(frame_projection);
      const VplView portal_view{.projection = *portal_projection, .clamp_distance = frame_clamp};
      this->vpl_index = drawing_index.value_or(index);
      VplSettings vpl_settings = vpl_settings_for(frame_settings, this->vpl_index, bounds, &view);
      vpl_settings.portal_view = &portal_view;
      vpls = sampler.generate(scene, backend, surface, brdf, vpl_settings);
      if (keep) share_direct_light(held_vpls.front().first, vpls);
      assign_vpl_radii(vpls);
      if (keep) held_vpls.emplace_back(vpls, this->vpl_index);  // the run's next draw (held_set == its place)
    }
    cutouts = CutoutMeshes(scene);
    see_through = SeeThroughMeshes(scene);
    this->scene = &scene;
    geometry.update(scene);
    projection.emplace(frame_projection);
    settings = frame_settings;
    clamp_distance = frame_clamp;
    ray_epsilon = ray_offset(bounds);
    tone_mapping = frame_tone_mapping;
    this->index = index;
    profile = false;
    keep_layers = false;
    pixel_jitter = glm::vec2(0.5f);
    texture_cone_scale = 1.0f;
    delta_lights = delta_light_keys(vpls);
    keeps_shadows = settings.reuse_shadows && settings.temporal_frames > 0 && settings.shadow_roulette == 0.0f &&
                    !see_through.any() && !delta_lights.empty();
    shadow_history = nullptr;
  }
  /// Lets first hits take the shadow answers of `history`'s previous frame where it may be reused
  /// (TemporalReuse::shadows_reusable) and shares a light with this one; else, or with a null
  /// `history`, every shadow ray is traced.
  void use_shadow_history(const TemporalReuse* history) {
    shadow_history = nullptr;
    if (!keeps_shadows || history == nullptr || !history->shadows_reusable()) return;
    previous_shadow_bit = previous_shadow_bits(delta_lights, history->shadow_keys());
    if (std::any_of(previous_shadow_bit.begin(), previous_shadow_bit.end(), [](std::int8_t bit) { return bit >= 0; }))
      shadow_history = history;
  }
  /// This frame's bit of delta light `vpl` (-1 for a VPL that is no delta light, or one beyond the bits).
  int delta_light_bit(const Vpl& vpl) const noexcept {
    if (vpl.kind == VplKind::surface) return -1;
    const auto found = std::find(delta_lights.begin(), delta_lights.end(), DeltaLightKey::of(vpl));
    return found == delta_lights.end() ? -1 : int(found - delta_lights.begin());
  }
  /// True once prepare has run.
  bool prepared() const noexcept { return projection.has_value(); }
  /// VPLs in all sets.
  int vpl_count() const noexcept {
    int n = 0;
    for (const auto& set : vpls.sets) n += int(set.size());
    return n;
  }
};

}  // namespace igi
