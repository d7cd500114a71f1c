#pragma once
/// \file
/// The image codecs behind igi/io/image_files.hpp (see there): included by it when igi is
/// header-only, compiled once by igi/separate_compilation.hpp under IGI_SEPARATE_COMPILATION
/// (igi/config.hpp).

#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <thread>
#include <vector>

#include <glm/vec3.hpp>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>
#include <unistd.h>

#include "igi/config.hpp"
#include "igi/io/image_files.hpp"
#include "igi/io/image_types.hpp"
#include "igi/io/srgb.hpp"

namespace igi {

namespace detail {

/// Checks that width x height is a sensible image size holding exactly `pixel_count` pixels.
inline void check_image_size(const std::filesystem::path& path, int width, int height, std::size_t pixel_count) {
  if (width <= 0 || height <= 0)
    image_error(path, "image size " + std::to_string(width) + " x " + std::to_string(height) + " is empty or negative");
  if (std::int64_t{width} * height > max_image_pixels)
    image_error(path, "image size " + std::to_string(width) + " x " + std::to_string(height) + " is too large");
  if (pixel_count != static_cast<std::size_t>(width) * static_cast<std::size_t>(height))
    image_error(path, "image of " + std::to_string(width) + " x " + std::to_string(height) + " holds " +
                          std::to_string(pixel_count) + " pixels instead of " +
                          std::to_string(std::int64_t{width} * height));
}

/// Checks every pixel is finite (NaN or infinity in an image is a bug upstream).
inline void check_finite(const std::filesystem::path& path, const Image& image, const char* what) {
  for (std::size_t i = 0; i < image.pixels.size(); ++i) {
    const glm::vec3& p = image.pixels[i];
    if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) {
      std::ostringstream message;
      message << what << " pixel (" << i % static_cast<std::size_t>(image.width) << ", "
              << i / static_cast<std::size_t>(image.width) << ") is not finite (" << p.r << ", " << p.g << ", " << p.b
              << ")";
      image_error(path, message.str());
    }
  }
}

/// The whole content of the file at `path`.
inline std::vector<unsigned char> read_file_bytes(const std::filesystem::path& path) {
  std::error_code error;
  const auto status = std::filesystem::status(path, error);
  if (!std::filesystem::exists(status)) image_error(path, "cannot read image: the file does not exist");
  if (!std::filesystem::is_regular_file(status)) image_error(path, "cannot read image: not a regular file");
  std::ifstream file(path, std::ios::binary);
  if (!file) image_error(path, "cannot read image: the file cannot be opened");
  std::vector<unsigned char> bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  if (file.bad()) image_error(path, "cannot read image: read error");
  if (bytes.empty()) image_error(path, "cannot read image: the file is empty");
  return bytes;
}

/// Process-wide counter that keeps temporary file names of concurrent writers apart.
inline std::atomic<unsigned> temporary_file_counter{0};

/// Writes `bytes` to `path` atomically: a temporary file in the same directory, then rename.
inline void write_file_atomically(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  const std::filesystem::path directory = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
  std::error_code error;
  if (!std::filesystem::is_directory(directory, error))
    image_error(path, "cannot write image: directory '" + directory.string() + "' does not exist");
  if (std::filesystem::is_directory(path, error)) image_error(path, "cannot write image: the path is a directory");
  std::filesystem::path temporary;
  std::FILE* file = nullptr;
  // Hidden name "<dir>/.<name>.<pid>-<thread>-<counter>.tmp", opened exclusively ("x"): a clash
  // with another writer just moves on to the next counter value (100 tries are plenty).
  for (int attempt = 0; attempt < 100 && file == nullptr; ++attempt) {
    std::string name = ".";  // built with += : GCC 12 gives a false -Wrestrict on "literal" + string
    name += path.filename().string();
    name += '.';
    name += std::to_string(::getpid());
    name += '-';
    name += std::to_string(std::hash<std::thread::id>{}(std::this_thread::get_id()) % 1000000);
    name += '-';
    name += std::to_string(temporary_file_counter.fetch_add(1));
    name += ".tmp";
    temporary = directory / name;
    file = std::fopen(temporary.c_str(), "wbx");
  }
  if (file == nullptr) image_error(path, "cannot write image: cannot create a temporary file in '" + directory.string() + "'");
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), file) == bytes.size();
  const bool closed = std::fclose(file) == 0;
  if (!written || !closed) {
    std::filesystem::remove(temporary, error);
    image_error(path, "cannot write image: writing '" + temporary.string() + "' failed (disk full?)");
  }
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::filesystem::remove(temporary, error);
    image_error(path, "cannot write image: renaming the temporary file onto it failed");
  }
}

