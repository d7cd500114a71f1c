#pragma once
// The command line igi-render and igi-cluster share: scene, camera, image, IGI settings and the
// backend choice, parsed by CommandLine, plus the scene loading and backend dispatch that follow it.

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <stdexcept>
#include <string>

#include "common/command_line.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/io/image_files.hpp"
#include "igi/render/settings.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"

namespace igi::programs {

/// What the shared options decide.
struct RenderOptions {
  std::string scene_file;               ///< glTF file, or empty with --builtin.
  std::string builtin;                  ///< "cornell", or empty with a file.
  std::string output = "out.png";       ///< Image to write.
  std::string size = "640x480";         ///< WIDTHxHEIGHT as typed.
  std::string filter = "discontinuity"; ///< Filter name.
  std::string backend = "embree";       ///< Backend name.
  std::string integrator = "igi";       ///< igi or path.
  std::string camera;                   ///< glTF camera name, or empty.
  std::string stats;                    ///< "json" or empty.
  int packet = 16;                      ///< Packet width.
  int frames = 1;                       ///< Frames (or path-tracer passes).
  int spp = 16;                         ///< Path-tracer samples per pixel per pass.
  RenderSettings settings;              ///< The IGI settings.
};

/// Adds the shared options to `command_line`; `threads_help` and `frames_help` let a program word those two.
inline void add_render_options(CommandLine& command_line, RenderOptions& o, const std::string& threads_help,
                               const std::string& frames_help) {
  command_line.add("scene", o.scene_file, "glTF scene (.gltf or .glb)");
  command_line.add("--builtin", o.builtin, "built-in scene instead of a file").choices({"cornell"});
  command_line.add("-o,--output", o.output, "output image: .png (tone mapped), .exr or .pfm (HDR)").show_default();
  command_line.add("--size", o.size, "image size WIDTHxHEIGHT").show_default();
  command_line.add("--vpls", o.settings.vpls_per_pixel, "VPLs per pixel (M, the target size of one interleaving set; a set holds at least one whole light path, so small M round up: about 2-3 VPLs in a closed room)").show_default();
  command_line.add("--interleave", o.settings.interleave, "interleaving pattern size S (S x S VPL sets)").show_default();
  command_line.add("--aa", o.settings.antialiasing, "primary rays per pixel N (interleaved super-sampling)").show_default();
  command_line.add("--filter", o.filter, "irradiance filter").choices({"discontinuity", "box", "none"}).show_default();
  command_line.add("--clamp", o.settings.clamp_distance, "minimum VPL distance in 1/d^2 (negative: 2% of the scene diagonal)").show_default();
  command_line.add("--backend", o.backend, "ray-tracing backend").choices({"embree", "saarcor", "reference"}).show_default();
  command_line.add("--packet", o.packet, "packet width W").choices({1, 4, 8, 16, 64}).show_default();
  command_line.add("--threads", o.settings.threads, threads_help).range(0, 1024).show_default();
  command_line.add("--frames", o.frames, frames_help).range(1, 100000).show_default();
  command_line.add("--integrator", o.integrator, "igi, or path for the reference path tracer").choices({"igi", "path"}).show_default();
  command_line.add("--spp", o.spp, "samples per pixel of the path tracer").range(1, 1 << 20).show_default();
  command_line.add("--camera", o.camera, "glTF camera name (default: the file's first, else a fitted view)");
  command_line.add("--seed", o.settings.seed, "randomisation seed").show_default();
  command_line.add("--stats", o.stats, "print statistics as one JSON object on stdout").choices({"json"});
}

/// Checks what the option checks cannot: the size, scene xor --builtin, the settings, the output format.
inline void check_render_options(RenderOptions& o) {
  int width = 0, height = 0;
  char x = 0, rest = 0;
  if (std::sscanf(o.size.c_str(), "%d%c%d%c", &width, &x, &height, &rest) != 3 || (x != 'x' && x != 'X'))
    throw UsageError("--size: '" + o.size + "' is not WIDTHxHEIGHT");
  o.settings.width = width;
  o.settings.height = height;
  if (o.scene_file.empty() == o.builtin.empty()) throw UsageError("give either a SCENE file or --builtin cornell");
  validate(o.settings);
  image_format(o.output);
}

/// The scene the options name.
inline Scene load_scene(const RenderOptions& o) { return o.builtin.empty() ? load_gltf(o.scene_file) : cornell_box(); }

/// The camera the options name: --camera, else the scene's first, else one fitted to the scene.
inline Camera choose_camera(const Scene& scene, const RenderOptions& o) {
  if (!o.camera.empty()) {
    const Camera* named = find_camera(scene, o.camera);
    if (!named) throw UsageError("--camera: no camera named '" + o.camera + "' in " + scene.name);
    return *named;
  }
  return scene.cameras.empty() ? default_camera(scene) : scene.cameras.front();
}

/// Calls `run.template operator()<B>()` with the backend type B the options choose.
template <class Run>
int with_backend(const RenderOptions& o, Run&& run) {
  const int p = o.packet;
  if (o.backend == "saarcor") {
    if (p != 16 && p != 64) throw UsageError("--packet: the saarcor backend traces 8x8 = 64-ray packets only");
    return run.template operator()<SaarcorBackend>();
  }
  if (o.backend == "embree") {
    if (p == 1) return run.template operator()<EmbreeBackend<1>>();
    if (p == 4) return run.template operator()<EmbreeBackend<4>>();
    if (p == 8) return run.template operator()<EmbreeBackend<8>>();
    if (p == 64) throw UsageError("--packet 64: Embree traces packets of 1, 4, 8 or 16 rays (64 is saarcor's)");
    return run.template operator()<EmbreeBackend<16>>();
  }
  if (p == 1) return run.template operator()<ReferenceBackend<1>>();
  if (p == 4) return run.template operator()<ReferenceBackend<4>>();
  if (p == 8) return run.template operator()<ReferenceBackend<8>>();
  if (p == 64) throw UsageError("--packet 64: the reference backend is built for packets of 1, 4, 8 or 16 rays");
  return run.template operator()<ReferenceBackend<16>>();
}

/// The files of an image sequence (an animation), named after --output: a name with a frame number
/// conversion %d or %0Nd (N = 1..9; a literal percent sign is %%) gets the number printed there
/// (frames/%04d.png -> frames/0007.png); any other name gets _NNNN before its extension
/// (out.png -> out_0007.png), four digits or as many as the last frame needs.
class FrameNames {
 public:
  /// Names for frames 0..frames-1 of `output`; throws UsageError for a malformed pattern.
  FrameNames(const std::string& output, int frames) {
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

  /// The file of frame `frame`.
  std::filesystem::path operator()(int frame) const {
    std::string number = std::to_string(frame);
    if (int(number.size()) < digits_) number.insert(0, std::size_t(digits_) - number.size(), '0');
    return before_ + number + after_;
  }

 private:
  std::string before_, after_;  ///< Text around the frame number.
  int digits_ = 4;              ///< Minimum digits of the frame number (zero padded).
};

/// Writes an image: PNG gets the tone-mapped pixels, EXR and PFM the linear radiance.
inline void write_output(const std::filesystem::path& path, const Image& hdr, const Rgb8Image& rgb8) {
  if (image_format(path) == ImageFormat::png)
    write_image(path, rgb8);
  else
    write_image(path, hdr);
}

}  // namespace igi::programs
