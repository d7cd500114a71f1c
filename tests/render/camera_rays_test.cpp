// The camera rays of a tile are traced before its interleaving sets are shaded, in packets of
// neighbouring pixels (Pipeline::trace_camera_rays), and each set's packets take their rays and
// hits from there. These tests check that every pixel and sub-sample gets its own ray's hit,
// against single rays cast by a W = 1 backend outside the pipeline, on image and tile sizes that
// leave partial packets at every tile's right and bottom edge; and that the reference path
// tracer's camera rays read textures as the pipeline's do.

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <mutex>
#include <span>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/tile_engine.hpp"
#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// A black, emitting quad tilted across a black background, seen whole: every pixel's radiance
/// is the share of its sub-sample rays that hit the quad (emission 1, nothing lit, albedo 0),
/// and its slanted edges cut pixels at every sub-sample position.
Scene tilted_emitter() {
  Scene scene;
  const int emitter = add_material(scene, glm::vec3(0.0f), glm::vec3(1.0f));
  const glm::vec3 u = glm::normalize(glm::vec3(1.0f, 0.35f, 0.0f)), v = glm::normalize(glm::vec3(-0.35f, 1.0f, 0.2f));
  add_quad(scene, glm::vec3(0.0f), u, v, glm::normalize(glm::cross(u, v)), 0.8f, emitter);
  scene.cameras.push_back(look_at({0.0f, 0.0f, 3.0f}, {0.0f, 0.0f, 0.0f}, 0.8f));
  return scene;
}

/// Settings whose image (61 x 37) and tiles (`tile` pixels) are no multiple of any packet shape.
RenderSettings odd_settings(int tile, int antialiasing) {
  RenderSettings settings;
  settings.width = 61;
  settings.height = 37;
  settings.tile_size = tile;
  settings.antialiasing = antialiasing;
  settings.vpls_per_pixel = 4;
  settings.threads = 1;
  return settings;
}

/// The frame and its pixels' layers through backend B, by TileEngine::render_tiles (every tile
/// shades its own border) or render_frame (tiles share their borders).
template <class B>
std::pair<Frame, std::vector<PixelLayers>> render_layers(Scene& scene, const RenderSettings& settings, bool shared) {
  const GltfMaterialShader surface(scene);
  const QmcVplSampler sampler;
  const StandardBrdf brdf;
  const DiscontinuityFilter filter;
  TileEngine<B, GltfMaterialShader, StandardBrdf, QmcVplSampler, DiscontinuityFilter> engine(scene, settings, surface,
                                                                                             brdf, sampler, filter);
  engine.begin_frame(scene.cameras.front(), 0, ToneMapping{}, FrameOptions{.keep_layers = true});
  Frame frame = Frame::blank(settings.width, settings.height, 0);
  std::vector<PixelLayers> layers(std::size_t(settings.width) * std::size_t(settings.height));
  std::mutex place;
  const auto done = [&](std::size_t, const TileResult& tile, double) {
    const std::lock_guard lock(place);
    place_tile(tile, frame, layers);
  };
  if (shared)
    engine.render_frame(done);
  else
    engine.render_tiles(engine.all_tiles(), done);
  return {std::move(frame), std::move(layers)};
}

/// Sub-sample k's camera ray through pixel (x, y), cast alone by `single`: its hit distance, or
/// a negative number on a miss.
float cast_alone(const EmbreeBackend<1>& single, const PinholeProjection& projection, const RenderSettings& settings,
                 int x, int y, int k) {
  float dx = 0.5f, dy = 0.5f;
  subsample_offset(k, settings.antialiasing, dx, dy);
  RayPacket<1> ray;
  HitPacket<1> hit;
  ray.set(vec3<1>(projection.origin()), vec3<1>(projection.direction(float(x) + dx, float(y) + dy)), vfloat<1>(0.0f),
          vfloat<1>(std::numeric_limits<float>::infinity()), vmask<1>(true));
  hit.clear();
  single.intersect(ray, hit, vmask<1>(true));
  return hit.valid()[0] ? ray.tfar[0] : -1.0f;
}

