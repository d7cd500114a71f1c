// Packet against single-ray shading, the paper's claim that SIMD packets pay off in shading too:
// the pipeline's VPL shading step - connect a hit point to a VPL, trace the shadow ray, evaluate
// the BRDF - run by the library's own code at packet widths W = 1, 4, 8, 16 (Embree) and 64 (SaarCOR), with and without the shadow rays.
// W = 1 is the same code at width 1: the paper's "single ray". `surface/…` times the surface
// shader (glTF materials, textures read at the pixels' footprints) alone over the same hit points.
//
//   shading_bench [--smoke] [--scenes=DIR] --benchmark_format=json
//
// Hit points come from real primary rays of a 640x480 view (the scene's camera), grouped as the
// pipeline groups them (per tile and interleaving set, in packets of sub-grid neighbours), shaded
// by the glTF material shader; each pixel connects to the 16 VPLs of its interleaving set from the
// QMC VPL sampler, VPL by VPL over the packets of one tile and set, as Pipeline::shade_level does.
// Only that loop is timed. Counters: items_per_second = shading samples (hit point x VPL) per CPU
// second, speedup_over_w1 = that rate over the W = 1 rate of the same scene and mode (present when
// W = 1 ran first in the same process, as it does by default).

#include <cstdint>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "common/backend_choice.hpp"
#include "frame_bench.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/lighting/vpl.hpp"
#include "igi/render/interleaving.hpp"
#include "igi/render/pipeline.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "igi/shading/surface_hit_builder.hpp"

