// Filters on synthetic G-buffers. Every filter of policy_lists.hpp is run through the properties
// every filter must have (no NaN, partial tiles, input checks, the interleaving pattern, depth
// edges), each excepting by name only the filters that lack it by design; then the discontinuity
// filter's exact averages, creases, misses and depth tolerance.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <thread>
#include <type_traits>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/filters/atrous_filter.hpp"
#include "igi/filters/tile_filters.hpp"
#include "policy_lists.hpp"

using namespace igi;

namespace {

// The irradiance factor of interleaving set (x mod S, y mod S): a fixed pattern of mean 1,
// what S^2 different VPL sets leave on a flat wall.
float pattern(int x, int y, int s) {
  static const float factors[9] = {0.2f, 1.9f, 0.7f, 1.4f, 0.4f, 1.1f, 1.6f, 0.3f, 1.4f};
  if (s == 3) return factors[(y % 3) * 3 + (x % 3)];
  return ((x + y) % 2 == 0) ? 0.5f : 1.5f;  // S = 2: a checkerboard of mean 1
}

// Makes pixel i of `g` a hit on a wall facing the camera: normal +z, depth 10, albedo 0.5.
void set_wall_pixel(TileGBuffer& g, std::size_t i) {
  g.hit[i] = 1;
  g.normal[i] = {0, 0, 1};
  g.depth[i] = 10.0f;
  g.albedo[i] = glm::vec3(0.5f);
}

// A G-buffer of w x h interior pixels plus a border of `border` pixels, all wall pixels.
TileGBuffer wall(int w, int h, int border = 1) {
  TileGBuffer g;
  g.border = border;
  g.resize(w + 2 * border, h + 2 * border);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) set_wall_pixel(g, g.index(x, y));
  return g;
}

// Variance of the red channel over a set of values.
double variance(const Vec3Plane& planes) {
  const std::vector<glm::vec3> values = planes.to_vector();
  double sum = 0.0, sum2 = 0.0;
  for (const glm::vec3& v : values) {
    sum += v.x;
    sum2 += double(v.x) * v.x;
  }
  const double mean = sum / double(values.size());
  return sum2 / double(values.size()) - mean * mean;
}

Vec3Plane interior(const TileGBuffer& g) {
  Vec3Plane out;
  out.assign(std::size_t(g.width - 2 * g.border) * std::size_t(g.height - 2 * g.border));
  std::size_t at = 0;
  for (int y = g.border; y < g.height - g.border; ++y)
    for (int x = g.border; x < g.width - g.border; ++x) out[at++] = g.irradiance[g.index(x, y)];
  return out;
}

}  // namespace

TEMPLATE_TEST_CASE("filters: every filter satisfies the Filter concept", "[filters]", IGI_ALL_FILTERS) {
  STATIC_REQUIRE(Filter<TestType>);
}

TEMPLATE_TEST_CASE("filters: the interleaving pattern on a flat wall is removed, except by the unfiltered copy",
                   "[filters]", IGI_ALL_FILTERS) {
  for (const int s : {2, 3}) {
    INFO(TestType::name() << ", S = " << s);
    // With the border the pipeline renders for this filter, as in an image.
    TileGBuffer g = wall(12, 12, TestType{}.border(s));
    for (int y = 0; y < g.height; ++y)
      for (int x = 0; x < g.width; ++x) g.irradiance[g.index(x, y)] = glm::vec3(2.0f * pattern(x, y, s));
    FilteredTile out;
    TestType{}.apply(g, s, out);
    REQUIRE(out.width == 12);
    REQUIRE(out.height == 12);
    const double before = variance(interior(g)), after = variance(out.irradiance);
    std::printf("interleaving pattern S=%d: irradiance variance before %.4f, after %s %.3g\n", s, before,
                TestType::name(), after);
    CHECK(before > 0.5);
    if constexpr (std::is_same_v<TestType, NoFilter>) {
      // The unfiltered copy is the reference that shows the pattern: it must keep it.
      CHECK(after == Approx(before));
    } else {
      // Every S x S window holds each set once, so every output is the exact pattern mean 2, up
      // to float rounding of a 9-term sum.
      CHECK(after < 1e-10);
      for (const glm::vec3& v : out.irradiance.to_vector()) CHECK(v.x == Approx(2.0f).epsilon(1e-6));
    }
  }
}


