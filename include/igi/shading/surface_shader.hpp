#pragma once
/// \file
/// The surface-shader policy: the user-programmable part that turns hits into BRDF parameters
/// (textures, procedural patterns, bump mapping). It never traces rays.

#include <concepts>

#include "igi/shading/surface_hit.hpp"

namespace igi {

/// A surface shader maps W hits to BRDF parameters; lanes outside `mask` yield zeros.
/// Implementations provide `template <int W> BrdfParameters<W> shade(const SurfaceHit<W>&, const vmask<W>&) const`.
template <class S, int W>
concept SurfaceShader = requires(const S& shader, const SurfaceHit<W>& hit, const vmask<W>& mask) {
  { S::name() } -> std::convertible_to<const char*>;
  { shader.shade(hit, mask) } -> std::same_as<BrdfParameters<W>>;
};

}  // namespace igi
