#pragma once
/// \file
/// The BRDF shaders: Lambert, energy-normalised Phong, perfect mirror, dielectric glass, and
/// `StandardBrdf`, which applies all of them lane by lane as the surface shader's parameters say
/// (the renderer's default). All contributions are computed on packets under masks; inactive
/// lanes, lanes the VPL does not reach and alpha cut-outs add nothing. No input (zero normals,
/// grazing angles, zero-length vectors, odd ior) produces NaN or Inf.
///
/// Models, per lane, with n the shading normal and wo, wi unit directions:
/// - diffuse: f = albedo / pi;
/// - glossy (modified Phong, energy-normalised): f = glossy (s + 2) / (2 pi) max(0, r.wi)^s with
///   r = 2 (n.wo) n - wo, so a white lobe reflects at most all energy at normal incidence;
/// - mirror: a reflection ray with weight `mirror`;
/// - glass: a dielectric interface with the exact unpolarised Fresnel reflectance
///   F = (r_s^2 + r_p^2) / 2 (exact rather than Schlick: the few more multiplies are nothing
///   next to a traced ray, and Schlick is poor for light leaving the denser medium near the
///   critical angle); reflection weight transmission x F, refraction weight transmission x (1 - F),
///   and all of it reflected under total internal reflection. The ray enters the medium on front
///   faces (eta = 1 / ior) and leaves it on back faces (eta = ior);
/// - thin-walled glass (glTF transmission without a volume): the same Fresnel reflection, and
///   light passing straight on with weight transmission x (1 - F) x base colour; alpha-blended
///   surfaces pass 1 - alpha straight on too (straight_transmittance).

#include <cmath>
#include <cstdint>
#include <limits>

#include <glm/glm.hpp>

#include "igi/lighting/vpl.hpp"
#include "igi/shading/brdf_shader.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/surface_hit.hpp"

