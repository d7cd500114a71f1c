// igi/io/metrics.hpp against values computed by hand (the arithmetic is in the comments).

#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "igi/io/metrics.hpp"

using namespace igi;

namespace {

/// A grey checkerboard (x + y odd -> `high`, else `low`), all three channels equal.
Image checkerboard(int width, int height, float low, float high) {
  Image image(width, height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) image(x, y) = glm::vec3((x + y) % 2 ? high : low);
  return image;
}

// Grey pixels have luminance (0.2126 + 0.7152 + 0.0722) v = v, up to float rounding of the
// weighted sum (relative 2^-23); comparisons below allow 1e-6, well above that and well below
// the last digit written in the hand computations.
constexpr double hand_tolerance = 1e-6;

}  // namespace

TEST_CASE("metrics: RMSE and relMSE of a 2 x 1 image by hand", "[io][metrics]") {
  Image reference(2, 1), test(2, 1);
  reference(0, 0) = glm::vec3(0, 0, 0);
  reference(1, 0) = glm::vec3(1, 1, 1);
  test(0, 0) = glm::vec3(0.5f, 0, 0);
  test(1, 0) = glm::vec3(1, 1, 0);
  // Squared differences: 0.25, 0, 0 | 0, 0, 1 -> mean 1.25 / 6 = 0.2083333 -> RMSE 0.4564355.
  CHECK(rmse(test, reference) == Approx(0.4564355).epsilon(hand_tolerance));
  // relMSE terms: 0.25 / (0 + 0.01) = 25, 0, 0 | 0, 0, 1 / (1 + 0.01) = 0.990099
  // -> mean 25.990099 / 6 = 4.3316832.
  CHECK(relmse(test, reference) == Approx(4.3316832).epsilon(hand_tolerance));
  // With epsilon = 1: 0.25 / 1 + 1 / 2 = 0.75 -> 0.75 / 6 = 0.125.
  CHECK(relmse(test, reference, {.epsilon = 1.0}) == Approx(0.125).epsilon(hand_tolerance));
  // An image against itself: zero error.
  CHECK(rmse(reference, reference) == 0.0);
  CHECK(relmse(test, test) == 0.0);
  // Fewer than 1000 pixels: 0.1 % rounds down to no pixel, so the option changes nothing.
  CHECK(relmse(test, reference, {.ignore_brightest = true}) == relmse(test, reference));
}

TEST_CASE("metrics: relMSE can ignore the brightest 0.1 % of reference pixels", "[io][metrics]") {
  // 1000 x 1 image (k = floor(0.001 * 1000) = 1 pixel ignored). Reference 0.5 everywhere except
  // a light of 100 at x = 10; the test misses the light (0) and is 0.6 at x = 500.
  Image reference(1000, 1, glm::vec3(0.5f)), test(1000, 1, glm::vec3(0.5f));
  reference(10, 0) = glm::vec3(100.0f);
  test(10, 0) = glm::vec3(0.0f);
  test(500, 0) = glm::vec3(0.6f);
  // Light: 100^2 / (100^2 + 0.01) = 0.999999 per channel; x = 500: 0.01 / (0.25 + 0.01) =
  // 0.0384615 per channel. All pixels: 3 (0.999999 + 0.0384615) / 3000 = 0.00103846.
  CHECK(relmse(test, reference) == Approx(0.00103846).epsilon(1e-5));
  // Without the light: 3 * 0.0384615 / (3 * 999) = 3.85000e-5.
  CHECK(relmse(test, reference, {.ignore_brightest = true}) == Approx(3.85000e-5).epsilon(1e-5));

  // Brightness is the reference's luminance, not the channel sum: pure blue 100 (luminance 7.22)
  // loses to green 20 (luminance 14.304), which is the pixel left out.
  Image coloured_reference(1000, 1, glm::vec3(0.5f)), coloured_test(1000, 1, glm::vec3(0.5f));
  coloured_reference(0, 0) = glm::vec3(0, 0, 100);
  coloured_reference(1, 0) = glm::vec3(0, 20, 0);
  coloured_test(0, 0) = coloured_reference(0, 0);  // the blue pixel is exact
  coloured_test(1, 0) = glm::vec3(0, 0, 0);        // error only on the green pixel
  CHECK(relmse(coloured_test, coloured_reference, {.ignore_brightest = true}) == Approx(0.0).margin(1e-12));
  CHECK(relmse(coloured_test, coloured_reference) > 0.0);

  // Ties: of two equally bright pixels the later one (row-major) is left out.
  Image tied_reference(1000, 1, glm::vec3(0.5f)), tied_test(1000, 1, glm::vec3(0.5f));
  tied_reference(3, 0) = glm::vec3(9.0f);
  tied_reference(7, 0) = glm::vec3(9.0f);
  tied_test(3, 0) = glm::vec3(0.0f);  // error on the earlier one: kept
  // 81 / 81.01 = 0.999877 per channel, over 3 * 999 values: 0.999877 / 999 = 1.000878e-3.
  CHECK(relmse(tied_test, tied_reference, {.ignore_brightest = true}) == Approx(1.000878e-3).epsilon(1e-5));
}

