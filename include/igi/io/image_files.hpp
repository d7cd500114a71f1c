#pragma once
/// \file
/// Reading and writing images as PNG (stb), EXR (tinyexr), PFM (written here) and Radiance HDR
/// (stb), chosen by the file extension. Writes are atomic: the data goes to a temporary file in the target's
/// directory, which is then renamed over the target. The codecs are IGI_INLINE functions
/// (igi/config.hpp): a program built with IGI_SEPARATE_COMPILATION compiles them, and includes
/// stb and tinyexr, in its one igi/separate_compilation.hpp translation unit only.

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <string>

#include "igi/config.hpp"
#include "igi/io/image_types.hpp"

namespace igi {

namespace detail {
/// Throws `ImageError("<path>: <problem>")`.
[[noreturn]] inline void image_error(const std::filesystem::path& path, const std::string& problem) {
  throw ImageError(path.string() + ": " + problem);
}
}  // namespace detail

/// Image file formats igi reads and writes.
enum class ImageFormat {
  png,  ///< 8-bit sRGB PNG (stb).
  exr,  ///< 32-bit float OpenEXR (tinyexr).
  pfm,  ///< 32-bit float portable float map.
  hdr,  ///< Radiance RGBE (.hdr), the common format of HDR environment maps (stb).
};

/// The format named by `path`'s extension (.png, .exr, .pfm; any letter case), else ImageError.
inline ImageFormat image_format(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".png") return ImageFormat::png;
  if (extension == ".exr") return ImageFormat::exr;
  if (extension == ".pfm") return ImageFormat::pfm;
  if (extension == ".hdr") return ImageFormat::hdr;
  detail::image_error(path, "unknown image extension '" + path.extension().string() + "' (expected .png, .exr, .pfm or .hdr)");
}

/// Writes `image` to `path` in the format of its extension (PNG: sRGB 8-bit, clamped to [0, 1]).
IGI_INLINE void write_image(const std::filesystem::path& path, const Image& image);

/// Writes an 8-bit sRGB image: byte for byte to PNG, decoded to linear floats for EXR and PFM.
IGI_INLINE void write_image(const std::filesystem::path& path, const Rgb8Image& image);

/// Reads the image at `path` (format from its extension) as linear RGB floats.
IGI_INLINE Image read_image(const std::filesystem::path& path);

}  // namespace igi

#if !defined(IGI_SEPARATE_COMPILATION)
#include "igi/io/impl/image_codecs.hpp"
#endif
