#pragma once
/// \file
/// The BRDF-shader policy: the few, SIMD-optimised reflection models. It adds VPL contributions
/// to an accumulator and spawns the secondary (mirror, refraction) ray streams.

#include <concepts>

#include "igi/lighting/vpl.hpp"
#include "igi/shading/surface_hit.hpp"

namespace igi {

/// What W receivers gathered from VPLs. `irradiance` is filtered by the discontinuity buffer and
/// multiplied by albedo/pi afterwards (so textures stay sharp); `glossy` is the radiance of the
/// glossy lobe, which the BRDF shader has already weighted by its reflectance.
template <int W>
struct VplAccumulator {
  vec3<W> irradiance;  ///< Sum of intensity x falloff x cos(theta_x), before the diffuse BRDF.
  vec3<W> glossy;      ///< Radiance towards wo through the glossy lobe.
};

/// W secondary rays with the throughput they carry back to the pixel. They start at the hit point;
/// the tracer moves them off the surface by its ray offset (leave_surface in shading/constants.hpp).
template <int W>
struct SecondaryRays {
  vec3<W> direction;  ///< Unit directions.
  vec3<W> weight;     ///< Factor of the traced radiance in the parent's radiance.
  vmask<W> active;    ///< Lanes that carry a ray.
};

/// A BRDF shader. `add_vpl` adds one VPL's contribution to the lanes of `visible` (hits the VPL's
/// shadow ray did not block); `spawn` fills the reflection and refraction streams of the lanes of
/// `mask` and returns the lanes that spawned anything; `evaluate` is f_r(wo, wi) x cos(theta_i)
/// for the path tracer.
template <class B, int W>
concept BrdfShader = requires(const B& brdf, const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters,
                              const VplGeometry<W>& geometry, const glm::vec3& intensity,
                              VplAccumulator<W>& accumulator, SecondaryRays<W>& reflection,
                              SecondaryRays<W>& refraction, const vec3<W>& wi, const vmask<W>& mask) {
  { B::name() } -> std::convertible_to<const char*>;
  { brdf.add_vpl(hit, parameters, geometry, intensity, accumulator, mask) } -> std::same_as<void>;
  { brdf.spawn(hit, parameters, reflection, refraction, mask) } -> std::same_as<vmask<W>>;
  { brdf.evaluate(hit, parameters, wi, mask) } -> std::same_as<vec3<W>>;
};

}  // namespace igi
