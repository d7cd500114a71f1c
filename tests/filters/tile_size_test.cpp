// Every filter through the whole pipeline: the image does not depend on the tile size. Tiles are
// rendered with the border their filter asks for (Filter::border), and each filter's output at
// a pixel depends only on the G-buffer within that border, so cutting the image into tiles of
// 40, 16 or 7 pixels (edges through the middle of the à-trous footprint, partial tiles at the
// image's right and bottom) must give the same pixels: what keeps the MPI farm's images, whose
// tiles go to different processes, identical to one process's.

#include <catch2/catch.hpp>

#include <cstring>
#include <mutex>

#include <glm/gtc/matrix_transform.hpp>

#include "igi/render/filter_choice.hpp"
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

/// render_frame against render_tiles with `filter` on the Cornell box (its red wall glossy metal
/// with `glossy_wall`), with S x S interleaving.
template <class F>
void check_shared_borders(const F& filter, bool glossy_wall, int interleave = 3) {
  Scene scene = cornell_box();
  if (glossy_wall) {
    scene.materials[1].metallic = 1.0f;  // 1: the red wall
    scene.materials[1].roughness = 0.5f;
  }
  RenderSettings settings;
  settings.width = 83;  // partial tiles at the right and bottom
  settings.height = 61;
  settings.vpls_per_pixel = 8;
  settings.threads = 2;
  settings.tile_size = 16;
  settings.antialiasing = 2;
  settings.shadow_roulette = 0.2f;
  settings.compensation_rays = 1;
  settings.interleave = interleave;
  const GltfMaterialShader surface(scene);
  const QmcVplSampler sampler;
  const StandardBrdf brdf;
  TileEngine<EmbreeBackend<8>, GltfMaterialShader, StandardBrdf, QmcVplSampler, F> engine(scene, settings, surface,
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
  for (const std::uint32_t index : {0u, 1u, 2u}) {
    INFO(filter.name() << ", S = " << interleave << ", frame " << index);
    // Frames 1 and 2 turn the camera by 0.25 radians (a quarter of the image) either way, so
    // tiles that filtered the glossy wall in the frame before no longer see it, and the reverse.
    Camera camera = scene.cameras.front();
    const float turn[] = {0.0f, 0.25f, -0.25f};
    camera.camera_to_world = camera.camera_to_world * glm::rotate(glm::mat4(1.0f), turn[index], glm::vec3(0.0f, 1.0f, 0.0f));
    engine.begin_frame(camera, index, ToneMapping{});
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

TEMPLATE_LIST_TEST_CASE("filters: tiles that share their borders give the bordered tiles' image", "[filters][render]",
                        AllFilters) {
  // TileEngine::render_frame (what Renderer uses) shades every pixel once and reads each tile's
  // border from its neighbours; render_tiles (what each MPI rank does) shades every tile with its
  // own border. The filter reads the same G-buffer values either way, so the images must agree
  // bit for bit, over three frames (the image's G-buffer is reused), with anti-aliasing, shadow
  // roulette and bias compensation, whose random numbers are hashed from the pixel. A staged
  // filter (AtrousFilter) also copies each stage's border from the neighbours' stages; with the
  // red wall glossy, tiles that filter glossy radiance border tiles that do not.
  for (const bool glossy_wall : {false, true}) {
    INFO((glossy_wall ? "glossy red wall" : "diffuse Cornell box"));
    check_shared_borders(TestType{}, glossy_wall);
  }
}

TEST_CASE("filters: FilterChoice runs its filter's stages as the filter alone does", "[filters][render]") {
  // The programs' run-time choice is itself a StagedFilter that forwards AtrousFilter's stages
  // (and runs the others whole in its one stage), so igi-render's frames share the stages too.
  STATIC_REQUIRE(StagedFilter<AtrousFilter>);
  STATIC_REQUIRE(StagedFilter<FilterChoice>);
  STATIC_REQUIRE(!StagedFilter<DiscontinuityFilter>);
  CHECK(FilterChoice("atrous").stage_count() == AtrousFilter().stage_count());
  CHECK(FilterChoice("discontinuity").stage_count() == 1);
  // Shared borders are as wide as one stage reads: the last pass's step (4 of the whole 8), the
  // S x S window's where that reaches farther; a filter that runs whole needs its whole border.
  CHECK(FilterChoice("atrous").staged_border(3) == 4);
  CHECK(AtrousFilter().border(3) == 8);
  CHECK(FilterChoice("discontinuity").staged_border(3) == 1);
  CHECK(FilterChoice("discontinuity").staged_border(5) == 2);
  AtrousSettings one_pass;
  one_pass.passes = 1;
  CHECK(AtrousFilter(one_pass).staged_border(3) == 1);
  CHECK(AtrousFilter(one_pass).staged_border(9) == 4);
  CHECK(AtrousFilter(one_pass).border(9) == 5);
  // Where the window reaches farther than the passes (S = 5: 2 pixels against one pass's 1), the
  // shared border is the window's, and the frame still the bordered tiles'.
  CHECK(AtrousFilter(one_pass).staged_border(5) == 2);
  check_shared_borders(AtrousFilter(one_pass), false, 5);
  for (const char* name : {"atrous", "discontinuity"}) {
    INFO(name);
    check_shared_borders(FilterChoice(name), true);
  }
}
