#pragma once
// The command line igi-render and igi-cluster share: scene, camera, image, IGI settings and the
// backend choice, made of the pieces of program_options.hpp, plus the camera choice, the backend
// dispatch and the --stats json fields that follow it.

#include <string>

#include "common/backend_choice.hpp"
#include "common/command_line.hpp"
#include "common/program_options.hpp"
#include "common/stats_json.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/io/image_files.hpp"
#include "igi/render/settings.hpp"
#include "igi/scene/camera.hpp"
#include "igi/simd/lanes.hpp"

namespace igi::programs {

/// What the shared options decide.
struct RenderOptions : SceneOptions {
  std::string output = "out.png";       ///< Image to write.
  std::string size = "640x480";         ///< WIDTHxHEIGHT as typed.
  std::string filter = "discontinuity"; ///< Filter name.
  std::string vpl_sampler = "qmc";      ///< VPL sampler name.
  std::string backend = "embree";       ///< Backend name.
  std::string integrator = "igi";       ///< igi or path.
  std::string camera;                   ///< glTF camera name, or empty.
  std::string stats;                    ///< "json" or empty.
  /// Packet width: by default one native register of floats (16 with AVX-512, 8 with AVX2, 4
  /// with SSE), where Embree has kernels of that width too. On an AVX2-only AMD EPYC, W = 8 took
  /// 0.91 of W = 16's time (two registers, Embree's 16-wide calls as halves) on Sponza_lit 640x480
  /// at 12 VPLs (median of 5 paired whole-process runs) and 0.83 on Cornell (run_all's width table).
  int packet = native_packet_width;
  int frames = 1;                       ///< Frames (or path-tracer passes).
  int spp = 16;                         ///< Path-tracer samples per pixel per pass.
  RenderSettings settings;              ///< The IGI settings.
};

/// Adds the shared options to `command_line`; `threads_help` and `frames_help` let a program word those two.
inline void add_render_options(CommandLine& command_line, RenderOptions& o, const std::string& threads_help,
                               const std::string& frames_help) {
  add_scene_options(command_line, o);
  command_line.add("-o,--output", o.output, "output image: .png (tone mapped), .exr or .pfm (HDR)").show_default();
  add_size_option(command_line, o.size);
  add_sampling_options(command_line, o.settings);
  add_filter_options(command_line, o.filter, o.settings);
  add_vpl_sampler_option(command_line, o.vpl_sampler);
  command_line.add("--clamp", o.settings.clamp_distance, "minimum VPL distance in 1/d^2 (negative: 2% of the scene diagonal)").show_default();
  command_line.add("--compensate", o.settings.compensation_rays,
                   "bias compensation: gather rays per pixel that return the light the clamp removes (0: off)")
      .range(0, igi::max_compensation_rays)
      .show_default();
  command_line.add("--roulette", o.settings.shadow_roulette,
                   "shadow-ray Russian roulette: VPLs below this fraction of a pixel's light so far get a shadow ray with "
                   "probability in proportion (unbiased; 0: every VPL gets one)")
      .range(0.0f, 1.0f)
      .show_default();
  command_line.add("--bounces", o.settings.max_bounces, "longest random walk of the light particles that leave VPLs")
      .range(0, 64)
      .show_default();
  add_backend_options(command_line, o.backend, o.packet);
  add_threads_option(command_line, o.settings.threads, threads_help);
  command_line.add("--tile", o.settings.tile_size, "tile edge in pixels (the image does not depend on it)").range(4, 1024).show_default();
  command_line.add("--frames", o.frames, frames_help).range(1, 100000).show_default();
  command_line.add("--integrator", o.integrator, "igi, or path for the reference path tracer").choices({"igi", "path"}).show_default();
  command_line.add("--spp", o.spp, "samples per pixel of the path tracer").range(1, 1 << 20).show_default();
  command_line.add("--camera", o.camera, "glTF camera name (default: the file's first, else a fitted view)");
  add_seed_option(command_line, o.settings.seed);
  command_line.add("--stats", o.stats, "print statistics as one JSON object on stdout").choices({"json"});
}

/// Checks what the option checks cannot: the size, scene xor --builtin, the settings, the output format.
inline void check_render_options(RenderOptions& o) {
  const ImageSize size = parse_image_size(o.size);
  o.settings.width = size.width;
  o.settings.height = size.height;
  check_scene_options(o);
  validate(o.settings);
  image_format(o.output);
}

/// The camera the options name: --camera, else the scene's first, else one fitted to the scene.
inline Camera choose_camera(const Scene& scene, const RenderOptions& o) {
  if (!o.camera.empty()) {
    const Camera* named = find_camera(scene, o.camera);
    if (!named) throw UsageError("--camera: no camera named '" + o.camera + "' in " + scene.name);
    return *named;
  }
  return scene.cameras.empty() ? default_camera(scene) : scene.cameras.front();
}

/// The backend types igi-render and igi-cluster run: every backend at every width it has.
using RenderBackends = BackendList<EmbreeBackend<1>, EmbreeBackend<4>, EmbreeBackend<8>, EmbreeBackend<16>,
                                   ReferenceBackend<1>, ReferenceBackend<4>, ReferenceBackend<8>,
                                   ReferenceBackend<16>, SaarcorBackend>;

/// Calls `run.template operator()<B>()` with the backend type B the options choose. --packet 16,
/// the default, means saarcor's one width with --backend saarcor.
template <class Run>
int with_backend(const RenderOptions& o, Run&& run) {
  const int p = o.packet;
  if (o.backend == "saarcor" && p != 16 && p != SaarcorBackend::width)
    throw UsageError("--packet: the saarcor backend traces 8x8 = 64-ray packets only");
  if (o.backend == "embree" && p == 64)
    throw UsageError("--packet 64: Embree traces packets of 1, 4, 8 or 16 rays (64 is saarcor's)");
  if (o.backend == "reference" && p == 64)
    throw UsageError("--packet 64: the reference backend is built for packets of 1, 4, 8 or 16 rays");
  return with_backend_of(RenderBackends{}, o.backend, o.backend == "saarcor" ? SaarcorBackend::width : p, run);
}

/// The --stats json fields of a run that igi-render and igi-cluster share: the scene, the image,
/// the backend, the output, the animation and, for IGI frames, the sampling settings and filter.
inline StatsJson run_statistics(const Scene& scene, const RenderOptions& o, const char* backend, int packet,
                                const std::string& animate) {
  StatsJson stats;
  stats.set("scene", scene.name)
      .set("triangles", std::uint64_t(scene.triangle_count()))
      .set("width", o.settings.width)
      .set("height", o.settings.height)
      .set("tile_size", o.settings.tile_size)
      .set("backend", backend)
      .set("packet", packet)
      .set("output", o.output)
      .set("animate", animate);
  return stats;
}

/// The --stats json fields of IGI's sampling settings, the filter `filter` and the VPL sampler
/// `vpl_sampler` (their own names for them).
inline StatsJson sampling_statistics(const RenderSettings& settings, const std::string& filter,
                                     const std::string& vpl_sampler) {
  StatsJson stats;
  stats.set("vpls_per_pixel", settings.vpls_per_pixel)
      .set("interleave", settings.interleave)
      .set("aa", settings.antialiasing)
      .set("filter", filter)
      .set("filter_delta_lights", settings.filter_delta_lights)
      .set("filter_textures", settings.filter_textures)
      .set("vpl_sampler", vpl_sampler);
  return stats;
}

}  // namespace igi::programs
