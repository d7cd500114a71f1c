// Every input in tests/data/fuzz - crashes and failures the fuzz harnesses (fuzz/) once found,
// minimized - has its expected outcome recorded in the table below: it loads and renders finite
// pixels, or the loader or the renderer refuses it with a SceneError naming the file and saying
// why. An input without an entry fails the test, so a new regression input comes with its
// expected outcome. fuzz/README.md lists what each one found.

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/scene/gltf.hpp"
#include "render/render_support.hpp"
#include "scenes.hpp"

namespace {

namespace fs = std::filesystem;

/// What becomes of a regression input.
enum class Outcome {
  renders,              ///< Loads, builds every backend and renders finite pixels.
  refused_by_loader,    ///< load_gltf throws a SceneError.
  refused_by_renderer,  ///< Loads, but the renderer throws a SceneError.
};

/// The recorded outcome of one input of tests/data/fuzz.
struct ExpectedOutcome {
  const char* file;            ///< File name in tests/data/fuzz.
  Outcome outcome;             ///< What happens to it.
  const char* message = "";    ///< A fragment of the SceneError's message, for the refusals.
};

/// One entry per input (fuzz/README.md says what each found). Both found overflows of
/// coordinates near float's maximum; igi now refuses world coordinates beyond +-1e12
/// (max_scene_coordinate), so the loader's validation refuses them, naming the vertex.
const ExpectedOutcome expected_outcomes[] = {
    // A triangle at +-1e30 beside a lamp: shadow rays to VPLs on it overflowed their squared
    // length and Embree's assertion aborted the process.
    {"embree_assert_triangle_at_1e30.gltf", Outcome::refused_by_loader, "beyond +-1e12, the largest coordinate igi traces"},
    // A Cornell box with vertices near float's maximum: the SaarCOR kd-tree build converted an
    // infinite extent to int.
    {"saarcor_kdtree_overflowing_extent.glb", Outcome::refused_by_loader, "beyond +-1e12, the largest coordinate igi traces"},
};

/// The regression inputs, sorted by name.
std::vector<fs::path> regression_inputs() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(igi::testing::data_path("fuzz")))
    if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// What became of an input: its outcome and, for the refusals, the SceneError's message.
struct Result {
  Outcome outcome = Outcome::renders;  ///< What happened.
  std::string message;                 ///< The SceneError's message, for the refusals.
};

/// Loads `file`, builds the SaarCOR kd-tree over it and renders it through EmbreeBackend<16>.
Result run(const fs::path& file) {
  igi::Scene scene;
  try {
    std::vector<std::string> warnings;
    scene = igi::load_gltf(file, &warnings);
  } catch (const igi::SceneError& error) {
    return {Outcome::refused_by_loader, error.what()};
  }
  igi::RenderSettings settings;
  settings.width = 16;
  settings.height = 16;
  settings.vpls_per_pixel = 2;
  settings.tile_size = 8;
  try {
    const igi::SaarcorBackend kd_tree(scene);
    const igi::Frame frame = igi::testing::render_once<igi::EmbreeBackend<16>>(scene, settings);
    CHECK(igi::testing::all_finite(frame));
  } catch (const igi::SceneError& error) {
    return {Outcome::refused_by_renderer, error.what()};
  }
  return {};
}

/// Name of an outcome, for messages.
const char* describe(Outcome outcome) {
  switch (outcome) {
    case Outcome::renders: return "renders";
    case Outcome::refused_by_loader: return "refused by the loader";
    case Outcome::refused_by_renderer: return "refused by the renderer";
  }
  return "?";
}

}  // namespace

TEST_CASE("fuzz regressions: every recorded input has the outcome its table entry records", "[robustness][fuzz]") {
  const std::vector<fs::path> files = regression_inputs();
  CHECK_FALSE(files.empty());
  for (const fs::path& file : files) {
    const std::string name = file.filename().string();
    INFO(name);
    const auto entry = std::find_if(std::begin(expected_outcomes), std::end(expected_outcomes),
                                    [&](const ExpectedOutcome& e) { return name == e.file; });
    if (entry == std::end(expected_outcomes)) {
      FAIL_CHECK("tests/data/fuzz/" << name << " has no entry in expected_outcomes: record what it must do");
      continue;
    }
    const Result result = run(file);
    INFO("expected: " << describe(entry->outcome) << ", got: " << describe(result.outcome) << " " << result.message);
    CHECK(result.outcome == entry->outcome);
    if (result.outcome != Outcome::renders) {
      CHECK_THAT(result.message, Catch::Contains(file.string()));
      CHECK_THAT(result.message, Catch::Contains(entry->message));
    }
  }
}

TEST_CASE("fuzz regressions: every table entry names an input that exists", "[robustness][fuzz]") {
  for (const ExpectedOutcome& entry : expected_outcomes) {
    INFO(entry.file);
    CHECK(fs::is_regular_file(igi::testing::data_path("fuzz") / entry.file));
    // A refusal is recorded with the reason it must give.
    if (entry.outcome != Outcome::renders) CHECK(std::string(entry.message).size() > 0);
  }
}
