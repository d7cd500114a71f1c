#pragma once
/// \file
/// The image types: linear RGB float images (`Image`), 8-bit sRGB images (`Rgb8Image`) and the
/// error images report (`ImageError`). Conversions between them are in igi/io/srgb.hpp, files in
/// igi/io/image_files.hpp.

#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace igi {

/// A failure to read or write an image; the message names the file and the problem.
class ImageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

namespace detail {
/// Largest pixel count accepted from a file or for writing: 2^28 (16384 x 16384).
// Far above any frame igi renders; it rejects absurd sizes from corrupt headers before any
// allocation, and keeps byte counts (12 per float RGB pixel) far from size_t overflow.
inline constexpr std::int64_t max_image_pixels = std::int64_t{1} << 28;
}  // namespace detail

/// Linear RGB image of floats, row-major, top row first.
struct Image {
  int width = 0;                  ///< Pixels per row.
  int height = 0;                 ///< Rows.
  std::vector<glm::vec3> pixels;  ///< width * height pixels, row by row from the top.

  /// An empty 0 x 0 image.
  Image() = default;
  /// A width x height image filled with `fill`; sizes must be positive.
  Image(int width_, int height_, glm::vec3 fill = glm::vec3(0.0f)) : width(width_), height(height_) {
    if (width_ <= 0 || height_ <= 0 || std::int64_t{width_} * height_ > detail::max_image_pixels)
      throw std::invalid_argument("Image: size " + std::to_string(width_) + " x " + std::to_string(height_) +
                                  " is not a positive size of at most 2^28 pixels");
    pixels.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_), fill);
  }
  /// Pixel (x, y), y counted from the top; unchecked.
  glm::vec3& operator()(int x, int y) noexcept { return pixels[static_cast<std::size_t>(y) * width + x]; }
  /// Pixel (x, y), y counted from the top; unchecked.
  const glm::vec3& operator()(int x, int y) const noexcept { return pixels[static_cast<std::size_t>(y) * width + x]; }
  /// Pixel (x, y) with bounds checking (std::out_of_range).
  const glm::vec3& at(int x, int y) const {
    if (x < 0 || y < 0 || x >= width || y >= height)
      throw std::out_of_range("Image::at: pixel (" + std::to_string(x) + ", " + std::to_string(y) +
                              ") is outside the " + std::to_string(width) + " x " + std::to_string(height) + " image");
    return (*this)(x, y);
  }
  /// True when the image has no pixels.
  bool empty() const noexcept { return pixels.empty(); }
};

/// 8-bit sRGB-encoded RGB image, row-major, top row first, 3 bytes per pixel.
struct Rgb8Image {
  int width = 0;                    ///< Pixels per row.
  int height = 0;                   ///< Rows.
  std::vector<std::uint8_t> bytes;  ///< width * height * 3 bytes: R, G, B of each pixel, rows from the top.

  /// An empty 0 x 0 image.
  Rgb8Image() = default;
  /// A width x height black image; sizes must be positive.
  Rgb8Image(int width_, int height_) : width(width_), height(height_) {
    if (width_ <= 0 || height_ <= 0 || std::int64_t{width_} * height_ > detail::max_image_pixels)
      throw std::invalid_argument("Rgb8Image: size " + std::to_string(width_) + " x " + std::to_string(height_) +
                                  " is not a positive size of at most 2^28 pixels");
    bytes.assign(static_cast<std::size_t>(width_) * static_cast<std::size_t>(height_) * 3, 0);
  }
  /// The 3 bytes of pixel (x, y); unchecked.
  std::uint8_t* pixel(int x, int y) noexcept { return bytes.data() + (static_cast<std::size_t>(y) * width + x) * 3; }
  /// The 3 bytes of pixel (x, y); unchecked.
  const std::uint8_t* pixel(int x, int y) const noexcept {
    return bytes.data() + (static_cast<std::size_t>(y) * width + x) * 3;
  }
};
}  // namespace igi
