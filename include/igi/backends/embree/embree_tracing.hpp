#pragma once
/// \file
/// Tracing igi packets with Embree 3, whatever the scene: which rtcIntersect1/4/8/16 and
/// rtcOccluded1/4/8/16 call each width takes, Embree's valid[] lanes and coherence flag, and the
/// layout checks that let Embree read and write RayPacket, HitPacket and RayHitPacket in place.
/// Packets go as halves where the device has no kernels of their width (EmbreePacketWidths) and
/// coherent 16-wide occlusion with the incoherent flag while Embree's coherent 16-wide occlusion
/// kernel can loop (`detail::embree_coherent_occlusion16_may_loop`). The scene these
/// calls trace is built and updated by igi/backends/embree/embree_scene.hpp; EmbreeBackend
/// (igi/backends/embree/embree_backend.hpp) joins the two.

#include <algorithm>
#include <cstddef>
#include <cstring>
#include <limits>
#include <type_traits>

#include <embree3/rtcore.h>

#include "igi/backends/coherence.hpp"
#include "igi/backends/packet.hpp"
#include "igi/simd/simd.hpp"

namespace igi::detail {

/// True while the linked Embree's coherent 16-wide occlusion kernel can loop forever, so that
/// EmbreeBackend<16> must not reach it. In Embree before 4.4.1, `occludedCoherent` (kernels/bvh/
/// bvh_intersector_hybrid.cpp) keeps its valid mask in a `size_t`; GCC before 14 stores the 16-bit
/// AVX-512 mask to a stack slot with `kmovw` and reads it back as 64 bits (`cmpq`, `tzcnt`), so
/// whatever the slot held before lands above bit 15. The octant loop
/// `do { i = bsf(valid_bits); ...; valid_bits &= ~movemask(octant_valid); } while (valid_bits);`
/// then picks a lane index of 16 or more, whose octant matches no lane, and never clears those
/// bits. Debian 12's libembree3 3.13.5 is built with GCC 12.2; gdb on a hung igi-render shows the
/// `kmovw %k6,0x640(%rsp)` / `cmpq $0x0,0x640(%rsp)` pair. What the slot holds depends on the
/// code that ran before, so the loop shows on some CPUs and `-march` builds and not on others.
/// Embree fixed it in 4.4.1 (RenderKit/embree pull request 574: the mask as `unsigned short`).
/// igi is written against Embree 3, whose RTC_VERSION is below 40000, so this is true for every
/// Embree igi can link today; the guard can go once igi moves to Embree 4.4.1 or later.
/// Embree 3.13.5's 4- and 8-wide coherent kernels and its coherent closest-hit kernels share the
/// loop's source, but not the miscompile: scripts/embree_mask_scan.py finds the 16-bit store read
/// back as 64 bits in the 16-wide occlusion kernels only (BVH4 and BVH8, robust or not), and
/// tests/backends/embree_hang_test.cpp traces every width and kind coherently after filling the
/// stack with ones (which makes Embree's own coherent 16-wide occlusion loop every time in a
/// two-level scene) and they return. So only that one kernel is avoided.
inline constexpr bool embree_coherent_occlusion16_may_loop = RTC_VERSION < 40401;

/// Embree's packet types for each width.
template <int W>
struct EmbreePacketTypes;
/// Width 1: Embree's single ray.
template <>
struct EmbreePacketTypes<1> {
  using Ray = RTCRay;        ///< Ray.
  using RayHit = RTCRayHit;  ///< Ray and hit.
};
/// Width 4.
template <>
struct EmbreePacketTypes<4> {
  using Ray = RTCRay4;        ///< Ray packet.
  using RayHit = RTCRayHit4;  ///< Ray and hit packet.
};
/// Width 8.
template <>
struct EmbreePacketTypes<8> {
  using Ray = RTCRay8;        ///< Ray packet.
  using RayHit = RTCRayHit8;  ///< Ray and hit packet.
};
/// Width 16.
template <>
struct EmbreePacketTypes<16> {
  using Ray = RTCRay16;        ///< Ray packet.
  using RayHit = RTCRayHit16;  ///< Ray and hit packet.
};

/// Whether RayHitPacket<W> is Embree's RTCRayHitN, so that rtcIntersectN may trace one in place:
/// true for W = 4, 8, 16 (checked in packet_layout_matches). At W = 1 Embree's hit record follows
/// the 48-byte RTCRay directly, where RayHitPacket<1> starts its hits at the next 64-byte boundary.
template <int W>
inline constexpr bool ray_hit_packet_is_embree_layout =
    offsetof(RayHitPacket<W>, hits) == offsetof(typename EmbreePacketTypes<W>::RayHit, hit);

/// Checks at compile time that RayPacket<W> / HitPacket<W> have Embree's field offsets and, for
/// W > 1, RayHitPacket<W> is laid out as RTCRayHitN, so Embree may read and write them in place.
template <int W>
constexpr bool packet_layout_matches() {
  using Ray = typename EmbreePacketTypes<W>::Ray;
  using RayHit = typename EmbreePacketTypes<W>::RayHit;
  using Hit = decltype(RayHit::hit);
  static_assert(offsetof(RayPacket<W>, org_x) == offsetof(Ray, org_x));
  static_assert(offsetof(RayPacket<W>, org_y) == offsetof(Ray, org_y));
  static_assert(offsetof(RayPacket<W>, org_z) == offsetof(Ray, org_z));
  static_assert(offsetof(RayPacket<W>, tnear) == offsetof(Ray, tnear));
  static_assert(offsetof(RayPacket<W>, dir_x) == offsetof(Ray, dir_x));
  static_assert(offsetof(RayPacket<W>, dir_y) == offsetof(Ray, dir_y));
  static_assert(offsetof(RayPacket<W>, dir_z) == offsetof(Ray, dir_z));
  static_assert(offsetof(RayPacket<W>, time) == offsetof(Ray, time));
  static_assert(offsetof(RayPacket<W>, tfar) == offsetof(Ray, tfar));
  static_assert(offsetof(RayPacket<W>, mask) == offsetof(Ray, mask));
  static_assert(offsetof(RayPacket<W>, id) == offsetof(Ray, id));
  static_assert(offsetof(RayPacket<W>, flags) == offsetof(Ray, flags));
  static_assert(sizeof(Ray) <= sizeof(RayPacket<W>) && alignof(Ray) <= alignof(RayPacket<W>));
  static_assert(offsetof(HitPacket<W>, Ng_x) == offsetof(Hit, Ng_x));
  static_assert(offsetof(HitPacket<W>, Ng_y) == offsetof(Hit, Ng_y));
  static_assert(offsetof(HitPacket<W>, Ng_z) == offsetof(Hit, Ng_z));
  static_assert(offsetof(HitPacket<W>, u) == offsetof(Hit, u));
  static_assert(offsetof(HitPacket<W>, v) == offsetof(Hit, v));
  static_assert(offsetof(HitPacket<W>, primID) == offsetof(Hit, primID));
  static_assert(offsetof(HitPacket<W>, geomID) == offsetof(Hit, geomID));
  static_assert(offsetof(HitPacket<W>, instID) == offsetof(Hit, instID));
  static_assert(sizeof(Hit) <= sizeof(HitPacket<W>));
  if constexpr (W > 1) {
    static_assert(sizeof(Ray) == sizeof(RayPacket<W>) && sizeof(Hit) == sizeof(HitPacket<W>));
    static_assert(offsetof(RayHitPacket<W>, rays) == offsetof(RayHit, ray));
    static_assert(offsetof(RayHitPacket<W>, hits) == offsetof(RayHit, hit));
    static_assert(sizeof(RayHit) == sizeof(RayHitPacket<W>) && alignof(RayHit) <= alignof(RayHitPacket<W>));
  }
  static_assert(ray_hit_packet_is_embree_layout<W> == (W > 1));
  static_assert(RTC_MAX_INSTANCE_LEVEL_COUNT == 1, "HitPacket holds one instance level");
  static_assert(invalid_id == RTC_INVALID_GEOMETRY_ID);
  return true;
}

/// Embree's valid[] array: -1 for lanes in `mask` with a non-empty interval, 0 elsewhere.
template <int N>
struct alignas(packet_alignment) EmbreeValidLanes {
  int lane[N];  ///< -1 = trace, 0 = leave alone; Embree loads it with aligned vector loads.
  /// The array, as Embree's calls take it.
  const int* data() const noexcept { return lane; }
  /// Lane `i`'s entry.
  int operator[](std::size_t i) const noexcept { return lane[i]; }
};

/// The valid[] array of `rays` traced in the lanes of `mask`.
template <int N>
EmbreeValidLanes<N> embree_valid_lanes(const RayPacket<N>& rays, const vmask<N>& mask) noexcept {
  EmbreeValidLanes<N> valid;
  for (int lane = 0; lane < N; ++lane) valid.lane[lane] = mask[lane] && rays.tnear[lane] <= rays.tfar[lane] ? -1 : 0;
  return valid;
}

/// An intersection context with Embree's coherence flag for an N-wide packet of `coherence`.
template <int N>
RTCIntersectContext embree_context(Coherence coherence) noexcept {
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  // Packets are coherent unless the caller says otherwise; a single ray has nothing to share.
  context.flags = N > 1 && coherence == Coherence::coherent ? RTC_INTERSECT_CONTEXT_FLAG_COHERENT
                                                            : RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
  return context;
}

/// The packet widths an Embree device traces with kernels of their own width. Without one,
/// Embree 3 traces an N-wide call as its ray stream (rtcore.cpp: rtcIntersect16 takes
/// `rayStreamFilters.intersectSOA` when `intersectors.intersector16` is null), and the stream
/// ignores valid[]: it traces every lane whose tnear <= tfar, writes its results there and
/// asserts (Debian builds Embree with assertions) that those lanes hold finite rays. That is
/// rtcIntersect16 / rtcOccluded16 on every CPU without AVX-512 and on devices made with a lower
/// "isa=", and the 8-wide calls without AVX; igi's masked-off lanes may hold anything (NaN
/// included), so such packets go as halves of a width the device has.
struct EmbreePacketWidths {
  bool eight = true;    ///< rtcIntersect8 / rtcOccluded8 have 8-wide kernels.
  bool sixteen = true;  ///< rtcIntersect16 / rtcOccluded16 have 16-wide kernels.
  /// What `device` has (Embree's RTC_DEVICE_PROPERTY_NATIVE_RAY8/16_SUPPORTED).
  static EmbreePacketWidths of(RTCDevice device) noexcept {
    return {rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY8_SUPPORTED) != 0,
            rtcGetDeviceProperty(device, RTC_DEVICE_PROPERTY_NATIVE_RAY16_SUPPORTED) != 0};
  }
  /// Whether N-wide calls have N-wide kernels; 1 and 4 always do (4 needs SSE2, which every
  /// x86-64 CPU has).
  constexpr bool native(int n) const noexcept { return n == 16 ? sixteen : n == 8 ? eight : true; }
};