/// PNG encoding of 8-bit RGB pixels.
inline std::vector<unsigned char> encode_png(const std::filesystem::path& path, const Rgb8Image& image) {
  std::vector<unsigned char> bytes;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* begin = static_cast<const unsigned char*>(data);
    out->insert(out->end(), begin, begin + size);
  };
  if (stbi_write_png_to_func(append, &bytes, image.width, image.height, 3, image.bytes.data(), image.width * 3) == 0)
    image_error(path, "PNG encoding failed");
  return bytes;
}

/// OpenEXR encoding (32-bit float R, G, B channels, ZIP compression).
inline std::vector<unsigned char> encode_exr(const std::filesystem::path& path, const Image& image) {
  // OpenEXR readers expect channels in alphabetical order: B, G, R.
  const std::size_t count = image.pixels.size();
  std::vector<float> blue(count), green(count), red(count);
  for (std::size_t i = 0; i < count; ++i) {
    red[i] = image.pixels[i].r;
    green[i] = image.pixels[i].g;
    blue[i] = image.pixels[i].b;
  }
  float* planes[3] = {blue.data(), green.data(), red.data()};
  EXRImage exr_image;
  InitEXRImage(&exr_image);
  exr_image.num_channels = 3;
  exr_image.images = reinterpret_cast<unsigned char**>(planes);
  exr_image.width = image.width;
  exr_image.height = image.height;

  EXRHeader header;
  InitEXRHeader(&header);
  EXRChannelInfo channels[3];
  std::memset(channels, 0, sizeof(channels));
  std::strcpy(channels[0].name, "B");
  std::strcpy(channels[1].name, "G");
  std::strcpy(channels[2].name, "R");
  int pixel_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  int requested_types[3] = {TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT, TINYEXR_PIXELTYPE_FLOAT};
  header.num_channels = 3;
  header.channels = channels;
  header.pixel_types = pixel_types;
  header.requested_pixel_types = requested_types;
  header.compression_type = TINYEXR_COMPRESSIONTYPE_ZIP;

  unsigned char* memory = nullptr;
  const char* message = nullptr;
  const std::size_t size = SaveEXRImageToMemory(&exr_image, &header, &memory, &message);
  if (size == 0 || memory == nullptr) {
    const std::string reason = message ? message : "unknown error";
    if (message) FreeEXRErrorMessage(message);
    std::free(memory);
    image_error(path, "EXR encoding failed: " + reason);
  }
  std::vector<unsigned char> bytes(memory, memory + size);
  std::free(memory);
  return bytes;
}

/// PFM encoding: "PF", size, scale -1 (little-endian), then float RGB rows from the bottom up.
inline std::vector<unsigned char> encode_pfm(const Image& image) {
  static_assert(std::endian::native == std::endian::little, "PFM writing assumes a little-endian machine");
  const std::string header = "PF\n" + std::to_string(image.width) + " " + std::to_string(image.height) + "\n-1\n";
  std::vector<unsigned char> bytes(header.begin(), header.end());
  const std::size_t row_bytes = static_cast<std::size_t>(image.width) * 3 * sizeof(float);
  bytes.resize(header.size() + row_bytes * static_cast<std::size_t>(image.height));
  unsigned char* out = bytes.data() + header.size();
  for (int y = image.height - 1; y >= 0; --y, out += row_bytes)
    for (int x = 0; x < image.width; ++x) std::memcpy(out + static_cast<std::size_t>(x) * 12, &image(x, y), 12);
  return bytes;
}

