// igi-cluster: the tile farm on MPI. Run as `mpirun -np N igi-cluster [igi-render options] --frames F`.
// Rank 0 hands out tiles on demand and writes the image of the last frame (or of every frame);
// ranks 1..N-1 render, filter and tone map tiles. Reports per frame: fps, bytes sent to rank 0 and
// tiles per worker. Options are igi-render's (examples/common/render_options.hpp), plus
// --animate, --play and --camera-path (the file's own animation and a walkthrough, sampled on
// rank 0 and broadcast as each frame's scene changes), --every-frame, the scheduling knobs and the --slow-rank test hook.
// Not igi-render's --temporal: every frame is rendered by itself (igi-render --temporal 0's frames).
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include <oneapi/tbb/info.h>

#include "common/command_line.hpp"
#include "common/program_options.hpp"
#include "common/render_options.hpp"
#include "common/stats_json.hpp"
#include "common/stop_signals.hpp"
#include "igi/render/animation.hpp"
#include "igi/distributed/tile_farm.hpp"
#include "common/importance_sampler.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace {

using namespace igi::programs;

/// Everything the command line decides: igi-render's options and the farm's.
struct Options : RenderOptions, PlayOptions {
  std::string animate = "none";  ///< Dynamic scene, if any.
  bool every_frame = false;      ///< Write every frame, not only the last (--play does too).
  igi::FarmOptions farm;         ///< Demand-driven scheduling knobs and the slow-rank test hook.
};

/// Writes a frame as igi-render does: PNG gets the tone-mapped pixels, EXR and PFM the radiance.
void write_frame(const std::filesystem::path& path, const igi::Frame& frame) { write_output(path, frame.hdr, frame.rgb8); }

