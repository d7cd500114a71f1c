// Tiles, interleaving sets and the per-set packet grouping of the paper's Figure 2.
#include <cmath>
#include <limits>
#include <set>
#include <utility>

#include <catch2/catch.hpp>

#include "igi/render/interleaving.hpp"
#include "igi/render/tone_mapping.hpp"
#include "igi/simd/sampling.hpp"

using namespace igi;

TEST_CASE("tiles cover the image exactly once", "[render][tiles]") {
  const auto tiles = make_tiles(103, 47, 40);
  REQUIRE(tiles.size() == 3 * 2);
  long area = 0;
  for (const PixelRect& t : tiles) {
    CHECK(t.width() <= 40);
    CHECK(t.height() <= 40);
    area += long(t.width()) * t.height();
  }
  CHECK(area == 103L * 47L);
  CHECK(tiles.back().x1 == 103);
  CHECK(tiles.back().y1 == 47);
}

TEMPLATE_TEST_CASE_SIG("set packets hold only their set's pixels, as sub-grid neighbours", "[render][interleaving]",
                       ((int W), W), 1, 4, 8, 16, 64) {
  for (int interleave : {1, 2, 3, 5}) {
    // A region not aligned to the pattern, as a tile with its border is.
    const PixelRect region{-1 + 7, -1 + 3, 41 + 7, 33 + 3};
    std::set<std::pair<int, int>> seen;
    std::vector<PixelPacket<W>> packets;
    for (int set = 0; set < interleave * interleave; ++set) {
      make_set_packets<W>(region, interleave, set, packets);
      for (const PixelPacket<W>& p : packets) {
        REQUIRE(p.count >= 1);
        REQUIRE(p.count <= W);
        int min_x = p.x[0], max_x = p.x[0], min_y = p.y[0], max_y = p.y[0];
        for (int i = 0; i < p.count; ++i) {
          CHECK(interleaving_set(p.x[i], p.y[i], interleave) == set);
          CHECK(seen.insert({p.x[i], p.y[i]}).second);
          min_x = std::min(min_x, p.x[i]);
          max_x = std::max(max_x, p.x[i]);
          min_y = std::min(min_y, p.y[i]);
          max_y = std::max(max_y, p.y[i]);
        }
        // Neighbours in the sub-grid: the packet spans at most its shape times the stride.
        CHECK(max_x - min_x <= (PacketShape<W>::width - 1) * interleave);
        CHECK(max_y - min_y <= (PacketShape<W>::height - 1) * interleave);
      }
    }
    CHECK(long(seen.size()) == long(region.width()) * region.height());
  }
}

TEST_CASE("anti-aliasing sub-samples are stratified inside the pixel", "[render][interleaving]") {
  float dx = 0, dy = 0;
  subsample_offset(0, 1, dx, dy);
  CHECK(dx == 0.5f);
  CHECK(dy == 0.5f);
  std::set<std::pair<float, float>> offsets;
  for (int k = 0; k < 4; ++k) {
    subsample_offset(k, 4, dx, dy);
    CHECK(dx > 0.0f);
    CHECK(dx < 1.0f);
    CHECK(dy > 0.0f);
    CHECK(dy < 1.0f);
    offsets.insert({dx, dy});
  }
  CHECK(offsets.size() == 4);
}

