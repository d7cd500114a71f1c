#pragma once
/// \file
/// The VPL-sampler policy: per frame, the VPL sets from the scene's lights. VPLs depend only on
/// the scene, the settings and the frame index, never on the tile, thread or process.

#include <concepts>
#include <cstdint>

#include "igi/lighting/vpl.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Settings of one frame's VPL generation.
struct VplSettings {
  int sets = 9;                  ///< Interleaving sets, S^2.
  int vpls_per_set = 16;         ///< M: VPLs each pixel connects to.
  std::uint32_t frame = 0;       ///< Frame index: the randomisation of the QMC sequence.
  std::uint32_t seed = 0;        ///< User seed.
  int max_bounces = 8;           ///< Longest random walk (Russian roulette usually ends it first).
  Bounds scene_bounds{};         ///< The scene's world bounds this frame (for lights at infinity); empty: the sampler computes them.
};

/// A VPL sampler: `generate(scene, tracer, settings)` returns `settings.sets` sets of about
/// `vpls_per_set` VPLs each. `Tracer` is any Backend (used with single rays).
template <class V, class Tracer>
concept VplSampler = requires(const V& sampler, const Scene& scene, const Tracer& tracer, const VplSettings& settings) {
  { V::name() } -> std::convertible_to<const char*>;
  { sampler.generate(scene, tracer, settings) } -> std::same_as<VplSets>;
};

}  // namespace igi
