// igi-render: renders a glTF scene or the built-in Cornell box with the IGI pipeline (or, later,
// the reference path tracer) and writes the image; the front door of every measurement.
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>
#include <oneapi/tbb/info.h>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/io/image.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace {

/// Everything the command line decides.
struct Options {
  std::string scene_file;
  std::string builtin;
  std::string output = "out.png";
  std::string size = "640x480";
  std::string filter = "discontinuity";
  std::string backend = "embree";
  std::string integrator = "igi";
  std::string camera;
  std::string stats;
  int packet = 16;
  int frames = 1;
  int spp = 16;
  igi::RenderSettings settings;
};

/// A usage error: exit code 2 with a one-line message.
struct UsageError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Parses "WIDTHxHEIGHT".
void parse_size(const std::string& text, igi::RenderSettings& settings) {
  int width = 0, height = 0;
  char x = 0, rest = 0;
  if (std::sscanf(text.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || (x != 'x' && x != 'X'))
    throw UsageError("--size: '" + text + "' is not WIDTHxHEIGHT");
  settings.width = width;
  settings.height = height;
}

/// The median of some values.
double median(std::vector<double> values) {
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

/// Renders with backend B and writes the image and statistics.
template <class B>
int run(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::QmcVplSampler sampler;
  const igi::FilterChoice filter(options.filter);
  igi::Renderer<B, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler, igi::FilterChoice> renderer(
      scene, options.settings, surface, brdf, sampler, filter);
  std::vector<double> milliseconds;
  igi::Frame frame;
  igi::RayCounts rays;
  for (int f = 0; f < options.frames; ++f) {
    frame = renderer.render(camera, std::uint32_t(f));
    milliseconds.push_back(frame.statistics.milliseconds);
    rays = frame.statistics.rays;
  }
  const std::filesystem::path output(options.output);
  // PNG gets the tone-mapped pixels; EXR and PFM the linear radiance.
  if (igi::image_format(output) == igi::ImageFormat::png)
    igi::write_image(output, frame.rgb8);
  else
    igi::write_image(output, frame.hdr);

  const double ms = median(milliseconds);
  const double mrays = ms > 0.0 ? double(rays.total()) / (ms * 1e3) : 0.0;
  const int threads = options.settings.threads > 0 ? options.settings.threads : tbb::info::default_concurrency();
  if (options.stats == "json") {
    nlohmann::json stats = {
        {"scene", scene.name},
        {"triangles", scene.triangle_count()},
        {"width", options.settings.width},
        {"height", options.settings.height},
        {"frames", options.frames},
        {"ms_per_frame", ms},
        {"fps", ms > 0.0 ? 1000.0 / ms : 0.0},
        {"rays_primary", rays.primary},
        {"rays_shadow", rays.shadow},
        {"rays_secondary", rays.secondary},
        {"mrays_per_s", mrays},
        {"backend", B::name()},
        {"packet", B::width},
        {"threads", threads},
        {"vpls_per_pixel", options.settings.vpls_per_pixel},
        {"interleave", options.settings.interleave},
        {"aa", options.settings.antialiasing},
        {"filter", filter.chosen()},
        {"clamp", options.settings.clamp_distance},
        {"vpls_per_frame", frame.statistics.vpls},
        {"vpl_ms", frame.statistics.vpl_milliseconds},
        {"output", options.output},
    };
    std::cout << stats.dump() << std::endl;
  } else {
    std::printf("%s: %zu triangles, %dx%d, %s/%d, %d threads, %d VPLs per pixel, S=%d, aa %d, filter %s\n",
                scene.name.c_str(), scene.triangle_count(), options.settings.width, options.settings.height,
                B::name(), B::width, threads, options.settings.vpls_per_pixel, options.settings.interleave,
                options.settings.antialiasing, filter.chosen());
    std::printf("frame time %.2f ms (median of %d), %.1f fps, %.2f Mrays/s (%llu primary, %llu shadow, %llu secondary)\n",
                ms, options.frames, ms > 0.0 ? 1000.0 / ms : 0.0, mrays, (unsigned long long)rays.primary,
                (unsigned long long)rays.shadow, (unsigned long long)rays.secondary);
    std::printf("wrote %s\n", options.output.c_str());
  }
  return 0;
}

/// Chooses the backend type from the options.
int dispatch(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  const int p = options.packet;
  if (options.backend == "saarcor") {
    if (p != 16 && p != 64) throw UsageError("--packet: the saarcor backend traces 8x8 = 64-ray packets only");
    return run<igi::SaarcorBackend>(scene, camera, options);
  }
  if (options.backend == "embree") {
    if (p == 1) return run<igi::EmbreeBackend<1>>(scene, camera, options);
    if (p == 4) return run<igi::EmbreeBackend<4>>(scene, camera, options);
    if (p == 8) return run<igi::EmbreeBackend<8>>(scene, camera, options);
    return run<igi::EmbreeBackend<16>>(scene, camera, options);
  }
  if (p == 1) return run<igi::ReferenceBackend<1>>(scene, camera, options);
  if (p == 4) return run<igi::ReferenceBackend<4>>(scene, camera, options);
  if (p == 8) return run<igi::ReferenceBackend<8>>(scene, camera, options);
  return run<igi::ReferenceBackend<16>>(scene, camera, options);
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CLI::App app{"igi-render: interactive global illumination (instant radiosity with interleaved sampling)"};
  app.add_option("scene", options.scene_file, "glTF scene (.gltf or .glb)");
  app.add_option("--builtin", options.builtin, "built-in scene instead of a file")->check(CLI::IsMember({"cornell"}));
  app.add_option("-o,--output", options.output, "output image: .png (tone mapped), .exr or .pfm (HDR)")->capture_default_str();
  app.add_option("--size", options.size, "image size WIDTHxHEIGHT")->capture_default_str();
  app.add_option("--vpls", options.settings.vpls_per_pixel, "VPLs per pixel (M, the size of one interleaving set)")->capture_default_str();
  app.add_option("--interleave", options.settings.interleave, "interleaving pattern size S (S x S VPL sets)")->capture_default_str();
  app.add_option("--aa", options.settings.antialiasing, "primary rays per pixel N (interleaved super-sampling)")->capture_default_str();
  app.add_option("--filter", options.filter, "irradiance filter")->check(CLI::IsMember({"discontinuity", "box", "none"}))->capture_default_str();
  app.add_option("--clamp", options.settings.clamp_distance, "minimum VPL distance in 1/d^2 (negative: 2% of the scene diagonal)")->capture_default_str();
  app.add_option("--backend", options.backend, "ray-tracing backend")->check(CLI::IsMember({"embree", "saarcor", "reference"}))->capture_default_str();
  app.add_option("--packet", options.packet, "packet width W")->check(CLI::IsMember({1, 4, 8, 16, 64}))->capture_default_str();
  app.add_option("--threads", options.settings.threads, "worker threads (0: all cores)")->check(CLI::Range(0, 1024))->capture_default_str();
  app.add_option("--frames", options.frames, "frames to render (timings are their median)")->check(CLI::Range(1, 100000))->capture_default_str();
  app.add_option("--integrator", options.integrator, "igi, or path for the reference path tracer")->check(CLI::IsMember({"igi", "path"}))->capture_default_str();
  app.add_option("--spp", options.spp, "samples per pixel of the path tracer")->check(CLI::Range(1, 1 << 20))->capture_default_str();
  app.add_option("--camera", options.camera, "glTF camera name (default: the file's first, else a fitted view)");
  app.add_option("--seed", options.settings.seed, "randomisation seed")->capture_default_str();
  app.add_option("--stats", options.stats, "print statistics as one JSON object on stdout")->check(CLI::IsMember({"json"}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "igi-render: " << e.what() << "\n";
    return 2;
  }
  try {
    parse_size(options.size, options.settings);
    if (options.scene_file.empty() == options.builtin.empty())
      throw UsageError("give either a SCENE file or --builtin cornell");
    if (options.integrator == "path")
      throw UsageError("--integrator path: the reference path tracer is not part of igi-render yet");
    igi::validate(options.settings);
  } catch (const std::exception& e) {
    std::cerr << "igi-render: " << e.what() << "\n";
    return 2;
  }
  try {
    igi::Scene scene = options.builtin.empty() ? igi::load_gltf(options.scene_file) : igi::cornell_box();
    igi::Camera camera;
    if (!options.camera.empty()) {
      const igi::Camera* named = igi::find_camera(scene, options.camera);
      if (!named) {
        std::cerr << "igi-render: --camera: no camera named '" << options.camera << "' in " << scene.name << "\n";
        return 2;
      }
      camera = *named;
    } else {
      camera = scene.cameras.empty() ? igi::default_camera(scene) : scene.cameras.front();
    }
    return dispatch(scene, camera, options);
  } catch (const std::exception& e) {
    std::cerr << "igi-render: " << e.what() << "\n";
    return 1;
  }
}
