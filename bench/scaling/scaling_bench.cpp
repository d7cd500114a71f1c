// Scene-size scaling of the IGI pipeline, to check the paper's claim that ray tracing scales with
// scene size: frame time against triangle count, with the acceleration-structure build time and
// memory reported apart.
//
//   size/cornell/n:K        the Cornell box, each triangle cut into K x K (34 K^2 + 2 triangles:
//                           the light's two are not cut)
//   size/sponza_lit/n:K     Sponza_lit, each triangle cut into K x K (262 k K^2 triangles
//                           rendered; Sponza places some meshes more than once, so 116 k K^2 unique)
//   size/sponza_lit/n:7/instances:4
//                           four copies of the 12.8 M-triangle Sponza side by side, placed by
//                           instances (the paper's power plant: 4 x 12.5 M); meshes and BVHs are
//                           stored once
//
// Cutting every triangle into K x K coplanar ones with interpolated normals and texture
// coordinates leaves the image as it was: what changes with K is only what the ray tracer has to
// search. Emissive meshes are not cut (the light sources, and so the VPLs, stay the same).
// Frames: 640x480, 16 VPLs per pixel, discontinuity filter, packet width 16, --threads threads.
// Counters: triangles (rendered), unique_triangles, instances, build_ms (Embree backend construction: all
// BVHs), move_all_instances_ms (median set-up of five frames in which every instance moves: the
// changes applied and committed), bvh_mb (resident memory the backend added, heap trimmed before and after), build_peak_mb (peak resident memory during
// the build over the memory before it), scene_mb (the igi Scene itself), ms_per_frame and the rest
// of report_frames.
//
//   scaling_bench [--smoke] [--frames=N] [--threads=N] [--scenes=DIR] --benchmark_filter=... --benchmark_format=json
//
// Run one size per process (run_all.sh does) so each one's peak memory is its own.

#include <malloc.h>

#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include "../pipeline/frame_bench.hpp"