/// Radiance RGBE (.hdr) encoding (run-length compressed scanlines, stb).
inline std::vector<unsigned char> encode_hdr(const std::filesystem::path& path, const Image& image) {
  std::vector<unsigned char> bytes;
  auto append = [](void* context, void* data, int size) {
    auto* out = static_cast<std::vector<unsigned char>*>(context);
    const auto* begin = static_cast<const unsigned char*>(data);
    out->insert(out->end(), begin, begin + size);
  };
  if (stbi_write_hdr_to_func(append, &bytes, image.width, image.height, 3, &image.pixels.front().x) == 0)
    image_error(path, "HDR encoding failed");
  return bytes;
}

/// Decodes a Radiance RGBE (.hdr) file's bytes to linear floats.
inline Image decode_hdr(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX)) image_error(path, "HDR file is too large");
  if (!stbi_is_hdr_from_memory(bytes.data(), static_cast<int>(bytes.size())))
    image_error(path, "not a Radiance HDR image (no #?RADIANCE or #?RGBE header)");
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<float, void (*)(void*)> pixels(
      stbi_loadf_from_memory(bytes.data(), static_cast<int>(bytes.size()), &width, &height, &channels, 3), stbi_image_free);
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    image_error(path, std::string("not a readable Radiance HDR image (") + (reason ? reason : "unknown error") + ")");
  }
  check_image_size(path, width, height, static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  Image image(width, height);
  std::memcpy(image.pixels.data(), pixels.get(), image.pixels.size() * sizeof(glm::vec3));
  check_finite(path, image, "HDR");
  return image;
}

/// Decodes a PNG file's bytes to linear floats.
inline Image decode_png(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  if (bytes.size() > static_cast<std::size_t>(INT32_MAX)) image_error(path, "PNG file is too large");
  int width = 0, height = 0, channels = 0;
  std::unique_ptr<stbi_uc, void (*)(void*)> pixels(
      stbi_load_from_memory(bytes.data(), static_cast<int>(bytes.size()), &width, &height, &channels, 3),
      stbi_image_free);
  if (!pixels) {
    const char* reason = stbi_failure_reason();
    image_error(path, std::string("not a readable PNG image (") + (reason ? reason : "unknown error") + ")");
  }
  Rgb8Image rgb8;
  rgb8.width = width;
  rgb8.height = height;
  check_image_size(path, width, height, static_cast<std::size_t>(width) * static_cast<std::size_t>(height));
  rgb8.bytes.assign(pixels.get(), pixels.get() + static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * 3);
  return dequantize(rgb8);
}

/// Frees a parsed EXR header when it goes out of scope.
struct ExrHeaderOwner {
  EXRHeader header;  ///< The header, initialized empty.
  /// An empty header.
  ExrHeaderOwner() { InitEXRHeader(&header); }
  ~ExrHeaderOwner() { FreeEXRHeader(&header); }
  ExrHeaderOwner(const ExrHeaderOwner&) = delete;
  ExrHeaderOwner& operator=(const ExrHeaderOwner&) = delete;
};

/// Frees loaded EXR pixel data when it goes out of scope.
struct ExrImageOwner {
  EXRImage image;  ///< The pixel data, initialized empty.
  /// Empty pixel data.
  ExrImageOwner() { InitEXRImage(&image); }
  ~ExrImageOwner() { FreeEXRImage(&image); }
  ExrImageOwner(const ExrImageOwner&) = delete;
  ExrImageOwner& operator=(const ExrImageOwner&) = delete;
};

