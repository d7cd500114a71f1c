#pragma once
// What the frame-level benchmarks (pipeline_bench, scaling_bench) share: the two scenes, the
// renderer they run, the command-line knobs outside Google Benchmark's own, and the helpers that
// turn rendered frames into Google Benchmark counters (by medians: programs::median).

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <time.h>

#include <benchmark/benchmark.h>
#include <glm/gtc/matrix_transform.hpp>

#include "common/program_options.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace igi::bench {

/// Knobs the benchmark programs take before Google Benchmark's own flags.
struct Options {
  bool smoke = false;       ///< Tiny images and one frame: checks that everything runs, measures nothing.
  int frames = 5;           ///< Timed frames per configuration (medians are reported).
  int threads = 2;          ///< Threads of multi-threaded runs (the machine's two cores).
  std::string scenes = IGI_SCENES_DIR;  ///< Folder of the shared glTF scenes.
};

/// The options of this process (set by parse_options).
inline Options& options() {
  static Options o;
  return o;
}

/// Takes --smoke, --frames=N, --threads=N and --scenes=DIR out of argv (the rest goes to Google
/// Benchmark); exits with a one-line message on a malformed value.
inline void parse_options(int& argc, char** argv) {
  Options& o = options();
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    auto number = [&](const char* prefix, int low, int high) {
      const std::string text = arg.substr(std::strlen(prefix));
      char* end = nullptr;
      const long value = std::strtol(text.c_str(), &end, 10);
      if (text.empty() || *end != '\0' || value < low || value > high) {
        std::fprintf(stderr, "%s: %s needs a whole number in %d..%d, got '%s'\n", argv[0], prefix, low, high, text.c_str());
        std::exit(2);
      }
      return int(value);
    };
    if (arg == "--smoke")
      o.smoke = true;
    else if (arg.rfind("--frames=", 0) == 0)
      o.frames = number("--frames=", 1, 1000);
    else if (arg.rfind("--threads=", 0) == 0)
      o.threads = number("--threads=", 1, 1024);
    else if (arg.rfind("--scenes=", 0) == 0)
      o.scenes = arg.substr(std::strlen("--scenes="));
    else
      argv[kept++] = argv[i];
  }
  argc = kept;
  if (o.smoke) o.frames = 1;
}

/// A scene to measure, its camera and the instance that moves in "dynamic" runs.
struct BenchScene {
  Scene scene;                ///< Geometry, materials, lights.
  Camera camera;              ///< The file's first camera, else a fitted one.
  int moving_instance = 0;    ///< Instance moved every frame in dynamic runs.
};

/// The instance dynamic runs move: Cornell's short block, else the last instance (any instance
/// costs the same: Embree re-commits the instance level whichever one moved).
inline int pick_moving_instance(const Scene& scene) {
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].name.find("short") != std::string::npos) return int(i);
  return int(scene.instances.size()) - 1;
}

/// Wraps a loaded scene with its camera and moving instance.
inline BenchScene make_bench_scene(Scene scene) {
  BenchScene b;
  b.camera = scene.cameras.empty() ? default_camera(scene) : scene.cameras.front();
  b.moving_instance = pick_moving_instance(scene);
  b.scene = std::move(scene);
  return b;
}

/// "cornell" (built in) or "sponza_lit" (Sponza_lit.gltf in the scenes folder), loaded once per
/// process; null (and `why` set) when the file is missing.
inline BenchScene* bench_scene(const std::string& name, std::string& why) {
  static std::map<std::string, std::unique_ptr<BenchScene>> cache;
  auto found = cache.find(name);
  if (found != cache.end()) return found->second.get();
  std::unique_ptr<BenchScene> loaded;
  if (name == "cornell") {
    loaded = std::make_unique<BenchScene>(make_bench_scene(cornell_box()));
  } else if (name == "sponza_lit") {
    const std::filesystem::path file = std::filesystem::path(options().scenes) / "sponza" / "Sponza_lit.gltf";
    if (!std::filesystem::exists(file)) {
      why = "scene file " + file.string() + " is missing (pass --scenes=DIR)";
      return nullptr;
    }
    loaded = std::make_unique<BenchScene>(make_bench_scene(load_gltf(file)));
    loaded->scene.name = "sponza_lit";
  } else {
    why = "unknown scene '" + name + "'";
    return nullptr;
  }
  return (cache[name] = std::move(loaded)).get();
}

