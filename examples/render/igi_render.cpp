// igi-render: renders a glTF scene or the built-in Cornell box with the IGI pipeline (or the
// reference path tracer) and writes the image, or with --animate an image sequence; the front door
// of every measurement. --play renders the file's own animation (glTF animations, skins, morph
// targets) frame by frame at --fps, --time one frame of it. A progress bar appears on stderr when it is a terminal.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include <oneapi/tbb/info.h>

#include "common/command_line.hpp"
#include "common/progress_bar.hpp"
#include "common/igi_render_options.hpp"
#include "common/stats_json.hpp"
#include "common/stop_signals.hpp"
#include "igi/render/animation.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "common/importance_sampler.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/render/light_check.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/renderer.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace {

using namespace igi::programs;

/// igi-render's options.
using Options = IgiRenderOptions;

/// Prints the statistics, as one JSON object with --stats json, else as two lines.
void report(const igi::Scene& scene, const Options& options, const char* backend, int packet, double ms,
            const igi::RayCounts& rays, const std::string& written, const StatsJson& extra) {
  const double mrays = ms > 0.0 ? double(rays.total()) / (ms * 1e3) : 0.0;
  const int threads = options.settings.threads > 0 ? options.settings.threads : tbb::info::default_concurrency();
  if (options.stats == "json") {
    run_statistics(scene, options, backend, packet, options.animate)
        .update(frame_time_statistics(options, ms, rays, threads))
        .update(extra)
        .print();
    return;
  }
  std::printf("%s: %zu triangles, %dx%d, %s/%d, %d threads, integrator %s\n", scene.name.c_str(),
              scene.triangle_count(), options.settings.width, options.settings.height, backend, packet, threads,
              options.integrator.c_str());
  std::printf("frame time %.2f ms (median of %d), %.1f fps, %.2f Mrays/s (%llu primary, %llu shadow, %llu secondary)\n",
              ms, options.frames, ms > 0.0 ? 1000.0 / ms : 0.0, mrays, (unsigned long long)rays.primary,
              (unsigned long long)rays.shadow, (unsigned long long)rays.secondary);
  std::printf("wrote %s\n", written.c_str());
}

/// Names on stderr an image that is black or far darker than the scene's lights would make it (igi::light_warning).
void warn_if_dark(const igi::Scene& scene, const igi::Image& hdr) {
  if (const std::string warning = igi::light_warning(scene, hdr); !warning.empty())
    std::cerr << "igi-render: warning: " << warning << "\n";
}

/// Renders with the IGI pipeline over backend B and writes the image and statistics.
template <class B>
int run_igi(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::programs::ProgramVplSampler sampler(options.vpl_sampler);
  const igi::FilterChoice filter(options.filter);
  igi::Renderer<B, igi::GltfMaterialShader, igi::StandardBrdf, igi::programs::ProgramVplSampler, igi::FilterChoice> renderer(
      scene, options.settings, surface, brdf, sampler, filter);
  renderer.set_profiling(options.profile);
  renderer.set_keep_layers(options.aov);
  const igi::Animation animation = igi::parse_animation(options.animate);
  const bool sequence = animation != igi::Animation::none || options.plays_sequence();
  const igi::Scene initial = animation != igi::Animation::none ? scene : igi::Scene{};  // animations are functions of the initial scene
  const igi::Animator animator(initial, camera, animation);
  // The file's animation samples the scene's own animation data, which applying changes leaves alone.
  std::optional<Playback> playback;
  if (options.plays_sequence()) playback.emplace(scene, options, chosen_camera_index(scene, options));
  const FrameNames names(options.output, options.frames);
  std::vector<double> sampling, deforming, applying;
  std::vector<igi::FrameStatistics> statistics;
  igi::Frame frame;
  ProgressBar progress(std::uint64_t(options.frames), "frames");
  for (int f = 0; f < options.frames; ++f) {
    const auto index = std::uint32_t(f);
    igi::Camera view = camera;
    igi::AnimationTimes times;
    if (playback) {
      const igi::SceneChanges changes = (*playback)(f, camera, &times);
      const auto apply_start = std::chrono::steady_clock::now();
      view = renderer.apply(changes);
      applying.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - apply_start).count());
    } else if (sequence) {
      view = renderer.apply(animator(index));
    }
    frame = renderer.render(view, index);
    if (stop_requested()) return stopped("igi-render");
    statistics.push_back(frame.statistics);
    sampling.push_back(times.sampling_milliseconds);
    deforming.push_back(times.deforming_milliseconds);
    if (sequence) write_output(names(f), frame.hdr, frame.rgb8);
    if (sequence && options.aov) write_aovs(names(f), renderer.layers(), frame.width, frame.height);
    progress.advance();
  }
  progress.finish();
  if (!sequence) write_output(options.output, frame.hdr, frame.rgb8);
  if (!sequence && options.aov) write_aovs(options.output, renderer.layers(), frame.width, frame.height);
  warn_if_dark(scene, frame.hdr);
  const std::string written = sequence ? names(0).string() + " .. " + names(options.frames - 1).string() + " (" +
                                             std::to_string(options.frames) + " frames)"
                                       : options.output;
  StatsJson extra = igi_frame_statistics(options, filter.chosen(), sampler.chosen(), statistics);
  const double bvh_update = median_over(statistics, [](const igi::FrameStatistics& f) { return f.commit_milliseconds; });
  if (options.play) {
    // Medians over the frames, as the frame time: sampling channels and nodes, skinning and
    // morphing vertices (these two before the frame), handing them to the scene and backend (also
    // before it), and committing them to the backend (refits, instance moves: part of the frame time).
    extra.set("animation_sampling_ms", median(sampling))
        .set("skinning_ms", median(deforming))
        .set("scene_update_ms", median(applying))
        .set("bvh_update_ms", bvh_update)
        .set("animation", playback->player()->animation().name)
        .set("play_fps", options.fps);
  }
  if (!options.camera_path.empty()) extra.set("camera_path", options.camera_path);
  report(scene, options, B::name(), B::width,
         median_over(statistics, [](const igi::FrameStatistics& f) { return f.milliseconds; }), median_rays(statistics),
         written, extra);
  if (options.play && options.stats != "json")
    std::printf("animation per frame (median): sampling %.3f ms, skinning %.3f ms, scene update %.3f ms, BVH update %.3f ms "
                "(the last within the frame time)\n",
                median(sampling), median(deforming), median(applying), bvh_update);
  return 0;
}