/// Runs the farm with backend B on this rank.
template <class B>
int run(igi::Scene& scene, const igi::Camera& camera, const Options& options, int rank) {
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::programs::ProgramVplSampler sampler(options.vpl_sampler);
  const igi::FilterChoice filter(options.filter);
  const igi::Animation animation = igi::parse_animation(options.animate);
  const igi::Scene initial = scene;  // animations are functions of the initial scene
  const igi::Animator animator(initial, camera, animation);
  // The file's animation samples the scene's own animation data, which applying changes leaves alone.
  std::optional<Playback> playback;
  if (options.plays_sequence()) playback.emplace(scene, options, chosen_camera_index(scene, options));
  using Renderer = igi::TileRenderer<B, igi::GltfMaterialShader, igi::StandardBrdf, igi::programs::ProgramVplSampler, igi::FilterChoice>;
  Renderer renderer(scene, options.settings, surface, brdf, sampler, filter);
  igi::FarmOptions farm_options = options.farm;
  farm_options.hdr_output = igi::image_format(options.output) != igi::ImageFormat::png;
  igi::TileFarm farm(MPI_COMM_WORLD, renderer, farm_options);
  if (rank != 0) {
    farm.serve();
    return stop_requested() ? stopped("igi-cluster") : 0;
  }
  // Checked in main() when --every-frame, --play or --camera-path is given; without them the name may hold any '%'.
  const bool sequence = options.every_frame || options.plays_sequence();
  const std::optional<FrameNames> names =
      sequence ? std::optional<FrameNames>(FrameNames(options.output, options.frames)) : std::nullopt;
  std::vector<StatsJson> frames;
  igi::Frame frame;
  for (int f = 0; f < options.frames; ++f) {
    const auto index = std::uint32_t(f);
    frame = farm.render_frame(playback ? (*playback)(f, camera) : animator(index), index);
    if (stop_requested()) {
      farm.shutdown();  // the workers return from serve() instead of waiting for the next frame
      return stopped("igi-cluster");
    }
    const igi::ClusterFrameReport& report = farm.report();
    if (names) write_frame((*names)(f), frame);
    std::string tiles;
    for (int r = 0; r < farm.size(); ++r) {
      if (r) tiles += ' ';
      tiles += std::to_string(report.tiles_per_rank[std::size_t(r)]);
    }
    if (options.stats != "json")
      std::printf("frame %u: %.2f ms, %.2f fps, %llu bytes to rank 0 (%llu pixel bytes%s), tiles per rank [%s]\n", index,
                  report.milliseconds, report.fps(), (unsigned long long)report.bytes_to_master,
                  (unsigned long long)report.pixel_bytes, report.hdr_sent ? ", HDR included" : "", tiles.c_str());
    frames.push_back(StatsJson()
                         .set("frame", index)
                         .set("ms", report.milliseconds)
                         .set("fps", report.fps())
                         .set("bytes_to_master", report.bytes_to_master)
                         .set("pixel_bytes", report.pixel_bytes)
                         .set("header_bytes", report.header_bytes)
                         .set("tile_messages", report.tile_messages)
                         .set("hdr_sent", report.hdr_sent)
                         .set("tiles_per_rank", report.tiles_per_rank)
                         .set("tile_ms_sum", report.tile_milliseconds)
                         .set("rays", report.rays.total()));
  }
  farm.shutdown();
  write_frame(options.output, frame);
  const int threads = options.settings.threads > 0 ? options.settings.threads : tbb::info::default_concurrency();
  if (options.stats == "json") {
    StatsJson played;
    if (playback && playback->player()) played.set("animation", playback->player()->animation().name);
    if (playback) played.set("play_fps", options.fps);
    if (!options.camera_path.empty()) played.set("camera_path", options.camera_path);
    run_statistics(scene, options, B::name(), B::width, options.animate)
        .update(sampling_statistics(options.settings, filter.chosen(), sampler.chosen()))
        .update(played)
        .set("ranks", farm.size())
        .set("workers", farm.size() > 1 ? farm.size() - 1 : 1)
        .set("tiles", std::uint64_t(renderer.tiles().size()))
        .set("threads_per_rank", threads)
        .set("slow_rank", options.farm.slow_rank)
        .set("slow_factor", options.farm.slow_factor)
        .set("prefetch", options.farm.prefetch)
        .set("frames", frames)
        .print();
  } else {
    std::printf("%s: %zu triangles, %dx%d, %s/%d, %d ranks x %d threads, wrote %s\n", scene.name.c_str(),
                scene.triangle_count(), options.settings.width, options.settings.height, B::name(), B::width,
                farm.size(), threads, options.output.c_str());
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Before MPI_Init, whose threads must inherit the blocked stop signals. A worker waiting for
  // tiles inside MPI ends after the grace period; mpirun then stops the other ranks.
  install_stop_signals();
  igi::MpiSession mpi(argc, argv);
  const int rank = mpi.rank();
  Options options;
  CommandLine command_line{"igi-cluster", "igi-render's IGI pipeline as the paper's tile farm on MPI (mpirun -np N igi-cluster ...)"};
  add_render_options(command_line, options, "threads per rank (0: all cores)",
                     "frames to render (indices 0..F-1), each by itself as in the paper (igi-render's default temporal "
                     "reuse needs every pixel's history, and a tile goes to any rank)");
  add_animate_option(command_line, options.animate, "dynamic scene: a deterministic function of the frame index");
  add_play_options(command_line, options);
  command_line.flag("--every-frame", options.every_frame,
                    "also write every frame, named as igi-render --animate names them (<stem>_NNNN<ext>, or a %04d pattern)");
  command_line.add("--tiles-per-request", options.farm.tiles_per_request, "tiles a worker asks for at once (0: its thread count)").range(0, 1 << 20).show_default();
  command_line.flag("--prefetch", options.farm.prefetch, "workers ask for the next tiles when they start a batch (hides the round trip)");
  command_line.add("--slow-rank", options.farm.slow_rank, "test hook: slow this rank down artificially").show_default();
  command_line.add("--slow-factor", options.farm.slow_factor, "the slowed rank sleeps (factor-1) x each tile's render time").range(1.0, 1000.0).show_default();
  // Only rank 0 speaks: every rank parses the same command line and would print the same message.
  auto say = [rank](const std::string& text) {
    if (rank == 0) std::cerr << "igi-cluster: " << text << "\n";
  };
  if (const std::optional<int> exit_code = command_line.parse(argc, argv, rank == 0)) return *exit_code;
  try {
    check_render_options(options);
    if (options.integrator == "path") throw UsageError("--integrator path: the path tracer does not run on the farm");
    if (options.farm.slow_rank >= mpi.size())
      throw UsageError("--slow-rank " + std::to_string(options.farm.slow_rank) + ": there are only " +
                       std::to_string(mpi.size()) + " ranks");
    igi::parse_animation(options.animate);
    check_play_options(options, options, options.animate);
    if (options.every_frame) static_cast<void>(FrameNames(options.output, options.frames));  // a malformed %d pattern fails here
  } catch (const std::exception& e) {
    say(e.what());
    return 2;
  }
  try {
    igi::Scene scene = load_scene(options);
    igi::Camera camera = choose_camera(scene, options);
    pose_for_play(scene, camera, options, chosen_camera_index(scene, options));
    return with_backend(options, [&]<class B>() { return run<B>(scene, camera, options, rank); });
  } catch (const std::exception& e) {
    // Every rank fails the same way on a bad scene; a rank alone failing must not leave others waiting.
    std::cerr << "igi-cluster (rank " << rank << "): " << e.what() << "\n";
    if (mpi.size() > 1) igi::MpiSession::abort(1);
    return 1;
  }
}