/// Embree's N-wide packet a query reads and writes: the rays alone for occlusion, rays and hit
/// record for closest hits.
template <int N, bool Closest>
using EmbreeQueryPacket =
    std::conditional_t<Closest, typename EmbreePacketTypes<N>::RayHit, typename EmbreePacketTypes<N>::Ray>;

/// Copies lanes [first, first + N/2) of every row of `whole` (an Embree packet is rows of N
/// 4-byte lanes) to `half`'s rows, or (`to_whole`) back.
template <int N, class Whole, class Half>
void copy_half_lanes(Whole& whole, Half& half, int first, bool to_whole) noexcept {
  constexpr std::size_t row = N * sizeof(float), half_row = row / 2;
  static_assert(sizeof(Whole) % row == 0 && sizeof(Half) * 2 == sizeof(Whole), "Embree packets are rows of 4-byte lanes");
  auto* whole_bytes = reinterpret_cast<unsigned char*>(&whole) + std::size_t(first) * sizeof(float);
  auto* half_bytes = reinterpret_cast<unsigned char*>(&half);
  for (std::size_t r = 0; r < sizeof(Whole) / row; ++r) {
    if (to_whole)
      std::memcpy(whole_bytes + r * row, half_bytes + r * half_row, half_row);
    else
      std::memcpy(half_bytes + r * half_row, whole_bytes + r * row, half_row);
  }
}

