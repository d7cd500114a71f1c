// igi-walkthrough: IGI under motion. Plays walkthroughs (camera paths stored as glTF files in
// bench/walkthrough/paths, a moving light and a moving object) with several IGI methods, and
// with what a user would build instead (the path tracer at 1 sample per pixel, averaged over
// time and à-trous filtered: DenoisedPathTracer), and measures every frame against a
// path-traced reference of that same frame:
//   relmse      relMSE against the reference, less the reference's own noise (the reference is
//               the mean of two half-budget seeds, so its noise is a quarter of their relMSE);
//   mean_ratio  the frame's mean over the reference's (the pulsing a user sees is its spread);
//   flicker     how far each pixel's frame-to-frame change departs from the reference's (the
//               previous frame reprojected with the camera motion: pixel-centre hits of both
//               frames on the same surface), summed over those pixels, over the summed reference
//               values: the change the method adds, flicker_floor the part of it the references'
//               own noise explains (half the two half-budget seeds' difference of changes);
//   ms          the frame's wall-clock time.
// Prints one JSON object; bench/walkthrough/charts.py draws it. References are cached in --work.
//
//   igi-walkthrough --work DIR [--scenes DIR] [--forest FILE] [--walks a,b] [--methods a,b]
//                   [--size 160x120] [--frames 32] [--reference-spp 256] [--threads 2]
//   igi-walkthrough --write-paths DIR    (writes the camera paths the walks follow)

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "common/command_line.hpp"
#include "common/importance_sampler.hpp"
#include "common/program_options.hpp"
#include "common/stats_json.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/io/camera_path_file.hpp"
#include "igi/io/image_files.hpp"
#include "igi/io/metrics.hpp"
#include "igi/render/animation.hpp"
#include "igi/render/denoised_path_tracer.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera_path.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace {

using namespace igi;
using namespace igi::programs;
using Backend = EmbreeBackend<native_packet_width>;

/// A point a camera path passes through, and where the camera looks from it.
struct Waypoint {
  glm::vec3 eye;     ///< Camera position.
  glm::vec3 target;  ///< A point it looks at.
};

/// A camera path as waypoints, spaced evenly in time over `seconds`.
struct PathPlan {
  std::string name;                 ///< File stem under bench/walkthrough/paths.
  float seconds;                    ///< Duration.
  float yfov;                       ///< Vertical field of view, radians.
  std::vector<Waypoint> waypoints;  ///< At least two.
};

/// The camera paths the walks follow. The rooms are x 0..5, z 0..4, y 0..2.8 m with the window
/// at z = 4 (window_room.hpp); Sponza_lit's atrium runs along x between its columns (z -3 .. 1.5)
/// over a floor at y = 4, walked at eye height; the forest
/// of bench/scenes/forest.py stands around the origin, its camera at (0, 1.7, 30) looking -z.
std::vector<PathPlan> path_plans() {
  return {
      {"room", 4.0f, 1.0f,
       {{{0.6f, 1.6f, 0.5f}, {2.5f, 1.2f, 4.0f}},
        {{2.0f, 1.6f, 0.9f}, {3.8f, 1.0f, 3.6f}},
        {{3.6f, 1.5f, 1.2f}, {1.2f, 0.9f, 3.6f}},
        {{4.3f, 1.4f, 2.2f}, {0.5f, 0.8f, 3.2f}}}},
      {"sponza", 4.0f, 0.9f,
       {{{14.0f, 5.6f, -0.5f}, {0.0f, 5.5f, -0.5f}},
        {{6.0f, 5.6f, 0.8f}, {-6.0f, 6.5f, -2.5f}},
        {{-2.0f, 5.6f, -1.2f}, {-14.0f, 7.0f, 1.5f}},
        {{-10.0f, 5.6f, -0.3f}, {-4.0f, 9.0f, 4.5f}}}},
      {"forest", 4.0f, 0.9f,
       {{{0.0f, 1.7f, 30.0f}, {0.0f, 1.2f, 0.0f}},
        {{3.0f, 1.7f, 20.0f}, {-3.0f, 2.0f, 0.0f}},
        {{-1.0f, 1.8f, 10.0f}, {-10.0f, 2.5f, -5.0f}}}},
  };
}