namespace {

/// Buffer columns below this are the near side of depth_step().
constexpr int depth_step_edge = 7;

/// A 12 x 6 wall whose buffer columns < depth_step_edge lie at depth 10 with irradiance 1 and
/// the rest at depth 20 (same normal) with irradiance 5, both modulated by the 3x3 pattern.
TileGBuffer depth_step() {
  TileGBuffer g = wall(12, 6);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const bool near = x < depth_step_edge;
      g.depth[g.index(x, y)] = near ? 10.0f : 20.0f;
      g.irradiance[g.index(x, y)] = glm::vec3((near ? 1.0f : 5.0f) * pattern(x, y, 3));
    }
  return g;
}

}  // namespace

TEMPLATE_TEST_CASE("filters: on a depth step no irradiance crosses the edge, except through the box filter",
                   "[filters]", IGI_ALL_FILTERS) {
  const TileGBuffer g = depth_step();
  FilteredTile out;
  TestType{}.apply(g, 3, out);
  // The near pixels next to the edge: 1.9 is the largest pattern value, so the brightest any of
  // them can be from near light alone; the far side is 5x brighter.
  int crossed = 0;
  for (int y = 0; y < out.height; ++y)
    if (out.irradiance.x[std::size_t(y * out.width + (depth_step_edge - 2))] > 1.9f) ++crossed;
  INFO(TestType::name());
  if constexpr (std::is_same_v<TestType, BoxFilter>) {
    // The box filter averages across any edge by design (it shows what the surface test of the
    // discontinuity filter is for): every row leaks.
    CHECK(crossed == out.height);
  } else {
    CHECK(crossed == 0);
    // And no near pixel anywhere takes more than the near side's brightest value, nor a far pixel
    // less than the far side's darkest (5 x 0.2).
    for (int y = 0; y < out.height; ++y)
      for (int x = 0; x < out.width; ++x) {
        const float value = out.irradiance.x[std::size_t(y * out.width + x)];
        INFO("pixel " << x << ", " << y);
        if (x + g.border < depth_step_edge) {
          CHECK(value <= 1.9f);
        } else {
          CHECK(value >= 1.0f);
        }
      }
  }
}

TEMPLATE_TEST_CASE("filters: misses, broken normals and depths and huge values give finite output", "[filters]",
                   IGI_ALL_FILTERS) {
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr float infinity = std::numeric_limits<float>::infinity();
  TileGBuffer g = wall(9, 9);
  for (int y = 0; y < g.height; ++y)
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = g.index(x, y);
      g.irradiance[i] = glm::vec3(1e30f * float((x + y) % 3));  // large but finite; sums stay below float max
      g.glossy[i] = glm::vec3(0.5f);
      // Every pixel gets one defect, in turn: a miss (zeros, as the pipeline writes), a zero,
      // NaN or infinite normal, a zero, NaN, infinite or negative depth, or none.
      switch ((x + 3 * y) % 9) {
        case 0: g.hit[i] = 0; g.normal[i] = glm::vec3(0.0f); g.depth[i] = 0.0f; g.irradiance[i] = glm::vec3(0.0f); break;
        case 1: g.normal[i] = glm::vec3(0.0f); break;
        case 2: g.normal[i] = glm::vec3(nan); break;
        case 3: g.normal[i] = glm::vec3(infinity, 0.0f, 0.0f); break;
        case 4: g.depth[i] = 0.0f; break;
        case 5: g.depth[i] = nan; break;
        case 6: g.depth[i] = infinity; break;
        case 7: g.depth[i] = -10.0f; break;
        default: break;
      }
    }
  for (const int s : {1, 2, 3, 4}) {
    INFO(TestType::name() << ", S = " << s);
    FilteredTile out;
    TestType{}.apply(g, s, out);
    REQUIRE(out.irradiance.size() == 81);
    for (std::size_t i = 0; i < out.irradiance.size(); ++i) {
      INFO("pixel " << i);
      CHECK(std::isfinite(out.irradiance.x[i]));
      CHECK(std::isfinite(out.glossy.x[i]));
    }
  }
}