namespace igi {

namespace brdf_detail {

/// The diffuse part: irradiance += intensity x falloff x cos(theta_x), given falloff x cos(theta_x).
template <int W>
void add_irradiance(const vfloat<W>& transfer, const glm::vec3& intensity, VplAccumulator<W>& accumulator,
                    const vmask<W>& mask) noexcept {
  accumulator.irradiance += keep(vec3<W>(intensity) * transfer, mask);
}

/// falloff x cos(theta_x) of one VPL at receivers of unit normal `n`: what the diffuse and glossy parts share.
template <int W>
vfloat<W> vpl_transfer(const vec3<W>& n, const VplGeometry<W>& geometry) noexcept {
  return geometry.falloff * max(dot(n, geometry.wi), vfloat<W>(0.0f));
}

/// x^s for x in [0, 1] and s >= 0 on packets, as exp2(s log2 x) with series for both (the
/// library pow loops over scalars and costs 5x more). Relative error below 2e-6 x (1 + s |ln x|)
/// down to 2^-64, zero below:
/// the logarithm comes from atanh's series on a mantissa folded into [1/sqrt2, sqrt2), the
/// exponential from e^z's Taylor series on z in [0, ln 2).
template <int W>
vfloat<W> pow_unit(const vfloat<W>& x, const vfloat<W>& s) noexcept {
  const vfloat<W> one(1.0f);
  // Smallest normal float: below it (and for x = 0) the result is 0 unless s = 0.
  const vmask<W> positive = x >= vfloat<W>(0x1p-126f);
  const vfloat<W> safe = select(positive, min(x, one), one);
  const vuint<W> bits = bit_cast<std::uint32_t>(safe);
  // Exponent and mantissa in [1, 2) from the IEEE 754 fields (8 exponent bits, bias 127, 23 mantissa bits).
  vfloat<W> exponent = convert<float>(bit_cast<std::int32_t>(bits >> 23)) - vfloat<W>(127.0f);
  vfloat<W> mantissa = bit_cast<float>((bits & vuint<W>(0x007fffffu)) | vuint<W>(0x3f800000u));
  // Fold into [1/sqrt2, sqrt2) so that x near 1 has no cancellation between exponent and mantissa.
  const vmask<W> high = mantissa > vfloat<W>(1.41421356f);
  mantissa = select(high, mantissa * vfloat<W>(0.5f), mantissa);
  exponent = select(high, exponent + one, exponent);
  // ln m = 2 atanh(t), t = (m - 1) / (m + 1) in (-0.172, 0.172): terms to t^9 leave < 1e-9.
  const vfloat<W> t = (mantissa - one) / (mantissa + one), t2 = t * t;
  const vfloat<W> series =
      one + t2 * (vfloat<W>(1.0f / 3.0f) + t2 * (vfloat<W>(1.0f / 5.0f) + t2 * (vfloat<W>(1.0f / 7.0f) + t2 * vfloat<W>(1.0f / 9.0f))));
  const vfloat<W> ln2(0.693147181f);
  const vfloat<W> log2_x = exponent + vfloat<W>(2.0f) * t * series / ln2;
  // 2^y for y <= 0. Below 2^-64 (5e-20, invisible in any image) the result is flushed to 0:
  // tiny lobe values would otherwise turn into denormals in the products that follow, and
  // denormal arithmetic runs about 100 times slower.
  const vfloat<W> raw_y = s * log2_x;
  const vmask<W> vanishing = raw_y < vfloat<W>(-64.0f);
  const vfloat<W> y = max(raw_y, vfloat<W>(-64.0f));
  const vfloat<W> whole = floor(y);
  const vfloat<W> z = (y - whole) * ln2;  // in [0, ln 2)
  // e^z to z^7 / 7!: the next term is below 0.7^8 / 8! = 1.5e-6.
  const vfloat<W> e_z =
      one + z * (one + z * (vfloat<W>(1.0f / 2) + z * (vfloat<W>(1.0f / 6) + z * (vfloat<W>(1.0f / 24) +
              z * (vfloat<W>(1.0f / 120) + z * (vfloat<W>(1.0f / 720) + z * vfloat<W>(1.0f / 5040))))))) ;
  const vfloat<W> scale = bit_cast<float>((convert<std::int32_t>(whole) + vint<W>(127)) << 23);
  const vfloat<W> result = e_z * scale;
  return select(positive & !vanishing, result, select(s == vfloat<W>(0.0f), one, vfloat<W>(0.0f)));
}

/// The glossy lobe value f_glossy / glossy at `wi` (without the reflectance colour) about the lobe's
/// axis (wo mirrored about the shading normal).
template <int W>
vfloat<W> phong_lobe_about(const vec3<W>& axis, const vfloat<W>& shininess, const vec3<W>& wi) noexcept {
  const vfloat<W> s = max(select(isfinite(shininess), shininess, vfloat<W>(1.0f)), vfloat<W>(0.0f));
  const vfloat<W> alignment = clamp(dot(axis, wi), vfloat<W>(0.0f), vfloat<W>(1.0f));
  return (s + vfloat<W>(2.0f)) * vfloat<W>(0.5f * inv_pi) * pow_unit(alignment, s);
}

/// The glossy lobe value f_glossy / glossy at `wi` for shading normal `n` and outgoing direction `wo`.
template <int W>
vfloat<W> phong_lobe(const vec3<W>& n, const vec3<W>& wo, const vfloat<W>& shininess, const vec3<W>& wi) noexcept {
  return phong_lobe_about(reflect(wo, n), shininess, wi);
}

/// The glossy part: glossy += intensity x glossy x min(falloff x cos(theta_x) x lobe, transfer_limit),
/// given `transfer` = falloff x cos(theta_x).
/// The lobe is that of a VPL spread over its sphere (VplGeometry::spread): the Phong lobe
/// cos^s, close to a Gaussian of angular variance 1/s, seen through a cone of half-angle a adds
/// about a^2 / 2 to that variance, so its exponent becomes s / (1 + s sin^2(a) / 2), the lobe
/// stays normalised (energy is kept, the highlight widens to the light the VPL stands for). Then
/// what is left sharper than the clamp admits is cut to the bound a diffuse receiver has, so no
/// single VPL makes a firefly on a glossy surface.
template <int W>
void add_glossy(const VplReceiver<W>& receiver, const BrdfParameters<W>& parameters, const vfloat<W>& transfer,
                const VplGeometry<W>& geometry, const glm::vec3& intensity, VplAccumulator<W>& accumulator,
                const vmask<W>& mask) noexcept {
  const vmask<W> lanes = mask & receiver.glossy;
  if (none(lanes)) return;
  const vfloat<W> shininess = parameters.shininess / (vfloat<W>(1.0f) + receiver.half_shininess * geometry.spread);
  const vfloat<W> scale = min(transfer * phong_lobe_about(receiver.lobe_axis, shininess, geometry.wi),
                              vfloat<W>(geometry.transfer_limit));
  accumulator.glossy += keep(vec3<W>(intensity) * parameters.glossy * scale, lanes);
}

/// f_r x cos(theta_i) of the diffuse and glossy parts.
template <int W>
vec3<W> evaluate_diffuse_glossy(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const vec3<W>& wi,
                                bool with_glossy, const vmask<W>& mask) noexcept {
  const vec3<W> n = shading_frame_normal(hit, parameters);
  const vec3<W> unit_wi = normalize(wi);
  const vfloat<W> cosine = dot(n, unit_wi);
  // Light from below the geometric surface cannot reach a one-sided reflector.
  const vmask<W> lanes = mask & parameters.opaque & (cosine > vfloat<W>(0.0f)) &
                         (dot(hit.geometric_normal, unit_wi) > vfloat<W>(0.0f));
  vec3<W> f = parameters.albedo * vfloat<W>(inv_pi);
  if (with_glossy) f += parameters.glossy * phong_lobe(n, hit.wo, parameters.shininess, unit_wi);
  return keep(f * cosine, lanes);
}

/// The exact unpolarised Fresnel reflectance F = (r_s^2 + r_p^2) / 2 of a dielectric interface
/// for light at `cos_i` (in [0, 1]) to its normal, `eta` the ratio of the indices of refraction
/// (incident side over far side); 1 under total internal reflection. `cos_t` gets the refracted
/// ray's cosine (0 under total internal reflection).
template <int W>
vfloat<W> dielectric_fresnel(const vfloat<W>& cos_i, const vfloat<W>& eta, vfloat<W>& cos_t) noexcept {
  const vfloat<W> zero(0.0f), one(1.0f);
  const vfloat<W> sin2_t = eta * eta * (one - cos_i * cos_i);
  const vmask<W> total_internal = sin2_t >= one;
  cos_t = sqrt(max(one - sin2_t, zero));
  // Denominators vanish only when both cosines are 0 (grazing at the critical angle); the
  // floor keeps the ratio finite there, where the limit is total reflection anyway.
  const vfloat<W> tiny(1e-12f);
  const vfloat<W> r_s = (eta * cos_i - cos_t) / max(eta * cos_i + cos_t, tiny);
  const vfloat<W> r_p = (cos_i - eta * cos_t) / max(cos_i + eta * cos_t, tiny);
  return select(total_internal, one, clamp(vfloat<W>(0.5f) * (r_s * r_s + r_p * r_p), zero, one));
}

/// `parameters.ior`, with a non-positive or non-finite ior taken as glTF's default 1.5.
template <int W>
vfloat<W> usable_ior(const BrdfParameters<W>& parameters) noexcept {
  const vfloat<W>& raw = parameters.ior;
  return select(isfinite(raw) & (raw > vfloat<W>(0.0f)), raw, vfloat<W>(1.5f));
}

/// What of a thin wall's transmission `t` (in [0, 1]) passes it on the lanes of `thin`, light
/// at `cos_i` to its normal: t x (1 - F) x transmission_tint, F the Fresnel reflectance of one
/// interface from air (eta = 1 / ior on either face). One interface, not a slab's two with their
/// inter-reflections ((1 - F) / (1 + F)): glTF defines a thin wall's BSDF by its surface's
/// Fresnel mix alone, so a pane passes what it passes in every glTF viewer, and reflection F plus
/// transmission 1 - F keep its energy. `fresnel` gets F on those lanes.
template <int W>
vec3<W> thin_wall_transmittance(const BrdfParameters<W>& parameters, const vfloat<W>& t, const vfloat<W>& cos_i,
                                vfloat<W>& fresnel, const vmask<W>& thin) noexcept {
  vfloat<W> cos_t;
  const vfloat<W> f = dielectric_fresnel(cos_i, vfloat<W>(1.0f) / usable_ior(parameters), cos_t);
  fresnel = select(thin, f, fresnel);
  return keep(parameters.transmission_tint * (t * (vfloat<W>(1.0f) - f)), thin);
}

/// The clamped transmission weight of `transmission` (NaN counts as none).
template <int W>
vfloat<W> usable_transmission(const vfloat<W>& transmission) noexcept {
  const vfloat<W> zero(0.0f);
  return clamp(select(isfinite(transmission), transmission, zero), zero, vfloat<W>(1.0f));
}

/// Mirror reflection and dielectric refraction streams with weights
/// reflection = mirror + transmission x F, refraction = transmission x (1 - F). Where the
/// transmission is thin-walled (and where the surface passes light on: pass_through), the
/// "refraction" goes straight on (-wo) with weight pass_through + transmission x (1 - F) x
/// transmission_tint (thin_wall_transmittance); a solid's refraction is then not added (the glTF
/// shader makes any blended transmission thin-walled).
template <int W>
vmask<W> spawn_specular(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const vec3<W>& mirror,
                        const vfloat<W>& transmission, SecondaryRays<W>& reflection,
                        SecondaryRays<W>& refraction, const vmask<W>& mask) noexcept {
  reflection = {};
  refraction = {};
  const vmask<W> lanes = mask & parameters.opaque;
  if (none(lanes)) return lanes;
  const vec3<W> n = shading_frame_normal(hit, parameters);
  const vec3<W>& geometric = hit.geometric_normal;
  const vfloat<W> zero(0.0f), one(1.0f);

  // Reflection about the shading normal; where that dips below the surface, about the geometric one.
  vec3<W> reflected = normalize(reflect(hit.wo, n));
  reflected = select(dot(reflected, geometric) > zero, reflected, normalize(reflect(hit.wo, geometric)));

  // Dielectric interface.
  const vfloat<W> t = usable_transmission(transmission);
  const vmask<W> glass = lanes & (t > zero);
  const vmask<W> thin = glass & parameters.thin_walled;
  const vmask<W> straight = thin | (lanes & (parameters.pass_through > zero));
  vec3<W> refracted;
  vec3<W> transmitted;
  vfloat<W> fresnel(0.0f);
  const vfloat<W> cos_i = clamp(dot(n, hit.wo), zero, one);
  const vmask<W> solid = glass & !straight;
  if (any(solid)) {
    const vfloat<W> ior = usable_ior(parameters);
    const vfloat<W> eta = select(hit.front_face, one / ior, ior);
    vfloat<W> cos_t;
    fresnel = dielectric_fresnel(cos_i, eta, cos_t);
    refracted = normalize(n * (eta * cos_i - cos_t) - hit.wo * eta);
    const vfloat<W> weight = t * (one - fresnel);
    transmitted = vec3<W>(weight, weight, weight);
  }
  if (any(straight)) {
    const vfloat<W> passed = clamp(parameters.pass_through, zero, one);
    const vec3<W> straight_weight =
        vec3<W>(passed, passed, passed) + (any(thin) ? thin_wall_transmittance(parameters, t, cos_i, fresnel, thin) : vec3<W>());
    transmitted = select(straight, straight_weight, transmitted);
    refracted = select(straight, -hit.wo, refracted);
  }
  reflection.weight = keep(mirror + vec3<W>(glm::vec3(1.0f)) * (t * keep(fresnel, glass)), lanes);
  reflection.direction = reflected;
  reflection.active = lanes & (max_component(reflection.weight) > zero);

  refraction.weight = keep(transmitted, solid | straight);
  refraction.direction = refracted;
  refraction.active = (solid | straight) & (max_component(refraction.weight) > zero) & (length_squared(refracted) > zero);

  reflection.direction = keep(reflection.direction, reflection.active);
  reflection.weight = keep(reflection.weight, reflection.active);
  refraction.direction = keep(refraction.direction, refraction.active);
  refraction.weight = keep(refraction.weight, refraction.active);
  return reflection.active | refraction.active;
}

}  // namespace brdf_detail

/// What passes the lanes of `mask` of a surface straight on along -wo, per channel:
/// pass_through plus, where the transmission is thin-walled, thin_wall_transmittance at wo's
/// angle to the shading normal (the same on both faces, and the same for light going either
/// way); 0 on a solid surface, also where a cut-out is opaque. A transparent cut-out's lanes
/// (not opaque) pass everything. What shadow rays and the path tracer's light rays multiply by
/// at every see-through surface they cross.
template <int W>
vec3<W> straight_transmittance(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const vmask<W>& mask) noexcept {
  const vfloat<W> zero(0.0f), one(1.0f);
  const vmask<W> solid = mask & parameters.opaque;
  const vfloat<W> passed = keep(clamp(parameters.pass_through, zero, one), solid);
  vec3<W> result(passed, passed, passed);
  const vfloat<W> t = brdf_detail::usable_transmission(parameters.transmission);
  const vmask<W> thin = solid & parameters.thin_walled & (t > zero);
  if (any(thin)) {
    const vfloat<W> cos_i = clamp(dot(shading_frame_normal(hit, parameters), hit.wo), zero, one);
    vfloat<W> fresnel(0.0f);
    result += brdf_detail::thin_wall_transmittance(parameters, t, cos_i, fresnel, thin);
  }
  const vmask<W> cut = mask & !parameters.opaque;
  return select(cut, vec3<W>(one, one, one), result);
}

/// Lambertian reflection: gathers irradiance, spawns nothing.
class LambertBrdf {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "lambert"; }
  /// irradiance += intensity x falloff x cos(theta_x) on the lanes of `mask`.
  template <int W>
  void add_vpl(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const VplGeometry<W>& geometry,
               const glm::vec3& intensity, VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    add_vpl(make_vpl_receiver(hit, parameters), parameters, geometry, intensity, accumulator, mask);
  }
  /// The same with the packet's shading frame resolved once for all its VPLs.
  template <int W>
  void add_vpl(const VplReceiver<W>& receiver, const BrdfParameters<W>& parameters, const VplGeometry<W>& geometry,
               const glm::vec3& intensity, VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    brdf_detail::add_irradiance(brdf_detail::vpl_transfer(receiver.normal, geometry), intensity, accumulator,
                                mask & parameters.opaque);
  }
  /// No secondary rays.
  template <int W>
  vmask<W> spawn(const SurfaceHit<W>&, const BrdfParameters<W>&, SecondaryRays<W>& reflection,
                 SecondaryRays<W>& refraction, const vmask<W>&) const noexcept {
    reflection = {};
    refraction = {};
    return vmask<W>(false);
  }
  /// albedo / pi x cos(theta_i).
  template <int W>
  vec3<W> evaluate(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const vec3<W>& wi,
                   const vmask<W>& mask) const noexcept {
    return brdf_detail::evaluate_diffuse_glossy(hit, parameters, wi, false, mask);
  }
};

