#pragma once
/// \file
/// Hit points as the shaders see them (`SurfaceHit<W>`), and what a surface shader hands the BRDF
/// shader (`BrdfParameters<W>`). Both are structure-of-arrays packets; inactive lanes hold zeros.

#include <concepts>

#include "igi/simd/simd.hpp"

namespace igi {

/// W ray hits in world space, ready for shading.
template <int W>
struct SurfaceHit {
  vec3<W> position;          ///< World-space hit point.
  vec3<W> geometric_normal;  ///< Unit triangle normal, flipped to face the incoming ray.
  vec3<W> shading_normal;    ///< Unit interpolated vertex normal, in the hemisphere of geometric_normal.
  vec3<W> wo;                ///< Unit direction from the hit back towards the ray origin.
  ///@{
  vfloat<W> u, v;            ///< Texture coordinates (TEXCOORD_0), 0 without them.
  ///@}
  /// World-space derivative of the position along u (normal maps' tangent), turned along the mesh's
  /// TANGENT where it has one; 0 without texture coordinates or tangents.
  vec3<W> dpdu;
  vec3<W> dpdv;  ///< Likewise along v (against the TANGENT's bitangent where there is one).
  /// Width of the ray's footprint at the hit in texture coordinates: its cone's width there,
  /// spread over the surface (over sqrt of the cosine to wo: the same area as the slanted
  /// ellipse), times the triangle's texture coordinates per unit of length. 0 for a ray without
  /// a cone (light walks, gather and path-traced rays): textures are then read at full resolution.
  vfloat<W> texture_footprint;
  vfloat<W> distance;        ///< Ray parameter of the hit (depth for the filter).
  vint<W> material;          ///< Index into Scene::materials, -1 for the default material.
  vint<W> mesh;              ///< Index into Scene::meshes.
  vint<W> instance;          ///< Index into Scene::instances.
  vint<W> triangle;          ///< Triangle index within the mesh.
  vmask<W> front_face;       ///< True where the ray hit the side the triangle's winding faces.

  /// Takes every field of `from` in the lanes of `mask`, keeps this packet's elsewhere.
  void assign(const SurfaceHit& from, const vmask<W>& mask) noexcept {
    position.assign(from.position, mask);
    geometric_normal.assign(from.geometric_normal, mask);
    shading_normal.assign(from.shading_normal, mask);
    wo.assign(from.wo, mask);
    u.assign(from.u, mask);
    v.assign(from.v, mask);
    dpdu.assign(from.dpdu, mask);
    dpdv.assign(from.dpdv, mask);
    texture_footprint.assign(from.texture_footprint, mask);
    distance.assign(from.distance, mask);
    material.assign(from.material, mask);
    mesh.assign(from.mesh, mask);
    instance.assign(from.instance, mask);
    triangle.assign(from.triangle, mask);
    front_face = (front_face & !mask) | (from.front_face & mask);
  }
};

/// Per-lane inputs of the BRDF shader, written by a surface shader.
template <int W>
struct BrdfParameters {
  vec3<W> albedo;          ///< Diffuse (Lambert) reflectance, linear RGB in [0, 1].
  vec3<W> glossy;          ///< Phong-lobe reflectance (energy-normalised lobe), linear RGB.
  vfloat<W> shininess;     ///< Phong exponent of the glossy lobe.
  vec3<W> mirror;          ///< Perfect-mirror reflectance, linear RGB.
  vfloat<W> transmission;  ///< Fraction of non-mirror light refracted by a dielectric (glass), [0, 1].
  vfloat<W> ior;           ///< Index of refraction of the dielectric.
  vec3<W> normal;          ///< Unit shading normal after bump mapping.
  vec3<W> emission;        ///< Emitted radiance towards wo.
  vmask<W> opaque;         ///< False where an alpha-mask cut-out lets the ray pass through.
  /// True where the transmission is thin-walled (glTF's, without a volume): light passes
  /// straight through, tinted by transmission_tint; false where it refracts into a solid.
  vmask<W> thin_walled;
  vec3<W> transmission_tint;  ///< Colour thin-walled transmission is filtered by (the base colour); read only where thin_walled.
  /// Fraction of light that passes on as if the surface were not there (1 - alpha of alphaMode
  /// BLEND; the other parameters then carry alpha's share); 0 on a solid surface.
  vfloat<W> pass_through;

  /// Takes every field of `from` in the lanes of `mask`, keeps this packet's elsewhere.
  void assign(const BrdfParameters& from, const vmask<W>& mask) noexcept {
    albedo.assign(from.albedo, mask);
    glossy.assign(from.glossy, mask);
    shininess.assign(from.shininess, mask);
    mirror.assign(from.mirror, mask);
    transmission.assign(from.transmission, mask);
    ior.assign(from.ior, mask);
    normal.assign(from.normal, mask);
    emission.assign(from.emission, mask);
    opaque = (opaque & !mask) | (from.opaque & mask);
    thin_walled = (thin_walled & !mask) | (from.thin_walled & mask);
    transmission_tint.assign(from.transmission_tint, mask);
    pass_through.assign(from.pass_through, mask);
  }
};

/// The unit normal shading uses: the surface shader's, or the geometric one where that is not
/// a usable unit vector (zero, NaN) or faces away from wo. The BRDF shaders' cosines and the
/// pipeline's gather rays all take it.
template <int W>
vec3<W> shading_frame_normal(const SurfaceHit<W>& hit, const BrdfParameters<W>& parameters) noexcept {
  const vfloat<W> length2 = length_squared(parameters.normal);
  // A unit normal has length^2 = 1; anything far from it (zero, or NaN which fails every
  // comparison) is replaced. 0.25 separates "zero or broken" from "unit up to rounding".
  const vmask<W> usable = (length2 > vfloat<W>(0.25f)) & (dot(parameters.normal, hit.wo) > vfloat<W>(0.0f));
  return select(usable, normalize(parameters.normal), hit.geometric_normal);
}

/// `a` in the lanes of `mask`, `b` elsewhere, for SurfaceHit and BrdfParameters alike.
template <class Packet, int W>
  requires std::same_as<Packet, SurfaceHit<W>> || std::same_as<Packet, BrdfParameters<W>>
Packet select(const vmask<W>& mask, const Packet& a, const Packet& b) noexcept {
  Packet result = b;
  result.assign(a, mask);
  return result;
}

}  // namespace igi