TEMPLATE_TEST_CASE("filters: partial tiles at the image's corner keep their size and a constant wall's value",
                   "[filters]", IGI_ALL_FILTERS) {
  // A tile cut by the image's right and bottom edge: the pipeline gives the filter a G-buffer of
  // the interior plus `border` pixels per side, where the right and bottom border lie outside the
  // image (zeros: no hit). On a wall of constant irradiance 3 every filter must return 3 wherever
  // its window sees only pixels inside the image.
  for (const int s : {1, 2, 3, 4}) {
    const int border = TestType{}.border(s);  // what the pipeline renders around a tile for this filter
    for (const glm::ivec2 size : {glm::ivec2(1, 1), glm::ivec2(7, 3), glm::ivec2(2, 5), glm::ivec2(40, 1)}) {
      INFO(TestType::name() << ", S = " << s << ", interior " << size.x << " x " << size.y);
      TileGBuffer g;
      g.border = border;
      g.resize(size.x + 2 * border, size.y + 2 * border);
      for (int y = 0; y < g.height; ++y)
        for (int x = 0; x < g.width; ++x) {
          if (x >= border + size.x || y >= border + size.y) continue;  // outside the image
          set_wall_pixel(g, g.index(x, y));
          g.irradiance[g.index(x, y)] = glm::vec3(3.0f);
        }
      FilteredTile out;
      TestType{}.apply(g, s, out);
      REQUIRE(out.width == size.x);
      REQUIRE(out.height == size.y);
      REQUIRE(out.irradiance.size() == std::size_t(size.x) * std::size_t(size.y));
      const int high = s - 1 - s / 2;  // the window's reach right and down
      for (int y = 0; y < size.y; ++y)
        for (int x = 0; x < size.x; ++x) {
          const float value = out.irradiance.x[std::size_t(y * size.x + x)];
          INFO("pixel " << x << ", " << y);
          CHECK(std::isfinite(value));
          const bool window_inside = x + high < size.x && y + high < size.y;
          if constexpr (std::is_same_v<TestType, BoxFilter>) {
            // The box filter counts missed pixels as zeros by design: its value is only bounded
            // where the window reaches outside the image.
            if (window_inside) {
              CHECK(value == Approx(3.0f).epsilon(1e-6));
            } else {
              CHECK(value <= 3.0f * (1.0f + 1e-6f));
            }
          } else {
            CHECK(value == Approx(3.0f).epsilon(1e-6));
          }
        }
    }
  }
}

TEMPLATE_TEST_CASE("filters: bad input is an error with a message", "[filters]", IGI_ALL_FILTERS) {
  INFO(TestType::name());
  TileGBuffer g = wall(4, 4);
  FilteredTile out;
  CHECK_THROWS_WITH(TestType{}.apply(g, 0, out), Catch::Contains("interleave"));
  g.depth.assign(g.depth.size() - 1);
  CHECK_THROWS_WITH(TestType{}.apply(g, 3, out), Catch::Contains("width x height"));
  g = wall(4, 4);
  g.border = 4;
  CHECK_THROWS_WITH(TestType{}.apply(g, 3, out), Catch::Contains("border"));
}

TEST_CASE("filters: the discontinuity filter averages exactly the same-side neighbours of a depth step", "[filters]") {
  const TileGBuffer g = depth_step();
  FilteredTile out;
  DiscontinuityFilter{}.apply(g, 3, out);
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; ++x) {
      const int bx = x + 1, by = y + 1;
      const bool near = bx < depth_step_edge;
      // The expected value averages only same-side neighbours of the window.
      float sum = 0.0f;
      int count = 0;
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx)
          if ((bx + dx < depth_step_edge) == near) {
            sum += g.irradiance.x[g.index(bx + dx, by + dy)];
            ++count;
          }
      INFO("pixel " << x << ", " << y);
      CHECK(out.irradiance.x[std::size_t(y * out.width + x)] == Approx(sum / float(count)).epsilon(1e-6));
    }
}

