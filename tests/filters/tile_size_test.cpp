// Every filter through the whole pipeline: the image does not depend on the tile size. Tiles are
// rendered with the border their filter asks for (Filter::border), and each filter's output at
// a pixel depends only on the G-buffer within that border, so cutting the image into tiles of
// 40, 16 or 7 pixels (edges through the middle of the à-trous footprint, partial tiles at the
// image's right and bottom) must give the same pixels: what keeps the MPI farm's images, whose
// tiles go to different processes, identical to one process's.

#include <catch2/catch.hpp>

#include <cstring>
#include <mutex>

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

TEMPLATE_LIST_TEST_CASE("filters: tiles that share their borders give the bordered tiles' image", "[filters][render]",
                        AllFilters) {
  // TileEngine::render_frame (what Renderer uses) shades every pixel once and reads each tile's
  // border from its neighbours; render_tiles (what each MPI rank does) shades every tile with its
  // own border. The filter reads the same G-buffer values either way, so the images must agree
  // bit for bit, over two frames (the image's G-buffer is reused), with anti-aliasing, shadow
  // roulette and bias compensation, whose random numbers are hashed from the pixel.
  Scene scene = cornell_box();
  RenderSettings settings;
  settings.width = 83;  // partial tiles at the right and bottom
  settings.height = 61;
  settings.vpls_per_pixel = 8;
  settings.threads = 2;
  settings.tile_size = 16;
  settings.antialiasing = 2;
  settings.shadow_roulette = 0.2f;
  settings.compensation_rays = 1;
  const GltfMaterialShader surface(scene);
  const QmcVplSampler sampler;
  const StandardBrdf brdf;
  const TestType filter;
  TileEngine<EmbreeBackend<8>, GltfMaterialShader, StandardBrdf, QmcVplSampler, TestType> engine(scene, settings, surface,
                                                                                               brdf, sampler, filter);
  const auto render = [&](bool shared_borders, RayCounts& rays) {
    Frame frame = Frame::blank(settings.width, settings.height, engine.frame().index);
    std::mutex merge;
    const auto done = [&](std::size_t, const TileResult& tile, double) {
      place_tile(tile, frame);
      const std::lock_guard lock(merge);
      rays.merge(tile.rays);
    };
    if (shared_borders)
      engine.render_frame(done);
    else
      engine.render_tiles(engine.all_tiles(), done);
    return frame;
  };
  for (const std::uint32_t index : {0u, 1u}) {
    INFO(TestType::name() << ", frame " << index);
    engine.begin_frame(scene.cameras.front(), index, ToneMapping{});
    RayCounts bordered_rays, shared_rays;
    const Frame bordered = render(false, bordered_rays);
    const Frame shared = render(true, shared_rays);
    REQUIRE(mean_radiance(shared) > 0.0);
    std::size_t differing = 0;
    for (std::size_t i = 0; i < bordered.hdr.pixels.size(); ++i)
      if (std::memcmp(&bordered.hdr.pixels[i], &shared.hdr.pixels[i], sizeof(glm::vec3)) != 0) ++differing;
    CHECK(differing == 0);
    CHECK(bordered.rgb8.bytes == shared.rgb8.bytes);
    // Every pixel's camera rays exactly once (the Cornell box has no alpha cut-outs to continue
    // through); the bordered tiles shade their borders as well.
    CHECK(shared_rays.primary == std::uint64_t(settings.width * settings.height * settings.antialiasing));
    if (filter.border(settings.interleave) > 0) CHECK(bordered_rays.primary > shared_rays.primary);
  }
}
