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

namespace brdf_detail {

/// Mirror direction of `wo` about unit `n`.
template <int W>
vec3<W> reflect(const vec3<W>& wo, const vec3<W>& n) noexcept {
  return n * (vfloat<W>(2.0f) * dot(n, wo)) - wo;
}

/// Largest of the three components per lane.
template <int W>
vfloat<W> max_component(const vec3<W>& v) noexcept {
  return max(max(v.x, v.y), v.z);
}

}  // namespace brdf_detail

/// What every VPL's contribution to one packet of receivers shares, resolved once per packet by
/// `make_vpl_receiver` instead of once per VPL: the shading frame and the glossy lobe's parts that
/// do not depend on the VPL.
template <int W>
struct VplReceiver {
  vec3<W> normal;             ///< shading_frame_normal(hit, parameters): unit, towards wo.
  vec3<W> lobe_axis;          ///< wo mirrored about `normal`: the glossy lobe's axis.
  vfloat<W> half_shininess;   ///< 0.5 x the Phong exponent, the factor of the lobe's widening by a VPL's spread.
  vmask<W> glossy;            ///< Opaque lanes with a non-zero glossy reflectance (none: the two above are zero).
};

/// The VplReceiver of a packet of hits and their surface shader's parameters. Without glossy
/// lanes the lobe's parts are left zero (nothing reads them).
template <int W>
VplReceiver<W> make_vpl_receiver(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters) noexcept {
  VplReceiver<W> receiver;
  receiver.normal = shading_frame_normal(hit, parameters);
  receiver.glossy = parameters.opaque & (brdf_detail::max_component(parameters.glossy) > vfloat<W>(0.0f));
  if (any(receiver.glossy)) {
    receiver.lobe_axis = brdf_detail::reflect(hit.wo, receiver.normal);
    receiver.half_shininess = vfloat<W>(0.5f) * parameters.shininess;
  }
  return receiver;
}

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

/// A BRDF shader whose `add_vpl` also takes the packet's VplReceiver (made by make_vpl_receiver
/// from the same hit and parameters) in place of the hit, and then adds exactly what the hit
/// form adds. The pipeline makes the receiver once per packet and calls this form per VPL; for
/// shaders with only the hit form it calls that.
template <class B, int W>
concept ReceiverBrdfShader =
    BrdfShader<B, W> && requires(const B& brdf, const VplReceiver<W>& receiver, const BrdfParameters<W>& parameters,
                                 const VplGeometry<W>& geometry, const glm::vec3& intensity,
                                 VplAccumulator<W>& accumulator, const vmask<W>& mask) {
      { brdf.add_vpl(receiver, parameters, geometry, intensity, accumulator, mask) } -> std::same_as<void>;
    };

}  // namespace igi