/// Catmull-Rom interpolation of `points` (uniform, end points repeated) at `t` in [0, 1].
glm::vec3 spline(const std::vector<glm::vec3>& points, float t) {
  const float scaled = t * float(points.size() - 1);
  const int i = std::min(int(scaled), int(points.size()) - 2);
  const float u = scaled - float(i);
  const auto at = [&](int k) { return points[std::size_t(std::clamp(k, 0, int(points.size()) - 1))]; };
  const glm::vec3 p0 = at(i - 1), p1 = at(i), p2 = at(i + 1), p3 = at(i + 2);
  return 0.5f * ((2.0f * p1) + (-p0 + p2) * u + (2.0f * p0 - 5.0f * p1 + 4.0f * p2 - p3) * u * u +
                 (-p0 + 3.0f * p1 - 3.0f * p2 + p3) * u * u * u);
}

/// Writes `plan` as a glTF camera path in `dir`: a key every 1/24 s along splines through the
/// eyes and the targets (smooth enough that the file's linear keys look like the curve).
void write_path(const PathPlan& plan, const std::filesystem::path& dir) {
  std::vector<glm::vec3> eyes, targets;
  for (const Waypoint& w : plan.waypoints) {
    eyes.push_back(w.eye);
    targets.push_back(w.target);
  }
  const int keys = int(std::lround(plan.seconds * 24.0f)) + 1;
  std::vector<CameraKey> path;
  for (int k = 0; k < keys; ++k) {
    const float t = float(k) / float(keys - 1);
    const glm::vec3 eye = spline(eyes, t), target = spline(targets, t);
    path.push_back({t * plan.seconds, glm::inverse(glm::lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f)))});
  }
  write_camera_path(dir / (plan.name + ".gltf"), path, plan.yfov, plan.name);
}

/// One walk: a scene, and what moves in it.
struct Walk {
  std::string name;     ///< Label.
  std::string scene;    ///< A built-in scene's name, or "sponza" / "forest" for those files.
  std::string path;     ///< Camera path stem, or empty for the scene's own still camera.
  Animation animation;  ///< What else moves.
};

/// The walks: the window-lit rooms and Sponza_lit and the forest along their paths, then the
/// window room with a still view while its light circles, and the Cornell box while its smallest object slides.
std::vector<Walk> all_walks() {
  return {{"window", "window-sky", "room", Animation::none},
          {"blinds", "blinds-sky", "room", Animation::none},
          {"sponza_lit", "sponza", "sponza", Animation::none},
          {"forest", "forest", "forest", Animation::none},
          {"window_light", "window-sky", "", Animation::light},
          {"cornell_object", "cornell", "", Animation::object}};
}

/// A method: a label and how it differs from IGI's default settings, or the denoised path tracer.
struct Method {
  std::string name;             ///< Label.
  std::string vpl_sampler;      ///< --vpl-sampler (IGI only).
  int temporal_frames;          ///< --temporal; the denoised path tracer's longest history.
  bool path_traced = false;     ///< DenoisedPathTracer at 1 sample per pixel instead of IGI.
  float portal_share = RenderSettings{}.portal_share;  ///< --portal-share (IGI only).
  int vpls = RenderSettings{}.vpls_per_pixel;          ///< --vpls (IGI only).
  float roulette = RenderSettings{}.shadow_roulette;   ///< --roulette (IGI only).
  int compensate = RenderSettings{}.compensation_rays; ///< --compensate (IGI only).
  int hold = RenderSettings{}.held_vpl_frames;         ///< --hold-vpls (IGI only).
  int held_sets = RenderSettings{}.held_vpl_sets;      ///< --held-vpl-sets (IGI only).
  float clamp = RenderSettings{}.clamp_distance;      ///< --clamp (IGI only; < 0: automatic).
  int interleave = RenderSettings{}.interleave;        ///< --interleave (IGI only).
  bool filter_textures = RenderSettings{}.filter_textures;  ///< Camera rays read textures at their footprint (IGI only; --point-textures turns it off).
  std::uint32_t seed = RenderSettings{}.seed;  ///< Randomisation of the VPLs' sequences (IGI only).
};