TEST_CASE("filters: creases, misses and depth tolerance", "[filters]") {
  TileGBuffer g = wall(5, 5);
  g.irradiance.assign(g.irradiance.size(), glm::vec3(1.0f));
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
  const auto at = [&](int x, int y) { return out.irradiance.x[std::size_t((y - 1) * out.width + (x - 1))]; };
  CHECK(at(2, 2) == 0.0f);                    // a miss gets nothing
  CHECK(at(3, 3) == Approx(1.0f));            // ignores the crease column and the miss
  CHECK(at(2, 1) == Approx((4.0f + 7.0f) / 8.0f));  // 8 hits around, one of them 4 (the 3% deeper one)
  // A tighter depth threshold (2%) excludes the deeper pixel.
  DiscontinuityFilter tight(DiscontinuitySettings{.max_relative_depth = 0.02f});
  tight.apply(g, 3, out);
  CHECK(at(2, 1) == Approx(1.0f));
  CHECK(at(1, 1) == Approx(4.0f));  // alone on its depth
}

TEST_CASE("filters: a negative discontinuity threshold is an error", "[filters]") {
  CHECK_THROWS_AS(DiscontinuityFilter(DiscontinuitySettings{.max_normal_angle = -1.0f}), std::invalid_argument);
}

namespace {

/// A 24 x 24 wall with the border AtrousFilter needs at S = 3, each pixel's irradiance 2 times a
/// pseudo-random factor in [0.5, 1.5): noise of every frequency, as VPL sets leave where they
/// disagree.
TileGBuffer noisy_wall() {
  TileGBuffer g = wall(24, 24, AtrousFilter{}.border(3));
  std::uint32_t state = 12345u;
  for (std::size_t i = 0; i < g.irradiance.size(); ++i) {
    state = state * 1664525u + 1013904223u;  // a linear congruential generator: fixed, portable noise
    g.irradiance[i] = glm::vec3(2.0f * (0.5f + float(state >> 8) / float(1u << 24)));
  }
  return g;
}

}  // namespace

TEST_CASE("filters: AtrousFilter without passes is the discontinuity buffer, bit for bit", "[filters]") {
  TileGBuffer g = noisy_wall();
  // A crease and a depth step so that the surface test matters.
  for (int y = 0; y < g.height; ++y) {
    g.normal[g.index(9, y)] = {1, 0, 0};
    for (int x = 15; x < g.width; ++x) g.depth[g.index(x, y)] = 13.0f;
  }
  FilteredTile window, atrous;
  DiscontinuityFilter{}.apply(g, 3, window);
  AtrousFilter(AtrousSettings{.passes = 0}).apply(g, 3, atrous);
  CHECK(atrous.irradiance.to_vector() == window.irradiance.to_vector());
  CHECK(atrous.glossy.to_vector() == window.glossy.to_vector());
}

TEST_CASE("filters: AtrousFilter smooths the noise the S x S window leaves on a flat wall", "[filters]") {
  const TileGBuffer g = noisy_wall();
  FilteredTile window, atrous;
  DiscontinuityFilter{}.apply(g, 3, window);
  AtrousFilter{}.apply(g, 3, atrous);
  const double before = variance(interior(g)), after_window = variance(window.irradiance),
               after_atrous = variance(atrous.irradiance);
  std::printf("noisy wall: irradiance variance %.4f, after the window %.5f, after atrous %.5f\n", before,
              after_window, after_atrous);
  // The window averages 9 pixels (variance / 9); three more passes, each averaging about 9
  // correlated neighbours, must take off at least half of what is left.
  CHECK(after_window < before / 5.0);
  CHECK(after_atrous < after_window / 2.0);
}