/// Lambert plus an energy-normalised Phong lobe; the lobe's VPL radiance goes to `glossy`.
class PhongBrdf {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "phong"; }
  /// Irradiance as LambertBrdf, and glossy += intensity x falloff x cos(theta_x) x f_glossy(wo, wi).
  template <int W>
  void add_vpl(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const VplGeometry<W>& geometry,
               const glm::vec3& intensity, VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    add_vpl(make_vpl_receiver(hit, parameters), parameters, geometry, intensity, accumulator, mask);
  }
  /// The same with the packet's shading frame and lobe axis resolved once for all its VPLs.
  template <int W>
  void add_vpl(const VplReceiver<W>& receiver, const BrdfParameters<W>& parameters, const VplGeometry<W>& geometry,
               const glm::vec3& intensity, VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    const vmask<W> lanes = mask & parameters.opaque;
    const vfloat<W> transfer = brdf_detail::vpl_transfer(receiver.normal, geometry);
    brdf_detail::add_irradiance(transfer, intensity, accumulator, lanes);
    brdf_detail::add_glossy(receiver, parameters, transfer, geometry, intensity, accumulator, lanes);
  }
  /// No secondary rays.
  template <int W>
  vmask<W> spawn(const SurfaceHit<W>&, const BrdfParameters<W>&, SecondaryRays<W>& reflection,
                 SecondaryRays<W>& refraction, const vmask<W>&) const noexcept {
    reflection = {};
    refraction = {};
    return vmask<W>(false);
  }
  /// (albedo / pi + f_glossy) x cos(theta_i).
  template <int W>
  vec3<W> evaluate(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const vec3<W>& wi,
                   const vmask<W>& mask) const noexcept {
    return brdf_detail::evaluate_diffuse_glossy(hit, parameters, wi, true, mask);
  }
};