/// The renderer every frame-level benchmark runs: glTF materials, the standard BRDF, QMC VPLs
/// and the discontinuity filter ("full shading and filtering"), over backend B.
template <class B>
using BenchRenderer = Renderer<B, GltfMaterialShader, StandardBrdf, QmcVplSampler, DiscontinuityFilter>;

/// The policies a BenchRenderer borrows, built for one scene.
struct Policies {
  explicit Policies(const Scene& scene) : surface(scene) {}
  GltfMaterialShader surface;  ///< glTF materials.
  StandardBrdf brdf;           ///< Lambert + Phong + mirror + glass.
  QmcVplSampler sampler;       ///< The paper's VPLs.
  DiscontinuityFilter filter;  ///< The paper's filter.
};

/// The programs' median (0 for none), which the frame-level benchmarks report timings by too.
using programs::median;

/// CPU time of the whole process (all threads) in milliseconds: on a loaded machine it says how
/// much work a frame was, where the wall clock also says how long it waited for a core.
inline double process_cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return double(t.tv_sec) * 1e3 + double(t.tv_nsec) * 1e-6;
}

/// Where the moving instance is in frame `index` of a dynamic run: its original transform
/// shifted along a small circle (1% of the scene diagonal), so every frame differs.
inline glm::mat4 moved(const glm::mat4& original, float diagonal, std::uint32_t index) {
  const float angle = 0.7f * float(index);
  const glm::vec3 offset = 0.01f * diagonal * glm::vec3(std::cos(angle), 0.0f, std::sin(angle));
  return glm::translate(glm::mat4(1.0f), offset) * original;
}

/// Timings of a run of frames.
struct FrameRun {
  std::vector<double> milliseconds;      ///< Whole frames.
  std::vector<double> vpl_milliseconds;  ///< Their set-up part (VPLs, matrices).
  std::vector<double> cpu_milliseconds;  ///< Process CPU time of each frame (all threads).
  RayCounts rays;                        ///< Rays of the last frame.
  int pixels = 0;                        ///< Pixels per frame.
  StageTimes stages;                     ///< CPU time per stage of one more frame, rendered with profiling.
};

/// Renders one untimed warm-up frame and then options().frames timed ones (frame indices
/// 1, 2, ...); with `dynamic` the scene's moving instance moves before every frame (the move and
/// Embree's re-commit are inside the timed frame). The renderer's scene is restored afterwards.
template <class R>
FrameRun render_frames(R& renderer, const BenchScene& bench, bool dynamic, int frames) {
  FrameRun run;
  const glm::mat4 original = bench.scene.instances[std::size_t(bench.moving_instance)].transform;
  const Bounds bounds = bench.scene.bounds();
  const float diagonal = glm::length(bounds.extent());
  for (int f = 0; f <= frames; ++f) {
    if (dynamic) renderer.set_instance_transform(bench.moving_instance, moved(original, diagonal, std::uint32_t(f)));
    const double cpu_start = process_cpu_ms();
    const Frame frame = renderer.render(bench.camera, std::uint32_t(f));
    const double cpu = process_cpu_ms() - cpu_start;
    if (f == 0) continue;  // warm-up: thread workspaces are allocated in the first frame
    run.cpu_milliseconds.push_back(cpu);
    run.milliseconds.push_back(frame.statistics.milliseconds);
    run.vpl_milliseconds.push_back(frame.statistics.vpl_milliseconds);
    run.rays = frame.statistics.rays;
    run.pixels = frame.width * frame.height;
  }
  // Where the time goes: one more frame with every stage timed (not among the timed frames: the
  // clock reads make a frame 2-9% slower).
  renderer.set_profiling(true);
  run.stages = renderer.render(bench.camera, std::uint32_t(frames)).statistics.stages;
  renderer.set_profiling(false);
  if (dynamic) {
    renderer.set_instance_transform(bench.moving_instance, original);
    renderer.render(bench.camera, 0);  // commits the restored transform
  }
  return run;
}

