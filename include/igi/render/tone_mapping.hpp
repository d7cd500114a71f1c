#pragma once
/// \file
/// Tone mapping from per-tile luminance statistics: tiles record statistics, a frame combines
/// them, and the next frame maps with the result (the paper's one frame of latency, which lets
/// tiles be tone mapped where they are rendered).

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <numbers>

#include <glm/glm.hpp>

#include "igi/io/srgb.hpp"

namespace igi {

/// Luminance statistics of some pixels; tiles' statistics add up to a frame's.
struct LuminanceStatistics {
  double log_sum = 0.0;        ///< Sum of log(delta + luminance) over counted pixels.
  std::uint64_t count = 0;     ///< Pixels counted.
  float max_luminance = 0.0f;  ///< Brightest counted pixel.

  /// Offset inside the logarithm so black pixels do not send the mean to -infinity (Reinhard's delta).
  static constexpr double delta = 1e-4;

  /// Counts one pixel (non-finite values are ignored).
  void add(const glm::vec3& rgb) noexcept {
    const float y = luminance(rgb);
    if (!std::isfinite(y) || y < 0.0f) return;
    log_sum += std::log(delta + double(y));
    ++count;
    max_luminance = std::max(max_luminance, y);
  }
  /// Adds another tile's statistics.
  void merge(const LuminanceStatistics& other) noexcept {
    log_sum += other.log_sum;
    count += other.count;
    max_luminance = std::max(max_luminance, other.max_luminance);
  }
  /// Log-average luminance (0 if nothing was counted).
  double log_average() const noexcept { return count ? std::exp(log_sum / double(count)) - delta : 0.0; }
};

/// Records many pixels into LuminanceStatistics as LuminanceStatistics::add does, with one
/// logarithm in all instead of one per pixel: the terms delta + luminance are multiplied in
/// double, the product's binary exponent taken out after each so it stays in [1, 2) before the
/// next factor (a factor lies in [1e-4, 3.4e38], so the product is always a normal double), and
/// `statistics` returns log(product) + exponents x ln 2 as log_sum. Each multiply rounds by at
/// most 2^-53 relative, so log_sum differs from the per-pixel sum of logarithms by at most
/// 1.1e-16 x pixels plus 1.1e-16 x |log_sum| (the last addition), the same order as that sum's
/// own rounding: far below the float the tone mapping's scale is rounded to (6e-8 relative).
class LuminanceAccumulator {
 public:
  /// Counts one pixel (non-finite and negative luminances are ignored, as by LuminanceStatistics::add).
  void add(const glm::vec3& rgb) noexcept {
    const float y = luminance(rgb);
    if (!std::isfinite(y) || y < 0.0f) return;
    const std::uint64_t bits = std::bit_cast<std::uint64_t>(product_ * (LuminanceStatistics::delta + double(y)));
    // IEEE 754 double: 11 exponent bits above 52 mantissa bits, bias 1023; the product is positive.
    exponent_ += std::int64_t(bits >> 52) - 1023;
    product_ = std::bit_cast<double>((bits & mantissa_bits) | one_bits);
    ++count_;
    max_luminance_ = std::max(max_luminance_, y);
  }
  /// What LuminanceStatistics::add would have recorded for the same pixels.
  LuminanceStatistics statistics() const noexcept {
    LuminanceStatistics stats;
    stats.log_sum = std::log(product_) + double(exponent_) * std::numbers::ln2;
    stats.count = count_;
    stats.max_luminance = max_luminance_;
    return stats;
  }

 private:
  /// The mantissa field of a double.
  static constexpr std::uint64_t mantissa_bits = (std::uint64_t(1) << 52) - 1;
  /// The bit pattern of 1.0 (exponent field 1023, mantissa 0).
  static constexpr std::uint64_t one_bits = std::uint64_t(1023) << 52;
  double product_ = 1.0;           ///< Product of the factors so far, divided by 2^exponent_, in [1, 2).
  std::int64_t exponent_ = 0;      ///< Binary exponents taken out of the product.
  std::uint64_t count_ = 0;        ///< Pixels counted.
  float max_luminance_ = 0.0f;     ///< Brightest counted pixel.
};

/// Parameters of Reinhard's global operator with a white point.
struct ToneMapping {
  float scale = 1.0f;        ///< Exposure: key / log-average luminance.
  float white = 1e30f;       ///< Scaled luminance that maps to 1 (burn-out point).

  /// Middle grey: the key Reinhard et al. suggest for average scenes.
  static constexpr float key = 0.18f;

  /// Parameters that map a frame with these statistics (the identity scale when it was empty or black).
  static ToneMapping from(const LuminanceStatistics& stats) noexcept {
    ToneMapping t;
    const double average = stats.log_average();
    if (stats.count == 0 || !(average > 0.0)) return t;
    t.scale = float(key / average);
    // The brightest pixel just reaches white, but never less than scaled luminance 1.5 so that a
    // nearly uniform image is not pushed to white.
    t.white = std::max(1.5f, stats.max_luminance * t.scale);
    return t;
  }
  /// Maps linear HDR radiance to display-linear [0, 1] RGB, keeping chromaticity.
  glm::vec3 apply(const glm::vec3& rgb) const noexcept {
    const float y = luminance(rgb);
    if (!(y > 0.0f) || !std::isfinite(y)) return glm::vec3(0.0f);
    const float l = y * scale;
    const float mapped = l * (1.0f + l / (white * white)) / (1.0f + l);
    return glm::clamp(rgb * (mapped / y), glm::vec3(0.0f), glm::vec3(1.0f));
  }
};

/// Display-linear RGB to 8-bit sRGB with rounding.
inline glm::u8vec3 quantize_srgb(const glm::vec3& display) noexcept {
  return {quantize(display.r), quantize(display.g), quantize(display.b)};
}

}  // namespace igi