/// Embree's N-wide call (N = 4, 8, 16) of a closest-hit or occlusion query on `packet`, honouring
/// valid[] on every device: N-wide where `widths` has N-wide kernels, else as two calls on the
/// halves (recursively), each of which Embree only makes when it has a lane to trace. Coherent
/// 16-wide occlusion goes with the incoherent flag while Embree's kernel for it can loop
/// (embree_coherent_occlusion16_may_loop): faster than the two coherent 8-wide halves taken
/// before on an AMD EPYC (Cornell 1.85x, Sponza 1.04x, a terrain 1.13x in occlusion16_bench;
/// whole frames 9-35% less shadow time), slower on Sponza alone on one Intel Xeon (0.87x).
template <int N, bool Closest>
void embree_trace_packet(const int* valid, RTCScene scene, RTCIntersectContext* context,
                         EmbreeQueryPacket<N, Closest>& packet, EmbreePacketWidths widths) {
  static_assert(N == 4 || N == 8 || N == 16);
  if constexpr (N > 4) {
    if (!widths.native(N)) {
      for (int first = 0; first < N; first += N / 2) {
        if (std::none_of(valid + first, valid + first + N / 2, [](int lane) { return lane != 0; })) continue;
        alignas(64) int half_valid[N / 2];  // Embree loads valid[] with aligned vector loads
        std::copy_n(valid + first, N / 2, half_valid);
        alignas(64) EmbreeQueryPacket<N / 2, Closest> half;
        copy_half_lanes<N>(packet, half, first, false);
        embree_trace_packet<N / 2, Closest>(half_valid, scene, context, half, widths);
        copy_half_lanes<N>(packet, half, first, true);
      }
      return;
    }
  }
  if constexpr (Closest) {
    if constexpr (N == 4) rtcIntersect4(valid, scene, context, &packet);
    else if constexpr (N == 8) rtcIntersect8(valid, scene, context, &packet);
    else rtcIntersect16(valid, scene, context, &packet);
  } else {
    if constexpr (N == 4) {
      rtcOccluded4(valid, scene, context, &packet);
    } else if constexpr (N == 8) {
      rtcOccluded8(valid, scene, context, &packet);
    } else if (embree_coherent_occlusion16_may_loop && context->flags == RTC_INTERSECT_CONTEXT_FLAG_COHERENT) {
      RTCIntersectContext incoherent = *context;
      incoherent.flags = RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT;
      rtcOccluded16(valid, scene, &incoherent, &packet);
    } else {
      rtcOccluded16(valid, scene, context, &packet);
    }
  }
}

