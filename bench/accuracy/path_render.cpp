// igi-path-render [SCENE.gltf | --builtin cornell] -o OUT.{exr,pfm,png} --size WxH --spp K [--aov]:
// the reference path tracer, for comparisons against other renderers (mitsuba_compare.sh), and
// with --aov the first hit's albedo and normal beside the image, what a denoiser reads
// (sky_anchor.py gives them to Open Image Denoise).
// Exit codes: 0 rendered, 1 the scene or image failed, 2 usage error.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "common/command_line.hpp"
#include "common/program_options.hpp"

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/io/image_files.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/pixel_layers.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace {

/// The file of the first-hit image `layer` beside the image `output`: out.pfm -> out_albedo.pfm;
/// a PNG image's go to EXR files, as albedo and normal are not display colours.
std::filesystem::path first_hit_path(const std::filesystem::path& output, const std::string& layer) {
  const bool png = igi::image_format(output) == igi::ImageFormat::png;
  std::filesystem::path path = output;
  path.replace_filename(output.stem().string() + "_" + layer + (png ? std::string(".exr") : output.extension().string()));
  return path;
}

/// Writes the albedo and shading normal of `layers` (width x height, row by row from the top; zero
/// where the ray escapes) beside the image `output`.
void write_first_hits(const std::filesystem::path& output, const std::vector<igi::PixelLayers>& layers, int width, int height) {
  igi::Image albedo(width, height), normal(width, height);
  for (std::size_t i = 0; i < layers.size(); ++i) {
    albedo.pixels[i] = layers[i].albedo;
    normal.pixels[i] = layers[i].normal;
  }
  igi::write_image(first_hit_path(output, "albedo"), albedo);
  igi::write_image(first_hit_path(output, "normal"), normal);
}

}  // namespace

int main(int argc, char** argv) {
  igi::programs::CommandLine command_line{"igi-path-render", "igi's reference path tracer into an HDR image"};
  igi::programs::SceneOptions scene_options;
  std::string output, size = "256x256";
  int spp = 64, threads = 0;
  std::uint32_t seed = 0;
  bool centre = false, aov = false;
  igi::programs::add_scene_options(command_line, scene_options);
  command_line.add("-o,--output", output, "Output image (.exr, .pfm or .png)").required();
  igi::programs::add_size_option(command_line, size);
  command_line.add("--spp", spp, "Samples per pixel").range(1, 1 << 20);
  igi::programs::add_seed_option(command_line, seed);
  igi::programs::add_threads_option(command_line, threads, "Worker threads (0: all cores)");
  command_line.flag("--pixel-centre", centre, "Sample pixel centres only (as IGI without anti-aliasing)");
  command_line.flag("--aov", aov,
                    "Also write the first hit's albedo and normal beside the image (OUT_albedo, OUT_normal), "
                    "of the ray through each pixel's centre");
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  int width = 0, height = 0;
  try {
    const igi::programs::ImageSize image_size = igi::programs::parse_image_size(size);
    width = image_size.width;
    height = image_size.height;
    igi::programs::check_scene_options(scene_options);
  } catch (const igi::programs::UsageError& error) {
    std::cerr << "igi-path-render: " << error.what() << "\n";
    return 2;
  }
  try {
    const igi::Scene scene = igi::programs::load_scene(scene_options);
    const igi::EmbreeBackend<1> backend(scene);
    const igi::GltfMaterialShader surface(scene);
    const igi::StandardBrdf brdf;
    igi::PathTracerSettings settings;
    settings.seed = seed;
    settings.threads = threads;
    settings.jitter = !centre;
    igi::PathTracer<igi::EmbreeBackend<1>, igi::GltfMaterialShader, igi::StandardBrdf> tracer(scene, backend, surface, brdf,
                                                                                              settings);
    const igi::Camera camera = scene.cameras.empty() ? igi::default_camera(scene) : scene.cameras.front();
    const auto start = std::chrono::steady_clock::now();
    const igi::Image image = tracer.render(camera, width, height, spp);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    igi::write_image(output, image);
    // The first hits are traced after the timed render, so the time above is the image's alone
    // (a renderer that samples pixel centres has them from its first sample's camera ray).
    double first_hit_seconds = 0.0;
    if (aov) {
      const auto first_hit_start = std::chrono::steady_clock::now();
      const std::vector<igi::PixelLayers> layers = tracer.first_hits();
      first_hit_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - first_hit_start).count();
      write_first_hits(output, layers, width, height);
    }
    // Before the report line, which stays the last (sky.py reads the time from it).
    if (aov) std::fprintf(stderr, "first hits (albedo, normal) in %.4f s\n", first_hit_seconds);
    const igi::PathTracerStatistics& s = tracer.statistics();
    std::fprintf(stderr, "%s: %dx%d, %d spp in %.3f s; rays: %llu primary, %llu shadow, %llu secondary; %llu invalid samples\n",
                 output.c_str(), width, height, spp, seconds, (unsigned long long)s.rays.primary,
                 (unsigned long long)s.rays.shadow, (unsigned long long)s.rays.secondary,
                 (unsigned long long)s.invalid_samples);
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "igi-path-render: " << error.what() << "\n";
    return 1;
  }
}
