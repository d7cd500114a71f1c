// libFuzzer harness (b): the scene-to-pixels path on arbitrary bytes. A scene the loader accepts
// is built into every backend (Embree W=16, Reference, SaarCOR) and rendered as one tiny IGI frame
// with each; every pixel must be finite. Refusals must be SceneError, SettingsError or
// std::invalid_argument with a message; anything else is a finding.

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "fuzz_support.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace {

/// One 16 x 16 frame of `scene` through backend B; aborts on a non-finite pixel.
template <class B>
void render_tiny_frame(igi::Scene& scene, const igi::Camera& camera, std::uint8_t knobs) {
  igi::RenderSettings settings;
  settings.width = 16;
  settings.height = 16;
  settings.tile_size = 8;
  settings.interleave = 1 + knobs % 2;         // 1x1 or 2x2 pattern
  settings.vpls_per_pixel = 1 + (knobs >> 1) % 4;  // 1 to 4 VPLs
  settings.threads = 1;                       // findings must reproduce from the input alone
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::QmcVplSampler sampler;
  const igi::DiscontinuityFilter filter;
  igi::Renderer<B, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler, igi::DiscontinuityFilter> renderer(
      scene, settings, surface, brdf, sampler, filter);
  const igi::Frame frame = renderer.render(camera, 0);
  for (const glm::vec3& pixel : frame.hdr.pixels)
    if (!std::isfinite(pixel.r) || !std::isfinite(pixel.g) || !std::isfinite(pixel.b))
      igi::fuzz::broken("a rendered pixel is not finite");
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static igi::fuzz::InputFile input;
  const auto& path = input.write(data, size);
  igi::Scene scene;
  try {
    std::vector<std::string> warnings;
    scene = igi::load_gltf(path, &warnings);
  } catch (const igi::SceneError&) {
    return 0;
  }
  igi::fuzz::check_loaded_scene(scene);
  if (scene.triangle_count() == 0) return 0;
  // The last byte picks interleaving and VPL count, so the fuzzer explores settings too.
  const std::uint8_t knobs = size > 0 ? data[size - 1] : 0;
  try {
    const igi::Camera camera = scene.cameras.empty() ? igi::default_camera(scene) : scene.cameras.front();
    render_tiny_frame<igi::EmbreeBackend<16>>(scene, camera, knobs);
    render_tiny_frame<igi::ReferenceBackend<8>>(scene, camera, knobs);
    render_tiny_frame<igi::SaarcorBackend>(scene, camera, knobs);
  } catch (const igi::SceneError&) {
  } catch (const std::invalid_argument&) {  // SettingsError and the backends' refusals of malformed scenes
  }
  return 0;
}
