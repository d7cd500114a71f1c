#pragma once
/// \file
/// The sRGB transfer functions, luminance, and quantization between linear float images and
/// 8-bit sRGB ones. Needs no image codec: tone mapping and the renderers include this, not the
/// file readers and writers.

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

#include <glm/vec3.hpp>

#include "igi/io/image_types.hpp"

namespace igi {

/// Relative luminance of linear Rec. 709 / sRGB primaries (the Y of CIE XYZ).
inline float luminance(const glm::vec3& rgb) noexcept {
  // Rec. 709 / sRGB luminance weights (the middle row of the RGB -> XYZ matrix).
  return 0.2126f * rgb.r + 0.7152f * rgb.g + 0.0722f * rgb.b;
}

/// sRGB transfer function (IEC 61966-2-1): linear [0, 1] -> encoded [0, 1]; clamps, NaN -> 0.
inline float srgb_encode(float linear) noexcept {
  if (!(linear > 0.0f)) return 0.0f;  // negative, zero and NaN
  if (linear >= 1.0f) return 1.0f;
  // The standard's constants: linear segment below 0.0031308, slope 12.92; power 1/2.4 above.
  if (linear <= 0.0031308f) return 12.92f * linear;
  return 1.055f * std::pow(linear, 1.0f / 2.4f) - 0.055f;
}

/// Inverse sRGB transfer function: encoded [0, 1] -> linear [0, 1]; clamps, NaN -> 0.
inline float srgb_decode(float encoded) noexcept {
  if (!(encoded > 0.0f)) return 0.0f;
  if (encoded >= 1.0f) return 1.0f;
  // The standard's constants: linear segment below 0.04045 (= 12.92 * 0.0031308).
  if (encoded <= 0.04045f) return encoded / 12.92f;
  return static_cast<float>(std::pow((static_cast<double>(encoded) + 0.055) / 1.055, 2.4));
}

/// Linear value -> 8-bit sRGB code straight from the transfer function (the definition `quantize`
/// reproduces from a table).
inline std::uint8_t quantize_direct(float linear) noexcept {
  // 255 codes above 0; + 0.5 then truncation rounds to nearest (the value is >= 0).
  return static_cast<std::uint8_t>(srgb_encode(linear) * 255.0f + 0.5f);
}

namespace image_detail {
/// Entry c - 1 is the smallest float whose code under `quantize_direct` is at least c (c = 1 .. 255),
/// found by bisection over the bit patterns of [0, 1], which are ordered like the floats.
inline const std::array<float, 255>& quantize_thresholds() noexcept {
  static const std::array<float, 255> thresholds = [] {
    std::array<float, 255> table{};
    for (int code = 1; code <= 255; ++code) {
      std::uint32_t low = std::bit_cast<std::uint32_t>(0.0f), high = std::bit_cast<std::uint32_t>(1.0f);
      while (low < high) {
        const std::uint32_t middle = low + (high - low) / 2;
        if (quantize_direct(std::bit_cast<float>(middle)) >= code)
          high = middle;
        else
          low = middle + 1;
      }
      table[static_cast<std::size_t>(code - 1)] = std::bit_cast<float>(low);
    }
    return table;
  }();
  return thresholds;
}
}  // namespace image_detail

namespace image_detail {
/// A direct index into the codes of `quantize_thresholds`: the floats of [2^-13, 1) cut into
/// buckets by their exponent and the top 7 bits of their mantissa (1664 buckets). Below 2^-13 every
/// code is 0 (code 1 starts at 1.5e-4). A bucket spans at most 2^-7 of its values, and the sRGB
/// curve climbs at most 255 x 1.055 / 2.4 = 112 codes per unit of ln(linear) (at 1; less below,
/// and the linear segment, code = 3295 x linear, climbs at most 10.3 at its top), so a bucket
/// holds at most 0.88 codes' worth: at most one threshold, which one comparison finds.
struct QuantizeBuckets {
  /// Bit pattern of 2^-13, where the buckets start.
  static constexpr std::uint32_t first_bits = 0x39000000u;
  /// Mantissa bits below the bucket index (23 - 7).
  static constexpr int shift = 16;
  /// Buckets: 13 binary octaves of 2^7 each.
  static constexpr std::size_t count = 13u << 7;
  std::array<std::uint8_t, count> code{};  ///< Code of each bucket's smallest float.
  std::array<float, 256> next{};           ///< Entry c: where code c + 1 starts (infinity for c = 255).
};

/// The buckets of `QuantizeBuckets`, built once from `quantize_thresholds`.
inline const QuantizeBuckets& quantize_buckets() noexcept {
  static const QuantizeBuckets buckets = [] {
    QuantizeBuckets b;
    const std::array<float, 255>& thresholds = quantize_thresholds();
    for (std::size_t c = 0; c < 255; ++c) b.next[c] = thresholds[c];
    b.next[255] = std::numeric_limits<float>::infinity();
    std::size_t code = 0;
    for (std::size_t i = 0; i < QuantizeBuckets::count; ++i) {
      const float start = std::bit_cast<float>(QuantizeBuckets::first_bits + (std::uint32_t(i) << QuantizeBuckets::shift));
      while (code < 255 && thresholds[code] <= start) ++code;
      b.code[i] = static_cast<std::uint8_t>(code);
    }
    return b;
  }();
  return buckets;
}
}  // namespace image_detail

/// Linear value -> 8-bit sRGB code, rounded to nearest (values outside [0, 1] clamp, NaN -> 0).
/// Equal to `quantize_direct` for every float, without a `pow` per call: the value's bucket gives
/// the code of the bucket's start, one comparison with the next code's threshold the rest.
inline std::uint8_t quantize(float linear) noexcept {
  const image_detail::QuantizeBuckets& buckets = image_detail::quantize_buckets();
  // Negative, zero, NaN and everything below the first bucket (all code 0).
  if (!(linear >= std::bit_cast<float>(image_detail::QuantizeBuckets::first_bits))) return 0;
  if (linear >= 1.0f) return 255;
  const std::uint32_t bucket =
      (std::bit_cast<std::uint32_t>(linear) - image_detail::QuantizeBuckets::first_bits) >> image_detail::QuantizeBuckets::shift;
  const std::uint8_t code = buckets.code[bucket];
  return static_cast<std::uint8_t>(code + (linear >= buckets.next[code] ? 1 : 0));
}

/// 8-bit sRGB code -> linear value (the exact inverse of `quantize` on codes).
inline float dequantize(std::uint8_t code) noexcept { return srgb_decode(static_cast<float>(code) / 255.0f); }

/// `image` quantized to 8-bit sRGB, pixel by pixel (see `quantize(float)`).
inline Rgb8Image quantize(const Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height))
    throw std::invalid_argument("quantize: " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                                " image holds " + std::to_string(image.pixels.size()) + " pixels");
  Rgb8Image result(image.width, image.height);
  for (std::size_t i = 0; i < image.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) result.bytes[i * 3 + c] = quantize(image.pixels[i][c]);
  return result;
}

/// `image` decoded to linear floats (see `dequantize(std::uint8_t)`).
inline Image dequantize(const Rgb8Image& image) {
  if (image.width <= 0 || image.height <= 0 ||
      image.bytes.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::invalid_argument("dequantize: " + std::to_string(image.width) + " x " + std::to_string(image.height) +
                                " RGB8 image holds " + std::to_string(image.bytes.size()) + " bytes");
  Image result(image.width, image.height);
  for (std::size_t i = 0; i < result.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) result.pixels[i][c] = dequantize(image.bytes[i * 3 + c]);
  return result;
}
}  // namespace igi
