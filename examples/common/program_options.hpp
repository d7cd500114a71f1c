#pragma once
// The pieces every program's command line is made of: the options several programs share (scene,
// image size, IGI settings, backend, threads, seed, animation), their checks, the median the
// programs report timings by, the writing of their images and the names of an image sequence's
// files. Compiled once, in
// program_options.cpp (the CMake target igi_command_line).

#include <cstdint>
#include <filesystem>
#include <initializer_list>
#include <optional>
#include <string>
#include <vector>

#include "common/command_line.hpp"
#include "igi/render/settings.hpp"
#include "igi/scene/scene.hpp"

namespace igi {
struct Image;
struct Rgb8Image;
}  // namespace igi

namespace igi::programs {

/// An image size in pixels.
struct ImageSize {
  int width = 0;   ///< Pixels per row.
  int height = 0;  ///< Rows.
};

/// Parses "WIDTHxHEIGHT" (or "WIDTHXHEIGHT"), both whole numbers of at least 1; throws UsageError
/// naming `option` and the text for anything else ("0x5", "10x", "axb", "-3x4").
ImageSize parse_image_size(const std::string& text, const std::string& option = "--size");

/// The median of `values` (the mean of the middle two for an even count); 0 for none.
double median(std::vector<double> values);

/// The scene a program renders: a glTF file or a built-in scene.
struct SceneOptions {
  std::string scene_file;  ///< glTF file, or empty with --builtin.
  std::string builtin;     ///< "cornell" or "window", or empty with a file.
  /// --environment: an equirectangular HDR map's file, "neutral" (neutral_sky()), "none", or
  /// empty for the scene's own light (the neutral sky where it has none).
  std::string environment;
  float environment_scale = 1.0f;     ///< --environment-scale: factor on the environment's radiance.
  float environment_rotation = 0.0f;  ///< --environment-rotation: degrees about +Y.
};

/// Adds the positional SCENE file, --builtin and the environment's options.
void add_scene_options(CommandLine& command_line, SceneOptions& scene);
/// Throws UsageError unless exactly one of a SCENE file and --builtin was given.
void check_scene_options(const SceneOptions& scene);
/// The scene the options name as it is: the glTF file loaded, or the built-in scene built.
Scene read_scene(const SceneOptions& scene);
/// Gives `scene` the environment the options name; a scene without light gets the neutral sky,
/// said in one line on stderr.
void light_scene(Scene& scene, const SceneOptions& options);
/// read_scene, then light_scene: the scene a program renders.
Scene load_scene(const SceneOptions& scene);

/// Adds --size WIDTHxHEIGHT (the text is parsed later, by parse_image_size).
void add_size_option(CommandLine& command_line, std::string& size);
/// Adds --vpls, --interleave and --aa: the IGI sampling settings M, S and N.
void add_sampling_options(CommandLine& command_line, RenderSettings& settings);
/// History length, in frames, of the temporal reuse igi-render and igi-view apply by default (the
/// library's RenderSettings::temporal_frames stays 0: a Renderer renders independent frames unless
/// asked). On every walkthrough temporal reuse lowered the image mean's variation, the flicker and
/// relMSE (bench/results/walkthrough.json); 32 frames, a second at 30 fps, lets a still view
/// converge far, while a moving camera caps the history at 8 frames by itself (TemporalReuse).
inline constexpr int default_temporal_frames = 32;
/// Adds --temporal (programs that render whole frames in one process), setting `temporal` when
/// given; unset, the program chooses (default_temporal_frames for IGI frames). `default_help`
/// says what the program does without it. Also --trace-shadows (RenderSettings::reuse_shadows off).
void add_temporal_option(CommandLine& command_line, std::optional<int>& temporal, RenderSettings& settings,
                         const std::string& default_help);
/// Adds --filter (discontinuity, atrous, box or none), --filter-delta-lights (RenderSettings::filter_delta_lights)
/// and --point-textures (RenderSettings::filter_textures off).
void add_filter_options(CommandLine& command_line, std::string& filter, RenderSettings& settings);
/// Adds --vpl-sampler: qmc or importance (names of igi::VplSamplerChoice).
void add_vpl_sampler_option(CommandLine& command_line, std::string& sampler);
/// Adds --backend (embree, saarcor or reference) and --packet (the packet width W).
void add_backend_options(CommandLine& command_line, std::string& backend, int& packet);
/// Adds --threads (0: all cores), worded by `help`.
void add_threads_option(CommandLine& command_line, int& threads, const std::string& help);
/// Adds --seed, the randomisation seed.
void add_seed_option(CommandLine& command_line, std::uint32_t& seed);
/// Adds --animate: what moves from frame to frame, explained by `help`, one of `names` (names of
/// igi::parse_animation; by default all of them).
void add_animate_option(CommandLine& command_line, std::string& animate, const std::string& help,
                        std::initializer_list<std::string> names = {"none", "light", "object", "camera"});

/// Writes an image: PNG gets the tone-mapped pixels `rgb8`, EXR and PFM the linear radiance `hdr`.
void write_output(const std::filesystem::path& path, const Image& hdr, const Rgb8Image& rgb8);

/// The files of an image sequence (an animation), named after --output: a name with a frame number
/// conversion %d or %0Nd (N = 1..9; a literal percent sign is %%) gets the number printed there
/// (frames/%04d.png -> frames/0007.png); any other name gets _NNNN before its extension
/// (out.png -> out_0007.png), four digits or as many as the last frame needs.
class FrameNames {
 public:
  /// Names for frames 0..frames-1 of `output`; throws UsageError for a malformed pattern.
  FrameNames(const std::string& output, int frames);
  /// The file of frame `frame`.
  std::filesystem::path operator()(int frame) const;

 private:
  std::string before_, after_;  ///< Text around the frame number.
  int digits_ = 4;              ///< Minimum digits of the frame number (zero padded).
};

}  // namespace igi::programs
