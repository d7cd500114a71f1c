// Resource limits: input that would not fit in memory (a glTF accessor claiming 2^40 elements, an
// image or a frame larger than the memory budget) fails with a clear message before allocating -
// under AddressSanitizer an attempted multi-TiB allocation would abort the test instead - and an
// image write that fails or is killed half-way leaves no file under the final name.

#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/io/image_files.hpp"
#include "igi/render/settings.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/memory.hpp"
#include "scene/gltf_builder.hpp"

namespace {

namespace fs = std::filesystem;
using Catch::Contains;
using igi::testing::GltfBuilder;
using igi::testing::scratch_dir;

/// glTF elements one accessor claims: 2^40, far past any machine's memory at 4 bytes or more each.
constexpr std::size_t absurd_count = std::size_t(1) << 40;

/// Caps the memory budget for one test and lifts the cap again at its end.
struct BudgetCap {
  explicit BudgetCap(std::size_t bytes) { igi::set_memory_budget(bytes); }
  ~BudgetCap() { igi::set_memory_budget(0); }
};

/// The message of the SceneError loading `file` throws; fails if it throws none.
std::string load_error(const fs::path& file) {
  try {
    igi::load_gltf(file);
  } catch (const igi::SceneError& error) {
    return error.what();
  }
  FAIL("no SceneError for " << file);
  return {};
}

/// CRC-32 of PNG chunks (ISO 3309, reflected polynomial 0xEDB88320).
std::uint32_t crc32(const std::string& bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const unsigned char byte : bytes) {
    crc ^= byte;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

/// A PNG whose header claims width x height RGBA8 pixels but whose data ends after the header.
std::string png_header_only(std::uint32_t width, std::uint32_t height) {
  const auto big_endian = [](std::uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  const std::string header = "IHDR" + big_endian(width) + big_endian(height) + std::string{8, 6, 0, 0, 0};
  return std::string("\x89PNG\r\n\x1a\n", 8) + big_endian(13) + header + big_endian(crc32(header));
}

/// Names of the files in `directory`.
std::vector<std::string> entries(const fs::path& directory) {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(directory)) names.push_back(entry.path().filename().string());
  return names;
}

/// A PFM image of 64 x 64 pixels: 48 KiB, more than the 4 KiB file-size limit the write tests set.
igi::Image large_image() { return igi::Image(64, 64, glm::vec3(0.25f, 0.5f, 1.0f)); }

/// File-size limit (RLIMIT_FSIZE) the write tests set: a write past it fails (or, unhandled, kills the writer) half-way.
constexpr rlim_t file_size_limit = 4096;

}  // namespace

TEST_CASE("resource limits: a glTF accessor claiming 2^40 positions fails before allocating", "[robustness]") {
  GltfBuilder document;
  // No bufferView: glTF means zeros (before sparse substitution), so nothing bounds the count but memory.
  document.doc["accessors"].push_back({{"componentType", igi::testing::f32}, {"count", absurd_count}, {"type", "VEC3"}});
  document.add_mesh("huge", {{{"attributes", {{"POSITION", 0}}}}});
  document.set_roots({document.add_node({{"mesh", 0}})});
  const fs::path file = document.write_gltf(scratch_dir("claims_2_40_positions"), "huge");
  CHECK_THAT(load_error(file), Contains("huge POSITION") && Contains("1099511627776") && Contains("needs 12 TiB") &&
                                   Contains("of memory available"));
}

TEST_CASE("resource limits: glTF indices claiming 2^40 triangles fail before allocating", "[robustness]") {
  GltfBuilder document;
  const int positions = document.add_positions({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}});
  // tinygltf insists on a bufferView for indices; this one holds one triangle, the count claims 2^40.
  const std::uint32_t triangle[3] = {0, 1, 2};
  const int view = document.add_view(triangle, sizeof triangle);
  document.doc["accessors"].push_back(
      {{"bufferView", view}, {"componentType", igi::testing::u32}, {"count", 3 * absurd_count}, {"type", "SCALAR"}});
  document.add_mesh("huge", {{{"attributes", {{"POSITION", positions}}}, {"indices", positions + 1}}});
  document.set_roots({document.add_node({{"mesh", 0}})});
  const fs::path file = document.write_gltf(scratch_dir("claims_2_40_triangles"), "huge");
  CHECK_THAT(load_error(file), Contains("huge indices") && Contains("needs 12 TiB"));
}