TEST_CASE("tone mapping maps the log-average luminance to the key", "[render][tone]") {
  LuminanceStatistics tile_a, tile_b;
  for (int i = 0; i < 50; ++i) tile_a.add(glm::vec3(0.5f));
  for (int i = 0; i < 50; ++i) tile_b.add(glm::vec3(2.0f));
  LuminanceStatistics frame = tile_a;
  frame.merge(tile_b);
  // log-average of 0.5 and 2 (equal counts) is 1, up to Reinhard's delta.
  CHECK(frame.log_average() == Approx(1.0).epsilon(1e-3));
  CHECK(frame.max_luminance == Approx(2.0f));
  const ToneMapping t = ToneMapping::from(frame);
  CHECK(t.scale == Approx(ToneMapping::key).epsilon(1e-3));
  // Monotone, bounded, black stays black, chromaticity kept.
  CHECK(luminance(t.apply(glm::vec3(0.5f))) < luminance(t.apply(glm::vec3(2.0f))));
  CHECK(t.apply(glm::vec3(1e6f)).r <= 1.0f);
  CHECK(t.apply(glm::vec3(0.0f)) == glm::vec3(0.0f));
  const glm::vec3 red = t.apply(glm::vec3(1.0f, 0.25f, 0.0f));
  CHECK(red.g / red.r == Approx(0.25f));
  CHECK(quantize_srgb(glm::vec3(1.0f)) == glm::u8vec3(255));
  CHECK(quantize_srgb(glm::vec3(0.0f)) == glm::u8vec3(0));
  // sRGB of 0.5 linear is 0.7354 -> 188.
  CHECK(int(quantize_srgb(glm::vec3(0.5f)).r) == 188);
}

TEST_CASE("the luminance accumulator records what per-pixel statistics record, with one logarithm", "[render][tone]") {
  // A tile's worth of pixels over the whole range luminances take: black, dim, bright, a sun
  // disc near float's largest, and the values add() ignores (negative, NaN, infinite).
  Rng rng(7);
  LuminanceStatistics per_pixel;
  LuminanceAccumulator accumulated;
  double magnitudes = 0.0;  // sum of |log(delta + luminance)| over the counted pixels
  const float nan = std::numeric_limits<float>::quiet_NaN(), infinity = std::numeric_limits<float>::infinity();
  for (int i = 0; i < 20000; ++i) {
    glm::vec3 rgb(rng.next(), rng.next(), rng.next());
    rgb *= std::exp2(60.0f * rng.next() - 40.0f);  // 2^-40 .. 2^20
    if (i % 97 == 0) rgb = glm::vec3(0.0f);
    if (i % 101 == 0) rgb = glm::vec3(1e38f, 2e38f, 1e38f);
    if (i % 103 == 0) rgb = glm::vec3(-1.0f, 0.0f, 0.0f);
    if (i % 107 == 0) rgb = glm::vec3(nan, 1.0f, 1.0f);
    if (i % 109 == 0) rgb = glm::vec3(infinity);
    per_pixel.add(rgb);
    accumulated.add(rgb);
    const float y = luminance(rgb);
    if (std::isfinite(y) && y >= 0.0f) magnitudes += std::abs(std::log(LuminanceStatistics::delta + double(y)));
  }
  const LuminanceStatistics statistics = accumulated.statistics();
  CHECK(statistics.count == per_pixel.count);
  CHECK(statistics.count < 20000);  // the ignored values were ignored
  CHECK(statistics.max_luminance == per_pixel.max_luminance);
  // Summing n terms rounds by at most n x 2^-53 x (the sum of their magnitudes) (the textbook
  // bound of recursive summation), which covers both the per-pixel sum and the accumulator's
  // product (2^-53 per factor) and exponent sum; twice it bounds their difference.
  const double unit_roundoff = std::numeric_limits<double>::epsilon() / 2.0;
  const double bound = 2.0 * double(per_pixel.count) * unit_roundoff * (magnitudes + double(per_pixel.count));
  CHECK(std::abs(statistics.log_sum - per_pixel.log_sum) <= bound);
  // Which the tone mapping, rounding its parameters to float, cannot see.
  const ToneMapping a = ToneMapping::from(statistics), b = ToneMapping::from(per_pixel);
  CHECK(a.scale == b.scale);
  CHECK(a.white == b.white);
  // Nothing counted: the empty statistics.
  const LuminanceStatistics empty = LuminanceAccumulator().statistics();
  CHECK(empty.count == 0);
  CHECK(empty.log_sum == 0.0);
}