/// The methods measured: igi-render's and igi-view's defaults (temporal reuse over 32 frames,
/// which a moving camera caps at 8), the paper's frame-independent mode (--temporal 0, portals as
/// the default), the paper's walks (no portals), view-importance VPLs (the last two each differ
/// from the defaults in that one setting), and the path tracer at 1 sample per pixel with
/// temporal reuse and the à-trous filter (its default history of 32 frames, capped as IGI's).
/// Then the frame budget's: the paper's single frame at 12 VPLs, and the defaults at 4 VPLs and at
/// the fewest (a set still holds one whole light path), whose history makes up the rest.
const std::vector<Method> all_methods = {
    {"default", "qmc", default_temporal_frames},
    {"paper", "qmc", 0},
    {"no portals", "qmc", default_temporal_frames, false, 0.0f},
    {"importance", "importance", default_temporal_frames},
    {"path 1spp denoised", "", DenoisedPathTracerSettings{}.temporal_frames, true},
    {"paper 12 VPLs", "qmc", 0, false, RenderSettings{}.portal_share, 12},
    {"default 4 VPLs", "qmc", default_temporal_frames, false, RenderSettings{}.portal_share, 4},
    {"default 1 VPL", "qmc", default_temporal_frames, false, RenderSettings{}.portal_share, 1}};

/// A method given by its settings: "custom" and then any of vpls=M, sampler=qmc|importance,
/// temporal=FRAMES, portal-share=SHARE, roulette=FRACTION, compensate=RAYS, hold=FRAMES, sets=DRAWS,
/// clamp=METRES, interleave=S, seed=N and textures=filtered|point, separated by
/// spaces; unnamed settings are the default method's. Throws UsageError naming a bad one.
Method custom_method(const std::string& spec) {
  Method method = all_methods.front();
  method.name = spec;
  std::istringstream words(spec);
  std::string word;
  words >> word;  // "custom"
  while (words >> word) {
    const std::size_t equals = word.find('=');
    const std::string key = word.substr(0, equals), value = equals == std::string::npos ? "" : word.substr(equals + 1);
    // How many characters of `value` the number read (0: no such setting).
    std::size_t used = 0;
    try {
      if (key == "vpls") method.vpls = std::stoi(value, &used);
      if (key == "temporal") method.temporal_frames = std::stoi(value, &used);
      if (key == "portal-share") method.portal_share = std::stof(value, &used);
      if (key == "roulette") method.roulette = std::stof(value, &used);
      if (key == "compensate") method.compensate = std::stoi(value, &used);
      if (key == "hold") method.hold = std::stoi(value, &used);
      if (key == "sets") method.held_sets = std::stoi(value, &used);
      if (key == "clamp") method.clamp = std::stof(value, &used);
      if (key == "interleave") method.interleave = std::stoi(value, &used);
      if (key == "seed") method.seed = std::uint32_t(std::stoul(value, &used));
      if (key == "textures" && (value == "filtered" || value == "point")) {
        method.filter_textures = value == "filtered";
        used = value.size();
      }
    } catch (const std::exception&) {
      used = 0;  // not a number
    }
    if (key == "sampler" && (value == "qmc" || value == "importance")) {
      method.vpl_sampler = value;
      used = value.size();
    }
    if (used == 0 || used != value.size())
      throw UsageError("--methods: '" + word + "' in '" + spec +
                       "' is not one of vpls=M, sampler=qmc|importance, temporal=FRAMES, portal-share=SHARE, "
                       "roulette=FRACTION, compensate=RAYS, hold=FRAMES, sets=DRAWS, clamp=METRES, interleave=S, "
                       "seed=N, textures=filtered|point");
  }
  return method;
}