TEST_CASE("filters: AtrousFilter's output does not depend on the tiles its thread filtered before", "[filters]") {
  // Its per-thread stage buffers are kept between tiles of one size and not cleared, so this
  // holds only if every stage writes all that the next one reads.
  TileGBuffer g = noisy_wall();
  for (int y = 0; y < g.height; ++y) {
    g.normal[g.index(9, y)] = {1, 0, 0};
    for (int x = 15; x < g.width; ++x) g.depth[g.index(x, y)] = 13.0f;
    for (int x = 0; x < 12; ++x) g.glossy[g.index(x, y)] = glm::vec3(0.1f * float((x + 3 * y) % 7));
  }
  for (int y = 12; y < 14; ++y)  // two rows of misses: sky seen through the wall
    for (int x = 0; x < g.width; ++x) {
      const std::size_t i = g.index(x, y);
      g.hit[i] = 0;
      g.normal[i] = {0, 0, 0};
      g.depth[i] = 0.0f;
      g.irradiance[i] = g.glossy[i] = glm::vec3(0.0f);
    }
  const AtrousFilter filter;
  FilteredTile fresh;
  std::thread([&] { filter.apply(g, 3, fresh); }).join();  // a new thread's buffers have seen nothing
  // A wall of the same size whose radiance is NaN everywhere leaves NaN in the stages wherever
  // the next tile's stages do not write.
  TileGBuffer poison = wall(24, 24, filter.border(3));
  for (Vec3Plane* planes : {&poison.irradiance, &poison.glossy})
    for (std::size_t i = 0; i < planes->size(); ++i) (*planes)[i] = glm::vec3(std::numeric_limits<float>::quiet_NaN());
  FilteredTile poisoned, after;
  filter.apply(poison, 3, poisoned);
  filter.apply(g, 3, after);
  CHECK(after.irradiance.to_vector() == fresh.irradiance.to_vector());
  CHECK(after.glossy.to_vector() == fresh.glossy.to_vector());
  // And the same on the diffuse path (no glossy radiance in the tile).
  for (std::size_t i = 0; i < g.glossy.size(); ++i) g.glossy[i] = glm::vec3(0.0f);
  std::thread([&] { filter.apply(g, 3, fresh); }).join();
  filter.apply(poison, 3, poisoned);
  filter.apply(g, 3, after);
  CHECK(after.irradiance.to_vector() == fresh.irradiance.to_vector());
  for (const glm::vec3& v : after.irradiance.to_vector()) REQUIRE(std::isfinite(v.x + v.y + v.z));
}

TEST_CASE("filters: AtrousFilter settings out of range are an error", "[filters]") {
  CHECK_THROWS_AS(AtrousFilter(AtrousSettings{.passes = -1}), std::invalid_argument);
  CHECK_THROWS_AS(AtrousFilter(AtrousSettings{.passes = AtrousFilter::max_passes + 1}), std::invalid_argument);
  CHECK_THROWS_AS(AtrousFilter(AtrousSettings{.luminance_sigma = 0.0f}), std::invalid_argument);
  CHECK_THROWS_AS(AtrousFilter(AtrousSettings{.depth_sigma = std::numeric_limits<float>::quiet_NaN()}),
                  std::invalid_argument);
  CHECK_THROWS_AS(AtrousFilter(AtrousSettings{.albedo_sigma = -1.0f}), std::invalid_argument);
  CHECK_THROWS_AS(AtrousFilter(AtrousSettings{.window = {.max_normal_angle = -1.0f}}), std::invalid_argument);
  // Its border grows with the passes' steps: S/2 + 1 + 2 + ... + 2^(passes-1).
  CHECK(AtrousFilter(AtrousSettings{.passes = 0}).border(3) == 1);
  CHECK(AtrousFilter(AtrousSettings{.passes = 3}).border(3) == 8);
  CHECK(AtrousFilter(AtrousSettings{.passes = 2}).border(4) == 5);
}

