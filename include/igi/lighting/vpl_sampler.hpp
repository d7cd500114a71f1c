#pragma once
/// \file
/// The VPL-sampler policy: per frame, the VPL sets from the scene's lights. A sampler walks the
/// scene with the frame's own surface shader and BRDF shader (one lane at a time), so the light
/// that bounces has the colours the camera sees. VPLs depend only on the scene, the shaders, the
/// settings and the frame index, never on the tile, thread or process.

#include <concepts>
#include <cstdint>

#include "igi/lighting/vpl.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/brdf_shader.hpp"
#include "igi/shading/surface_shader.hpp"

namespace igi {

/// The view a frame is rendered from, for samplers that place VPLs where the camera looks.
struct VplView {
  PinholeProjection projection;  ///< The frame's primary rays (camera and image size).
  float clamp_distance = 0.0f;   ///< The frame's resolved minimum VPL distance in 1/d^2.
};

/// Settings of one frame's VPL generation.
struct VplSettings {
  int sets = 9;                  ///< Interleaving sets, S^2.
  int vpls_per_set = 16;         ///< M: VPLs each pixel connects to.
  std::uint32_t frame = 0;       ///< Frame index: the randomisation of the QMC sequence.
  std::uint32_t seed = 0;        ///< User seed.
  int max_bounces = 32;          ///< Longest random walk (Russian roulette usually ends it first; RenderSettings::max_bounces says why 32).
  int environment_directions = 32; ///< Directional VPLs of the environment's direct light, shared by every set (RenderSettings::environment_directions).
  float portal_share = 0.7f;     ///< Share of the sun's, the sky's and outside emitters' particles aimed through the view's openings (RenderSettings::portal_share says why 0.7).
  Bounds scene_bounds{};         ///< The scene's world bounds this frame (for lights at infinity); empty: the sampler computes them.
  const VplView* view = nullptr; ///< The frame's view, borrowed for one generate call; samplers that do not look at the camera ignore it.
  /// The view whose openings the particles are aimed through (find_portals), borrowed as `view`;
  /// null: `view`. A run of frames drawing with the same numbers keeps its first view's, so that
  /// its light walks stay the same while a sampler chooses among them for each view.
  const VplView* portal_view = nullptr;
};

/// A VPL sampler: `generate(scene, tracer, surface, brdf, settings)` returns `settings.sets` sets
/// of about `vpls_per_set` VPLs each, shading the hits of its walks with `surface` and scattering
/// them with `brdf`. `Tracer` is any Backend (used with single rays); the shaders are the frame's
/// policies, used at width 1.
template <class V, class Tracer, class Surface, class Brdf>
concept VplSampler = SurfaceShader<Surface, 1> && BrdfShader<Brdf, 1> &&
                     requires(const V& sampler, const Scene& scene, const Tracer& tracer, const Surface& surface,
                              const Brdf& brdf, const VplSettings& settings) {
                       { V::name() } -> std::convertible_to<const char*>;
                       { sampler.generate(scene, tracer, surface, brdf, settings) } -> std::same_as<VplSets>;
                     };

/// Whether `sampler` chooses its VPLs for the frame's view (VplSettings::view), so that they fit
/// no other view: a sampler says so with a member `chooses_for_view()`; one without it does not.
/// A moving camera's frames draw such VPLs anew, with the random numbers of those they replace,
/// instead of keeping them (Renderer::render).
template <class V>
constexpr bool chooses_for_view(const V& sampler) noexcept {
  if constexpr (requires {
                  { sampler.chooses_for_view() } -> std::convertible_to<bool>;
                })
    return sampler.chooses_for_view();
  else
    return false;
}

}  // namespace igi