TEST_CASE("metrics: SSIM of constant images by hand", "[io][metrics]") {
  // Constants a = 0.5 and b = 0.25: variances and covariance are 0, so the structure term is
  // C2 / C2 = 1 and SSIM = (2ab + C1) / (a^2 + b^2 + C1) = (0.25 + 0.0001) / (0.3125 + 0.0001)
  // = 0.2501 / 0.3126 = 0.8000640 for any window.
  const Image a(16, 12, glm::vec3(0.5f)), b(16, 12, glm::vec3(0.25f));
  CHECK(ssim(a, b) == Approx(0.8000640).epsilon(hand_tolerance));
  CHECK(ssim(a, b, SsimWindow::box8) == Approx(0.8000640).epsilon(hand_tolerance));
  CHECK(ssim(a, a) == Approx(1.0).epsilon(1e-12));
  // Black against black: (0 + C1)(0 + C2) / ((0 + C1)(0 + C2)) = 1, no division by zero.
  const Image black(11, 11, glm::vec3(0.0f));
  CHECK(ssim(black, black) == 1.0);
}

TEST_CASE("metrics: SSIM with an 8 x 8 box window by hand", "[io][metrics]") {
  // Reference: a 0/1 checkerboard. Every 8 x 8 window holds 32 zeros and 32 ones: mean 0.5,
  // variance 0.25.
  const Image reference = checkerboard(8, 8, 0.0f, 1.0f);
  // Offset by 0.1: covariance = variance = 0.25, so structure = 1, and
  // SSIM = (2 * 0.6 * 0.5 + 0.0001) / (0.36 + 0.25 + 0.0001) = 0.6001 / 0.6101 = 0.9836093.
  CHECK(ssim(checkerboard(8, 8, 0.1f, 1.1f), reference, SsimWindow::box8) == Approx(0.9836093).epsilon(hand_tolerance));
  // Inverted: same means (luminance term 1), covariance -0.25:
  // (-0.5 + 0.0009) / (0.5 + 0.0009) = -0.4991 / 0.5009 = -0.9964065.
  CHECK(ssim(checkerboard(8, 8, 1.0f, 0.0f), reference, SsimWindow::box8) == Approx(-0.9964065).epsilon(hand_tolerance));
  // Flat grey 0.5: means equal, test variance 0: C2 / (0.25 + C2) = 0.0009 / 0.2509 = 0.0035871.
  CHECK(ssim(Image(8, 8, glm::vec3(0.5f)), reference, SsimWindow::box8) == Approx(0.0035871).epsilon(1e-5));
  // 9 x 8: two window positions, both an 8 x 8 checkerboard: the mean is the same 0.9836093.
  CHECK(ssim(checkerboard(9, 8, 0.1f, 1.1f), checkerboard(9, 8, 0.0f, 1.0f), SsimWindow::box8) ==
        Approx(0.9836093).epsilon(hand_tolerance));
  // Windows that differ: 16 x 8 with columns 8..15 inverted. Every column holds four 0s and
  // four 1s, so both means are 0.5 in every window (luminance term 1), both variances 0.25. The
  // window at x0 = j (j = 0..8) holds j inverted columns: covariance 0.25 (8 - 2j) / 8, so
  // SSIM_j = ((8 - 2j) / 16 + 0.0009) / 0.5009. The (8 - 2j) sum to 0 over j = 0..8, so the mean
  // over the 9 windows is 0.0009 / 0.5009 = 0.0017968.
  Image half = checkerboard(16, 8, 0.0f, 1.0f);
  const Image half_reference = half;
  for (int y = 0; y < 8; ++y)
    for (int x = 8; x < 16; ++x) half(x, y) = glm::vec3(1.0f) - half(x, y);
  CHECK(ssim(half, half_reference, SsimWindow::box8) == Approx(0.0017968).epsilon(1e-4));
}

