// single-process-frames: the frames igi-cluster renders, made by one process with igi::Renderer
// and the same deterministic scene changes (igi/render/animation.hpp). The distributed
// tests compare the cluster's frames with these pixel for pixel.
#include <iostream>
#include <optional>
#include <string>

#include "common/command_line.hpp"
#include "common/program_options.hpp"

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/render/animation.hpp"
#include "igi/io/image_files.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

int main(int argc, char** argv) {
  igi::programs::SceneOptions scene_options;
  std::string output = "frame.png", size = "160x120", animate = "none", filter_name = "discontinuity";
  int frames = 1;
  igi::RenderSettings settings;
  igi::programs::CommandLine command_line{"single-process-frames", "igi-cluster's frames from one process (Renderer + the same animation)"};
  igi::programs::add_scene_options(command_line, scene_options);
  command_line.add("-o,--output", output, "frames go to <stem>_NNNN<ext> (as igi-render --animate names them)");
  command_line.add("--size", size, "WIDTHxHEIGHT");
  command_line.add("--vpls", settings.vpls_per_pixel, "VPLs per pixel");
  command_line.add("--interleave", settings.interleave, "interleaving S");
  command_line.add("--aa", settings.antialiasing, "primary rays per pixel");
  command_line.add("--filter", filter_name, "irradiance filter").choices({"discontinuity", "box", "none"});
  command_line.add("--threads", settings.threads, "threads");
  command_line.add("--seed", settings.seed, "seed");
  command_line.add("--tile", settings.tile_size, "tile edge");
  command_line.add("--frames", frames, "frames").range(1, 100000);
  command_line.add("--animate", animate, "animation").choices({"none", "light", "camera", "object"});
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  try {
    const igi::programs::ImageSize image_size = igi::programs::parse_image_size(size);
    settings.width = image_size.width;
    settings.height = image_size.height;
    igi::programs::check_scene_options(scene_options);
    igi::Scene scene = igi::programs::load_scene(scene_options);
    const igi::Camera camera = scene.cameras.empty() ? igi::default_camera(scene) : scene.cameras.front();
    const igi::Scene initial = scene;
    const igi::Animation animation = igi::parse_animation(animate);
    const igi::Animator animator(initial, camera, animation);
    const igi::GltfMaterialShader surface(scene);
    const igi::StandardBrdf brdf;
    const igi::QmcVplSampler sampler;
    const igi::FilterChoice filter(filter_name);
    igi::Renderer<igi::EmbreeBackend<16>, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                  igi::FilterChoice>
        renderer(scene, settings, surface, brdf, sampler, filter);
    const igi::programs::FrameNames names(output, frames);
    for (int f = 0; f < frames; ++f) {
      // Only values that differ are set, as TileRenderer::apply does (an unchanged scene is not re-committed).
      const igi::Camera view = renderer.apply(animator(std::uint32_t(f)));
      const igi::Frame frame = renderer.render(view, std::uint32_t(f));
      igi::write_image(names(f), frame.rgb8);
    }
  } catch (const std::exception& e) {
    std::cerr << "single-process-frames: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