TEST_CASE("resource limits: a texture too large for the memory budget is dropped with a warning before decoding", "[robustness]") {
  // 64 MiB; the image claims 16384 x 16384 RGBA8, twice that (stb's buffer and the copy) is 2 GiB.
  // (stb_image itself refuses images over 1 GiB; this one is just inside its limit.)
  const BudgetCap cap(std::size_t(64) << 20);
  GltfBuilder document;
  const std::string png = png_header_only(16384, 16384);
  document.doc["images"] = {{{"bufferView", document.add_view(png.data(), png.size())}, {"mimeType", "image/png"}}};
  document.doc["textures"] = {{{"source", 0}}};
  document.doc["materials"] = {{{"pbrMetallicRoughness", {{"baseColorTexture", {{"index", 0}}}, {"baseColorFactor", {0.5, 0.5, 0.5, 1.0}}}}}};
  document.set_roots({document.add_quad_node("quad")});
  document.doc["meshes"][0]["primitives"][0]["material"] = 0;
  std::vector<std::string> warnings;
  const igi::Scene scene = igi::load_gltf(document.write_glb(scratch_dir("huge_texture"), "huge_texture"), &warnings);
  CHECK(scene.textures.empty());
  REQUIRE(scene.materials.size() == 1);
  CHECK(scene.materials[0].base_color_texture == -1);
  CHECK(scene.materials[0].base_color == glm::vec4(0.5f, 0.5f, 0.5f, 1.0f));
  REQUIRE(warnings.size() == 1);
  CHECK_THAT(warnings[0], Contains("16384x16384") && Contains("needs 2 GiB") && Contains("more than the 64 MiB"));
}

TEST_CASE("resource limits: a frame larger than the memory budget is a settings error before allocating", "[robustness]") {
  igi::RenderSettings settings;
  settings.width = 4096;
  settings.height = 4096;  // 16 Mi pixels x 15 bytes = 240 MiB
  CHECK_NOTHROW(igi::validate(settings));
  const BudgetCap cap(std::size_t(64) << 20);
  CHECK_THROWS_WITH(igi::validate(settings), Contains("size 4096x4096") && Contains("needs 240 MiB") &&
                                                 Contains("more than the 64 MiB of memory available"));
}

TEST_CASE("resource limits: the memory budget is the available memory, or the cap if lower", "[robustness]") {
  const std::size_t available = igi::available_memory();
  CHECK(available > 0);
  CHECK(igi::memory_budget() == available);
  const BudgetCap cap(1000);
  CHECK(igi::memory_budget() == 1000);
  CHECK(igi::memory_shortfall(10, 100).empty());
  CHECK(igi::memory_shortfall(11, 100) == "needs 1.07 KiB, more than the 1000 bytes of memory available");
}

TEST_CASE("atomic writes: a write that fails half-way leaves no file under the final name", "[robustness][io]") {
  const fs::path directory = scratch_dir("failed_write");
  const fs::path target = directory / "frame.pfm";
  rlimit previous{};
  REQUIRE(getrlimit(RLIMIT_FSIZE, &previous) == 0);
  // With SIGXFSZ ignored, writing past the limit fails with EFBIG after the first 4 KiB reached the disk.
  const auto old_handler = signal(SIGXFSZ, SIG_IGN);
  rlimit limited = previous;
  limited.rlim_cur = file_size_limit;
  REQUIRE(setrlimit(RLIMIT_FSIZE, &limited) == 0);
  bool threw = false;
  try {
    igi::write_image(target, large_image());
  } catch (const igi::ImageError& error) {
    threw = true;
    CHECK_THAT(error.what(), Contains("frame.pfm") && Contains("failed"));
  }
  setrlimit(RLIMIT_FSIZE, &previous);
  signal(SIGXFSZ, old_handler);
  CHECK(threw);
  CHECK_FALSE(fs::exists(target));
  CHECK(entries(directory).empty());  // the half-written temporary was removed too
  igi::write_image(target, large_image());  // with the limit lifted the same write succeeds
  CHECK(igi::read_image(target).pixels == large_image().pixels);
}

TEST_CASE("atomic writes: a writer killed half-way leaves no file under the final name", "[robustness][io]") {
  const fs::path directory = scratch_dir("killed_write");
  const fs::path target = directory / "frame.pfm";
  const pid_t child = fork();
  REQUIRE(child >= 0);
  if (child == 0) {
    // The child is killed by SIGXFSZ (default action) at its first write past 4 KiB: an
    // interruption in the middle of the image, with part of it already on disk.
    const rlimit no_core{0, 0};
    setrlimit(RLIMIT_CORE, &no_core);
    const rlimit limited{file_size_limit, file_size_limit};
    setrlimit(RLIMIT_FSIZE, &limited);
    signal(SIGXFSZ, SIG_DFL);
    try {
      igi::write_image(target, large_image());
    } catch (...) {
    }
    _exit(0);  // not reached when the signal kills the writer
  }
  int status = 0;
  REQUIRE(waitpid(child, &status, 0) == child);
  REQUIRE(WIFSIGNALED(status));
  CHECK(WTERMSIG(status) == SIGXFSZ);
  CHECK_FALSE(fs::exists(target));
  // What the killed writer left is only its hidden temporary file, never the final name.
  for (const std::string& name : entries(directory)) CHECK_THAT(name, Catch::StartsWith(".frame.pfm") && Catch::EndsWith(".tmp"));
}