/// Everything the command line decides.
struct Options {
  std::string work;                    ///< Folder of the cached references.
  std::string scenes = IGI_SCENES_DIR; ///< Folder of the shared scenes.
  std::string forest;                  ///< The outdoor scene's file (bench/scenes/forest.py), or empty.
  std::string walks;                   ///< Walks to measure, comma-separated; empty: all.
  std::string methods;                 ///< Methods to measure, comma-separated; empty: all.
  std::string size = "160x120";        ///< Image size as typed.
  std::string write_paths;             ///< With a folder: write the camera paths there and stop.
  int frames = 32;                     ///< Frames per walk.
  int warm_up = 0;                     ///< Frames of the walk's first view rendered before it (not measured).
  int reference_spp = 256;             ///< Path-traced samples per pixel of each reference frame.
  int threads = 2;                     ///< Threads (0: all cores).
  double fps = 8.0;                    ///< Frames per second along the camera paths.
};

/// The frames of a walk: its scene as loaded and each frame's changes.
struct WalkFrames {
  Scene scene;                        ///< Before any change.
  std::vector<SceneChanges> changes;  ///< Per frame.
};

/// The scene of `walk` and the changes of each of its frames (camera paths read from `paths`).
WalkFrames walk_frames(const Walk& walk, const Options& options, const std::filesystem::path& paths) {
  SceneOptions scene_options;
  if (walk.scene == "sponza")
    scene_options.scene_file = (std::filesystem::path(options.scenes) / "sponza" / "Sponza_lit.gltf").string();
  else if (walk.scene == "forest")
    scene_options.scene_file = options.forest;
  else
    scene_options.builtin = walk.scene;
  WalkFrames frames{load_scene(scene_options), {}};
  const Camera still = frames.scene.cameras.empty() ? default_camera(frames.scene) : frames.scene.cameras.front();
  std::optional<CameraPath> path;
  if (!walk.path.empty()) path.emplace(paths / (walk.path + ".gltf"));
  const Animator animator(frames.scene, still, walk.animation);
  for (int f = 0; f < options.frames; ++f) {
    SceneChanges changes = animator(std::uint32_t(f));
    if (path) changes.camera = path->at(double(f) / options.fps);
    frames.changes.push_back(std::move(changes));
  }
  return frames;
}

/// Pixel-centre first hits of `camera` (NaN where a ray leaves the scene).
std::vector<glm::vec3> first_hits(const Backend& backend, const Camera& camera, int width, int height) {
  const PinholeProjection projection(camera, width, height);
  std::vector<glm::vec3> hits(std::size_t(width) * std::size_t(height), glm::vec3(std::nanf("")));
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) {
      RayPacket<1> ray;
      HitPacket<1> hit;
      const glm::vec3 direction = projection.direction(float(x) + 0.5f, float(y) + 0.5f);
      ray.set(vec3<1>(projection.origin()), vec3<1>(direction), vfloat<1>(0.0f),
              vfloat<1>(std::numeric_limits<float>::infinity()), vmask<1>(true));
      hit.clear();
      backend.intersect(ray, hit, vmask<1>(true));
      if (hit.geomID[0] != invalid_id) hits[std::size_t(y) * std::size_t(width) + std::size_t(x)] = projection.origin() + ray.tfar[0] * direction;
    }
  return hits;
}

