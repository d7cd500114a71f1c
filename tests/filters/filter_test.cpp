// Filters on synthetic G-buffers: the discontinuity buffer keeps edges, removes the interleaving
// pattern; the box filter blurs across edges; bad input is an error.

#include <cmath>
#include <cstdio>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/filters/tile_filters.hpp"

using namespace igi;

namespace {

// The irradiance factor of interleaving set (x mod S, y mod S): a fixed pattern of mean 1,
// what S^2 different VPL sets leave on a flat wall.
float pattern(int x, int y, int s) {
  static const float factors[9] = {0.2f, 1.9f, 0.7f, 1.4f, 0.4f, 1.1f, 1.6f, 0.3f, 1.4f};
  if (s == 3) return factors[(y % 3) * 3 + (x % 3)];
  return ((x + y) % 2 == 0) ? 0.5f : 1.5f;  // S = 2: a checkerboard of mean 1
}

// A G-buffer of w x h interior pixels plus a border of 1, all hit, normal +z, depth 10.
TileGBuffer wall(int w, int h) {
  TileGBuffer g;
  g.border = 1;
  g.resize(w + 2, h + 2);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = g.index(x, y);
      g.hit[i] = 1;
      g.normal[i] = {0, 0, 1};
      g.depth[i] = 10.0f;
      g.albedo[i] = glm::vec3(0.5f);
    }
  return g;
}

// Variance of the red channel over a set of values.
double variance(const std::vector<glm::vec3>& values) {
  double sum = 0.0, sum2 = 0.0;
  for (const glm::vec3& v : values) {
    sum += v.x;
    sum2 += double(v.x) * v.x;
  }
  const double mean = sum / double(values.size());
  return sum2 / double(values.size()) - mean * mean;
}

std::vector<glm::vec3> interior(const TileGBuffer& g) {
  std::vector<glm::vec3> out;
  for (int y = g.border; y < g.height - g.border; ++y)
    for (int x = g.border; x < g.width - g.border; ++x) out.push_back(g.irradiance[g.index(x, y)]);
  return out;
}

}  // namespace

TEST_CASE("filters: all three satisfy the Filter concept", "[filters]") {
  STATIC_REQUIRE(Filter<DiscontinuityFilter>);
  STATIC_REQUIRE(Filter<BoxFilter>);
  STATIC_REQUIRE(Filter<NoFilter>);
}

TEST_CASE("filters: the 3x3 interleaving pattern on a flat wall is removed", "[filters]") {
  for (const int s : {2, 3}) {
    INFO("S = " << s);
    TileGBuffer g = wall(12, 12);
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) g.irradiance[g.index(x, y)] = glm::vec3(2.0f * pattern(x, y, s));
    FilteredTile out;
    DiscontinuityFilter{}.apply(g, s, out);
    REQUIRE(out.width == 12);
    REQUIRE(out.height == 12);
    const double before = variance(interior(g)), after = variance(out.irradiance);
    std::printf("interleaving pattern S=%d: irradiance variance before %.4f, after discontinuity filter %.3g\n", s,
                before, after);
    CHECK(before > 0.5);
    // Every window holds each set once, so every output is the exact pattern mean 2, up to
    // float rounding of a 9-term sum.
    CHECK(after < 1e-10);
    for (const glm::vec3& v : out.irradiance) CHECK(v.x == Approx(2.0f).epsilon(1e-6));
    // The unfiltered copy keeps the pattern.
    NoFilter{}.apply(g, s, out);
    CHECK(variance(out.irradiance) == Approx(before));
  }
}

