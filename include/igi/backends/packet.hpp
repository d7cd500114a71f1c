#pragma once
/// \file
/// Ray and hit packets shared by every backend. The memory order is that of Embree's
/// `RTCRayNt<N>` / `RTCHitNt<N>` (and `RTCRay` / `RTCHit` at W = 1), so the Embree backend hands
/// them to `rtcIntersectN` without a copy; the other backends read the same arrays.

#include <cstdint>
#include <limits>

#include "igi/simd/simd.hpp"

namespace igi {

/// Id of "no geometry / no instance", equal to Embree's RTC_INVALID_GEOMETRY_ID.
inline constexpr std::uint32_t invalid_id = std::numeric_limits<std::uint32_t>::max();

/// Byte alignment of packets: Embree requires 16/32/64 for widths 4/8/16; 64 fits all.
inline constexpr std::size_t packet_alignment = 64;

/// W rays, laid out as `RTCRayNt<W>`.
template <int W>
struct alignas(packet_alignment) RayPacket {
  static constexpr int width = W;  ///< Lanes.
  float org_x[W], org_y[W], org_z[W];  ///< Origins.
  float tnear[W];                      ///< Start of the valid interval.
  float dir_x[W], dir_y[W], dir_z[W];  ///< Directions (need not be unit length).
  float time[W];                       ///< Motion-blur time, unused (0).
  float tfar[W];                       ///< End of the interval; the hit distance after intersect, -inf after an occlusion hit (Embree's convention).
  std::uint32_t mask[W];               ///< Embree ray mask, all ones.
  std::uint32_t id[W];                 ///< Free for the caller.
  std::uint32_t flags[W];              ///< Must be 0.

  /// Sets lanes of `active` to the given rays; other lanes are made inert (tnear > tfar).
  void set(const vec3<W>& origin, const vec3<W>& direction, const vfloat<W>& t_min, const vfloat<W>& t_max,
           const vmask<W>& active) noexcept {
    origin.x.store(org_x);
    origin.y.store(org_y);
    origin.z.store(org_z);
    direction.x.store(dir_x);
    direction.y.store(dir_y);
    direction.z.store(dir_z);
    t_min.store(tnear);
    // Inactive lanes get tnear = 0 > tfar = -inf, which every backend treats as "no ray".
    select(active, t_max, vfloat<W>(-std::numeric_limits<float>::infinity())).store(tfar);
    vfloat<W>(0.0f).store(time);
    vuint<W>(invalid_id).store(mask);
    convert<std::uint32_t>(lane_index<W>()).store(id);
    vuint<W>(0u).store(flags);
  }
  /// Origins as a packet.
  vec3<W> origin() const noexcept { return {vfloat<W>::load(org_x), vfloat<W>::load(org_y), vfloat<W>::load(org_z)}; }
  /// Directions as a packet.
  vec3<W> direction() const noexcept { return {vfloat<W>::load(dir_x), vfloat<W>::load(dir_y), vfloat<W>::load(dir_z)}; }
  /// Interval ends (hit distances after intersect).
  vfloat<W> far() const noexcept { return vfloat<W>::load(tfar); }
  /// Interval starts.
  vfloat<W> near() const noexcept { return vfloat<W>::load(tnear); }
};

/// W hits, laid out as `RTCHitNt<W>` with one instance level.
template <int W>
struct alignas(packet_alignment) HitPacket {
  static constexpr int width = W;  ///< Lanes.
  float Ng_x[W], Ng_y[W], Ng_z[W];  ///< Unnormalized geometric normal (backend-defined space; shading recomputes it).
  float u[W], v[W];                 ///< Barycentrics of vertices 1 and 2.
  std::uint32_t primID[W];          ///< Triangle index within the mesh.
  std::uint32_t geomID[W];          ///< Mesh index (Scene::meshes), invalid_id on a miss.
  std::uint32_t instID[W];          ///< Instance index (Scene::instances), invalid_id on a miss.

  /// Marks every lane as a miss.
  void clear() noexcept {
    for (float* channel : {Ng_x, Ng_y, Ng_z, u, v}) vfloat<W>(0.0f).store(channel);
    for (std::uint32_t* id : {primID, geomID, instID}) vuint<W>(invalid_id).store(id);
  }
  /// Lanes that hit something.
  vmask<W> valid() const noexcept { return vuint<W>::load(geomID) != vuint<W>(invalid_id); }
};

}  // namespace igi
