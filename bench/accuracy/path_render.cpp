// igi-path-render [SCENE.gltf | --builtin cornell] -o OUT.{exr,pfm,png} --size WxH --spp K:
// the reference path tracer, for comparisons against other renderers (mitsuba_compare.sh).
// Exit codes: 0 rendered, 1 the scene or image failed, 2 usage error.
#include <chrono>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "common/command_line.hpp"
#include "common/program_options.hpp"

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/io/image_files.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

int main(int argc, char** argv) {
  igi::programs::CommandLine command_line{"igi-path-render", "igi's reference path tracer into an HDR image"};
  igi::programs::SceneOptions scene_options;
  std::string output, size = "256x256";
  int spp = 64, threads = 0;
  std::uint32_t seed = 0;
  bool centre = false;
  igi::programs::add_scene_options(command_line, scene_options);
  command_line.add("-o,--output", output, "Output image (.exr, .pfm or .png)").required();
  igi::programs::add_size_option(command_line, size);
  command_line.add("--spp", spp, "Samples per pixel").range(1, 1 << 20);
  igi::programs::add_seed_option(command_line, seed);
  igi::programs::add_threads_option(command_line, threads, "Worker threads (0: all cores)");
  command_line.flag("--pixel-centre", centre, "Sample pixel centres only (as IGI without anti-aliasing)");
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
    const igi::PathTracerStatistics& s = tracer.statistics();
    std::fprintf(stderr, "%s: %dx%d, %d spp in %.2f s; rays: %llu primary, %llu shadow, %llu secondary; %llu invalid samples\n",
                 output.c_str(), width, height, spp, seconds, (unsigned long long)s.rays.primary,
                 (unsigned long long)s.rays.shadow, (unsigned long long)s.rays.secondary,
                 (unsigned long long)s.invalid_samples);
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "igi-path-render: " << error.what() << "\n";
    return 1;
  }
}