namespace {

using namespace igi;
using namespace igi::bench;

/// `mesh` with every triangle cut into n x n: vertices on a barycentric grid (shared inside one
/// original triangle), attributes interpolated, winding kept.
Mesh tessellate(const Mesh& mesh, int n) {
  if (n <= 1) return mesh;
  Mesh out;
  out.name = mesh.name;
  out.material = mesh.material;
  const std::size_t grid = std::size_t(n + 1) * std::size_t(n + 2) / 2;
  out.positions.reserve(mesh.triangles.size() * grid);
  out.triangles.reserve(mesh.triangles.size() * std::size_t(n) * std::size_t(n));
  const bool normals = !mesh.normals.empty(), uvs = !mesh.uvs.empty(), uvs1 = !mesh.uvs1.empty(),
             tangents = !mesh.tangents.empty();
  for (const glm::uvec3& t : mesh.triangles) {
    const auto first = unsigned(out.positions.size());
    // Grid point (i, j) = a + i/n (b - a) + j/n (c - a), rows of constant i stored one after another.
    std::vector<unsigned> row_start(std::size_t(n) + 2);
    for (int i = 0; i <= n; ++i) {
      row_start[std::size_t(i)] = unsigned(out.positions.size()) - first;
      for (int j = 0; i + j <= n; ++j) {
        const float wb = float(i) / float(n), wc = float(j) / float(n), wa = 1.0f - wb - wc;
        auto blend = [&](const auto& v) { return wa * v[t.x] + wb * v[t.y] + wc * v[t.z]; };
        out.positions.push_back(blend(mesh.positions));
        if (normals) out.normals.push_back(glm::normalize(blend(mesh.normals)));
        if (uvs) out.uvs.push_back(blend(mesh.uvs));
        if (uvs1) out.uvs1.push_back(blend(mesh.uvs1));
        if (tangents) {  // interpolated and renormalised; a corner without a usable tangent (w = 0) leaves none
          const float sign = mesh.tangents[t.x].w;
          const bool usable = sign != 0.0f && mesh.tangents[t.y].w != 0.0f && mesh.tangents[t.z].w != 0.0f;
          out.tangents.push_back(usable ? glm::vec4(glm::normalize(glm::vec3(blend(mesh.tangents))), sign) : glm::vec4(0.0f));
        }
      }
    }
    auto at = [&](int i, int j) { return first + row_start[std::size_t(i)] + unsigned(j); };
    for (int i = 0; i < n; ++i)
      for (int j = 0; i + j < n; ++j) {
        out.triangles.emplace_back(at(i, j), at(i + 1, j), at(i, j + 1));
        if (i + j < n - 1) out.triangles.emplace_back(at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
      }
  }
  return out;
}

/// The scene with every non-emissive mesh cut n x n and, with `copies` > 1, each instance
/// repeated that many times along x, one scene width (and a tenth) apart.
Scene scaled_scene(const Scene& source, int n, int copies) {
  Scene scene = source;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (!scene.material_of(int(m)).emissive()) scene.meshes[m] = tessellate(source.meshes[m], n);
  if (copies > 1) {
    const float step = 1.1f * source.bounds().extent().x;
    const std::vector<Instance> originals = scene.instances;
    for (int c = 1; c < copies; ++c)
      for (Instance instance : originals) {
        instance.name += " copy " + std::to_string(c);
        instance.transform = glm::translate(glm::mat4(1.0f), glm::vec3(step * float(c), 0.0f, 0.0f)) * instance.transform;
        scene.instances.push_back(instance);
      }
  }
  return scene;
}

/// Bytes the igi Scene's meshes hold.
double scene_bytes(const Scene& scene) {
  double bytes = 0.0;
  for (const Mesh& m : scene.meshes)
    bytes += double(m.positions.capacity() * sizeof(glm::vec3) + m.normals.capacity() * sizeof(glm::vec3) +
                    m.uvs.capacity() * sizeof(glm::vec2) + m.uvs1.capacity() * sizeof(glm::vec2) +
                    m.tangents.capacity() * sizeof(glm::vec4) +
                    m.triangles.capacity() * sizeof(glm::uvec3));
  return bytes;
}

void size_benchmark(benchmark::State& state, const std::string& name, int n, int copies) {
  std::string why;
  const BenchScene* source = bench_scene(name, why);
  if (!source) {
    state.SkipWithError(why.c_str());
    return;
  }
  BenchScene bench = make_bench_scene(scaled_scene(source->scene, n, copies));
  bench.camera = source->camera;  // the copies stand beside the original: the view stays the same
  RenderSettings settings;
  settings.width = options().smoke ? 64 : 640;
  settings.height = options().smoke ? 48 : 480;
  settings.vpls_per_pixel = 16;
  settings.threads = options().threads;
  const Policies policies(bench.scene);
  constexpr double megabyte = 1024.0 * 1024.0;
  // Freed heap pages go back to the system first, so the backend's allocations cannot hide in
  // memory that was already resident (scene building frees a lot).
  malloc_trim(0);
  const Memory before = memory_now();
  reset_peak_memory();
  const auto start = std::chrono::steady_clock::now();
  BenchRenderer<EmbreeBackend<16>> renderer(bench.scene, settings, policies.surface, policies.brdf, policies.sampler,
                                            policies.filter);
  const double build_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  malloc_trim(0);  // what the build freed is not the BVH's
  const Memory after = memory_now();
  report_frames(state, render_frames(renderer, bench, false, options().frames), settings.threads);
  state.counters["triangles"] = double(bench.scene.triangle_count());
  state.counters["unique_triangles"] = double(bench.scene.unique_triangle_count());
  state.counters["build_ms"] = build_ms;
  state.counters["bvh_mb"] = (after.resident - before.resident) / megabyte;
  state.counters["build_peak_mb"] = (after.peak - before.resident) / megabyte;
  state.counters["scene_mb"] = scene_bytes(bench.scene) / megabyte;
  state.counters["process_peak_mb"] = memory_now().peak / megabyte;
  // A frame of an animation that moves every instance (glTF node animations move instances):
  // its set-up, the changes applied and the backend's commit, should grow with the instances and
  // not with the triangles, since instances move in the two-level BVH's top level alone.
  const std::vector<Instance> placed = bench.scene.instances;
  const float step = 1e-3f * glm::length(bench.scene.bounds().extent());
  std::vector<double> setup;
  for (int f = 1; f <= 5; ++f) {
    SceneChanges changes;
    changes.camera = bench.camera;
    for (std::size_t i = 0; i < placed.size(); ++i)
      changes.instances.emplace_back(int(i), glm::translate(glm::mat4(1.0f), glm::vec3(step * float(f), 0.0f, 0.0f)) * placed[i].transform);
    const auto apply_start = std::chrono::steady_clock::now();
    renderer.apply(changes);
    const double apply_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - apply_start).count();
    setup.push_back(apply_ms + renderer.render(bench.camera, std::uint32_t(f)).statistics.commit_milliseconds);
  }
  state.counters["instances"] = double(placed.size());
  state.counters["move_all_instances_ms"] = median(setup);
}

void register_all() {
  // Cornell: 36 triangles up to 34 x 550^2 + 2 = 10.3 M unique. Sponza_lit: 262 k rendered up to
  // 262 k x 10^2 = 26 M rendered, 11.6 M unique; and four instances of the 7 x 7 cut (4 x 12.8 M
  // = 51 M rendered, the paper's power plant). --smoke keeps only the smallest of each.
  const bool smoke = options().smoke;
  const std::vector<int> cornell = smoke ? std::vector<int>{1} : std::vector<int>{1, 8, 64, 550};
  const std::vector<int> sponza = smoke ? std::vector<int>{1} : std::vector<int>{1, 2, 4, 7, 10};
  const int power_plant = smoke ? 1 : 7;
  for (const int n : cornell)
    register_once("size/cornell/n:" + std::to_string(n), [=](benchmark::State& s) { size_benchmark(s, "cornell", n, 1); });
  for (const int n : sponza)
    register_once("size/sponza_lit/n:" + std::to_string(n), [=](benchmark::State& s) { size_benchmark(s, "sponza_lit", n, 1); });
  register_once("size/sponza_lit/n:" + std::to_string(power_plant) + "/instances:4",
                [=](benchmark::State& s) { size_benchmark(s, "sponza_lit", power_plant, 4); });
}

}  // namespace

int main(int argc, char** argv) { return igi::bench::run_benchmarks(argc, argv, register_all); }
