// libFuzzer harness (a): the glTF loader on arbitrary bytes, as .gltf JSON or .glb. A load may
// throw SceneError; anything else (another exception, a crash, a sanitizer report, a scene that
// breaks the loader's promises) is a finding.

#include <cstddef>
#include <cstdint>

#include "fuzz_support.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static igi::fuzz::InputFile input;
  const auto& path = input.write(data, size);
  try {
    std::vector<std::string> warnings;
    const igi::Scene scene = igi::load_gltf(path, &warnings);
    igi::fuzz::check_loaded_scene(scene);
  } catch (const igi::SceneError&) {
    // a clear refusal is the expected outcome for most inputs
  }
  return 0;
}