/// What the delta BRDFs (mirror, glass) share: no light from VPLs, nothing to evaluate.
class DeltaBrdf {
 public:
  /// A delta BRDF gathers nothing from point lights.
  template <int W>
  void add_vpl(const SurfaceHit<W>&, const BrdfParameters<W>&, const VplGeometry<W>&, const glm::vec3&,
               VplAccumulator<W>&, const vmask<W>&) const noexcept {}
  /// Nothing either, from a resolved receiver.
  template <int W>
  void add_vpl(const VplReceiver<W>&, const BrdfParameters<W>&, const VplGeometry<W>&, const glm::vec3&,
               VplAccumulator<W>&, const vmask<W>&) const noexcept {}
  /// Zero: a delta lobe has no density to evaluate.
  template <int W>
  vec3<W> evaluate(const SurfaceHit<W>&, const BrdfParameters<W>&, const vec3<W>&, const vmask<W>&) const noexcept {
    return {};
  }
};

/// A perfect mirror of reflectance `parameters.mirror`: no VPL light, one reflection ray.
class MirrorBrdf : public DeltaBrdf {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "mirror"; }
  /// Reflection rays of weight `mirror` on the lanes of `mask` with a non-zero mirror colour.
  template <int W>
  vmask<W> spawn(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, SecondaryRays<W>& reflection,
                 SecondaryRays<W>& refraction, const vmask<W>& mask) const noexcept {
    return brdf_detail::spawn_specular(hit, parameters, parameters.mirror, vfloat<W>(0.0f), reflection, refraction, mask);
  }
};