TEST_CASE("filters: the G-buffer's planes read and write like arrays of vec3 and carry their padding", "[filters]") {
  TileGBuffer g;
  g.resize(5, 3);
  REQUIRE(g.normal.size() == 15);
  g.normal[g.index(4, 2)] = glm::vec3(1.0f, 2.0f, 3.0f);
  g.normal[g.index(4, 2)] += glm::vec3(0.5f);
  const TileGBuffer& read = g;
  CHECK(read.normal[14] == glm::vec3(1.5f, 2.5f, 3.5f));
  // Structure of arrays: one plane per component, pixel after pixel.
  CHECK(g.normal.x.data()[14] == 1.5f);
  CHECK(g.normal.z.data()[14] == 3.5f);
  // A row read of the widest packet from the last pixel on, or ending at the first, stays in
  // the plane's allocation (the padding is zeros after resize).
  CHECK(g.depth.data()[14 + PixelPlane::padding] == 0.0f);
  CHECK(g.depth.data()[-std::ptrdiff_t(PixelPlane::padding)] == 0.0f);
  CHECK(g.normal.to_vector().size() == 15);
}

TEST_CASE("filters: the à-trous weights' exponential and normal term hold their documented accuracy", "[filters]") {
  constexpr int W = filter_detail::row_lanes;
  // e^-t to a relative error below 4e-6 on [0, 87), over a sweep fine enough to cross every
  // rounding step of n = round(t log2 e) in it (87000 x 0.001f rounds above 87: not swept), with
  // multiply-adds fused or not (the debug build fuses none: there u computed from the rounded
  // t log2 e, before Cody and Waite's split of ln2, reached 5.1e-6).
  double worst = 0.0;
  for (int i = 0; i < 87 * 1000; i += W) {
    const vfloat<W> t([&](int lane) { return float(i + lane) * 0.001f; });
    const vfloat<W> e = filter_detail::exp_negative(t);
    for (int lane = 0; lane < W && i + lane < 87 * 1000; ++lane) {
      const double exact = std::exp(-double(t[lane]));
      worst = std::max(worst, std::abs(double(e[lane]) - exact) / exact);
    }
  }
  std::printf("exp_negative: worst relative error on [0, 87] %.3g\n", worst);
  CHECK(worst < 4e-6);
  // Zero past 87 (beyond the smallest normal float), for infinity and NaN; 1 for t <= 0.
  const float nan = std::numeric_limits<float>::quiet_NaN(), infinity = std::numeric_limits<float>::infinity();
  for (const float t : {87.5f, 1000.0f, infinity, nan}) CHECK(filter_detail::exp_negative(vfloat<W>(t))[0] == 0.0f);
  for (const float t : {0.0f, -0.0f, -3.0f}) CHECK(filter_detail::exp_negative(vfloat<W>(t))[0] == 1.0f);

  // e^-(128 (1 - cos)) against SVGF's cos^128: within 0.1% at 5 degrees and 1.6% at 10, below
  // 1e-5 from 25 degrees on and 0 for back-facing normals; NaN normals weigh 0.
  const auto weight = [](float degrees) {
    const float angle = degrees * float(std::numbers::pi / 180.0);
    const vec3<W> n(glm::vec3(0, 0, 1)), m(glm::vec3(std::sin(angle), 0, std::cos(angle)));
    return double(filter_detail::exp_negative(filter_detail::normal_exponent(n, m))[0]);
  };
  const auto svgf = [](float degrees) { return std::pow(std::cos(double(degrees) * std::numbers::pi / 180.0), 128.0); };
  CHECK(weight(0.0f) == Approx(1.0).epsilon(1e-6));
  CHECK(weight(5.0f) == Approx(svgf(5.0f)).epsilon(0.001));
  CHECK(weight(10.0f) == Approx(svgf(10.0f)).epsilon(0.016));
  for (const float degrees : {25.0f, 40.0f, 89.0f}) CHECK(weight(degrees) < 1e-5);
  for (const float degrees : {91.0f, 180.0f}) CHECK(weight(degrees) == 0.0);
  const vec3<W> broken(glm::vec3(nan, 0, 1)), up(glm::vec3(0, 0, 1));
  CHECK(filter_detail::exp_negative(filter_detail::normal_exponent(broken, up))[0] == 0.0f);
}