/// For each pixel of frame `now`, the pixel of frame `before` that shows the same surface point
/// (its pixel-centre hit within 1% of the distance: the same surface, not one behind it), or -1.
std::vector<int> reprojection(const std::vector<glm::vec3>& hits_now, const std::vector<glm::vec3>& hits_before,
                              const Camera& camera_now, const Camera& camera_before, int width, int height) {
  const PinholeProjection before(camera_before, width, height);
  const glm::vec3 eye = glm::vec3(camera_now.camera_to_world[3]);
  std::vector<int> found(hits_now.size(), -1);
  for (std::size_t p = 0; p < hits_now.size(); ++p) {
    const glm::vec3 point = hits_now[p];
    if (std::isnan(point.x)) continue;
    const std::optional<glm::vec2> seen = before.project(point);
    if (!seen) continue;
    const int x = int(std::floor(seen->x)), y = int(std::floor(seen->y));
    if (x < 0 || y < 0 || x >= width || y >= height) continue;
    const std::size_t q = std::size_t(y) * std::size_t(width) + std::size_t(x);
    if (!std::isnan(hits_before[q].x) && glm::length(hits_before[q] - point) <= 0.01f * glm::length(point - eye)) found[p] = int(q);
  }
  return found;
}

/// Mean of an image's channels.
double image_mean(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += double(p.x) + double(p.y) + double(p.z);
  return sum / (3.0 * double(image.pixels.size()));
}

/// Summed departure of `now` - `before` (reprojected by `found`) from `reference_now` -
/// `reference_before`, over the reprojected pixels, and the summed reference values there.
std::pair<double, double> departure(const Image& now, const Image& before, const Image& reference_now,
                                    const Image& reference_before, const std::vector<int>& found) {
  double departed = 0.0, value = 0.0;
  for (std::size_t p = 0; p < found.size(); ++p) {
    if (found[p] < 0) continue;
    const std::size_t q = std::size_t(found[p]);
    const glm::dvec3 change = glm::dvec3(now.pixels[p]) - glm::dvec3(before.pixels[q]);
    const glm::dvec3 expected = glm::dvec3(reference_now.pixels[p]) - glm::dvec3(reference_before.pixels[q]);
    const glm::dvec3 away = glm::abs(change - expected);
    departed += away.x + away.y + away.z;
    value += double(reference_now.pixels[p].x) + double(reference_now.pixels[p].y) + double(reference_now.pixels[p].z);
  }
  return {departed, value};
}

/// A frame's path-traced reference: the mean of two half-budget seeds, the seeds themselves, and
/// the mean's noise (a quarter of the seeds' relMSE).
struct Reference {
  Image mean;                 ///< The reference.
  std::array<Image, 2> half;  ///< Seeds 1 and 2 at half the samples each.
  double noise = 0.0;         ///< relMSE the mean's own noise adds to a comparison with it.
};

/// The path-traced reference of every frame (seeds 1 and 2 at half the budget each, cached in `work`).
std::vector<Reference> references(const WalkFrames& frames, const Walk& walk, const Options& options,
                                                 const ImageSize& size, const std::filesystem::path& work) {
  std::vector<Reference> result;
  // A textured scene's references read their textures over each camera ray's footprint, as IGI's
  // frames do (files of their own: those read at points compared IGI's filtered textures with
  // aliased ones, and their difference dwarfed the light's error); untextured ones are the same either way.
  const std::string footprint = frames.scene.textures.empty() ? "" : "_footprint";
  for (std::size_t f = 0; f < frames.changes.size(); ++f) {
    std::vector<Image> halves;
    for (std::uint32_t seed : {1u, 2u}) {
      const std::filesystem::path file = work / (walk.name + "_" + std::to_string(size.width) + "x" + std::to_string(size.height) +
                                                 "_spp" + std::to_string(options.reference_spp) + "_f" + std::to_string(f) +
                                                 "_s" + std::to_string(seed) + footprint + ".pfm");
      if (std::filesystem::exists(file)) {
        halves.push_back(read_image(file));
        continue;
      }
      Scene scene = frames.scene;
      frames.changes[f].apply_to(scene);
      const Backend backend(scene);
      const GltfMaterialShader surface(scene);
      const StandardBrdf brdf;
      PathTracerSettings settings;
      settings.seed = seed;
      settings.threads = options.threads;
      settings.jitter = false;  // pixel centres, as IGI without anti-aliasing samples them
      settings.filter_textures = RenderSettings{}.filter_textures;
      PathTracer<Backend, GltfMaterialShader, StandardBrdf> tracer(scene, backend, surface, brdf, settings);
      halves.push_back(tracer.render(frames.changes[f].camera, size.width, size.height, options.reference_spp / 2));
      write_image(file, halves.back());
    }
    Reference reference{halves[0], {halves[0], halves[1]}, 0.25 * relmse(halves[0], halves[1])};
    for (std::size_t p = 0; p < reference.mean.pixels.size(); ++p)
      reference.mean.pixels[p] = 0.5f * (halves[0].pixels[p] + halves[1].pixels[p]);
    result.push_back(std::move(reference));
  }
  return result;
}

