#pragma once
/// \file
/// Hit points as the shaders see them (`SurfaceHit<W>`), and what a surface shader hands the BRDF
/// shader (`BrdfParameters<W>`). Both are structure-of-arrays packets; inactive lanes hold zeros.

#include "igi/simd/simd.hpp"

namespace igi {

/// W ray hits in world space, ready for shading.
template <int W>
struct SurfaceHit {
  vec3<W> position;          ///< World-space hit point.
  vec3<W> geometric_normal;  ///< Unit triangle normal, flipped to face the incoming ray.
  vec3<W> shading_normal;    ///< Unit interpolated vertex normal, in the hemisphere of geometric_normal.
  vec3<W> wo;                ///< Unit direction from the hit back towards the ray origin.
  vfloat<W> u, v;            ///< Texture coordinates (TEXCOORD_0), 0 without them.
  vfloat<W> distance;        ///< Ray parameter of the hit (depth for the filter).
  vint<W> material;          ///< Index into Scene::materials, -1 for the default material.
  vint<W> mesh;              ///< Index into Scene::meshes.
  vint<W> instance;          ///< Index into Scene::instances.
  vint<W> triangle;          ///< Triangle index within the mesh.
  vmask<W> front_face;       ///< True where the ray hit the side the triangle's winding faces.
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
};

}  // namespace igi