TEST_CASE("filters: on a depth step no irradiance crosses the edge; the box filter blurs it", "[filters]") {
  // Left half at depth 10 with irradiance 1, right half at depth 20 (same normal) with
  // irradiance 5, both modulated by the interleaving pattern.
  TileGBuffer g = wall(12, 6);
  const int edge = 7;  // buffer columns < 7 are near
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const bool near = x < edge;
      g.depth[g.index(x, y)] = near ? 10.0f : 20.0f;
      g.irradiance[g.index(x, y)] = glm::vec3((near ? 1.0f : 5.0f) * pattern(x, y, 3));
    }
  FilteredTile out;
  DiscontinuityFilter{}.apply(g, 3, out);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const int bx = x + 1, by = y + 1;
      const bool near = bx < edge;
      // The expected value averages only same-side neighbours of the window.
      float sum = 0.0f;
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if ((bx + dx < edge) == near) {
            sum += g.irradiance[g.index(bx + dx, by + dy)].x;
            ++count;
          }
      INFO("pixel " << x << ", " << y);
      CHECK(out.irradiance[std::size_t(y * out.width + x)].x == Approx(sum / float(count)).epsilon(1e-6));
    }
  // Near pixels next to the edge never see the far side's 5x brighter light: bounded by the
  // near side's largest pattern value.
  for (int y = 0; y < out.height; ++y) CHECK(out.irradiance[std::size_t(y * out.width + (edge - 2))].x <= 1.9f);

  // The box filter mixes the far side in: the same pixels get brighter than any near value.
  BoxFilter{}.apply(g, 3, out);
  int crossed = 0;
  for (int y = 0; y < out.height; ++y)
    if (out.irradiance[std::size_t(y * out.width + (edge - 2))].x > 1.9f) ++crossed;
  CHECK(crossed == out.height);
}

TEST_CASE("filters: creases, misses and depth tolerance", "[filters]") {
  TileGBuffer g = wall(5, 5);
  for (std::size_t i = 0; i < g.irradiance.size(); ++i) g.irradiance[i] = glm::vec3(1.0f);
  // Column 4 of the buffer is a wall at 90 degrees with irradiance 9; pixel (2, 2) missed.
  for (int y = 0; y < g.height; ++y) {
    g.normal[g.index(4, y)] = {1, 0, 0};
    g.irradiance[g.index(4, y)] = glm::vec3(9.0f);
  }
  const std::size_t missed = g.index(2, 2);
  g.hit[missed] = 0;
  g.normal[missed] = glm::vec3(0.0f);
  g.depth[missed] = 0.0f;
  g.irradiance[missed] = glm::vec3(100.0f);
  // Pixel (1, 1) is 3% deeper: within the 5% threshold, still averaged.
  g.depth[g.index(1, 1)] = 10.3f;
  g.irradiance[g.index(1, 1)] = glm::vec3(4.0f);
  FilteredTile out;
  DiscontinuityFilter{}.apply(g, 3, out);
  const auto at = [&](int x, int y) { return out.irradiance[std::size_t((y - 1) * out.width + (x - 1))].x; };
  CHECK(at(2, 2) == 0.0f);                    // a miss gets nothing
  CHECK(at(3, 3) == Approx(1.0f));            // ignores the crease column and the miss
  CHECK(at(2, 1) == Approx((4.0f + 7.0f) / 8.0f));  // 8 hits around, one of them 4 (the 3% deeper one)
  // A tighter depth threshold (2%) excludes the deeper pixel.
  DiscontinuityFilter tight(DiscontinuitySettings{.max_relative_depth = 0.02f});
  tight.apply(g, 3, out);
  CHECK(at(2, 1) == Approx(1.0f));
  CHECK(at(1, 1) == Approx(4.0f));  // alone on its depth
}

TEST_CASE("filters: bad input is an error with a message", "[filters]") {
  TileGBuffer g = wall(4, 4);
  FilteredTile out;
  CHECK_THROWS_WITH(DiscontinuityFilter{}.apply(g, 0, out), Catch::Contains("interleave"));
  g.depth.pop_back();
  CHECK_THROWS_WITH(BoxFilter{}.apply(g, 3, out), Catch::Contains("width x height"));
  g = wall(4, 4);
  g.border = 4;
  CHECK_THROWS_WITH(NoFilter{}.apply(g, 3, out), Catch::Contains("border"));
  CHECK_THROWS_AS(DiscontinuityFilter(DiscontinuitySettings{.max_normal_angle = -1.0f}), std::invalid_argument);
}