/// Coefficient of variation of `values`.
double variation(const std::vector<double>& values) {
  double mean = 0.0, square = 0.0;
  for (const double v : values) mean += v;
  mean /= double(values.size());
  for (const double v : values) square += (v - mean) * (v - mean);
  return mean != 0.0 ? std::sqrt(square / double(values.size())) / mean : 0.0;
}

/// Splits "a,b,c".
std::vector<std::string> split(const std::string& text) {
  std::vector<std::string> parts;
  std::stringstream stream(text);
  for (std::string part; std::getline(stream, part, ',');)
    if (!part.empty()) parts.push_back(part);
  return parts;
}

/// Measures one walk with every chosen method.
StatsJson measure(const Walk& walk, const std::vector<Method>& methods, const Options& options, const ImageSize& size,
                  const std::filesystem::path& paths, const std::filesystem::path& work) {
  const WalkFrames frames = walk_frames(walk, options, paths);
  std::cerr << "igi-walkthrough: " << walk.name << ": references (" << options.reference_spp << " spp)\n";
  const std::vector<Reference> reference = references(frames, walk, options, size, work);
  // Pixel-centre hits of every frame, in the frame's own scene.
  std::vector<std::vector<glm::vec3>> hits;
  {
    Scene scene = frames.scene;
    Backend backend(scene);
    for (const SceneChanges& changes : frames.changes) {
      for (const auto& [index, transform] : changes.instances) backend.set_instance_transform(index, transform);
      for (const MeshVertices& vertices : changes.meshes) backend.set_mesh_positions(vertices.mesh, vertices.positions);
      backend.commit();
      hits.push_back(first_hits(backend, changes.camera, size.width, size.height));
    }
  }
  std::vector<std::vector<int>> found(frames.changes.size());
  std::vector<double> noise_floor(frames.changes.size(), 0.0);
  for (std::size_t f = 1; f < frames.changes.size(); ++f) {
    found[f] = reprojection(hits[f], hits[f - 1], frames.changes[f].camera, frames.changes[f - 1].camera, size.width, size.height);
    // The mean's change carries half the noise of the seeds' changes' difference.
    const auto [departed, value] = departure(reference[f].half[0], reference[f - 1].half[0], reference[f].half[1],
                                             reference[f - 1].half[1], found[f]);
    noise_floor[f] = value > 0.0 ? 0.5 * departed / value : 0.0;
  }
  std::vector<StatsJson> measured;
  for (const Method& method : methods) {
    std::cerr << "igi-walkthrough: " << walk.name << ": " << method.name << "\n";
    Scene scene = frames.scene;
    const GltfMaterialShader surface(scene);
    const StandardBrdf brdf;
    const FilterChoice filter("discontinuity");
    std::optional<ProgramVplSampler> sampler;
    std::optional<Renderer<Backend, GltfMaterialShader, StandardBrdf, ProgramVplSampler, FilterChoice>> renderer;
    std::optional<DenoisedPathTracer<Backend, GltfMaterialShader, StandardBrdf>> denoised;
    if (method.path_traced) {
      DenoisedPathTracerSettings settings;
      settings.width = size.width;
      settings.height = size.height;
      settings.temporal_frames = method.temporal_frames;
      settings.path_tracer.threads = options.threads;
      denoised.emplace(scene, surface, brdf, settings);
    } else {
      RenderSettings settings;
      settings.width = size.width;
      settings.height = size.height;
      settings.threads = options.threads;
      settings.temporal_frames = method.temporal_frames;
      settings.portal_share = method.portal_share;
      settings.vpls_per_pixel = method.vpls;
      settings.shadow_roulette = method.roulette;
      settings.compensation_rays = method.compensate;
      settings.held_vpl_frames = method.hold;
      settings.held_vpl_sets = method.held_sets;
      settings.clamp_distance = method.clamp;
      settings.interleave = method.interleave;
      settings.filter_textures = method.filter_textures;
      settings.seed = method.seed;
      sampler.emplace(method.vpl_sampler);
      renderer.emplace(scene, settings, surface, brdf, *sampler, filter);
    }
    // Frame f of the walk, its scene changes applied first, as frame `index` of the run.
    const auto render = [&](std::size_t f, std::size_t index) {
      if (denoised) return denoised->render(denoised->apply(frames.changes[f]), std::uint32_t(index));
      return renderer->render(renderer->apply(frames.changes[f]), std::uint32_t(index));
    };
    // A viewer shows its first view for a while before the walk begins: its histories are then
    // those of a still view, not empty.
    const std::size_t warm_up = std::size_t(options.warm_up);
    for (std::size_t index = 0; index < warm_up; ++index) render(0, index);
    std::vector<StatsJson> per_frame;
    std::vector<double> ratios, errors, flickers, floors, times;
    Image previous;
    for (std::size_t f = 0; f < frames.changes.size(); ++f) {
      const Frame frame = render(f, warm_up + f);
      const double error = relmse(frame.hdr, reference[f].mean) - reference[f].noise;
      const double ratio = image_mean(frame.hdr) / image_mean(reference[f].mean);
      StatsJson row;
      row.set("frame", int(f)).set("ms", frame.statistics.milliseconds).set("relmse", error).set("mean_ratio", ratio);
      if (f > 0) {
        const auto [departed, value] = departure(frame.hdr, previous, reference[f].mean, reference[f - 1].mean, found[f]);
        const double flicker = value > 0.0 ? departed / value : 0.0;
        row.set("flicker", flicker).set("flicker_floor", noise_floor[f]);
        flickers.push_back(flicker);
        floors.push_back(noise_floor[f]);
      }
      per_frame.push_back(row);
      ratios.push_back(ratio);
      errors.push_back(error);
      times.push_back(frame.statistics.milliseconds);
      previous = frame.hdr;
    }
    StatsJson result;
    result.set("method", method.name)
        .set("mean_ratio_cv", variation(ratios))
        .set("relmse_median", median(errors))
        .set("relmse_worst", *std::max_element(errors.begin(), errors.end()))
        .set("flicker_median", median(flickers))
        .set("flicker_floor_median", median(floors))
        .set("ms_median", median(times))
        .set("frames", per_frame);
    measured.push_back(result);
  }
  StatsJson result;
  result.set("walk", walk.name).set("scene", walk.scene).set("camera_path", walk.path).set("methods", measured);
  return result;
}

}  // namespace