namespace {

using namespace igi;
using igi::bench::options;

/// The view: the paper's 640x480 (a tenth of it with --smoke).
RenderSettings view_settings() {
  RenderSettings settings;  // S = 3, M = 16 VPLs per pixel: the paper's configuration
  settings.width = options().smoke ? 64 : 640;
  settings.height = options().smoke ? 48 : 480;
  return settings;
}

/// What every width shares for one scene: the frame set-up of the pipeline (VPL sets from the
/// QMC sampler, instance matrices, projection, clamp distance, ray offset).
struct SceneFrame {
  const Scene* scene = nullptr;  ///< The scene (owned by frame_bench's cache).
  RenderSettings settings;       ///< View and VPL counts.
  FrameState frame;              ///< FrameState::prepare's output, as the renderer makes it.
};

/// The frame of scene `name` ("cornell", "sponza_lit"), made once; null (and `why` set) if missing.
SceneFrame* scene_frame_of(const std::string& name, std::string& why) {
  static std::map<std::string, std::unique_ptr<SceneFrame>> cache;
  if (auto found = cache.find(name); found != cache.end()) return found->second.get();
  bench::BenchScene* loaded = bench::bench_scene(name, why);
  if (!loaded) return nullptr;
  auto made = std::make_unique<SceneFrame>();
  made->scene = &loaded->scene;
  made->settings = view_settings();
  const EmbreeBackend<16> backend(loaded->scene);  // VPL walks trace single rays: any backend gives the same VPLs
  made->frame.prepare(loaded->scene, loaded->scene.bounds(), backend, GltfMaterialShader(loaded->scene), StandardBrdf{},
                      QmcVplSampler{}, made->settings, loaded->camera, 0, ToneMapping{});
  return (cache[name] = std::move(made)).get();
}

/// The hit points of one scene as packets of width W, grouped like the pipeline's streams: one
/// group per (tile, interleaving set), connected to that set's VPLs.
template <class B>
struct ShadingPoints {
  static constexpr int W = B::width;
  /// One group of packets (the stream of one tile and set).
  struct Group {
    int set = 0;                 ///< Interleaving set: which VPLs its pixels connect to.
    std::size_t begin = 0, end = 0;  ///< Its packets.
  };
  std::unique_ptr<B> backend;               ///< The scene's backend at width W.
  std::vector<Group> groups;                ///< Streams in pipeline order.
  std::vector<SurfaceHit<W>> surfaces;      ///< Hit points per packet.
  std::vector<BrdfParameters<W>> parameters;  ///< Surface shader output per packet.
  std::vector<vmask<W>> hit;                ///< Lanes that hit something.
  std::int64_t hit_points = 0;              ///< Lanes that hit something.
  std::int64_t samples = 0;                 ///< Hit points x VPLs of their set: shading samples per pass.
};

/// Traces the primary rays of `frame` at width B::width (pixel centres, no anti-aliasing) and
/// shades their hit points with the glTF material shader.
template <class B>
std::unique_ptr<ShadingPoints<B>> make_points(const SceneFrame& scene_frame) {
  constexpr int W = B::width;
  auto points = std::make_unique<ShadingPoints<B>>();
  const Scene& scene = *scene_frame.scene;
  const FrameState& context = scene_frame.frame;
  const RenderSettings& s = scene_frame.settings;
  points->backend = std::make_unique<B>(scene);
  const GltfMaterialShader surface(scene);
  std::vector<PixelPacket<W>> pixels;
  for (const PixelRect& tile : make_tiles(s.width, s.height, s.tile_size))
    for (int set = 0; set < s.interleave * s.interleave; ++set) {
      make_set_packets<W>(tile, s.interleave, set, pixels);
      if (pixels.empty()) continue;
      typename ShadingPoints<B>::Group group{set, points->surfaces.size(), 0};
      for (const PixelPacket<W>& packet : pixels) {
        const vmask<W> active = vmask<W>::first(packet.count);
        const vfloat<W> px([&](int i) { return i < packet.count ? float(packet.x[i]) + 0.5f : 0.0f; });
        const vfloat<W> py([&](int i) { return i < packet.count ? float(packet.y[i]) + 0.5f : 0.0f; });
        RayPacket<W> rays;
        rays.set(vec3<W>(context.projection->origin()), keep(context.projection->direction(px, py), active),
                 vfloat<W>(0.0f), vfloat<W>(std::numeric_limits<float>::infinity()), active);
        HitPacket<W> hits;
        hits.clear();
        points->backend->intersect(rays, hits, active);
        const vmask<W> hit = active & hits.valid();
        // The camera rays' cones, as the pipeline's first level makes them, so textures are read at
        // the pixels' footprints (aa 1).
        points->surfaces.push_back(make_surface_hit(scene, context.geometry, rays, hits, hit,
                                                    context.texture_cone_scale * context.projection->pixel_spread()));
        points->parameters.push_back(surface.shade(points->surfaces.back(), hit));
        points->hit.push_back(hit);
        points->hit_points += popcount(hit);
        points->samples += std::int64_t(popcount(hit)) *
                           std::int64_t(context.vpls.sets[std::size_t(set)].size());
      }
      group.end = points->surfaces.size();
      points->groups.push_back(group);
    }
  return points;
}

/// The points of the (scene, backend) measured now; the previous pair's are freed first (each
/// holds a 640x480 image of hit points, and benchmarks of one pair run one after another).
template <class B>
ShadingPoints<B>& points_for(const std::string& scene_name, const SceneFrame& scene_frame) {
  static std::string key;
  static std::shared_ptr<void> current;
  const std::string wanted = scene_name + "/" + B::name() + "/" + std::to_string(B::width);
  if (key != wanted) {
    current.reset();
    current = std::shared_ptr<ShadingPoints<B>>(make_points<B>(scene_frame));
    key = wanted;
  }
  return *static_cast<ShadingPoints<B>*>(current.get());
}

/// CPU seconds of this thread (the timed loop runs on one thread).
double thread_cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

/// Shading samples per CPU second at W = 1, by "scene/mode", for the speed-up counters.
std::map<std::string, double>& single_ray_rates() {
  static std::map<std::string, double> rates;
  return rates;
}

/// One pass of the pipeline's VPL step over all hit points: for each (tile, set) stream, for each
/// of the set's VPLs, for each packet: connect, shadow ray (if `shadows`), BRDF contribution.
/// Each packet's shading frame is resolved once for all its VPLs, as the pipeline does after the
/// surface shader (timed here with the rest).
template <class B>
void shade_all(const ShadingPoints<B>& points, const FrameState& context, const StandardBrdf& brdf, bool shadows,
               std::vector<VplAccumulator<B::width>>& light, std::vector<VplReceiver<B::width>>& receivers) {
  constexpr int W = B::width;
  for (const auto& group : points.groups) {
    light.assign(group.end - group.begin, VplAccumulator<W>{});
    receivers.resize(group.end - group.begin);
    for (std::size_t p = group.begin; p < group.end; ++p)
      receivers[p - group.begin] = make_vpl_receiver(points.surfaces[p], points.parameters[p]);
    for (const Vpl& vpl : context.vpls.sets[std::size_t(group.set)]) {
      for (std::size_t p = group.begin; p < group.end; ++p) {
        const SurfaceHit<W>& surface = points.surfaces[p];
        if (none(points.hit[p])) continue;
        const VplGeometry<W> geometry =
            connect(vpl, surface.position, surface.geometric_normal, context.clamp_distance, points.hit[p]);
        if (none(geometry.reaches)) continue;
        vmask<W> visible = geometry.reaches;
        if (shadows) {
          // The pipeline's shadow ray: offset off the surface, stopping short of the VPL by the same offset.
          RayPacket<W> shadow;
          const vec3<W> origin = surface.position + surface.geometric_normal * vfloat<W>(context.ray_epsilon);
          const vfloat<W> length = max(geometry.distance - vfloat<W>(2.0f * context.ray_epsilon), vfloat<W>(0.0f));
          shadow.set(origin, geometry.wi, vfloat<W>(0.0f), length, geometry.reaches);
          visible &= !points.backend->occluded(shadow, geometry.reaches);
        }
        brdf.add_vpl(receivers[p - group.begin], points.parameters[p], geometry, vpl.intensity, light[p - group.begin], visible);
      }
    }
    benchmark::DoNotOptimize(light.data());
    benchmark::ClobberMemory();
  }
}

/// The frame of `scene_name`, or null with the benchmark skipped and the reason given.
SceneFrame* scene_frame_or_skip(benchmark::State& state, const std::string& scene_name) {
  std::string why;
  SceneFrame* scene_frame = scene_frame_of(scene_name, why);
  if (!scene_frame) state.SkipWithError(("skipped: " + why).c_str());
  return scene_frame;
}

/// Reports `items` per iteration over the benchmark's `seconds` of CPU time, and (for `mode`,
/// "scene/what") the rate's speed-up over W = 1's, which W = 1 records when it runs first.
template <class B>
void count_items(benchmark::State& state, const std::string& mode, std::int64_t items, double seconds) {
  state.SetItemsProcessed(state.iterations() * items);
  const double rate = seconds > 0.0 ? double(state.iterations() * items) / seconds : 0.0;
  if (B::width == 1 && std::string(B::name()) == "embree") single_ray_rates()[mode] = rate;
  if (auto found = single_ray_rates().find(mode); found != single_ray_rates().end() && found->second > 0.0)
    state.counters["speedup_over_w1"] = rate / found->second;
}

/// The benchmark: shade every hit point of `scene_name` with its 16 VPLs at width B::width.
template <class B>
void shading(benchmark::State& state, const std::string& scene_name, bool shadows) {
  SceneFrame* scene_frame = scene_frame_or_skip(state, scene_name);
  if (!scene_frame) return;
  const ShadingPoints<B>& points = points_for<B>(scene_name, *scene_frame);
  const StandardBrdf brdf;
  std::vector<VplAccumulator<B::width>> light;
  std::vector<VplReceiver<B::width>> receivers;
  const double start = thread_cpu_seconds();
  for (auto _ : state) shade_all(points, scene_frame->frame, brdf, shadows, light, receivers);
  const double seconds = thread_cpu_seconds() - start;
  state.counters["hit_points"] = double(points.hit_points);
  state.counters["shadow_rays"] = shadows ? 1.0 : 0.0;
  count_items<B>(state, scene_name + (shadows ? "/shadow" : "/no_shadow"), points.samples, seconds);
}

/// The surface shader alone: the glTF material shader over every hit packet of the view (the
/// pipeline's step 3 after make_surface_hit), hit points per CPU second.
template <class B>
void surface_shading(benchmark::State& state, const std::string& scene_name) {
  SceneFrame* scene_frame = scene_frame_or_skip(state, scene_name);
  if (!scene_frame) return;
  const ShadingPoints<B>& points = points_for<B>(scene_name, *scene_frame);
  const GltfMaterialShader surface(*scene_frame->scene);  // its mip chains built before the timing
  const double start = thread_cpu_seconds();
  for (auto _ : state)
    for (std::size_t p = 0; p < points.surfaces.size(); ++p) {
      BrdfParameters<B::width> parameters = surface.shade(points.surfaces[p], points.hit[p]);
      benchmark::DoNotOptimize(parameters);
    }
  const double seconds = thread_cpu_seconds() - start;
  count_items<B>(state, scene_name + "/surface", points.hit_points, seconds);
}

/// Registers one benchmark pair (with and without shadow rays) of backend B on `scene`.
template <class B>
void register_pair(const std::string& scene) {
  for (const bool shadows : {true, false})
    benchmark::RegisterBenchmark(("shading/" + scene + "/" + B::name() + "/" + std::to_string(B::width) +
                                  (shadows ? "/shadow" : "/no_shadow"))
                                     .c_str(),
                                 [scene, shadows](benchmark::State& state) { shading<B>(state, scene, shadows); })
        ->Unit(benchmark::kMillisecond);
  benchmark::RegisterBenchmark(("surface/" + scene + "/" + B::name() + "/" + std::to_string(B::width)).c_str(),
                               [scene](benchmark::State& state) { surface_shading<B>(state, scene); })
      ->Unit(benchmark::kMillisecond);
}

/// Registers every scene's benchmarks, width by width in the list's order (W = 1 first: the
/// speed-ups divide by it; a width's two modes run back to back on the same hit points).
void register_all() {
  using Widths = programs::BackendList<EmbreeBackend<1>, EmbreeBackend<4>, EmbreeBackend<8>, EmbreeBackend<16>, SaarcorBackend>;
  for (const char* scene : {"cornell", "sponza_lit"})
    programs::for_each_backend(Widths{}, [&]<class B>() { register_pair<B>(scene); });
}

}  // namespace

int main(int argc, char** argv) { return igi::bench::run_benchmarks(argc, argv, register_all); }
