#pragma once
// igi-render's whole command line: the options it shares with igi-cluster (render_options.hpp)
// plus its own (animation, temporal reuse, the file's animations, profiling), their checks and
// the --stats json fields of IGI frames. The Python module (python/) builds its keyword
// arguments from this same table, so every igi-render option is one of its keywords by name.

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "common/render_options.hpp"
#include "igi/render/renderer.hpp"

namespace igi::programs {

/// igi-render's options beside the shared ones (and those that play animations and camera paths).
struct IgiRenderOptions : RenderOptions, PlayOptions {
  std::string animate = "none";  ///< What moves from frame to frame (none: a still scene).
  bool profile = false;          ///< Time each pipeline stage (stats: stage_cpu_ms).
  bool aov = false;              ///< Also write the G-buffer images (write_aovs) beside each image.
  /// --temporal as given; unset, check_igi_render_options chooses default_temporal_frames for IGI
  /// frames and 0 for the path tracer.
  std::optional<int> temporal;
};

/// Adds every option of igi-render to `command_line`.
inline void add_igi_render_options(CommandLine& command_line, IgiRenderOptions& options) {
  add_render_options(command_line, options, "worker threads (0: all cores)",
                     "frames to render (timings are their median; with --integrator path: passes of --spp samples)");
  add_animate_option(command_line, options.animate,
                     "render --frames frames of a moving scene to an image sequence: -o out.png writes out_0000.png, "
                     "out_0001.png, ...; -o frames/%04d.png numbers them printf-style. light: the lights circle, "
                     "object: the smallest object slides, camera: the view orbits the scene");
  add_temporal_option(command_line, options.temporal, options.settings,
                      "By default " + std::to_string(default_temporal_frames) +
                          " frames with --integrator igi (the path tracer accumulates its passes anyway)");
  add_play_options(command_line, options);
  command_line.flag("--aov", options.aov,
                    "also write the G-buffer beside each image, for a denoiser or compositing: the first hit's albedo, "
                    "shading normal and depth (distance along the camera ray; 0 where it hit nothing), as out_albedo.exr, "
                    "out_normal.exr and out_depth.exr for -o out.exr (.pfm for .pfm; EXR for a PNG)");
  command_line.flag("--profile", options.profile,
                    "time each pipeline stage; --stats json then reports the last frame's CPU ms per stage as "
                    "stage_cpu_ms (the clock reads make the frames 2-9% slower)");
}

/// Resolves --temporal's default into the settings and checks the combinations the option checks
/// cannot (check_render_options, then igi-render's own); throws UsageError naming the problem. `sequences` says whether --output names an image
/// sequence to check (igi-render writes files; the Python module does not).
inline void check_igi_render_options(IgiRenderOptions& options, bool sequences = true) {
  if (options.temporal.value_or(0) > 0 && options.integrator != "igi")
    throw UsageError("--temporal averages IGI frames: it needs --integrator igi (the path tracer accumulates its passes anyway)");
  options.settings.temporal_frames = options.temporal.value_or(options.integrator == "igi" ? default_temporal_frames : 0);
  check_render_options(options);
  if (options.animate != "none") {
    if (options.integrator != "igi")
      throw UsageError("--animate renders with --integrator igi only (the path tracer accumulates one still image)");
    if (sequences) static_cast<void>(FrameNames(options.output, options.frames));  // a malformed %d pattern fails here, before any rendering
  }
  check_play_options(options, options, options.animate, sequences);
}

/// The --stats json fields of a run's frame time and rays: `milliseconds` per frame, `rays` per
/// frame, over `threads` worker threads.
inline StatsJson frame_time_statistics(const IgiRenderOptions& options, double milliseconds, const RayCounts& rays, int threads) {
  const double mrays = milliseconds > 0.0 ? double(rays.total()) / (milliseconds * 1e3) : 0.0;
  StatsJson stats;
  stats.set("frames", options.frames)
      .set("ms_per_frame", milliseconds)
      .set("fps", milliseconds > 0.0 ? 1000.0 / milliseconds : 0.0)
      .set("rays_primary", rays.primary)
      .set("rays_shadow", rays.shadow)
      .set("rays_secondary", rays.secondary)
      .set("mrays_per_s", mrays)
      .set("threads", threads)
      .set("integrator", options.integrator);
  return stats;
}

/// The median over `frames` of `value(frame)` (0 for no frames).
template <class Value>
double median_over(std::span<const FrameStatistics> frames, Value&& value) {
  std::vector<double> values;
  values.reserve(frames.size());
  for (const FrameStatistics& frame : frames) values.push_back(double(value(frame)));
  return median(std::move(values));
}

/// Each count's median over `frames`, so that rays per frame go with the frames' median time.
inline RayCounts median_rays(std::span<const FrameStatistics> frames) {
  const auto of = [&](std::uint64_t RayCounts::*count) {
    return std::uint64_t(std::llround(median_over(frames, [&](const FrameStatistics& f) { return f.rays.*count; })));
  };
  return {.primary = of(&RayCounts::primary), .shadow = of(&RayCounts::shadow), .secondary = of(&RayCounts::secondary)};
}

/// The --stats json fields of IGI `frames` beside the frame time: the sampling settings under the
/// names `filter` and `vpl_sampler` chose, the clamp and the rest of the settings, and what the
/// frames cost, each time and count the median over them (as ms_per_frame is; a view that moves
/// changes them from frame to frame); stage_cpu_ms is null unless the options profile.
inline StatsJson igi_frame_statistics(const IgiRenderOptions& options, const std::string& filter,
                                      const std::string& vpl_sampler, std::span<const FrameStatistics> frames) {
  StatsJson stats = sampling_statistics(options.settings, filter, vpl_sampler);
  stats.set("clamp", options.settings.clamp_distance)
      .set("compensation_rays", options.settings.compensation_rays)
      .set("shadow_roulette", double(options.settings.shadow_roulette))
      .set("max_bounces", options.settings.max_bounces)
      .set("temporal_frames", options.settings.temporal_frames)
      .set("reuse_shadows", options.settings.reuse_shadows && options.settings.temporal_frames > 0)
      .set("vpls_per_frame", int(std::lround(median_over(frames, [](const FrameStatistics& f) { return f.vpls; }))))
      .set("vpl_ms", median_over(frames, [](const FrameStatistics& f) { return f.vpl_milliseconds; }))
      .set("temporal_ms", median_over(frames, [](const FrameStatistics& f) { return f.temporal_milliseconds; }));
  if (options.profile) {
    StatsJson stages;
    StageTimes{}.each([&](const char* name, std::uint64_t) {
      const std::string stage = name;
      stages.set(name, 1e-6 * median_over(frames, [&](const FrameStatistics& f) {
                         std::uint64_t nanoseconds = 0;
                         f.stages.each([&](const char* other, std::uint64_t ns) {
                           if (other == stage) nanoseconds = ns;
                         });
                         return nanoseconds;
                       }));
    });
    stages.set("total", 1e-6 * median_over(frames, [](const FrameStatistics& f) { return f.stages.total(); }));
    stats.set("stage_cpu_ms", stages);
  } else {
    stats.set("stage_cpu_ms", nullptr);
  }
  return stats;
}

/// The file of the G-buffer image `layer` ("albedo", "normal", "depth") beside the image `output`:
/// out.exr -> out_albedo.exr; the G-buffer of a PNG image goes to EXR files, as it is not a colour.
inline std::filesystem::path aov_path(const std::filesystem::path& output, const std::string& layer) {
  std::filesystem::path path = output;
  const bool png = image_format(output) == ImageFormat::png;
  path.replace_filename(output.stem().string() + "_" + layer + (png ? std::string(".exr") : output.extension().string()));
  return path;
}

/// Writes the G-buffer `layers` (width x height, row by row from the top) beside the image
/// `output` (aov_path): albedo, normal and depth (the distance in all three channels).
inline void write_aovs(const std::filesystem::path& output, std::span<const PixelLayers> layers, int width, int height) {
  Image albedo(width, height), normal(width, height), depth(width, height);
  for (std::size_t i = 0; i < layers.size(); ++i) {
    albedo.pixels[i] = layers[i].albedo;
    normal.pixels[i] = layers[i].normal;
    depth.pixels[i] = glm::vec3(layers[i].depth);
  }
  write_image(aov_path(output, "albedo"), albedo);
  write_image(aov_path(output, "normal"), normal);
  write_image(aov_path(output, "depth"), depth);
}

/// The tone-mapped pixels of a converged image (the path tracer's): mapped with its own luminance
/// statistics, since it has no previous frame.
inline Rgb8Image tone_map_converged(const Image& hdr) {
  LuminanceStatistics luminance;
  for (const glm::vec3& p : hdr.pixels) luminance.add(p);
  const ToneMapping tone = ToneMapping::from(luminance);
  Rgb8Image rgb8(hdr.width, hdr.height);
  for (int y = 0; y < hdr.height; ++y)
    for (int x = 0; x < hdr.width; ++x) store_pixel(rgb8, x, y, quantize_srgb(tone.apply(hdr(x, y))));
  return rgb8;
}

}  // namespace igi::programs
