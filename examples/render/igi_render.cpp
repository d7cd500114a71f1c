// igi-render: renders a glTF scene or the built-in Cornell box with the IGI pipeline (or, later,
// the reference path tracer) and writes the image; the front door of every measurement.
#include <algorithm>
#include <chrono>
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
#include "igi/render/path_tracer.hpp"
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

/// Writes the image: PNG gets the tone-mapped pixels, EXR and PFM the linear radiance.
void write_output(const Options& options, const igi::Image& hdr, const igi::Rgb8Image& rgb8) {
  const std::filesystem::path output(options.output);
  if (igi::image_format(output) == igi::ImageFormat::png)
    igi::write_image(output, rgb8);
  else
    igi::write_image(output, hdr);
}

/// Prints the statistics, as one JSON object with --stats json, else as two lines.
void report(const igi::Scene& scene, const Options& options, const char* backend, int packet, double ms,
            const igi::RayCounts& rays, const nlohmann::json& extra) {
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
        {"backend", backend},
        {"packet", packet},
        {"threads", threads},
        {"integrator", options.integrator},
        {"output", options.output},
    };
    stats.update(extra);
    std::cout << stats.dump() << std::endl;
    return;
  }
  std::printf("%s: %zu triangles, %dx%d, %s/%d, %d threads, integrator %s\n", scene.name.c_str(),
              scene.triangle_count(), options.settings.width, options.settings.height, backend, packet, threads,
              options.integrator.c_str());
  std::printf("frame time %.2f ms (median of %d), %.1f fps, %.2f Mrays/s (%llu primary, %llu shadow, %llu secondary)\n",
              ms, options.frames, ms > 0.0 ? 1000.0 / ms : 0.0, mrays, (unsigned long long)rays.primary,
              (unsigned long long)rays.shadow, (unsigned long long)rays.secondary);
  std::printf("wrote %s\n", options.output.c_str());
}

/// Renders with the IGI pipeline over backend B and writes the image and statistics.
template <class B>
int run_igi(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::QmcVplSampler sampler;
  const igi::FilterChoice filter(options.filter);
  igi::Renderer<B, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler, igi::FilterChoice> renderer(
      scene, options.settings, surface, brdf, sampler, filter);
  std::vector<double> milliseconds;
  igi::Frame frame;
  for (int f = 0; f < options.frames; ++f) {
    frame = renderer.render(camera, std::uint32_t(f));
    milliseconds.push_back(frame.statistics.milliseconds);
  }
  write_output(options, frame.hdr, frame.rgb8);
  report(scene, options, B::name(), B::width, median(milliseconds), frame.statistics.rays,
         {{"vpls_per_pixel", options.settings.vpls_per_pixel},
          {"interleave", options.settings.interleave},
          {"aa", options.settings.antialiasing},
          {"filter", filter.chosen()},
          {"clamp", options.settings.clamp_distance},
          {"vpls_per_frame", frame.statistics.vpls},
          {"vpl_ms", frame.statistics.vpl_milliseconds}});
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
  for (int f = 0; f < options.frames; ++f) {
    const auto start = std::chrono::steady_clock::now();
    tracer.add_samples(options.spp);
    milliseconds.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  const igi::Image hdr = tracer.image();
  // A converged reference has no previous frame: it is tone mapped with its own statistics.
  igi::LuminanceStatistics luminance;
  for (const glm::vec3& p : hdr.pixels) luminance.add(p);
  const igi::ToneMapping tone = igi::ToneMapping::from(luminance);
  igi::Rgb8Image rgb8(hdr.width, hdr.height);
  for (int y = 0; y < hdr.height; ++y)
    for (int x = 0; x < hdr.width; ++x) {
      const glm::u8vec3 q = igi::quantize_srgb(tone.apply(hdr(x, y)));
      std::uint8_t* p = rgb8.pixel(x, y);
      p[0] = q.r;
      p[1] = q.g;
      p[2] = q.b;
    }
  write_output(options, hdr, rgb8);
  igi::RayCounts per_pass = tracer.statistics().rays;
  const auto passes = std::uint64_t(options.frames);
  per_pass = {per_pass.primary / passes, per_pass.shadow / passes, per_pass.secondary / passes};
  report(scene, options, B::name(), B::width, median(milliseconds), per_pass,
         {{"spp", options.spp}, {"spp_total", tracer.samples()}});
  return 0;
}

/// Runs the chosen integrator over backend B.
template <class B>
int run(igi::Scene& scene, const igi::Camera& camera, const Options& options) {
  return options.integrator == "path" ? run_path<B>(scene, camera, options) : run_igi<B>(scene, camera, options);
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
  app.add_option("--frames", options.frames, "frames to render (timings are their median; with --integrator path: passes of --spp samples)")->check(CLI::Range(1, 100000))->capture_default_str();
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
