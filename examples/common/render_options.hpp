#pragma once
// The command line igi-render and igi-cluster share: scene, camera, image, IGI settings and the
// backend choice, made of the pieces of program_options.hpp, plus the camera choice, playing the
// file's animation, the backend dispatch and the --stats json fields that follow it.

#include <cmath>
#include <limits>
#include <optional>
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
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/camera_path.hpp"
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

/// Index into scene.cameras of the camera the options choose (-1: the default camera, no node).
inline int chosen_camera_index(const Scene& scene, const RenderOptions& o) {
  if (o.camera.empty()) return scene.cameras.empty() ? -1 : 0;
  const Camera* named = find_camera(scene, o.camera);
  return named != nullptr ? int(named - scene.cameras.data()) : -1;
}

/// What the options that play the file's own animation or a camera path decide.
struct PlayOptions {
  bool play = false;  ///< Render --frames frames of the file's animation, frame i at i / fps seconds.
  double fps = 24.0;  ///< Frames per second of --play and --camera-path.
  /// With --time: the one time (seconds) of the file's animation and camera path to render
  /// (before their first key they hold their first pose); NaN without --time.
  double time = std::numeric_limits<double>::quiet_NaN();
  std::string animation = "0";  ///< The file's animation to play: its name or index.
  bool loop = false;            ///< Time wraps around the animation's duration instead of holding its last pose.
  std::string camera_path;      ///< A glTF file whose animated camera the frames follow (a walkthrough), or empty.

  /// Whether the options render one moment of the animation or path (--time).
  bool at_one_time() const { return !std::isnan(time); }
  /// Whether the options render a sequence of moments: --play, or --camera-path without --time.
  bool plays_sequence() const { return play || (!camera_path.empty() && !at_one_time()); }
};

/// Adds --play, --fps, --time, --animation, --loop and --camera-path to `command_line`.
inline void add_play_options(CommandLine& command_line, PlayOptions& o) {
  command_line.flag("--play", o.play,
                    "render --frames frames of the file's own animation (glTF animations, skins, morph targets), frame i at "
                    "time i / --fps, to an image sequence named as with --animate");
  command_line.add("--fps", o.fps, "frames per second of --play and --camera-path").show_default();
  command_line.add("--time", o.time, "render one frame of the file's animation (and camera path) at this time, in seconds");
  command_line.add("--animation", o.animation, "the file's animation --play and --time play: its name or index").show_default();
  command_line.flag("--loop", o.loop, "--play, --time and --camera-path wrap around the animation instead of holding its last pose");
  command_line.add("--camera-path", o.camera_path,
                   "a glTF file whose animated camera the view follows (a walkthrough: its first camera and first "
                   "animation): --frames frames at --fps, or one at --time; with --play the scene's own animation plays too");
}

/// Checks what the option checks cannot: --play and --time against each other, --animate,
/// --camera and the integrator, --fps, and (with `sequences`: for a program that writes files)
/// the names of an image sequence.
inline void check_play_options(const PlayOptions& o, const RenderOptions& render, const std::string& animate,
                               bool sequences = true) {
  if (!o.play && !o.at_one_time() && o.camera_path.empty()) return;
  if (animate != "none") throw UsageError("--play, --time and --camera-path play files' animations: they exclude --animate");
  if (o.play && o.at_one_time()) throw UsageError("--play renders a sequence and --time one frame: choose one");
  if (!o.camera_path.empty() && !render.camera.empty())
    throw UsageError("--camera-path gives the camera: it excludes --camera");
  if (o.plays_sequence() && render.integrator != "igi")
    throw UsageError("a sequence (--play, --camera-path) renders with --integrator igi only (the path tracer accumulates "
                     "one still image; --time renders one moment with it)");
  if (!(o.fps > 0.0) || !std::isfinite(o.fps)) throw UsageError("--fps must be a positive number");
  if (o.plays_sequence() && sequences) static_cast<void>(FrameNames(render.output, render.frames));  // a malformed %d pattern fails here
}

/// A camera path the options name, as a UsageError if it cannot be followed.
inline CameraPath open_camera_path(const PlayOptions& o) {
  try {
    return CameraPath(o.camera_path, "0", o.loop);
  } catch (const SceneError& e) {
    throw UsageError(std::string("--camera-path: ") + e.what());
  }
}

/// What a sequence of frames plays: the file's own animation (--play) and a camera path.
class Playback {
 public:
  /// Plays what `o` asks of `scene`, seen by the camera of scene.cameras[camera_index] (-1: one
  /// of the program's own); throws UsageError naming a missing animation or a bad path.
  Playback(const Scene& scene, const PlayOptions& o, int camera_index) : fps_(o.fps), camera_index_(camera_index) {
    if (o.play) {
      try {
        player_.emplace(scene, find_animation(scene, o.animation), o.loop);
      } catch (const SceneError& e) {
        throw UsageError(e.what());
      }
    }
    if (!o.camera_path.empty()) path_.emplace(open_camera_path(o));
  }
  /// The scene changes of frame `frame` (at frame / fps seconds) seen from `camera`, or from the
  /// camera path; `times` receives what sampling the animation cost.
  SceneChanges operator()(int frame, const Camera& camera, AnimationTimes* times = nullptr) const {
    const double seconds = double(frame) / fps_;
    SceneChanges changes;
    changes.camera = camera;
    if (player_) changes = (*player_)(seconds, camera, camera_index_, times);
    if (path_) changes.camera = path_->at(seconds);
    return changes;
  }
  /// The file's animation played, if any.
  const AnimationPlayer* player() const noexcept { return player_ ? &*player_ : nullptr; }

 private:
  double fps_;                            ///< Frames per second.
  int camera_index_;                      ///< The scene camera the animation may move (-1: none).
  std::optional<AnimationPlayer> player_;  ///< The file's animation, with --play.
  std::optional<CameraPath> path_;         ///< The camera path, with --camera-path.
};

/// With --time, poses `scene` and `camera` at that time: the file's animation (unless the scene
/// has none and a camera path gives the motion) and the camera path; with --play, checks that the
/// animation exists. A missing animation or bad path is a UsageError naming it.
inline void pose_for_play(Scene& scene, Camera& camera, const PlayOptions& o, int camera_index) {
  if (o.play) static_cast<void>(Playback(scene, o, camera_index));
  if (!o.at_one_time()) return;
  if (!scene.animations.empty() || o.camera_path.empty()) {
    try {
      const AnimationPlayer player(scene, find_animation(scene, o.animation), o.loop);
      const SceneChanges changes = player(o.time, camera, camera_index);
      changes.apply_to(scene);
      camera = changes.camera;
    } catch (const SceneError& e) {
      throw UsageError(e.what());
    }
  }
  if (!o.camera_path.empty()) camera = open_camera_path(o).at(o.time);
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
