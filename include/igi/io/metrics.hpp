#pragma once
/// \file
/// Image error metrics against a reference: RMSE, relMSE (with an option to ignore the brightest
/// pixels) and SSIM. Every metric checks that the images match in size and are finite, and
/// throws std::invalid_argument naming the problem otherwise.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "igi/io/srgb.hpp"

namespace igi {

namespace detail {
/// Throws unless `test` and `reference` are non-empty, equally sized and finite.
inline void check_metric_inputs(const char* metric, const Image& test, const Image& reference) {
  auto describe = [](const Image& image) { return std::to_string(image.width) + " x " + std::to_string(image.height); };
  for (const Image* image : {&test, &reference})
    if (image->width <= 0 || image->height <= 0 ||
        image->pixels.size() != static_cast<std::size_t>(image->width) * static_cast<std::size_t>(image->height))
      throw std::invalid_argument(std::string(metric) + ": " + (image == &test ? "test" : "reference") + " image (" +
                                  describe(*image) + ", " + std::to_string(image->pixels.size()) +
                                  " pixels) is empty or inconsistent");
  if (test.width != reference.width || test.height != reference.height)
    throw std::invalid_argument(std::string(metric) + ": test image is " + describe(test) + " but the reference is " +
                                describe(reference));
  for (const Image* image : {&test, &reference})
    for (std::size_t i = 0; i < image->pixels.size(); ++i) {
      const glm::vec3& p = image->pixels[i];
      if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) {
        std::ostringstream message;
        message << metric << ": " << (image == &test ? "test" : "reference") << " pixel ("
                << i % static_cast<std::size_t>(image->width) << ", " << i / static_cast<std::size_t>(image->width)
                << ") is not finite";
        throw std::invalid_argument(message.str());
      }
    }
}
}  // namespace detail

/// Root mean squared error over all pixels and the three channels.
inline double rmse(const Image& test, const Image& reference) {
  detail::check_metric_inputs("rmse", test, reference);
  double sum = 0.0;
  for (std::size_t i = 0; i < test.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      const double difference = static_cast<double>(test.pixels[i][c]) - reference.pixels[i][c];
      sum += difference * difference;
    }
  return std::sqrt(sum / (3.0 * static_cast<double>(test.pixels.size())));
}

/// Fraction of pixels `RelMseOptions::ignore_brightest` drops: the brightest 0.1 %.
inline constexpr double brightest_outlier_fraction = 0.001;

/// Settings of `relmse`.
struct RelMseOptions {
  /// Added to ref^2 in the denominator: keeps dark pixels from dominating (0.01, the usual value).
  double epsilon = 0.01;
  /// Drop the floor(0.1 % of the pixel count) pixels of highest reference luminance.
  bool ignore_brightest = false;
};

/// Relative mean squared error: mean over pixels and channels of (test - ref)^2 / (ref^2 + epsilon).
// With `ignore_brightest`, the k = floor(0.001 * pixel count) pixels with the largest reference
// luminance (Rec. 709 weights, see `luminance`; ties broken towards the later pixel in row-major
// order) are left out, and the mean runs over the 3 (N - k) remaining values. This removes the
// light sources and fireflies whose huge reference values would otherwise decide the metric.
inline double relmse(const Image& test, const Image& reference, const RelMseOptions& options = {}) {
  detail::check_metric_inputs("relmse", test, reference);
  if (!(options.epsilon > 0.0) || !std::isfinite(options.epsilon))
    throw std::invalid_argument("relmse: epsilon must be positive and finite, not " + std::to_string(options.epsilon));
  const std::size_t count = test.pixels.size();
  std::vector<bool> ignored(count, false);
  if (options.ignore_brightest) {
    const auto k = static_cast<std::size_t>(std::floor(brightest_outlier_fraction * static_cast<double>(count)));
    std::vector<std::size_t> order(count);
    std::iota(order.begin(), order.end(), std::size_t{0});
    // Brightest first; among equal luminances the later pixel counts as brighter (a fixed rule
    // keeps the result a pure function of the images).
    std::partial_sort(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k), order.end(),
                      [&](std::size_t a, std::size_t b) {
                        const float la = luminance(reference.pixels[a]), lb = luminance(reference.pixels[b]);
                        return la != lb ? la > lb : a > b;
                      });
    for (std::size_t i = 0; i < k; ++i) ignored[order[i]] = true;
  }
  double sum = 0.0;
  std::size_t used = 0;
  for (std::size_t i = 0; i < count; ++i) {
    if (ignored[i]) continue;
    ++used;
    for (int c = 0; c < 3; ++c) {
      const double r = reference.pixels[i][c];
      const double difference = static_cast<double>(test.pixels[i][c]) - r;
      sum += difference * difference / (r * r + options.epsilon);
    }
  }
  return sum / (3.0 * static_cast<double>(used));
}