/// Renders with the reference path tracer over backend B (the frames are passes of --spp each,
/// accumulated) and writes the image and statistics.
template <class B>
int run_path(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  const B backend(scene);
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  igi::PathTracerSettings settings;
  settings.seed = options.settings.seed;
  settings.threads = options.settings.threads;
  igi::PathTracer<B, igi::GltfMaterialShader, igi::StandardBrdf> tracer(scene, backend, surface, brdf, settings);
  tracer.reset(camera, options.settings.width, options.settings.height);
  std::vector<double> milliseconds;
  // Each pass is added in steps so the bar moves; samples are pure functions of their index, so
  // the image is the same as with one add_samples(spp). 16 steps per pass: smooth enough to watch.
  const int step = std::max(1, options.spp / 16);
  ProgressBar progress(std::uint64_t(options.frames) * std::uint64_t(options.spp), "spp");
  for (int f = 0; f < options.frames; ++f) {
    const auto start = std::chrono::steady_clock::now();
    for (int added = 0; added < options.spp; added += step) {
      const int now = std::min(step, options.spp - added);
      tracer.add_samples(now);
      if (stop_requested()) return stopped("igi-render");
      progress.advance(std::uint64_t(now));
    }
    milliseconds.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  progress.finish();
  const igi::Image hdr = tracer.image();
  const igi::Rgb8Image rgb8 = tone_map_converged(hdr);
  write_output(options.output, hdr, rgb8);
  if (options.aov) write_aovs(options.output, tracer.first_hits(), hdr.width, hdr.height);
  warn_if_dark(scene, hdr);
  igi::RayCounts per_pass = tracer.statistics().rays;
  const auto passes = std::uint64_t(options.frames);
  per_pass = {per_pass.primary / passes, per_pass.shadow / passes, per_pass.secondary / passes};
  report(scene, options, B::name(), B::width, median(milliseconds), per_pass, options.output,
         StatsJson().set("spp", options.spp).set("spp_total", tracer.samples()));
  return 0;
}

/// Runs the chosen integrator over backend B.
template <class B>
int run(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  return options.integrator == "path" ? run_path<B>(scene, camera, options) : run_igi<B>(scene, camera, options);
}

}  // namespace

int main(int argc, char** argv) {
  install_stop_signals();
  Options options;
  CommandLine command_line{"igi-render", "interactive global illumination (instant radiosity with interleaved sampling)"};
  add_igi_render_options(command_line, options);
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  try {
    check_igi_render_options(options);
  } catch (const std::exception& e) {
    std::cerr << "igi-render: " << e.what() << "\n";
    return 2;
  }
  try {
    igi::Scene scene = load_scene(options);
    igi::Camera camera = choose_camera(scene, options);
    pose_for_play(scene, camera, options, chosen_camera_index(scene, options));
    try {
      igi::animate(scene, camera, igi::parse_animation(options.animate), 1);  // can this scene move that way?
    } catch (const igi::SettingsError& e) {
      throw UsageError(e.what());
    }
    return with_backend(options, [&]<class B>() { return run<B>(scene, camera, options); });
  } catch (const UsageError& e) {
    std::cerr << "igi-render: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "igi-render: " << e.what() << "\n";
    return 1;
  }
}