/// A clear dielectric interface of index `parameters.ior`: Fresnel reflection and refraction.
class GlassBrdf : public DeltaBrdf {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "glass"; }
  /// Reflection (weight F) and refraction (weight 1 - F) rays; reflection only under total internal reflection.
  template <int W>
  vmask<W> spawn(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, SecondaryRays<W>& reflection,
                 SecondaryRays<W>& refraction, const vmask<W>& mask) const noexcept {
    return brdf_detail::spawn_specular(hit, parameters, vec3<W>(), vfloat<W>(1.0f), reflection, refraction, mask);
  }
};

/// Everything at once, lane by lane: diffuse and glossy VPL light, mirror reflection and glass
/// by `mirror`, `transmission` and `ior`. The renderer's default BRDF shader.
class StandardBrdf {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "standard"; }
  /// Diffuse irradiance and glossy radiance of one VPL on the lanes of `mask`.
  template <int W>
  void add_vpl(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const VplGeometry<W>& geometry,
               const glm::vec3& intensity, VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    PhongBrdf{}.add_vpl(hit, parameters, geometry, intensity, accumulator, mask);
  }
  /// The same with the packet's shading frame and lobe axis resolved once for all its VPLs.
  template <int W>
  void add_vpl(const VplReceiver<W>& receiver, const BrdfParameters<W>& parameters, const VplGeometry<W>& geometry,
               const glm::vec3& intensity, VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    PhongBrdf{}.add_vpl(receiver, parameters, geometry, intensity, accumulator, mask);
  }
  /// Reflection (mirror + transmission x F) and refraction (transmission x (1 - F)) rays.
  template <int W>
  vmask<W> spawn(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, SecondaryRays<W>& reflection,
                 SecondaryRays<W>& refraction, const vmask<W>& mask) const noexcept {
    return brdf_detail::spawn_specular(hit, parameters, parameters.mirror, parameters.transmission, reflection,
                                       refraction, mask);
  }
  /// (albedo / pi + f_glossy) x cos(theta_i); the mirror and glass parts are deltas and not included.
  template <int W>
  vec3<W> evaluate(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters, const vec3<W>& wi,
                   const vmask<W>& mask) const noexcept {
    return brdf_detail::evaluate_diffuse_glossy(hit, parameters, wi, true, mask);
  }
};

}  // namespace igi
