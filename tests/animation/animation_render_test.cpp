// A file's own animation rendered: a skinned and a morphed mesh at a sampled time, applied as
// scene changes (the backends refit their BVHs), render the same image on every backend, and the
// same image as a backend built afresh on the scene posed at that time.

#include <string>

#include <catch2/catch.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/gltf.hpp"
#include "render/render_support.hpp"
#include "scene/animated_gltf.hpp"

namespace {

using namespace igi;
using namespace igi::testing;

/// The time the tests sample: 60% of the way, the bone bent 54 degrees and the quad 60% morphed.
constexpr double sampled_time = 0.6;

/// Small, single-threaded frames: the comparisons are of whole images, pixel by pixel.
RenderSettings small_settings() {
  RenderSettings s;
  s.width = 72;
  s.height = 54;
  s.vpls_per_pixel = 8;
  s.threads = 1;
  return s;
}

/// Frame 0 of `file`'s animation "all" at `seconds`, through backend B: the renderer is built on
/// the scene at rest, renders it once, then applies the sampled changes (so meshes are refitted).
template <class B>
Frame render_animated(const std::filesystem::path& file, double seconds) {
  Scene scene = load_gltf(file);
  const RenderSettings settings = small_settings();
  const GltfMaterialShader surface(scene);
  const StandardBrdf brdf;
  const QmcVplSampler sampler;
  const DiscontinuityFilter filter;
  Renderer<B, GltfMaterialShader, StandardBrdf, QmcVplSampler, DiscontinuityFilter> renderer(scene, settings, surface, brdf,
                                                                                              sampler, filter);
  const AnimationPlayer player(scene, find_animation(scene, "all"));
  static_cast<void>(renderer.render(scene.cameras.front(), 0));  // at rest: everything committed once
  const Camera camera = renderer.apply(player(seconds, scene.cameras.front(), 0));
  return renderer.render(camera, 0);
}

/// Checks `other` against `reference` as the cross-backend test of test_pipeline.cpp does:
/// backends find hit distances with different watertight algorithms, so a shadow ray grazing an
/// edge may flip on at most 0.5% of the pixels, and the image mean agrees to 1e-3 relative.
void compare(const Frame& reference, const Frame& other, const char* what) {
  INFO(what);
  CHECK(differing_pixels(reference, other, 1e-4f) <= reference.hdr.pixels.size() / 200);
  CHECK(mean_radiance(other) == Approx(mean_radiance(reference)).epsilon(1e-3));
}

TEST_CASE("a skinned and morphed scene at a sampled time renders the same image on every backend", "[render][animation]") {
  const std::filesystem::path file = write_deforming_scene(scratch_dir("animated_backends"), "deforming");
  const Frame reference = render_animated<EmbreeBackend<16>>(file, sampled_time);
  REQUIRE(all_finite(reference));
  REQUIRE(mean_radiance(reference) > 0.0);
  // The animation shows: the sampled frame differs from the rest pose's.
  const Frame rest = render_animated<EmbreeBackend<16>>(file, 0.0);
  CHECK(rmse(reference, rest) > 0.01 * mean_radiance(rest));
  compare(reference, render_animated<EmbreeBackend<4>>(file, sampled_time), "embree 4");
  compare(reference, render_animated<EmbreeBackend<1>>(file, sampled_time), "embree 1");
  compare(reference, render_animated<ReferenceBackend<8>>(file, sampled_time), "reference 8");
  compare(reference, render_animated<ReferenceBackend<1>>(file, sampled_time), "reference 1");
  compare(reference, render_animated<SaarcorBackend>(file, sampled_time), "saarcor 64");
}

TEST_CASE("changes applied to a running renderer render what a renderer built on the posed scene renders", "[render][animation]") {
  const std::filesystem::path file = write_deforming_scene(scratch_dir("animated_refit"), "deforming");
  const Frame refitted = render_animated<EmbreeBackend<8>>(file, sampled_time);
  Scene posed = load_gltf(file);
  const AnimationPlayer player(posed, find_animation(posed, "all"));
  const SceneChanges changes = player(sampled_time, posed.cameras.front(), 0);
  changes.apply_to(posed);
  REQUIRE(changes.meshes.size() == 2);  // the skinned and the morphed mesh
  const Frame built = render_once<EmbreeBackend<8>>(posed, small_settings());
  compare(built, refitted, "refitted against built afresh");
}

}  // namespace
