// Bias compensation adds nothing where no surface is within the clamp distance and gives the
// same image on every backend, packet width, thread count and tile size (that it returns the
// clamp's light is checked against the path tracer in tests/accuracy/stability_test.cpp).

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// The Cornell box seen into the corner of floor, back wall and the x = 0 wall from close by: the
/// view where the clamp removes most light.
Scene corner_view() {
  Scene scene = cornell_box();
  scene.cameras.front() = cornell_corner_camera();
  return scene;
}

}  // namespace

TEST_CASE("bias compensation adds nothing where no surface is within the clamp distance", "[render][compensation]") {
  // The default Cornell view with a clamp of 1 mm: gather rays that short hit only within a
  // millimetre of an edge, so the image barely changes; with the clamp switched off there is
  // nothing to return and the image is bit-identical.
  Scene scene = cornell_box();
  RenderSettings s;
  s.width = 48;
  s.height = 36;
  s.vpls_per_pixel = 16;
  s.clamp_distance = 0.0f;
  const Frame off = render_once<EmbreeBackend<8>>(scene, s);
  RenderSettings with = s;
  with.compensation_rays = 4;
  CHECK(render_once<EmbreeBackend<8>>(scene, with).hdr.pixels == off.hdr.pixels);
  s.clamp_distance = with.clamp_distance = 0.001f;
  const double before = mean_radiance(render_once<EmbreeBackend<8>>(scene, s));
  const double after = mean_radiance(render_once<EmbreeBackend<8>>(scene, with));
  CHECK(after >= before);
  CHECK(after < before * 1.002);
}

TEST_CASE("bias compensation: every backend, packet width and thread count renders the same image", "[render][compensation][determinism]") {
  Scene scene = corner_view();
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  s.vpls_per_pixel = 8;
  s.clamp_distance = 0.1f;
  s.compensation_rays = 2;
  s.threads = 1;
  const Frame reference = render_once<EmbreeBackend<16>>(scene, s);
  REQUIRE(all_finite(reference));
  const auto compare = [&](const Frame& other, const char* what) {
    INFO(what);
    // As the determinism test without compensation: hit points differ between backends in the
    // last float bits, so pixels agree to 1e-4 relative except where a shadow or gather ray
    // grazes an edge and flips; those may be 1% of the pixels (a gather ray's verdict moves a
    // pixel by one share as a shadow ray's does, and there are more rays per pixel here).
    CHECK(differing_pixels(reference, other, 1e-4f) <= reference.hdr.pixels.size() / 100);
    CHECK(mean_radiance(other) == Approx(mean_radiance(reference)).epsilon(1e-3));
  };
  compare(render_once<EmbreeBackend<4>>(scene, s), "embree 4");
  compare(render_once<EmbreeBackend<8>>(scene, s), "embree 8");
  compare(render_once<ReferenceBackend<8>>(scene, s), "reference 8");
  compare(render_once<SaarcorBackend>(scene, s), "saarcor 64");
  RenderSettings two = s;
  two.threads = 2;
  CHECK(render_once<EmbreeBackend<16>>(scene, two).hdr.pixels == reference.hdr.pixels);
  // Tiles of another size cut the gather rays' pixels into other packets: the same image.
  RenderSettings tiles = s;
  tiles.tile_size = 8;
  CHECK(render_once<EmbreeBackend<16>>(scene, tiles).hdr.pixels == reference.hdr.pixels);
}