TEST_CASE("metrics: SSIM with the 11 x 11 Gaussian window by hand", "[io][metrics]") {
  // Reference: 0.75 left of the centre column, 0.25 right of it, 0.5 on it. The Gaussian is
  // symmetric, so the weighted mean is exactly 0.5 whatever the weights.
  Image reference(11, 11);
  for (int y = 0; y < 11; ++y)
    for (int x = 0; x < 11; ++x) reference(x, y) = glm::vec3(x < 5 ? 0.75f : x > 5 ? 0.25f : 0.5f);
  // Offset by 0.1: structure term 1, luminance term (2 * 0.6 * 0.5 + 0.0001) / (0.36 + 0.25 +
  // 0.0001) = 0.9836093, as for the box window.
  Image offset = reference;
  for (auto& p : offset.pixels) p += glm::vec3(0.1f);
  CHECK(ssim(offset, reference) == Approx(0.9836093).epsilon(hand_tolerance));
  // Mirrored about 0.5 (1 - reference): luminance term 1; variance 0.0625 (1 - w5) where w5 is
  // the centre column's weight 1 / sum_{i=-5..5} exp(-i^2 / 4.5) = 1 / 3.758737 = 0.266047:
  // variance 0.0458721, covariance -0.0458721; structure (-0.0917442 + 0.0009) /
  // (0.0917442 + 0.0009) = -0.0908442 / 0.0926442 = -0.980571.
  Image mirrored = reference;
  for (auto& p : mirrored.pixels) p = glm::vec3(1.0f) - p;
  CHECK(ssim(mirrored, reference) == Approx(-0.980571).epsilon(1e-5));
}

TEST_CASE("metrics: mismatched, empty, non-finite and too small inputs are rejected", "[io][metrics]") {
  const Image a(12, 12, glm::vec3(0.5f)), b(12, 11, glm::vec3(0.5f));
  CHECK_THROWS_WITH(rmse(a, b), Catch::Contains("12 x 12") && Catch::Contains("12 x 11"));
  CHECK_THROWS_AS(relmse(a, b), std::invalid_argument);
  CHECK_THROWS_AS(ssim(a, b), std::invalid_argument);
  CHECK_THROWS_WITH(rmse(Image(), Image()), Catch::Contains("empty"));
  Image with_nan = a;
  with_nan(3, 4).b = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(relmse(with_nan, a), Catch::Contains("test pixel (3, 4) is not finite"));
  CHECK_THROWS_WITH(ssim(a, with_nan), Catch::Contains("reference pixel (3, 4) is not finite"));
  CHECK_THROWS_WITH(relmse(a, a, {.epsilon = 0.0}), Catch::Contains("epsilon"));
  const Image small(10, 20, glm::vec3(0.5f));
  CHECK_THROWS_WITH(ssim(small, small), Catch::Contains("smaller than the 11 x 11 window"));
  CHECK(ssim(small, small, SsimWindow::box8) == Approx(1.0).epsilon(1e-12));
}