/// Decodes an OpenEXR file's bytes: R, G, B channels (others such as A are ignored) or a single
/// grey channel; half and float channels as float, unsigned int channels converted to float.
// Written on tinyexr's lower-level calls rather than LoadEXRFromMemory, which (in 1.0.1) leaks
// the parsed header on its error paths and reinterprets unsigned int channels as floats.
inline Image decode_exr(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  auto fail = [&](const std::string& what, const char* message) {
    const std::string reason = message ? message : "unknown error";
    if (message) FreeEXRErrorMessage(message);
    image_error(path, "not a readable EXR image (" + what + reason + ")");
  };
  EXRVersion version;
  if (ParseEXRVersionFromMemory(&version, bytes.data(), bytes.size()) != TINYEXR_SUCCESS)
    image_error(path, "not a readable EXR image (no OpenEXR magic number and version)");
  if (version.multipart || version.non_image) image_error(path, "multi-part and deep EXR images are not supported");
  ExrHeaderOwner header;
  const char* message = nullptr;
  if (ParseEXRHeaderFromMemory(&header.header, &version, bytes.data(), bytes.size(), &message) != TINYEXR_SUCCESS)
    fail("header: ", message);
  const EXRHeader& h = header.header;
  int red = -1, green = -1, blue = -1;
  std::string names;
  for (int c = 0; c < h.num_channels; ++c) {
    const std::string name = h.channels[c].name;
    names += (c ? ", " : "") + name;
    if (name == "R") red = c;
    if (name == "G") green = c;
    if (name == "B") blue = c;
    if (h.pixel_types[c] == TINYEXR_PIXELTYPE_HALF) h.requested_pixel_types[c] = TINYEXR_PIXELTYPE_FLOAT;
  }
  if (red < 0 || green < 0 || blue < 0) {
    if (h.num_channels != 1)
      image_error(path, "EXR image has neither R, G and B channels nor a single grey channel (channels: " + names + ")");
    red = green = blue = 0;
  }
  ExrImageOwner pixels;
  if (LoadEXRImageFromMemory(&pixels.image, &header.header, bytes.data(), bytes.size(), &message) != TINYEXR_SUCCESS)
    fail("pixels: ", message);
  const EXRImage& e = pixels.image;
  check_image_size(path, e.width, e.height, static_cast<std::size_t>(e.width) * static_cast<std::size_t>(e.height));
  // One channel value as float, whatever its stored type (halves were requested as floats).
  auto value = [&](unsigned char* const* planes, int channel, std::size_t index) {
    if (h.requested_pixel_types[channel] == TINYEXR_PIXELTYPE_UINT)
      return static_cast<float>(reinterpret_cast<const std::uint32_t*>(planes[channel])[index]);
    return reinterpret_cast<const float*>(planes[channel])[index];
  };
  Image image(e.width, e.height);
  if (h.tiled) {
    if (e.tiles == nullptr) image_error(path, "EXR image is tiled but holds no tiles");
    for (int t = 0; t < e.num_tiles; ++t) {
      const EXRTile& tile = e.tiles[t];
      for (int j = 0; j < tile.height; ++j)
        for (int i = 0; i < tile.width; ++i) {
          const int x = tile.offset_x * h.tile_size_x + i, y = tile.offset_y * h.tile_size_y + j;
          if (x < 0 || y < 0 || x >= e.width || y >= e.height) continue;
          const auto index = static_cast<std::size_t>(j) * static_cast<std::size_t>(h.tile_size_x) + i;
          image(x, y) = {value(tile.images, red, index), value(tile.images, green, index), value(tile.images, blue, index)};
        }
    }
  } else {
    if (e.images == nullptr) image_error(path, "EXR image holds no scanline data");
    for (std::size_t i = 0; i < image.pixels.size(); ++i)
      image.pixels[i] = {value(e.images, red, i), value(e.images, green, i), value(e.images, blue, i)};
  }
  check_finite(path, image, "EXR");
  return image;
}