/// Closest hits in `top` of the rays in `mask`: hit lanes get tfar = distance, Embree's ids and
/// Ng; missing lanes get invalid ids; other lanes are untouched. `widths`: what the device of
/// `top` traces natively (EmbreePacketWidths::of).
template <int N>
void embree_intersect(RTCScene top, EmbreePacketWidths widths, RayPacket<N>& rays, HitPacket<N>& hits,
                      Coherence coherence, const vmask<N>& mask) {
  using EmbreeRay = typename EmbreePacketTypes<N>::Ray;
  using EmbreeRayHit = typename EmbreePacketTypes<N>::RayHit;
  RTCIntersectContext ctx = embree_context<N>(coherence);
  const EmbreeValidLanes<N> valid = embree_valid_lanes(rays, mask);
  // Rays and hits that form a RayHitPacket (as the pipeline's stream packets begin) are Embree's
  // RTCRayHitN for N = 4, 8, 16: Embree traces them in place.
  if constexpr (ray_hit_packet_is_embree_layout<N>) {
    if (RayHitPacket<N>* const packet = RayHitPacket<N>::from_members(rays, hits)) {
      // Embree writes nothing on a miss: active lanes start as misses.
      for (int lane = 0; lane < N; ++lane)
        if (mask[lane]) packet->hits.geomID[lane] = packet->hits.primID[lane] = packet->hits.instID[lane] = invalid_id;
      embree_trace_packet<N, true>(valid.data(), top, &ctx, *reinterpret_cast<EmbreeRayHit*>(packet), widths);
      return;
    }
  }
  // Otherwise the ray block (laid out as Embree's, checked above) is copied next to a hit block
  // and the active lanes' results copied back.
  alignas(packet_alignment) EmbreeRayHit both;
  std::memcpy(&both.ray, &rays, sizeof(EmbreeRay));
  // Embree's hit block is laid out as HitPacket (checked above) but, in RTCRayHit (N = 1), only
  // 16-byte aligned: it is filled and read through aligned copies, never through a cast.
  static_assert(sizeof(both.hit) <= sizeof(HitPacket<N>));
  HitPacket<N> lanes_out;
  lanes_out.clear();
  std::memcpy(&both.hit, &lanes_out, sizeof(both.hit));
  if constexpr (N == 1) {
    if (valid[0]) rtcIntersect1(top, &ctx, &both);
  } else {
    embree_trace_packet<N, true>(valid.data(), top, &ctx, both, widths);
  }
  std::memcpy(&lanes_out, &both.hit, sizeof(both.hit));
  const HitPacket<N>* hit_lanes = &lanes_out;
  const auto* traced = reinterpret_cast<const RayPacket<N>*>(&both.ray);
  for (int lane = 0; lane < N; ++lane) {
    if (!mask[lane]) continue;
    rays.tfar[lane] = traced->tfar[lane];
    hits.Ng_x[lane] = hit_lanes->Ng_x[lane];
    hits.Ng_y[lane] = hit_lanes->Ng_y[lane];
    hits.Ng_z[lane] = hit_lanes->Ng_z[lane];
    hits.u[lane] = hit_lanes->u[lane];
    hits.v[lane] = hit_lanes->v[lane];
    hits.primID[lane] = hit_lanes->primID[lane];
    hits.geomID[lane] = hit_lanes->geomID[lane];
    hits.instID[lane] = hit_lanes->instID[lane];
  }
}

