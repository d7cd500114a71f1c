// Throughput of every backend and packet width: Mrays/s for coherent primary rays, coherent
// shadow rays to a point and incoherent bounce rays, on the Cornell box and Sponza, with 1 and 2
// TBB threads; the SaarCOR emulation also reports its hardware counters per ray.
//
//   backends_bench --benchmark_format=json --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cstdint>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include <pmmintrin.h>
#include <xmmintrin.h>

#include <benchmark/benchmark.h>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "workloads.hpp"

namespace {

using igi::bench::RaySet;
using igi::bench::Workload;
using igi::bench::workloads;

/// One backend per scene, built on first use and kept (builds are not what is measured).
template <class B>
const B& backend_for(std::size_t scene) {
  static std::vector<std::unique_ptr<B>> built(workloads().size());
  if (!built[scene]) built[scene] = std::make_unique<B>(workloads()[scene].scene);
  return *built[scene];
}

enum class Kind { primary, shadow, bounce };

/// Traces every packet of `set` once: closest hit for primary and bounce rays, occlusion for shadows.
template <class B>
void trace_all(const B& backend, const RaySet& set, Kind kind, int threads, tbb::task_arena& arena) {
  constexpr int W = B::width;
  const std::size_t packets = set.origin.size() / W;
  const auto body = [&](const tbb::blocked_range<std::size_t>& range) {
    // Denormals flushed to zero on every tracing thread, as Embree asks; the same for all backends.
    _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
    _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
    for (std::size_t p = range.begin(); p != range.end(); ++p) {
      igi::RayPacket<W> rays;
      igi::HitPacket<W> hits;
      const igi::vmask<W> mask = igi::bench::load_packet(set, p, rays);
      // Primary and shadow packets are coherent; bounce packets are not (Embree uses the hint).
      const igi::Coherence coherence = kind == Kind::bounce ? igi::Coherence::incoherent : igi::Coherence::coherent;
      if (kind == Kind::shadow) {
        benchmark::DoNotOptimize(backend.occluded(rays, coherence, mask));
      } else {
        backend.intersect(rays, hits, coherence, mask);
        benchmark::DoNotOptimize(&hits);
        benchmark::ClobberMemory();
      }
    }
  };
  // Grain: 64 rays' worth of packets per task, enough to amortise scheduling for every width.
  const std::size_t grain = std::max<std::size_t>(1, 64 / W);
  if (threads == 1) {
    body(tbb::blocked_range<std::size_t>(0, packets));
  } else {
    arena.execute([&] { tbb::parallel_for(tbb::blocked_range<std::size_t>(0, packets, grain), body); });
  }
}

template <class B>
void run(benchmark::State& state, std::size_t scene, Kind kind, int threads) {
  const Workload& w = workloads()[scene];
  const RaySet& set = kind == Kind::primary ? w.primary : kind == Kind::shadow ? w.shadow : w.bounce;
  const B& backend = backend_for<B>(scene);
  tbb::task_arena arena(threads);
  if constexpr (std::is_same_v<B, igi::SaarcorBackend>) backend.reset_stats();
  for (auto _ : state) trace_all(backend, set, kind, threads, arena);
  const double rays = double(set.active_count) * double(state.iterations());
  state.counters["Mrays/s"] = benchmark::Counter(rays * 1e-6, benchmark::Counter::kIsRate);
  state.counters["rays"] = double(set.active_count);
  if constexpr (std::is_same_v<B, igi::SaarcorBackend>) {
    const igi::SaarcorStats s = backend.stats();
    const double per_ray = 1.0 / double(s.rays);
    state.counters["steps/ray"] = double(s.traversal_steps) * per_ray;
    state.counters["leaves/ray"] = double(s.leaf_visits) * per_ray;
    state.counters["tri_fetch/ray"] = double(s.triangle_tests) * per_ray;
    state.counters["ray_tri_tests/ray"] = double(s.ray_triangle_tests) * per_ray;
    state.counters["kd_bytes/ray"] = double(s.kd_node_bytes) * per_ray;
    state.counters["tri_bytes/ray"] = double(s.triangle_bytes) * per_ray;
    state.counters["active_lanes"] = s.active_lane_ratio();
    state.counters["packets/pass"] = double(s.packets) / double(state.iterations());
  }
}

template <class B>
void register_backend(const std::string& label) {
  static const char* kind_names[] = {"primary", "shadow", "bounce"};
  for (std::size_t scene = 0; scene < workloads().size(); ++scene)
    for (int k = 0; k < 3; ++k)
      for (int threads : {1, 2}) {
        const std::string name = label + "/W:" + std::to_string(B::width) + "/" + workloads()[scene].name + "/" +
                                 kind_names[k] + "/threads:" + std::to_string(threads);
        benchmark::RegisterBenchmark(name.c_str(), [=](benchmark::State& state) { run<B>(state, scene, Kind(k), threads); })
            ->UseRealTime()
            ->Unit(benchmark::kMillisecond);
      }
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  register_backend<igi::EmbreeBackend<1>>("embree");
  register_backend<igi::EmbreeBackend<4>>("embree");
  register_backend<igi::EmbreeBackend<8>>("embree");
  register_backend<igi::EmbreeBackend<16>>("embree");
  register_backend<igi::SaarcorBackend>("saarcor");
  register_backend<igi::ReferenceBackend<1>>("reference");
  register_backend<igi::ReferenceBackend<4>>("reference");
  register_backend<igi::ReferenceBackend<8>>("reference");
  register_backend<igi::ReferenceBackend<16>>("reference");
  register_backend<igi::ReferenceBackend<64>>("reference");
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