/// Window over which SSIM computes local statistics.
enum class SsimWindow {
  gaussian11,  ///< 11 x 11 Gaussian weights, sigma 1.5 (Wang et al. 2004), normalized to sum 1.
  box8,        ///< 8 x 8 equal weights.
};

/// Mean structural similarity of the luminances of `test` and `reference` (1 = identical).
// SSIM(x, y) = (2 mx my + C1)(2 sxy + C2) / ((mx^2 + my^2 + C1)(sx^2 + sy^2 + C2)) with weighted
// local means m, variances s^2 and covariance sxy (weights summing to 1, no n-1 correction),
// C1 = (0.01 L)^2 and C2 = (0.03 L)^2 for the dynamic range L = 1 (linear luminance of a display
// referred image; values above 1 are not clipped). Windows slide by one pixel and lie entirely
// inside the image; the result is the mean over all window positions. Luminance is Rec. 709
// (see `luminance`). The images must be at least as large as the window.
inline double ssim(const Image& test, const Image& reference, SsimWindow window = SsimWindow::gaussian11) {
  detail::check_metric_inputs("ssim", test, reference);
  // One-dimensional weights; both windows are separable (outer product of these with themselves).
  std::vector<double> weights;
  if (window == SsimWindow::gaussian11) {
    const double sigma = 1.5;  // Wang et al.'s standard deviation for the 11-tap window
    for (int i = -5; i <= 5; ++i) weights.push_back(std::exp(-0.5 * i * i / (sigma * sigma)));
  } else {
    weights.assign(8, 1.0);
  }
  const double total = std::accumulate(weights.begin(), weights.end(), 0.0);
  for (double& w : weights) w /= total;
  const int size = static_cast<int>(weights.size());
  const int width = test.width, height = test.height;
  if (width < size || height < size)
    throw std::invalid_argument("ssim: the " + std::to_string(width) + " x " + std::to_string(height) +
                                " images are smaller than the " + std::to_string(size) + " x " + std::to_string(size) +
                                " window");

  // Per pixel: x, y, x^2, y^2, x y; filtered along rows, then along columns.
  constexpr int moments = 5;
  std::vector<std::array<double, moments>> values(test.pixels.size());
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double x = luminance(test.pixels[i]), y = luminance(reference.pixels[i]);
    values[i] = {x, y, x * x, y * y, x * y};
  }
  const int out_width = width - size + 1, out_height = height - size + 1;
  std::vector<std::array<double, moments>> rows(static_cast<std::size_t>(out_width) * height);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < out_width; ++x) {
      std::array<double, moments> sum{};
      for (int k = 0; k < size; ++k) {
        const auto& v = values[static_cast<std::size_t>(y) * width + x + k];
        for (int m = 0; m < moments; ++m) sum[m] += weights[k] * v[m];
      }
      rows[static_cast<std::size_t>(y) * out_width + x] = sum;
    }
  // The stabilizing constants of Wang et al.: K1 = 0.01, K2 = 0.03, dynamic range L = 1.
  const double c1 = 0.01 * 0.01, c2 = 0.03 * 0.03;
  double total_ssim = 0.0;
  for (int y = 0; y < out_height; ++y)
    for (int x = 0; x < out_width; ++x) {
      std::array<double, moments> sum{};
      for (int k = 0; k < size; ++k) {
        const auto& v = rows[static_cast<std::size_t>(y + k) * out_width + x];
        for (int m = 0; m < moments; ++m) sum[m] += weights[k] * v[m];
      }
      const double mean_x = sum[0], mean_y = sum[1];
      const double variance_x = sum[2] - mean_x * mean_x, variance_y = sum[3] - mean_y * mean_y;
      const double covariance = sum[4] - mean_x * mean_y;
      total_ssim += (2 * mean_x * mean_y + c1) * (2 * covariance + c2) /
                    ((mean_x * mean_x + mean_y * mean_y + c1) * (variance_x + variance_y + c2));
    }
  return total_ssim / (static_cast<double>(out_width) * out_height);
}

}  // namespace igi
