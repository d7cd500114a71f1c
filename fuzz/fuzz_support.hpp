#pragma once
// Shared by igi's libFuzzer harnesses: the fuzz input as a file the glTF loader can open, and the
// invariants every scene the loader accepts must hold.

#include <unistd.h>

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "igi/scene/gltf.hpp"
#include "igi/scene/memory.hpp"

namespace igi::fuzz {

/// Reports a broken invariant and aborts, which libFuzzer records as a finding with its input.
[[noreturn]] inline void broken(const char* what) {
  std::fprintf(stderr, "igi fuzz: invariant broken: %s\n", what);
  std::abort();
}

/// Writes each input to one file in a private folder (tinygltf reads files; the loader takes a
/// path). The folder links the Cornell box's .bin so seeds referring to it by URI still load.
class InputFile {
 public:
  InputFile() {
    directory_ = std::filesystem::temp_directory_path() / ("igi-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(directory_);
    const std::filesystem::path bin = std::filesystem::path(IGI_SCENES_DIR) / "cornell" / "cornell_box.bin";
    std::error_code ignored;
    if (std::filesystem::exists(bin)) std::filesystem::create_symlink(bin, directory_ / "cornell_box.bin", ignored);
    path_ = directory_ / "input.gltf";  // the loader tells .gltf from .glb by the magic, not the name
    // The loader must refuse what would not fit before allocating it. 1 GiB, half of libFuzzer's
    // -rss_limit_mb=2048: igi's refusal comes before libFuzzer's out-of-memory report would.
    set_memory_budget(std::size_t(1) << 30);
  }
  ~InputFile() {
    std::error_code ignored;
    std::filesystem::remove_all(directory_, ignored);
  }
  /// The file now holding `data`.
  const std::filesystem::path& write(const std::uint8_t* data, std::size_t size) {
    std::ofstream out(path_, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path_;
  }

 private:
  std::filesystem::path directory_;
  std::filesystem::path path_;
};

/// Aborts unless `scene` holds what the loader promises: valid references, finite values, unit normals.
inline void check_loaded_scene(const Scene& scene) {
  Scene copy = scene;
  try {
    std::vector<std::string> warnings;
    validate_scene(copy, &warnings);
  } catch (const SceneError&) {
    broken("a loaded scene fails validate_scene");
  }
  for (const Mesh& mesh : scene.meshes)
    for (const glm::vec3& normal : mesh.normals)
      // 1e-3: float normalization leaves a few ulps; anything further off was never normalized.
      if (!(std::abs(glm::length(normal) - 1.0f) < 1e-3f)) broken("a vertex normal is not unit length");
}

}  // namespace igi::fuzz