/// Puts a run's medians into `state`'s counters and its manual time: ms per frame, fps, Mrays/s
/// (total and per thread), ns per pixel, set-up ms and the ray counts by kind; the CPU time per
/// frame, and cpu_share = CPU time / (wall time x threads), which is near 1 on an idle machine;
/// and the profiled frame's CPU ms per pipeline stage (stage_ms_*).
inline void report_frames(benchmark::State& state, const FrameRun& run, int threads) {
  const double ms = median(run.milliseconds);
  const double cpu_ms = median(run.cpu_milliseconds);
  state.counters["cpu_ms_per_frame"] = cpu_ms;
  state.counters["cpu_share"] = ms > 0.0 ? cpu_ms / (ms * threads) : 0.0;
  // Rays per second of CPU time: the paper's "per CPU" figure, whatever else ran on the machine.
  state.counters["mrays_per_cpu_s"] = cpu_ms > 0.0 ? double(run.rays.total()) / (cpu_ms * 1e3) : 0.0;
  const double mrays = ms > 0.0 ? double(run.rays.total()) / (ms * 1e3) : 0.0;
  state.counters["ms_per_frame"] = ms;
  state.counters["fps"] = ms > 0.0 ? 1000.0 / ms : 0.0;
  state.counters["mrays_per_s"] = mrays;
  state.counters["mrays_per_s_per_thread"] = mrays / threads;
  state.counters["ns_per_pixel"] = run.pixels > 0 ? ms * 1e6 / run.pixels : 0.0;
  state.counters["setup_ms"] = median(run.vpl_milliseconds);
  state.counters["rays_primary"] = double(run.rays.primary);
  state.counters["rays_shadow"] = double(run.rays.shadow);
  state.counters["rays_secondary"] = double(run.rays.secondary);
  state.counters["threads"] = threads;
  state.counters["frames"] = double(run.milliseconds.size());
  // CPU ms per stage of the profiled frame (stage_ms_total: all of them, against cpu_ms_per_frame).
  run.stages.each([&](const char* name, std::uint64_t ns) { state.counters[std::string("stage_ms_") + name] = double(ns) * 1e-6; });
  state.counters["stage_ms_total"] = double(run.stages.total()) * 1e-6;
}

/// Runs `body(state)` as the one iteration of a benchmark whose time is set by the body
/// (frame-level benchmarks time their own frames and report medians as counters).
template <class Body>
void once(benchmark::State& state, Body&& body) {
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    body(state);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count());
  }
}

/// Registers a frame-level benchmark run once, timed manually, reported in milliseconds.
template <class Body>
void register_once(const std::string& name, Body body) {
  benchmark::RegisterBenchmark(name.c_str(), [body](benchmark::State& state) { once(state, body); })
      ->Iterations(1)
      ->UseManualTime()
      ->Unit(benchmark::kMillisecond);
}

/// The main() of a benchmark program: our options, then `register_all()`, then Google Benchmark.
inline int run_benchmarks(int argc, char** argv, void (*register_all)()) {
  parse_options(argc, argv);
  register_all();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 2;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

/// Current and peak resident memory of this process in bytes, from /proc/self/status.
struct Memory {
  double resident = 0.0;  ///< VmRSS.
  double peak = 0.0;      ///< VmHWM (since the last reset_peak_memory()).
};
/// Reads Memory (zeros where /proc is not there).
inline Memory memory_now() {
  Memory m;
  std::ifstream status("/proc/self/status");
  std::string key;
  double kilobytes = 0.0;
  std::string unit;
  while (status >> key) {
    if (key == "VmRSS:" && status >> kilobytes >> unit) m.resident = kilobytes * 1024.0;
    else if (key == "VmHWM:" && status >> kilobytes >> unit) m.peak = kilobytes * 1024.0;
  }
  return m;
}
/// Resets the kernel's peak-RSS mark to the current RSS (Linux: "5" into clear_refs).
inline void reset_peak_memory() {
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
}

}  // namespace igi::bench
