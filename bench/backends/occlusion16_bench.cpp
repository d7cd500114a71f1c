// Which way should EmbreeBackend<16> trace coherent shadow packets while Embree's coherent
// 16-wide occlusion kernel can loop forever (embree_backend.hpp, `coherent_occlusion16_may_loop`)?
// Embree alone, one thread, on igi's own Embree scene: the same shadow rays traced as
//   coherent16        rtcOccluded16 with the coherent flag: the path that can loop, so it is run
//                     only on an Embree that has the fix (and still under a watchdog);
//   incoherent16      rtcOccluded16 with the incoherent flag;
//   coherent8x2       two rtcOccluded8 calls with the coherent flag, one per half (what
//                     EmbreeBackend<16> does: detail::embree_trace_packet);
//   coherent16_avx2   rtcOccluded16 coherent on a device made with "isa=avx2" (no AVX-512 kernels).
//
//   occlusion16_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <thread>
#include <tuple>
#include <vector>

#include <benchmark/benchmark.h>

#include "igi/backends/embree/embree_backend.hpp"
#include "workloads.hpp"

namespace {

using igi::bench::RaySet;
using igi::bench::Workload;

enum class Strategy { coherent16, incoherent16, coherent8x2, coherent16_avx2 };
constexpr const char* strategy_names[] = {"coherent16", "incoherent16", "coherent8x2", "coherent16_avx2"};

/// Embree's valid[] of one packet: -1 = trace; read with aligned vector loads.
struct alignas(64) Valid16 {
  int lane[16];
};

/// The shadow rays of `set` in Embree's 16-wide layout, with Embree's valid[] per packet.
struct Packets {
  std::vector<igi::RayPacket<16>> rays;  ///< Fresh copies for each pass (Embree overwrites tfar).
  std::vector<Valid16> valid;            ///< Per packet.
};

Packets pack(const RaySet& set) {
  Packets packets;
  const std::size_t count = set.origin.size() / 16;
  packets.rays.resize(count);
  packets.valid.resize(count);
  for (std::size_t p = 0; p < count; ++p) {
    igi::RayPacket<16>& rays = packets.rays[p];
    const igi::vmask<16> active = igi::bench::load_packet(set, p, rays);
    for (int lane = 0; lane < 16; ++lane) {
      packets.valid[p].lane[lane] = active[lane] ? -1 : 0;
      if (!active[lane]) {
        // An inactive lane holds a finite ray with an empty interval: the AVX2 device's 16-wide
        // path is Embree's ray stream, which ignores valid[] (rtcore.cpp, rtcOccluded16) and
        // asserts finite rays, so igi would have to write such lanes for it too.
        rays.org_x[lane] = rays.org_y[lane] = rays.org_z[lane] = 0.0f;
        rays.dir_x[lane] = rays.dir_y[lane] = 0.0f;
        rays.dir_z[lane] = 1.0f;
        rays.tnear[lane] = 1.0f;
        rays.tfar[lane] = 0.0f;
      }
    }
  }
  return packets;
}

/// The backend of `workload` on a device with `config`, built once per (workload, config).
const igi::EmbreeBackend<16>& backend(const Workload& workload, const std::string& config) {
  static std::vector<std::tuple<const Workload*, std::string, std::unique_ptr<igi::EmbreeBackend<16>>>> built;
  for (auto& [w, c, b] : built)
    if (w == &workload && c == config) return *b;
  built.emplace_back(&workload, config, std::make_unique<igi::EmbreeBackend<16>>(workload.scene, config));
  return *std::get<2>(built.back());
}

/// Traces every packet once with `strategy`; returns the occluded rays (checked to agree).
std::int64_t trace(RTCScene scene, const Packets& source, std::vector<igi::RayPacket<16>>& work, Strategy strategy) {
  work = source.rays;
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = strategy == Strategy::incoherent16 ? RTC_INTERSECT_CONTEXT_FLAG_INCOHERENT
                                                     : RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  std::int64_t occluded = 0;
  for (std::size_t p = 0; p < work.size(); ++p) {
    const int* valid = source.valid[p].lane;
    auto* rays = reinterpret_cast<RTCRay16*>(&work[p]);
    if (strategy == Strategy::coherent8x2) {
      // What EmbreeBackend<16> does with a coherent packet while the 16-wide kernel can loop.
      igi::detail::EmbreePacketWidths halves;
      halves.sixteen = false;
      igi::detail::embree_trace_packet<16, false>(valid, scene, &context, *rays, halves);
    } else {
      rtcOccluded16(valid, scene, &context, rays);
    }
    for (int lane = 0; lane < 16; ++lane) occluded += valid[lane] != 0 && rays->tfar[lane] < 0.0f;
  }
  return occluded;
}

void run(benchmark::State& state, const Workload* workload, Strategy strategy) {
  if (strategy == Strategy::coherent16 && igi::detail::embree_coherent_occlusion16_may_loop) {
    state.SkipWithError("not run: this Embree's coherent 16-wide occlusion kernel can loop forever");
    return;
  }
  // Denormals flushed to zero, as on igi's tracing threads.
  _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
  _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
  static std::map<const Workload*, Packets> packed;
  if (!packed.contains(workload)) packed.emplace(workload, pack(workload->shadow));
  const Packets& packets = packed.at(workload);
  const igi::EmbreeBackend<16>& traced = backend(*workload, strategy == Strategy::coherent16_avx2 ? "isa=avx2" : "");
  // The occluded count of the incoherent flag, which never loops: every strategy must agree.
  std::vector<igi::RayPacket<16>> work;
  const std::int64_t expected = trace(backend(*workload, "").embree_scene(), packets, work, Strategy::incoherent16);
  std::int64_t occluded = 0;
  for (auto _ : state) occluded = trace(traced.embree_scene(), packets, work, strategy);
  if (occluded != expected)
    state.SkipWithError(("occluded " + std::to_string(occluded) + " rays, incoherent16 " + std::to_string(expected)).c_str());
  state.counters["Mrays/s"] =
      benchmark::Counter(double(workload->shadow.active_count) * double(state.iterations()) * 1e-6,
                         benchmark::Counter::kIsRate);
  state.counters["occluded"] = double(occluded);
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  // A loop inside Embree would hang the run: a watchdog ends the process with a message instead.
  // 20 minutes: the whole program takes under 2 on 2 cores.
  std::thread([] {
    std::this_thread::sleep_for(std::chrono::minutes(20));
    std::fputs("occlusion16_bench: still running after 20 minutes (a loop inside Embree?); stopped\n", stderr);
    std::_Exit(3);
  }).detach();
  std::vector<const Workload*> list;
  for (const Workload& w : igi::bench::workloads()) list.push_back(&w);
  list.push_back(&igi::bench::million_triangles());
  for (const Workload* w : list)
    for (int s = 0; s < 4; ++s) {
      const std::string name = std::string("occlusion16/") + strategy_names[s] + "/" + w->name;
      benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) { run(state, w, Strategy(s)); })
          ->UseRealTime()
          ->Unit(benchmark::kMillisecond);
    }
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
