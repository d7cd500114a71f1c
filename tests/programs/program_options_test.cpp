// The pieces every program's command line is made of: the WIDTHxHEIGHT parser, the median the
// programs report timings by, the --stats json writer, the backend dispatch and igi-render's
// default of --temporal.
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "common/backend_choice.hpp"
#include "common/command_line.hpp"
#include "common/igi_render_options.hpp"
#include "common/program_options.hpp"
#include "common/render_options.hpp"
#include "common/stats_json.hpp"
#include "igi/lighting/vpl_sampler_choice.hpp"
#include "igi/scene/cornell.hpp"

using igi::programs::ImageSize;
using igi::programs::parse_image_size;
using igi::programs::StatsJson;
using igi::programs::UsageError;

TEST_CASE("WIDTHxHEIGHT parses to its two numbers, in either case of x", "[programs]") {
  const ImageSize size = parse_image_size("640x480");
  CHECK(size.width == 640);
  CHECK(size.height == 480);
  const ImageSize upper = parse_image_size("7X3");
  CHECK(upper.width == 7);
  CHECK(upper.height == 3);
}

TEST_CASE("anything but two positive whole numbers around an x is a usage error naming the option and the text", "[programs]") {
  for (const std::string bad : {"0x5", "5x0", "10x", "x10", "axb", "-3x4", "3x-4", "+3x4", "10x5x2", "10 x5", "10x5 ",
                                "", "640", "99999999999x2"}) {
    INFO("'" << bad << "'");
    CHECK_THROWS_AS(parse_image_size(bad), UsageError);
    CHECK_THROWS_WITH(parse_image_size(bad, "--size"), Catch::StartsWith("--size: '" + bad + "' is not WIDTHxHEIGHT"));
  }
  // A zero side is well formed but empty: the message says why it is refused.
  CHECK_THROWS_WITH(parse_image_size("0x5"), Catch::Contains("at least 1"));
  CHECK_THROWS_WITH(parse_image_size("4x3y", "--window"), Catch::StartsWith("--window: '4x3y'"));
}

TEST_CASE("the median is the middle value, or the mean of the middle two for an even count", "[programs]") {
  using igi::programs::median;
  CHECK(median({3.0, 1.0, 2.0}) == 2.0);
  CHECK(median({5.0}) == 5.0);
  CHECK(median({4.0, 1.0, 3.0, 2.0}) == 2.5);
  CHECK(median({10.0, 20.0}) == 15.0);
  CHECK(median({}) == 0.0);
}

TEST_CASE("the stats writer prints one line of JSON with every field as its type", "[programs]") {
  StatsJson frame;
  frame.set("frame", 1u).set("tiles_per_rank", std::vector<int>{3, 4});
  StatsJson stats;
  stats.set("scene", std::string("cornell"))
      .set("backend", "embree")
      .set("width", 96)
      .set("rays", std::uint64_t(1) << 40)
      .set("offset", std::int64_t(-7))
      .set("ms_per_frame", 2.5)
      .set("hdr_sent", true)
      .set("stage_cpu_ms", nullptr)
      .set("frames", std::vector<StatsJson>{frame, frame})
      .set("width", 97);  // a name set again holds the newer value
  stats.update(StatsJson().set("extra", 1.0).set("scene", "box"));
  const std::string text = stats.dump();
  CHECK(text.find('\n') == std::string::npos);
  const nlohmann::json parsed = nlohmann::json::parse(text);
  CHECK(parsed.size() == 10);
  CHECK(parsed["scene"] == "box");
  CHECK(parsed["backend"] == "embree");
  CHECK(parsed["width"] == 97);
  CHECK(parsed["rays"].get<std::uint64_t>() == std::uint64_t(1) << 40);
  CHECK(parsed["offset"] == -7);
  CHECK(parsed["ms_per_frame"].is_number_float());
  CHECK(parsed["ms_per_frame"] == 2.5);
  CHECK(parsed["hdr_sent"] == true);
  CHECK(parsed["stage_cpu_ms"].is_null());
  CHECK(parsed["extra"] == 1.0);
  REQUIRE(parsed["frames"].size() == 2);
  CHECK(parsed["frames"][1]["frame"] == 1);
  CHECK(parsed["frames"][1]["tiles_per_rank"] == nlohmann::json::array({3, 4}));
  // A copy is independent of its original.
  StatsJson copy = stats;
  copy.set("scene", "other");
  CHECK(nlohmann::json::parse(stats.dump())["scene"] == "box");
}

TEST_CASE("a run's shared stats fields are the scene, image, backend, output, animation and sampling settings", "[programs]") {
  const igi::Scene scene = igi::cornell_box();
  igi::programs::RenderOptions options;
  options.settings.width = 32;
  options.settings.height = 24;
  options.output = "out.pfm";
  const nlohmann::json run = nlohmann::json::parse(
      igi::programs::run_statistics(scene, options, "embree", 16, "light")
          .update(igi::programs::sampling_statistics(options.settings, "box", "importance"))
          .dump());
  CHECK(run["scene"] == scene.name);
  CHECK(run["triangles"] == scene.triangle_count());
  CHECK(run["width"] == 32);
  CHECK(run["height"] == 24);
  CHECK(run["backend"] == "embree");
  CHECK(run["packet"] == 16);
  CHECK(run["output"] == "out.pfm");
  CHECK(run["animate"] == "light");
  CHECK(run["vpls_per_pixel"] == options.settings.vpls_per_pixel);
  CHECK(run["interleave"] == options.settings.interleave);
  CHECK(run["aa"] == options.settings.antialiasing);
  CHECK(run["filter"] == "box");
  CHECK(run["vpl_sampler"] == "importance");
  CHECK(run["filter_delta_lights"] == false);
  CHECK(run["filter_textures"] == true);
}