int main(int argc, char** argv) {
  Options options;
  CommandLine command_line{"igi-walkthrough", "IGI methods along walkthroughs against path-traced frames (JSON on stdout)"};
  command_line.add("--work", options.work, "folder for the cached references");
  command_line.add("--scenes", options.scenes, "folder of the shared scenes (sponza/Sponza_lit.gltf)");
  command_line.add("--forest", options.forest, "the outdoor scene: a file of bench/scenes/forest.py (the forest walk is skipped without it)");
  command_line.add("--walks", options.walks, "walks to measure, comma-separated (default: all)");
  command_line.add("--methods", options.methods,
                   "methods to measure, comma-separated (default: all); 'custom vpls=4 roulette=0.5' is the default "
                   "method with the settings named (vpls, sampler, temporal, portal-share, roulette, compensate, hold, sets, clamp, interleave, textures)");
  command_line.add("--size", options.size, "image size");
  command_line.add("--frames", options.frames, "frames per walk").range(2, 100000);
  command_line.add("--fps", options.fps, "frames per second along the camera paths");
  command_line.add("--reference-spp", options.reference_spp, "path-traced samples per pixel of each reference frame").range(2, 1 << 20);
  command_line.add("--threads", options.threads, "threads (0: all cores)");
  command_line.add("--warm-up", options.warm_up,
                   "frames of each walk's first view rendered before the walk, not measured (a viewer's still view before it moves)")
      .range(0, 100000);
  command_line.add("--write-paths", options.write_paths, "write the camera paths into this folder and stop");
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  try {
    if (!options.write_paths.empty()) {
      std::filesystem::create_directories(options.write_paths);
      for (const PathPlan& plan : path_plans()) write_path(plan, options.write_paths);
      return 0;
    }
    if (options.work.empty()) throw UsageError("--work is required");
    std::filesystem::create_directories(options.work);
    const ImageSize size = parse_image_size(options.size);
    const std::filesystem::path paths = std::filesystem::path(IGI_WALKTHROUGH_PATHS);
    const std::vector<std::string> walk_names = split(options.walks), method_names = split(options.methods);
    std::vector<Method> methods;
    for (const Method& method : all_methods)
      if (method_names.empty() || std::find(method_names.begin(), method_names.end(), method.name) != method_names.end())
        methods.push_back(method);
    for (const std::string& name : method_names)
      if (name.rfind("custom", 0) == 0)
        methods.push_back(custom_method(name));
      else if (std::none_of(all_methods.begin(), all_methods.end(), [&](const Method& m) { return m.name == name; }))
        throw UsageError("--methods: no method '" + name +
                         "' (default, paper, no portals, importance, path 1spp denoised, paper 12 VPLs, default 4 VPLs, "
                         "default 1 VPL, or custom followed by settings)");
    const std::vector<Walk> known = all_walks();
    for (const std::string& name : walk_names)
      if (std::none_of(known.begin(), known.end(), [&](const Walk& w) { return w.name == name; }))
        throw UsageError("--walks: no walk '" + name + "' (window, blinds, sponza_lit, forest, window_light, cornell_object)");
    std::vector<StatsJson> walks;
    for (const Walk& walk : all_walks()) {
      if (!walk_names.empty() && std::find(walk_names.begin(), walk_names.end(), walk.name) == walk_names.end()) continue;
      if (walk.scene == "sponza" && !std::filesystem::exists(std::filesystem::path(options.scenes) / "sponza" / "Sponza_lit.gltf")) {
        std::cerr << "igi-walkthrough: SKIPPED " << walk.name << ": " << options.scenes << "/sponza/Sponza_lit.gltf is missing\n";
        continue;
      }
      if (walk.scene == "forest" && options.forest.empty()) {
        std::cerr << "igi-walkthrough: SKIPPED " << walk.name << ": no --forest file\n";
        continue;
      }
      walks.push_back(measure(walk, methods, options, size, paths, options.work));
    }
    StatsJson()
        .set("size", options.size)
        .set("frames", options.frames)
        .set("warm_up", options.warm_up)
        .set("fps", options.fps)
        .set("reference_spp", options.reference_spp)
        .set("threads", options.threads)
        .set("walks", walks)
        .print();
  } catch (const UsageError& e) {
    std::cerr << "igi-walkthrough: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "igi-walkthrough: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
