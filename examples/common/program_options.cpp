// The shared command-line pieces of igi's programs (see program_options.hpp).
#include "common/program_options.hpp"

#include <algorithm>
#include <charconv>
#include <iostream>
#include <memory>
#include <optional>
#include <string_view>
#include <system_error>

#include "igi/io/environment_file.hpp"
#include "igi/io/image.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/window_room.hpp"

namespace igi::programs {

namespace {

/// The whole number that `text` is exactly (digits only, no sign), if it is one that fits an int.
std::optional<int> whole_number(std::string_view text) {
  if (text.empty() || !std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; }))
    return std::nullopt;
  int value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

ImageSize parse_image_size(const std::string& text, const std::string& option) {
  const std::size_t x = text.find_first_of("xX");
  const std::optional<int> width = x == std::string::npos ? std::nullopt : whole_number(std::string_view(text).substr(0, x));
  const std::optional<int> height = x == std::string::npos ? std::nullopt : whole_number(std::string_view(text).substr(x + 1));
  if (!width || !height) throw UsageError(option + ": '" + text + "' is not WIDTHxHEIGHT");
  if (*width < 1 || *height < 1)
    throw UsageError(option + ": '" + text + "' is not WIDTHxHEIGHT with WIDTH and HEIGHT at least 1");
  return {*width, *height};
}

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  const std::size_t n = values.size();
  std::sort(values.begin(), values.end());
  return n % 2 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

void add_scene_options(CommandLine& command_line, SceneOptions& scene) {
  command_line.add("scene", scene.scene_file, "glTF scene (.gltf or .glb)");
  command_line.add("--builtin", scene.builtin,
                   "built-in scene instead of a file: cornell (the Cornell box), window (a furnished room lit by the sun and sky through one window) or blinds (that room with venetian blinds in the window: the sun in stripes); window-sky and blinds-sky: those rooms under the sky instead of their sky panel; two-windows: the room under the sky with a second window in the left wall")
      .choices({"cornell", "window", "blinds", "window-sky", "blinds-sky", "two-windows"});
  command_line.add("--environment", scene.environment,
                   "light from all around: an equirectangular HDR map (.exr, .hdr; +Y up, the top row the zenith, "
                   "its left edge towards -Z), neutral (an overcast sky whose light on open ground is pi, beside the "
                   "scene's lights) or none; by default the scene's own lights, and the neutral sky for a scene that has none");
  command_line.add("--environment-scale", scene.environment_scale, "factor on the environment's radiance")
      .range(0.0f, 1e30f)
      .show_default();
  command_line.add("--environment-rotation", scene.environment_rotation, "turn of the environment about +Y, degrees")
      .range(-1e6f, 1e6f)
      .show_default();
}

void check_scene_options(const SceneOptions& scene) {
  if (scene.scene_file.empty() == scene.builtin.empty())
    throw UsageError("give either a SCENE file or --builtin cornell|window|blinds|window-sky|blinds-sky|two-windows");
}

Scene read_scene(const SceneOptions& options) {
  Scene scene;
  if (options.builtin.empty())
    scene = load_gltf(options.scene_file);
  else if (options.builtin == "window")
    scene = window_room();
  else if (options.builtin == "blinds")
    scene = window_room_with_blinds();
  else if (options.builtin == "window-sky")
    scene = with_sky(window_room());
  else if (options.builtin == "blinds-sky")
    scene = with_sky(window_room_with_blinds());
  else if (options.builtin == "two-windows")
    scene = two_window_room();
  else
    scene = cornell_box();
  return scene;
}

void light_scene(Scene& scene, const SceneOptions& options) {
  if (options.environment == "none") {
    scene.environment = nullptr;
  } else if (options.environment == "neutral") {
    scene.environment = std::make_shared<const Environment>(neutral_sky(options.environment_scale));
  } else if (!options.environment.empty()) {
    scene.environment = read_environment(options.environment, options.environment_scale, options.environment_rotation);
  } else if (light_with_default_sky(scene, options.environment_scale)) {
    std::cerr << "igi: scene '" << scene.name
              << "' has no lights; it is lit by the neutral default sky (--environment FILE for another, --environment none for none)\n";
  }
}

Scene load_scene(const SceneOptions& options) {
  Scene scene = read_scene(options);
  light_scene(scene, options);
  return scene;
}

void add_size_option(CommandLine& command_line, std::string& size) {
  command_line.add("--size", size,
                   "image size WIDTHxHEIGHT; pixels stay square: the camera's vertical field of view (glTF yfov) spans the height, the width follows the image's aspect, whatever the camera's aspectRatio")
      .show_default();
}

void add_sampling_options(CommandLine& command_line, RenderSettings& settings) {
  command_line.add("--vpls", settings.vpls_per_pixel, "VPLs per pixel (M, the target size of one interleaving set; a set holds at least one whole light path, so small M round up: about 2-3 VPLs in a closed room)").show_default();
  command_line.add("--interleave", settings.interleave, "interleaving pattern size S (S x S VPL sets)").show_default();
  command_line.add("--aa", settings.antialiasing, "primary rays per pixel N (interleaved super-sampling)").show_default();
  command_line.add("--environment-directions", settings.environment_directions,
                   "directional VPLs carrying the environment's direct light, drawn by its brightness and shared by "
                   "every pixel (each costs a shadow ray per pixel besides the --vpls)")
      .range(0, max_environment_directions)
      .show_default();
  command_line.add("--portal-share", settings.portal_share,
                   "share of the light particles of the sun, the sky and emitters outside (a panel beyond a window) "
                   "aimed through the openings (windows) by which their light reaches the view, found each frame; the rest spread over the scene (0: none, the paper's "
                   "walks, whose window-lit rooms flicker between frames; docs/sky.md)")
      .range(0.0, 0.99)
      .show_default();
}

void add_temporal_option(CommandLine& command_line, std::optional<int>& temporal, RenderSettings& settings,
                         const std::string& default_help) {
  command_line.add("--temporal", temporal,
                   "temporal reuse: each pixel averages up to this many frames of its history, reprojected with the "
                   "camera's motion, dropped where another surface shows and clamped to the new frame's neighbourhood "
                   "where the scene changed; while the view stays still the clamp shrinks, so the image converges "
                   "towards the unclamped one. " + default_help +
                   "; 0: off, every frame rendered by itself as in the paper")
      .range(0, max_temporal_frames);
  // CLI11's {false}: the flag sets reuse_shadows to false.
  command_line.flag("--trace-shadows{false}", settings.reuse_shadows,
                    "with temporal reuse, trace every shadow ray towards the point, spot and directional lights in "
                    "every frame (default: a first hit that shows the surface the previous frame showed around it "
                    "takes that frame's answers where they agree, and traces them every 8th frame)");
  command_line.add("--hold-vpls", settings.held_vpl_frames,
                   "with temporal reuse, while the camera moves through an unchanged scene the frames keep VPLs "
                   "drawn before them (--held-vpl-sets draws, one a frame), for up to this many frames in a row, so "
                   "the image's brightness stays steady, and a light that changes draws its VPLs with the previous ones' random numbers, so "
                   "they move with it; a still view or a moved object draws new ones (0: new VPLs every frame)")
      .range(0, max_held_vpl_frames);
  command_line.add("--held-vpl-sets", settings.held_vpl_sets,
                   "with held VPLs, how many draws of them the moving frames cycle through, one a frame; each "
                   "pixel averages each draw apart and shows their mean, so the view holds all their light paths "
                   "without changing from frame to frame as they come round (1: the previous frame's alone)")
      .show_default()
      .range(1, max_held_vpl_sets);
}

void add_filter_options(CommandLine& command_line, std::string& filter, RenderSettings& settings) {
  command_line.add("--filter", filter, "irradiance filter: discontinuity (the paper's S x S buffer), atrous (edge-avoiding a-trous wavelet passes after it: smoother, renders a wider border around each tile), box or none")
      .choices({"discontinuity", "atrous", "box", "none"})
      .show_default();
  command_line.flag("--filter-delta-lights", settings.filter_delta_lights,
                    "filter the direct light of point, spot and directional lights with the VPLs' light, as the paper "
                    "does (default: composed per pixel, since it has no noise to filter and keeps its shadow edges sharp)");
  // CLI11's {false}: the flag sets filter_textures to false.
  command_line.flag("--point-textures{false}", settings.filter_textures,
                    "read textures at each camera ray's point at full resolution, as the paper did (default: "
                    "trilinear from mip maps at the ray's footprint, one pixel wide, so texture detail finer than a "
                    "pixel does not alias)");
}

void add_vpl_sampler_option(CommandLine& command_line, std::string& sampler) {
  command_line.add("--vpl-sampler", sampler,
                   "VPL sampler: qmc (the paper's light walks; VPLs where the light goes) or importance (the same "
                   "walks, VPLs kept by their contribution to the view, for light that reaches the view through a "
                   "window or a gap)")
      .choices({"qmc", "importance"})
      .show_default();
}

void add_backend_options(CommandLine& command_line, std::string& backend, int& packet) {
  command_line.add("--backend", backend, "ray-tracing backend").choices({"embree", "saarcor", "reference"}).show_default();
  command_line.add("--packet", packet, "packet width W").choices({1, 4, 8, 16, 64}).show_default();
}

void add_threads_option(CommandLine& command_line, int& threads, const std::string& help) {
  command_line.add("--threads", threads, help).range(0, 1024).show_default();
}

void add_seed_option(CommandLine& command_line, std::uint32_t& seed) {
  command_line.add("--seed", seed, "randomisation seed").show_default();
}

void add_animate_option(CommandLine& command_line, std::string& animate, const std::string& help,
                        std::initializer_list<std::string> names) {
  command_line.add("--animate", animate, help).choices(names).show_default();
}

void write_output(const std::filesystem::path& path, const Image& hdr, const Rgb8Image& rgb8) {
  if (image_format(path) == ImageFormat::png)
    write_image(path, rgb8);
  else
    write_image(path, hdr);
}

FrameNames::FrameNames(const std::string& output, int frames) {
  int conversions = 0;
  std::string* text = &before_;
  for (std::size_t i = 0; i < output.size(); ++i) {
    if (output[i] != '%') {
      *text += output[i];
      continue;
    }
    if (i + 1 < output.size() && output[i + 1] == '%') {
      *text += '%';
      ++i;
      continue;
    }
    std::size_t j = i + 1;
    int digits = 1;
    if (j + 1 < output.size() && output[j] == '0' && output[j + 1] >= '1' && output[j + 1] <= '9') {
      digits = output[j + 1] - '0';
      j += 2;
    }
    if (j >= output.size() || output[j] != 'd')
      throw UsageError("--output '" + output + "': write the frame number as %d or %0Nd (N = 1..9), a percent sign as %%");
    if (++conversions > 1) throw UsageError("--output '" + output + "' has more than one frame number");
    digits_ = digits;
    text = &after_;
    i = j;
  }
  if (conversions == 0) {
    const std::filesystem::path path(before_);
    before_ = (path.parent_path() / path.stem()).string() + "_";
    after_ = path.extension().string();
    digits_ = std::max(4, int(std::to_string(std::max(frames - 1, 0)).size()));
  }
}

std::filesystem::path FrameNames::operator()(int frame) const {
  std::string number = std::to_string(frame);
  if (int(number.size()) < digits_) number.insert(0, std::size_t(digits_) - number.size(), '0');
  return before_ + number + after_;
}

}  // namespace igi::programs