/// Decodes a PFM file's bytes ("PF" colour or "Pf" grey; either byte order).
inline Image decode_pfm(const std::filesystem::path& path, const std::vector<unsigned char>& bytes) {
  std::size_t position = 0;
  auto is_space = [](unsigned char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
  // The header is three whitespace-separated tokens after the magic; one whitespace byte ends it.
  auto next_token = [&]() {
    while (position < bytes.size() && is_space(bytes[position])) ++position;
    const std::size_t start = position;
    while (position < bytes.size() && !is_space(bytes[position]) && position - start < 64) ++position;
    if (position >= bytes.size() || !is_space(bytes[position])) image_error(path, "PFM header is truncated or malformed");
    return std::string(bytes.begin() + static_cast<std::ptrdiff_t>(start), bytes.begin() + static_cast<std::ptrdiff_t>(position));
  };
  const std::string magic = next_token();
  if (magic != "PF" && magic != "Pf") image_error(path, "not a PFM image (magic '" + magic.substr(0, 8) + "', expected PF or Pf)");
  const int channels = magic == "PF" ? 3 : 1;
  auto parse_int = [&](const std::string& token, const char* what) {
    char* end = nullptr;
    const long value = std::strtol(token.c_str(), &end, 10);
    if (token.empty() || *end != '\0' || value <= 0 || value > (1L << 20))
      image_error(path, std::string("PFM ") + what + " '" + token + "' is not a positive integer of at most 2^20");
    return static_cast<int>(value);
  };
  const int width = parse_int(next_token(), "width");
  const int height = parse_int(next_token(), "height");
  const std::string scale_token = next_token();
  char* end = nullptr;
  const double scale = std::strtod(scale_token.c_str(), &end);
  if (*end != '\0' || !std::isfinite(scale) || scale == 0.0)
    image_error(path, "PFM scale '" + scale_token + "' is not a non-zero number");
  ++position;  // the single whitespace byte after the scale
  if (std::int64_t{width} * height > max_image_pixels)
    image_error(path, "PFM image size " + std::to_string(width) + " x " + std::to_string(height) + " is too large");
  const std::size_t expected = static_cast<std::size_t>(width) * static_cast<std::size_t>(height) * channels * sizeof(float);
  const std::size_t available = bytes.size() - position;
  if (available != expected)
    image_error(path, "PFM pixel data is " + std::to_string(available) + " bytes, expected " + std::to_string(expected) +
                          " for " + std::to_string(width) + " x " + std::to_string(height) +
                          (available < expected ? " (truncated)" : " (trailing bytes)"));
  const bool little_endian = scale < 0.0;  // the PFM convention: negative scale = little-endian
  Image image(width, height);
  const unsigned char* data = bytes.data() + position;
  auto read_float = [&](std::size_t index) {
    std::uint32_t word;
    std::memcpy(&word, data + index * 4, 4);
    if (little_endian != (std::endian::native == std::endian::little)) word = __builtin_bswap32(word);
    return std::bit_cast<float>(word);
  };
  for (int row = 0; row < height; ++row) {  // file rows run from the bottom of the image up
    const int y = height - 1 - row;
    for (int x = 0; x < width; ++x) {
      const std::size_t first = (static_cast<std::size_t>(row) * width + x) * channels;
      image(x, y) = channels == 3 ? glm::vec3(read_float(first), read_float(first + 1), read_float(first + 2))
                                  : glm::vec3(read_float(first));
    }
  }
  check_finite(path, image, "PFM");
  return image;
}

}  // namespace detail

IGI_INLINE void write_image(const std::filesystem::path& path, const Image& image) {
  const ImageFormat format = image_format(path);
  detail::check_image_size(path, image.width, image.height, image.pixels.size());
  detail::check_finite(path, image, "cannot write image:");
  switch (format) {
    case ImageFormat::png: detail::write_file_atomically(path, detail::encode_png(path, quantize(image))); return;
    case ImageFormat::exr: detail::write_file_atomically(path, detail::encode_exr(path, image)); return;
    case ImageFormat::pfm: detail::write_file_atomically(path, detail::encode_pfm(image)); return;
    case ImageFormat::hdr: detail::write_file_atomically(path, detail::encode_hdr(path, image)); return;
  }
}

IGI_INLINE void write_image(const std::filesystem::path& path, const Rgb8Image& image) {
  const ImageFormat format = image_format(path);
  detail::check_image_size(path, image.width, image.height, image.bytes.size() / 3);
  if (image.bytes.size() % 3 != 0) detail::image_error(path, "RGB8 image byte count is not a multiple of 3");
  if (format == ImageFormat::png)
    detail::write_file_atomically(path, detail::encode_png(path, image));
  else
    write_image(path, dequantize(image));
}

IGI_INLINE Image read_image(const std::filesystem::path& path) {
  const ImageFormat format = image_format(path);
  const std::vector<unsigned char> bytes = detail::read_file_bytes(path);
  switch (format) {
    case ImageFormat::png: return detail::decode_png(path, bytes);
    case ImageFormat::exr: return detail::decode_exr(path, bytes);
    case ImageFormat::pfm: return detail::decode_pfm(path, bytes);
    case ImageFormat::hdr: return detail::decode_hdr(path, bytes);
  }
  detail::image_error(path, "unreachable image format");
}

}  // namespace igi
