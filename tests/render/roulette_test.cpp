// Shadow-ray Russian roulette: fewer shadow rays, the same expected image (unbiased), and the
// same choices on every packet width, thread count and tile size.

#include <catch2/catch.hpp>

#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

TEST_CASE("shadow-ray roulette traces fewer rays and keeps the image's mean", "[render][roulette]") {
  Scene scene = cornell_box();
  RenderSettings s;
  s.width = 64;
  s.height = 48;
  s.vpls_per_pixel = 64;
  RenderSettings roulette = s;
  roulette.shadow_roulette = 0.2f;
  // 16 frames (independent VPL sets): the roulette's extra noise in the mean (about 0.3% per
  // frame, measured) averages to well below the 1% checked.
  double plain_mean = 0.0, roulette_mean = 0.0;
  std::uint64_t plain_rays = 0, roulette_rays = 0;
  for (std::uint32_t index = 0; index < 16; ++index) {
    const Frame plain = render_once<EmbreeBackend<8>>(scene, s, index);
    const Frame played = render_once<EmbreeBackend<8>>(scene, roulette, index);
    REQUIRE(all_finite(played));
    plain_mean += mean_radiance(plain) / 16.0;
    roulette_mean += mean_radiance(played) / 16.0;
    plain_rays += plain.statistics.rays.shadow;
    roulette_rays += played.statistics.rays.shadow;
  }
  INFO("mean " << plain_mean << " -> " << roulette_mean << ", shadow rays " << plain_rays << " -> " << roulette_rays);
  CHECK(roulette_rays < plain_rays * 9 / 10);
  CHECK(roulette_mean == Approx(plain_mean).epsilon(0.01));
}

TEST_CASE("shadow-ray roulette: every packet width, thread count and tile size makes the same choices", "[render][roulette][determinism]") {
  Scene scene = cornell_box();
  RenderSettings s;
  s.width = 40;
  s.height = 30;
  s.vpls_per_pixel = 16;
  s.shadow_roulette = 0.2f;
  s.threads = 1;
  const Frame reference = render_once<EmbreeBackend<16>>(scene, s);
  // The same backend at other widths: the same per-pixel sums in the same order, and the same
  // random numbers (hashed from the pixel, not the lane), so the roulette changes nothing at
  // float rounding; 1e-5 relative is what packets of other widths differ by without it.
  for (const auto& [frame, what] : {std::pair{render_once<EmbreeBackend<4>>(scene, s), "embree 4"},
                                    std::pair{render_once<EmbreeBackend<8>>(scene, s), "embree 8"}}) {
    INFO(what);
    CHECK(differing_pixels(reference, frame, 1e-5f) == 0);
  }
  RenderSettings two = s;
  two.threads = 2;
  CHECK(render_once<EmbreeBackend<16>>(scene, two).hdr.pixels == reference.hdr.pixels);
  RenderSettings tiles = s;
  tiles.tile_size = 8;
  CHECK(render_once<EmbreeBackend<16>>(scene, tiles).hdr.pixels == reference.hdr.pixels);
}