TEST_CASE("the filter options: --point-textures turns texture filtering off, without it camera rays read at their footprint", "[programs]") {
  for (const bool point : {false, true}) {
    igi::RenderSettings settings;
    std::string filter = "discontinuity";
    igi::programs::CommandLine command_line{"test", "filter options"};
    igi::programs::add_filter_options(command_line, filter, settings);
    std::vector<std::string> words = {"test"};
    if (point) words.push_back("--point-textures");
    std::vector<char*> argv;
    for (std::string& word : words) argv.push_back(word.data());
    REQUIRE_FALSE(command_line.parse(int(argv.size()), argv.data(), false).has_value());
    CHECK(settings.filter_textures == !point);
  }
}

TEST_CASE("the built-in scenes are the Cornell box and the window room, and the VPL sampler option names a VplSamplerChoice", "[programs]") {
  igi::programs::SceneOptions scene;
  scene.builtin = "window";
  CHECK(igi::programs::load_scene(scene).name == "window");
  scene.builtin = "cornell";
  CHECK(igi::programs::load_scene(scene).name == igi::cornell_box().name);
  // The option's default and every choice it offers make a sampler; so its default is QMC's.
  const igi::programs::RenderOptions options;
  CHECK(std::string(igi::VplSamplerChoice(options.vpl_sampler).chosen()) == "qmc");
  for (const char* name : {"qmc", "importance"}) CHECK(std::string(igi::VplSamplerChoice(name).chosen()) == name);
}

namespace {

/// Stand-ins for backend types: a name and a width, as the dispatch reads them.
template <int W>
struct FastBackend {
  static constexpr int width = W;
  static constexpr const char* name() noexcept { return "fast"; }
};
struct WideBackend {
  static constexpr int width = 64;
  static constexpr const char* name() noexcept { return "wide"; }
};
using Backends = igi::programs::BackendList<FastBackend<8>, FastBackend<1>, WideBackend>;

}  // namespace

TEST_CASE("the backend dispatch runs the listed type of the name and width, and refuses the others", "[programs]") {
  const auto width_of = [](const std::string& name, int packet) {
    return igi::programs::with_backend_of(Backends{}, name, packet, []<class B>() { return B::width * 1000 + int(std::string(B::name()).size()); });
  };
  CHECK(width_of("fast", 8) == 8004);
  CHECK(width_of("fast", 1) == 1004);
  CHECK(width_of("wide", 64) == 64004);
  CHECK_THROWS_AS(width_of("fast", 64), UsageError);
  CHECK_THROWS_WITH(width_of("slow", 8), "--backend/--packet: slow/8 is not one of fast/8,1, wide/64");
  CHECK(igi::programs::describe_backends(igi::programs::RenderBackends{}) ==
        "embree/1,4,8,16, reference/1,4,8,16, saarcor/64");
  std::vector<int> widths;
  igi::programs::for_each_backend(Backends{}, [&]<class B>() { widths.push_back(B::width); });
  CHECK(widths == std::vector<int>{8, 1, 64});
}

namespace {

/// igi-render's options after parsing `arguments` (the built-in Cornell box added) and checking them.
igi::programs::IgiRenderOptions igi_render_options(const std::vector<std::string>& arguments) {
  igi::programs::IgiRenderOptions options;
  igi::programs::CommandLine command_line{"igi-render", "test"};
  igi::programs::add_igi_render_options(command_line, options);
  std::vector<std::string> words = {"--builtin", "cornell"};
  words.insert(words.end(), arguments.begin(), arguments.end());
  command_line.parse_arguments(words);
  igi::programs::check_igi_render_options(options, /*sequences=*/false);
  return options;
}

}  // namespace

TEST_CASE("igi-render averages IGI frames by default, --temporal 0 renders each by itself, the path tracer takes no --temporal N", "[programs]") {
  CHECK(igi::RenderSettings{}.temporal_frames == 0);  // the library renders independent frames
  CHECK(igi_render_options({}).settings.temporal_frames == igi::programs::default_temporal_frames);
  CHECK(igi_render_options({"--temporal", "0"}).settings.temporal_frames == 0);
  CHECK(igi_render_options({"--temporal", "8"}).settings.temporal_frames == 8);
  CHECK(igi_render_options({"--integrator", "path"}).settings.temporal_frames == 0);
  CHECK(igi_render_options({"--integrator", "path", "--temporal", "0"}).settings.temporal_frames == 0);
  CHECK_THROWS_WITH(igi_render_options({"--integrator", "path", "--temporal", "8"}),
                    Catch::Contains("needs --integrator igi"));
  CHECK_THROWS_AS(igi_render_options({"--temporal", "-1"}), UsageError);
  // The delta lights' shadow answers are reused with temporal reuse unless --trace-shadows.
  CHECK(igi_render_options({}).settings.reuse_shadows);
  CHECK_FALSE(igi_render_options({"--trace-shadows"}).settings.reuse_shadows);
}
