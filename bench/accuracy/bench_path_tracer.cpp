// Throughput of the reference path tracer: one sample per pixel of the built-in Cornell box at
// 64 x 64, per iteration; reports paths and rays per second.
#include <benchmark/benchmark.h>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

static void path_tracer_cornell(benchmark::State& state) {
  const igi::Scene scene = igi::cornell_box();
  const igi::EmbreeBackend<1> backend(scene);
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  igi::PathTracerSettings settings;
  settings.threads = int(state.range(0));
  igi::PathTracer<igi::EmbreeBackend<1>, igi::GltfMaterialShader, igi::StandardBrdf> tracer(scene, backend, surface, brdf, settings);
  tracer.reset(scene.cameras.front(), 64, 64);
  for (auto _ : state) tracer.add_samples(1);
  const igi::PathTracerStatistics& s = tracer.statistics();
  state.counters["paths/s"] = benchmark::Counter(double(s.paths), benchmark::Counter::kIsRate);
  state.counters["rays/s"] = benchmark::Counter(double(s.rays.total()), benchmark::Counter::kIsRate);
}
BENCHMARK(path_tracer_cornell)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();

BENCHMARK_MAIN();
