// Throughput of every backend and packet width: Mrays/s for coherent primary rays, coherent
// shadow rays to a point and incoherent bounce rays, on the Cornell box and Sponza, with 1 and 2
// TBB threads; the SaarCOR emulation also reports its hardware counters per ray.
//
//   backends_bench --benchmark_format=json --benchmark_repetitions=5 --benchmark_report_aggregates_only=true

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <memory>
#include <random>
#include <string>
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
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"

namespace {

/// Image side for the ray sets: 256 x 256 = 65536 rays per set, 1024 SaarCOR packets.
constexpr int image_size = 256;

/// A ray list in packet order (8x8 tiles, Morton order inside: every width gets compact blocks).
struct RaySet {
  std::vector<glm::vec3> origin, direction;  // Per ray.
  std::vector<float> tnear, tfar;            // Per ray.
  std::vector<char> active;                  // Masked-off lanes (e.g. shadow rays of missed pixels).
  std::int64_t active_count = 0;             // Rays actually traced per pass.
};

/// The three workloads of one scene.
struct Workload {
  std::string name;     // "cornell" or "sponza".
  igi::Scene scene;     // Geometry.
  RaySet primary, shadow, bounce;  // Coherent primary, coherent shadow to a point, incoherent bounce.
};

glm::ivec2 morton_pixel(int index) {
  glm::ivec2 p(0);
  for (int bit = 0; bit < 3; ++bit) {
    p.x |= ((index >> (2 * bit)) & 1) << bit;
    p.y |= ((index >> (2 * bit + 1)) & 1) << bit;
  }
  return p;
}

void push(RaySet& set, const glm::vec3& origin, const glm::vec3& direction, float tnear, float tfar, bool active) {
  set.origin.push_back(origin);
  set.direction.push_back(direction);
  set.tnear.push_back(tnear);
  set.tfar.push_back(tfar);
  set.active.push_back(active);
  set.active_count += active;
}

Workload make_workload(const std::string& name, igi::Scene scene) {
  Workload w{name, std::move(scene), {}, {}, {}};
  const igi::Camera camera = w.scene.cameras.empty() ? igi::default_camera(w.scene) : w.scene.cameras.front();
  const igi::PinholeProjection projection(camera, image_size, image_size);
  for (int ty = 0; ty < image_size; ty += 8)
    for (int tx = 0; tx < image_size; tx += 8)
      for (int i = 0; i < 64; ++i) {
        const glm::ivec2 p = glm::ivec2(tx, ty) + morton_pixel(i);
        push(w.primary, projection.origin(), projection.direction(float(p.x) + 0.5f, float(p.y) + 0.5f), 0.0f,
             std::numeric_limits<float>::infinity(), true);
      }

  // Hit points from the reference; shadow rays go to one point light, bounce rays leave in
  // cosine-distributed random directions (seeded) about the normal facing the viewer.
  const igi::ReferenceBackend<1> reference(w.scene);
  const igi::Bounds bounds = w.scene.bounds();
  const glm::vec3 light = bounds.center() + glm::vec3(0.0f, 0.4f * bounds.extent().y, 0.0f);
  // Offset of secondary rays from their surface: 1e-4 of the scene size, well above the rounding
  // of a hit point and below any feature of the scenes.
  const float offset = 1e-4f * glm::length(bounds.extent());
  std::mt19937 rng(2003);
  std::uniform_real_distribution<float> unit(0.0f, 1.0f);
  for (std::size_t i = 0; i < w.primary.origin.size(); ++i) {
    igi::RayPacket<1> ray;
    igi::HitPacket<1> hit;
    ray.set(igi::vec3<1>(w.primary.origin[i]), igi::vec3<1>(w.primary.direction[i]), igi::vfloat<1>(0.0f),
            igi::vfloat<1>(std::numeric_limits<float>::infinity()), igi::vmask<1>(true));
    hit.clear();
    reference.intersect(ray, hit, igi::vmask<1>(true));
    const bool found = hit.geomID[0] != igi::invalid_id;
    const glm::vec3 point = w.primary.origin[i] + ray.tfar[0] * w.primary.direction[i];
    glm::vec3 normal(hit.Ng_x[0], hit.Ng_y[0], hit.Ng_z[0]);
    normal = found && glm::dot(normal, normal) > 0.0f ? glm::normalize(normal) : glm::vec3(0.0f, 1.0f, 0.0f);
    if (glm::dot(normal, w.primary.direction[i]) > 0.0f) normal = -normal;
    const glm::vec3 to_light = light - point;
    const float distance = glm::length(to_light);
    push(w.shadow, point, to_light, offset / std::max(distance, offset), 1.0f - offset / std::max(distance, offset), found);
    const glm::vec3 tangent = glm::normalize(std::abs(normal.x) > 0.5f ? glm::cross(normal, glm::vec3(0, 1, 0))
                                                                      : glm::cross(normal, glm::vec3(1, 0, 0)));
    const glm::vec3 bitangent = glm::cross(normal, tangent);
    const float r = std::sqrt(unit(rng)), phi = 6.2831853f * unit(rng);
    const glm::vec3 direction = r * std::cos(phi) * tangent + r * std::sin(phi) * bitangent +
                                std::sqrt(std::max(0.0f, 1.0f - r * r)) * normal;
    push(w.bounce, point, direction, offset, std::numeric_limits<float>::infinity(), found);
  }
  return w;
}

/// Cornell and (if present) Sponza, loaded once.
const std::vector<Workload>& workloads() {
  static const std::vector<Workload> all = [] {
    std::vector<Workload> list;
    list.push_back(make_workload("cornell", igi::cornell_box()));
    const std::filesystem::path sponza = std::filesystem::path(IGI_SCENES_DIR) / "sponza" / "Sponza.gltf";
    if (std::filesystem::exists(sponza)) list.push_back(make_workload("sponza", igi::load_gltf(sponza)));
    return list;
  }();
  return all;
}

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
      igi::vmask<W> mask;
      for (int lane = 0; lane < W; ++lane) {
        const std::size_t i = p * W + std::size_t(lane);
        rays.org_x[lane] = set.origin[i].x;
        rays.org_y[lane] = set.origin[i].y;
        rays.org_z[lane] = set.origin[i].z;
        rays.dir_x[lane] = set.direction[i].x;
        rays.dir_y[lane] = set.direction[i].y;
        rays.dir_z[lane] = set.direction[i].z;
        rays.tnear[lane] = set.tnear[i];
        rays.tfar[lane] = set.tfar[i];
        rays.time[lane] = 0.0f;
        rays.mask[lane] = igi::invalid_id;
        rays.id[lane] = std::uint32_t(lane);
        rays.flags[lane] = 0;
        mask.set(lane, set.active[i] != 0);
      }
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
