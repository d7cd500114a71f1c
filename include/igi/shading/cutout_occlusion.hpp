#pragma once
/// \file
/// Shadow rays through alpha cut-outs: `occluded_by_opaque` answers an occlusion query as the
/// camera rays and the path tracer see the scene, where a cut-out (glTF alphaMode MASK) blocks
/// light only where its surface shader finds it opaque. A backend's `occluded` knows nothing of
/// materials and stops at any triangle, which made foliage and chains cast solid shadows.
/// `shadow_transmittance` goes further for see-through surfaces (thin-walled glass, alpha
/// blending): how much light of each colour gets through, window panes attenuating it.

#include <concepts>
#include <exception>
#include <limits>

#include "igi/backends/backend.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"

namespace igi {

/// An OcclusionCandidate as the ray and hit a closest-hit query returns (one lane).
struct CandidateHit {
  RayPacket<1> ray;  ///< The candidate's ray, tfar at its distance.
  HitPacket<1> hit;  ///< Its ids and barycentrics.
};

/// `candidate` as a traced ray and its hit, for make_surface_hit.
inline CandidateHit candidate_hit(const OcclusionCandidate& candidate) noexcept {
  CandidateHit traced;
  const vmask<1> one(true);
  traced.ray.set(vec3<1>(candidate.origin), vec3<1>(candidate.direction), vfloat<1>(0.0f), vfloat<1>(candidate.distance), one);
  traced.hit.clear();
  traced.hit.u[0] = candidate.u;
  traced.hit.v[0] = candidate.v;
  traced.hit.geomID[0] = candidate.mesh;
  traced.hit.instID[0] = candidate.instance;
  traced.hit.primID[0] = candidate.primitive;
  return traced;
}

/// A surface shader that can tell whether a cut-out blocks a shadow ray at a candidate without
/// shading the whole hit (GltfMaterialShader: its alpha test alone).
template <class S>
concept CutoutOpacityShader = requires(const S& shader, const OcclusionCandidate& candidate) {
  { shader.opaque_at(candidate) } -> std::same_as<bool>;
};

/// Gives `backend` the cut-out test of `surface` on `scene` (both kept by reference: they must
/// outlive the backend's use of it): a cut-out's triangle blocks where the surface shader calls
/// it opaque, by its `opaque_at` where it has one, else by shading the candidate as a hit of the
/// ray that met it. An id the scene lacks (which no backend built from `scene` reports) counts as opaque.
template <class B, class Surface>
  requires CutoutTestingBackend<B>
void test_cutouts_with(B& backend, const Scene& scene, const Surface& surface) {
  backend.set_cutout_test([&scene, &surface](const OcclusionCandidate& candidate) {
    try {
      if constexpr (CutoutOpacityShader<Surface>) {
        return surface.opaque_at(candidate);
      } else {
        const vmask<1> one(true);
        const CandidateHit traced = candidate_hit(candidate);
        return bool(surface.shade(make_surface_hit(scene, traced.ray, traced.hit, one), one).opaque[0]);
      }
    } catch (const std::exception&) {
      return true;  // never thrown through the backend's traversal (Embree's is C code)
    }
  });
}

/// Lanes of `mask` whose segment [tnear, tfar] of `rays` an opaque surface blocks; those get
/// tfar = -inf, as from Backend::occluded. A backend with a cut-out test set (test_cutouts_with)
/// answers that itself, in one traversal. Otherwise the backend's query finds every lane
/// something blocks; where `cutouts` has meshes, those lanes are traced again hit by hit (with
/// `coherence`), and a hit on a cut-out mesh lets the ray on from just behind it (the camera
/// rays' offset, `ray_epsilon`) where `surface` shades it transparent, for up to
/// max_cutout_layers hits: the same answer, at the cost of a closest-hit query per layer for every
/// blocked lane. Scenes without cut-outs pay nothing. `N` is the backend's width or 1.
template <class B, class Surface, int N>
vmask<N> occluded_by_opaque(const B& backend, const Surface& surface, const Scene& scene, const SceneGeometry& geometry,
                            const CutoutMeshes& cutouts, float ray_epsilon, RayPacket<N>& rays, Coherence coherence,
                            const vmask<N>& mask) {
  if constexpr (CutoutTestingBackend<B>)
    if (backend.cutout_test_set()) return backend.occluded(rays, coherence, mask);
  if (!cutouts.any()) return backend.occluded(rays, coherence, mask);
  const vfloat<N> far = rays.far();
  const vfloat<N> near = rays.near();
  vmask<N> blocked = backend.occluded(rays, coherence, mask);
  if (none(blocked)) return blocked;
  // The blocked lanes again, from their start: which surface blocks, and is it a cut-out?
  vmask<N> pending = blocked;
  select(pending, far, rays.far()).store(rays.tfar);
  // As the path tracer's shadow rays: after max_cutout_layers cut-outs passed, the ray counts as blocked.
  for (int layer = 0; layer < max_cutout_layers && any(pending); ++layer) {
    HitPacket<N> hits;
    hits.clear();
    backend.intersect(rays, hits, coherence, pending);
    vmask<N> cutout;
    for (int lane = 0; lane < N; ++lane) {
      if (!pending[lane]) continue;
      if (hits.geomID[lane] == invalid_id) {
        blocked.set(lane, false);  // only cut-outs lie on the way, and it passed them all
        pending.set(lane, false);
      } else if (cutouts.contains(hits.geomID[lane])) {
        cutout.set(lane, true);
      } else {
        pending.set(lane, false);  // an opaque mesh: blocked
      }
    }
    if (none(cutout)) break;
    const SurfaceHit<N> hit = make_surface_hit(scene, geometry, rays, hits, cutout);
    const vmask<N> transparent = cutout & !surface.shade(hit, cutout).opaque;
    // Opaque cut-out lanes are blocked; transparent ones go on from just behind the cut-out.
    pending = transparent;
    select(pending, rays.far() + vfloat<N>(ray_epsilon), rays.near()).store(rays.tnear);
    select(pending, far, rays.far()).store(rays.tfar);
  }
  select(blocked, vfloat<N>(-std::numeric_limits<float>::infinity()), far).store(rays.tfar);
  select(mask, near, rays.near()).store(rays.tnear);
  return blocked;
}

/// Per channel, the light that gets through the segment [tnear, tfar] of `rays` on the lanes of
/// `mask` (zero elsewhere): 0 where an opaque surface blocks it, else the product of
/// straight_transmittance over the see-through surfaces on the way (thin-walled glass, alpha
/// blending; `see_through` names their meshes) and 1 over the transparent parts of cut-outs.
/// Deterministic, not a pass-or-stop chance: a window pane dims the sun by its transmittance in
/// every pixel alike, without noise. The backend's occlusion query first finds the lanes
/// nothing stops (1); those something stops are traced again hit by hit from their start
/// (with `coherence`): an opaque mesh's hit ends the lane at 0, a cut-out's or see-through
/// mesh's is shaded by `surface` and multiplies the lane's light by what passes, which goes on
/// from just behind it (`ray_epsilon`), for up to max_cutout_layers hits (then 0). Without
/// see-through meshes this is occluded_by_opaque's answer as 0 or 1. `rays` is left as it came.
template <class B, class Surface, int N>
vec3<N> shadow_transmittance(const B& backend, const Surface& surface, const Scene& scene, const SceneGeometry& geometry,
                             const CutoutMeshes& cutouts, const SeeThroughMeshes& see_through, float ray_epsilon,
                             RayPacket<N>& rays, Coherence coherence, const vmask<N>& mask) {
  const vfloat<N> zero(0.0f), one(1.0f);
  const vfloat<N> far = rays.far();
  const vfloat<N> near = rays.near();
  if (!see_through.any()) {
    const vmask<N> blocked = occluded_by_opaque(backend, surface, scene, geometry, cutouts, ray_epsilon, rays, coherence, mask);
    select(mask, far, rays.far()).store(rays.tfar);
    const vfloat<N> passed = select(mask & !blocked, one, zero);
    return {passed, passed, passed};
  }
  const vfloat<N> start = select(mask, one, zero);
  vec3<N> light(start, start, start);
  vmask<N> pending = backend.occluded(rays, coherence, mask);
  select(pending, far, rays.far()).store(rays.tfar);
  for (int layer = 0; layer < max_cutout_layers && any(pending); ++layer) {
    HitPacket<N> hits;
    hits.clear();
    backend.intersect(rays, hits, coherence, pending);
    vmask<N> crossed;  // lanes on a surface that may let light on
    for (int lane = 0; lane < N; ++lane) {
      if (!pending[lane]) continue;
      if (hits.geomID[lane] == invalid_id) {
        pending.set(lane, false);  // nothing more on the way: the lane keeps what got this far
      } else if (cutouts.contains(hits.geomID[lane]) || see_through.contains(hits.geomID[lane])) {
        crossed.set(lane, true);
      } else {
        pending.set(lane, false);  // an opaque mesh: no light
        light.set(lane, glm::vec3(0.0f));
      }
    }
    if (none(crossed)) break;
    const SurfaceHit<N> hit = make_surface_hit(scene, geometry, rays, hits, crossed);
    light = select(crossed, light * straight_transmittance(hit, surface.shade(hit, crossed), crossed), light);
    // Lanes some light still passes go on from just behind the surface.
    pending = crossed & (brdf_detail::max_component(light) > zero);
    select(pending, rays.far() + vfloat<N>(ray_epsilon), rays.near()).store(rays.tnear);
    select(pending, far, rays.far()).store(rays.tfar);
  }
  light = select(pending, vec3<N>(), light);  // more layers than max_cutout_layers: taken as blocked
  select(mask, near, rays.near()).store(rays.tnear);
  select(mask, far, rays.far()).store(rays.tfar);
  return keep(light, mask);
}

}  // namespace igi