/// Lanes of `mask` whose interval [tnear, tfar] is blocked in `top`; Embree sets their tfar to
/// -inf. `widths` as for embree_intersect.
template <int N>
vmask<N> embree_occluded(RTCScene top, EmbreePacketWidths widths, RayPacket<N>& rays, Coherence coherence,
                         const vmask<N>& mask) {
  using EmbreeRay = typename EmbreePacketTypes<N>::Ray;
  // Never Embree's coherent 16-wide occlusion kernel where it can loop forever (see
  // detail::embree_coherent_occlusion16_may_loop): embree_trace_packet sends coherent packets as
  // two coherent 8-wide halves. Of the ways around it (bench/backends/occlusion16_bench.cpp,
  // docs/performance.md), the halves were fastest on Sponza (1.17x the incoherent flag) and a
  // million-triangle terrain (1.02x), the incoherent flag on the 36-triangle Cornell box (1.38x
  // the halves); on whole frames the halves make Sponza_lit 2-5% faster and Cornell 5% slower.
  RTCIntersectContext ctx = embree_context<N>(coherence);
  const EmbreeValidLanes<N> valid = embree_valid_lanes(rays, mask);
  // Occlusion needs no hit record: Embree reads and writes the packet in place.
  auto* embree_rays = reinterpret_cast<EmbreeRay*>(&rays);
  if constexpr (N == 1) {
    if (valid[0]) rtcOccluded1(top, &ctx, embree_rays);
  } else {
    embree_trace_packet<N, false>(valid.data(), top, &ctx, *embree_rays, widths);
  }
  vmask<N> blocked;
  for (int lane = 0; lane < N; ++lane)
    blocked.set(lane, valid[std::size_t(lane)] != 0 && rays.tfar[lane] == -std::numeric_limits<float>::infinity());
  return blocked;
}

}  // namespace igi::detail
