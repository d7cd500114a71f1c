// Every input in tests/data/fuzz - crashes and failures the fuzz harnesses (fuzz/) once found,
// minimized - must now load into a valid scene or fail with a SceneError naming the file, and a
// scene it loads into must render finite pixels. fuzz/README.md lists what each one found.

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/scene/gltf.hpp"
#include "render/render_support.hpp"
#include "scenes.hpp"

namespace {

namespace fs = std::filesystem;

/// The regression inputs, sorted by name.
std::vector<fs::path> regression_inputs() {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(igi::testing::data_path("fuzz")))
    if (entry.is_regular_file() && entry.path().filename() != "README.md") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace

TEST_CASE("fuzz regressions: every recorded input loads and renders, or is refused with a SceneError", "[robustness][fuzz]") {
  const std::vector<fs::path> files = regression_inputs();
  CHECK_FALSE(files.empty());
  for (const fs::path& file : files) {
    INFO(file.filename().string());
    igi::Scene scene;
    try {
      std::vector<std::string> warnings;
      scene = igi::load_gltf(file, &warnings);
    } catch (const igi::SceneError& error) {
      CHECK_THAT(error.what(), Catch::Contains(file.string()));
      continue;
    }
    if (scene.triangle_count() == 0) continue;
    igi::RenderSettings settings;
    settings.width = 16;
    settings.height = 16;
    settings.vpls_per_pixel = 2;
    settings.tile_size = 8;
    try {
      CHECK(igi::testing::all_finite(igi::testing::render_once<igi::EmbreeBackend<16>>(scene, settings)));
    } catch (const igi::SceneError& error) {
      SUCCEED(error.what());  // e.g. a scene without a finite default camera
    }
  }
}