/// Checks the frame of backend B against single rays: each pixel's radiance is the share of its
/// sub-sample rays that hit, and its kept depth is its sub-sample 0 ray's hit distance.
template <class B>
void check_against_single_rays(const char* name) {
  Scene scene = tilted_emitter();
  const EmbreeBackend<1> single(scene);
  std::size_t edge_pixels = 0;
  for (const int antialiasing : {1, 4})
    for (const int tile : {7, 13, 48})
      for (const bool shared : {false, true}) {
        INFO(name << ", aa " << antialiasing << ", tile " << tile << (shared ? ", shared borders" : ", own borders"));
        const RenderSettings settings = odd_settings(tile, antialiasing);
        const auto [frame, layers] = render_layers<B>(scene, settings, shared);
        const PinholeProjection projection(scene.cameras.front(), settings.width, settings.height);
        std::size_t wrong_radiance = 0, wrong_depth = 0;
        for (int y = 0; y < settings.height; ++y)
          for (int x = 0; x < settings.width; ++x) {
            const std::size_t i = std::size_t(y) * std::size_t(settings.width) + std::size_t(x);
            int hits = 0;
            for (int k = 0; k < antialiasing; ++k) hits += cast_alone(single, projection, settings, x, y, k) >= 0.0f;
            if (hits > 0 && hits < antialiasing) ++edge_pixels;
            // Quarters of the emission 1 add up exactly; a pixel whose ray lies on the quad's
            // edge (a shared edge of its two triangles or its outline) may go either way in
            // another backend's last bit, which 1e-6 does not excuse: such rays miss by more.
            const float expected = float(hits) / float(antialiasing);
            if (std::abs(frame.hdr.pixels[i].g - expected) > 1e-6f) ++wrong_radiance;
            const float distance = cast_alone(single, projection, settings, x, y, 0);
            const PixelLayers& kept = layers[i];
            // Hit distances agree to float rounding between backends and packet widths.
            if (kept.hit != (distance >= 0.0f) || (kept.hit && std::abs(kept.depth - distance) > 1e-5f * distance))
              ++wrong_depth;
          }
        CHECK(wrong_radiance == 0);
        CHECK(wrong_depth == 0);
      }
  // The slanted edges did cut pixels between their sub-samples, so a sub-sample given another's
  // hit would have shown.
  CHECK(edge_pixels > 50);
}

}  // namespace

TEST_CASE("camera rays: every pixel and sub-sample gets its own ray's hit, at every packet width",
          "[render][packets]") {
  check_against_single_rays<EmbreeBackend<4>>("embree 4");
  check_against_single_rays<EmbreeBackend<8>>("embree 8");
  check_against_single_rays<EmbreeBackend<16>>("embree 16");
  check_against_single_rays<ReferenceBackend<8>>("reference 8");
  check_against_single_rays<SaarcorBackend>("saarcor 64");
}

TEST_CASE("camera rays: the path tracer's pixel-centre rays read textures over the footprint IGI's do", "[render][texture]") {
  // A floor seen at a grazing angle with a checkerboard of single texels 256 across: each pixel
  // spans many texels far off, few near. The reference path tracer through the pixel centres
  // with PathTracerSettings::filter_textures must read each first hit's albedo as IGI's camera
  // rays do (RenderSettings::filter_textures), so that a comparison of the two measures the
  // light only; read at points, the checks alias.
  Scene scene;
  scene.name = "checkerboard floor";
  Texture board{.name = "checks", .width = 256, .height = 256, .texels = {}};
  for (int y = 0; y < board.height; ++y)
    for (int x = 0; x < board.width; ++x) {
      const std::uint8_t code = (x + y) % 2 ? 255 : 0;
      board.texels.insert(board.texels.end(), {code, code, code, 255});
    }
  scene.textures.push_back(board);
  const int floor = add_material(scene, glm::vec3(1.0f));
  scene.materials[std::size_t(floor)].base_color_texture = 0;
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 3.0f, floor);
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .intensity = 2.0f,
                          .direction = glm::normalize(glm::vec3(-1.0f, -1.0f, 0.0f))});
  scene.cameras.push_back(look_at({0.0f, 1.0f, 3.5f}, {0.0f, 0.0f, 0.0f}, 1.0f));
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.threads = 2;
  RoomRenderer igi(scene, settings);
  igi.renderer.set_keep_layers(true);
  igi.render(scene.cameras.front(), 0);
  const std::span<const PixelLayers> igi_layers = igi.renderer.layers();

  const EmbreeBackend<1> backend(scene);
  const auto path_traced_layers = [&](bool filter_textures) {
    PathTracerSettings path_settings;
    path_settings.jitter = false;
    path_settings.filter_textures = filter_textures;
    path_settings.threads = 2;
    PathTracer<EmbreeBackend<1>, GltfMaterialShader, StandardBrdf> tracer(scene, backend, igi.surface, igi.brdf, path_settings);
    tracer.reset(scene.cameras.front(), settings.width, settings.height);
    return tracer.first_hits();
  };
  const std::vector<PixelLayers> footprint = path_traced_layers(true), points = path_traced_layers(false);
  REQUIRE(footprint.size() == igi_layers.size());
  float largest_difference = 0.0f, largest_aliasing = 0.0f;
  int hits = 0;
  for (std::size_t i = 0; i < footprint.size(); ++i) {
    REQUIRE(footprint[i].hit == igi_layers[i].hit);
    if (!footprint[i].hit) continue;
    ++hits;
    largest_difference = std::max(largest_difference, glm::length(footprint[i].albedo - igi_layers[i].albedo));
    largest_aliasing = std::max(largest_aliasing, glm::length(points[i].albedo - igi_layers[i].albedo));
  }
  INFO(hits << " pixels on the floor: largest albedo difference " << largest_difference << " at the footprint, "
            << largest_aliasing << " at points");
  REQUIRE(hits > settings.width * settings.height / 2);
  // The same cone through the same pixel centre: the same lookups up to float rounding.
  CHECK(largest_difference < 1e-5f);
  // Read at points, far-off pixels take a black or a white texel where the footprint reads grey.
  CHECK(largest_aliasing > 0.3f);
}
