#pragma once
/// \file
/// Ray and hit packets shared by every backend, and their layout contract. Every field is an
/// array of W 4-byte lanes, in declaration order without gaps; that is the memory order of
/// Embree's `RTCRayNt<N>` / `RTCHitNt<N>` (and `RTCRay` / `RTCHit` at W = 1), and `RayHitPacket`
/// is that of `RTCRayHitNt<N>` for W = 4, 8, 16, so the Embree backend hands them to
/// `rtcIntersectN` / `rtcOccludedN` without a copy; the other backends read the same arrays. The
/// contract is checked at the end of this file; igi/backends/embree/embree_tracing.hpp checks
/// it against Embree's own types.

#include <cstddef>
#include <cstdint>
#include <limits>
#include <type_traits>

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
  ///@{
  float org_x[W], org_y[W], org_z[W];  ///< Origins.
  ///@}
  float tnear[W];                      ///< Start of the valid interval.
  ///@{
  float dir_x[W], dir_y[W], dir_z[W];  ///< Directions (need not be unit length).
  ///@}
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
  ///@{
  float Ng_x[W], Ng_y[W], Ng_z[W];  ///< Unnormalized geometric normal (backend-defined space; shading recomputes it).
  ///@}
  ///@{
  float u[W], v[W];                 ///< Barycentrics of vertices 1 and 2.
  ///@}
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

/// W rays directly followed by their W hits, laid out as Embree's `RTCRayHitNt<W>` for W = 4, 8,
/// 16: a backend may trace both in place with one closest-hit call.
template <int W>
struct alignas(packet_alignment) RayHitPacket {
  RayPacket<W> rays;  ///< The rays.
  HitPacket<W> hits;  ///< Their hits, at the first byte after the rays.

  /// `rays` and `hits` seen as one RayHitPacket when `hits` lies exactly where a RayHitPacket
  /// keeps its hits after its rays (the two members of a RayHitPacket, or the first two members
  /// of a struct that begins as one does), else null.
  static RayHitPacket* from_members(RayPacket<W>& rays, HitPacket<W>& hits) noexcept {
    unsigned char* const rays_start = reinterpret_cast<unsigned char*>(&rays);
    if (reinterpret_cast<unsigned char*>(&hits) != rays_start + offsetof(RayHitPacket, hits)) return nullptr;
    return reinterpret_cast<RayHitPacket*>(rays_start);
  }
};

namespace detail {

/// Checks at compile time the layout contract of the packets at width W, without reference to
/// any backend: each field is W 4-byte lanes at its position in declaration order, the packets
/// are padded only at their ends (to packet_alignment), and RayHitPacket puts the hits right
/// after the rays.
template <int W>
constexpr bool packet_layout_is_lane_arrays() {
  using Rays = RayPacket<W>;
  using Hits = HitPacket<W>;
  constexpr std::size_t field = sizeof(float) * W;  // bytes of one field: W lanes of 4 bytes
  static_assert(sizeof(float) == 4 && sizeof(std::uint32_t) == 4);
  static_assert(std::is_standard_layout_v<Rays> && std::is_standard_layout_v<Hits> &&
                std::is_standard_layout_v<RayHitPacket<W>>);
  static_assert(offsetof(Rays, org_x) == 0 * field && offsetof(Rays, org_y) == 1 * field &&
                offsetof(Rays, org_z) == 2 * field && offsetof(Rays, tnear) == 3 * field &&
                offsetof(Rays, dir_x) == 4 * field && offsetof(Rays, dir_y) == 5 * field &&
                offsetof(Rays, dir_z) == 6 * field && offsetof(Rays, time) == 7 * field &&
                offsetof(Rays, tfar) == 8 * field && offsetof(Rays, mask) == 9 * field &&
                offsetof(Rays, id) == 10 * field && offsetof(Rays, flags) == 11 * field);
  static_assert(offsetof(Hits, Ng_x) == 0 * field && offsetof(Hits, Ng_y) == 1 * field &&
                offsetof(Hits, Ng_z) == 2 * field && offsetof(Hits, u) == 3 * field && offsetof(Hits, v) == 4 * field &&
                offsetof(Hits, primID) == 5 * field && offsetof(Hits, geomID) == 6 * field &&
                offsetof(Hits, instID) == 7 * field);
  // 12 ray fields and 8 hit fields, each rounded up to whole alignment blocks.
  constexpr auto padded = [](std::size_t bytes) { return (bytes + packet_alignment - 1) / packet_alignment * packet_alignment; };
  static_assert(sizeof(Rays) == padded(12 * field) && sizeof(Hits) == padded(8 * field));
  static_assert(alignof(Rays) == packet_alignment && alignof(Hits) == packet_alignment);
  static_assert(offsetof(RayHitPacket<W>, rays) == 0 && offsetof(RayHitPacket<W>, hits) == sizeof(Rays) &&
                sizeof(RayHitPacket<W>) == sizeof(Rays) + sizeof(Hits));
  return true;
}

static_assert(packet_layout_is_lane_arrays<1>() && packet_layout_is_lane_arrays<4>() &&
              packet_layout_is_lane_arrays<8>() && packet_layout_is_lane_arrays<16>());

}  // namespace detail

}  // namespace igi
