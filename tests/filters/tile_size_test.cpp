// Every filter through the whole pipeline: the image does not depend on the tile size. Tiles are
// rendered with the border their filter asks for (Filter::border), and each filter's output at
// a pixel depends only on the G-buffer within that border, so cutting the image into tiles of
// 40, 16 or 7 pixels (edges through the middle of the à-trous footprint, partial tiles at the
// image's right and bottom) must give the same pixels: what keeps the MPI farm's images, whose
// tiles go to different processes, identical to one process's.

#include <catch2/catch.hpp>

#include <cstring>

#include "policy_lists.hpp"
#include "render/render_support.hpp"

using namespace igi;
using namespace igi::testing;

TEMPLATE_LIST_TEST_CASE("filters: every filter's image is the same whatever the tile size", "[filters][render]",
                        AllFilters) {
  Scene scene = cornell_box();
  RenderSettings settings;
  // Not a multiple of any tile size below: the last column and row of tiles are partial.
  settings.width = 83;
  settings.height = 61;
  settings.vpls_per_pixel = 8;
  settings.threads = 1;
  for (const int interleave : {3, 4}) {
    settings.interleave = interleave;
    settings.tile_size = 40;
    const Frame reference = render_once<EmbreeBackend<8>, StandardBrdf, TestType>(scene, settings);
    REQUIRE(all_finite(reference));
    REQUIRE(mean_radiance(reference) > 0.0);
    for (const int tile_size : {16, 7}) {
      INFO(TestType::name() << ", S = " << interleave << ", tile size " << tile_size << " against 40");
      settings.tile_size = tile_size;
      const Frame tiled = render_once<EmbreeBackend<8>, StandardBrdf, TestType>(scene, settings);
      REQUIRE(tiled.hdr.pixels.size() == reference.hdr.pixels.size());
      // Bit for bit: a pixel's rays, their packets' lanes and its filter taps are the same
      // whatever tile holds it, and every operation is lane-wise.
      std::size_t differing = 0;
      for (std::size_t i = 0; i < reference.hdr.pixels.size(); ++i)
        if (std::memcmp(&reference.hdr.pixels[i], &tiled.hdr.pixels[i], sizeof(glm::vec3)) != 0) ++differing;
      CHECK(differing == 0);
    }
  }
}
