// igi/io/image.hpp: sRGB quantization, PNG / EXR / PFM round trips, hand-made files, errors and
// atomic writes.

#include <bit>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <string>
#include <vector>

#include <catch2/catch.hpp>
#include <stb/stb_image.h>
#include <stb/stb_image_write.h>
#include <tinyexr.h>
#include <unistd.h>

#include "igi/io/image.hpp"
#include "igi/simd/sampling.hpp"

using namespace igi;
namespace fs = std::filesystem;

namespace {

/// A fresh empty directory for one test, removed with everything in it at the end.
class ScratchDirectory {
 public:
  explicit ScratchDirectory(const std::string& name)
      : path_(fs::temp_directory_path() / ("igi_io_" + name + "_" + std::to_string(::getpid()))) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDirectory() {
    std::error_code ignored;
    fs::remove_all(path_, ignored);
  }
  ScratchDirectory(const ScratchDirectory&) = delete;
  ScratchDirectory& operator=(const ScratchDirectory&) = delete;
  /// A file name inside the directory.
  fs::path operator/(const std::string& file) const { return path_ / file; }
  /// Names of the entries in the directory.
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(path_)) names.push_back(entry.path().filename().string());
    return names;
  }

 private:
  fs::path path_;
};

/// A width x height image of seeded random values in [low, high) (non-square sizes catch
/// transposed rows and columns; distinct values catch flipped rows).
Image random_image(int width, int height, std::uint32_t seed, float low, float high) {
  Image image(width, height);
  Rng rng(seed);
  for (auto& p : image.pixels) p = glm::vec3(rng.next(), rng.next(), rng.next()) * (high - low) + glm::vec3(low);
  return image;
}

/// Bytes of a file.
std::vector<unsigned char> file_bytes(const fs::path& path) {
  std::ifstream file(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>()};
}

/// Writes raw bytes to a file.
void write_bytes(const fs::path& path, const std::vector<unsigned char>& bytes) {
  std::ofstream file(path, std::ios::binary);
  file.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
}

/// Appends the 4 bytes of `value`, big- or little-endian.
void append_float(std::vector<unsigned char>& bytes, float value, bool big_endian) {
  std::uint32_t word = std::bit_cast<std::uint32_t>(value);
  for (int i = 0; i < 4; ++i) {
    const int shift = big_endian ? 24 - 8 * i : 8 * i;
    bytes.push_back(static_cast<unsigned char>(word >> shift));
  }
}

/// Writes an EXR file with the named channels, each a plane of `type` pixels (float or uint32
/// values in `planes`), through tinyexr's low-level writer: files igi itself never writes.
void write_custom_exr(const fs::path& path, int width, int height, const std::vector<std::string>& names,
                      const std::vector<std::vector<std::uint32_t>>& planes, int type) {
  std::vector<EXRChannelInfo> channels(names.size());
  std::vector<int> types(names.size(), type);
  std::vector<unsigned char*> pointers;
  for (std::size_t c = 0; c < names.size(); ++c) {
    std::memset(&channels[c], 0, sizeof(EXRChannelInfo));
    std::strncpy(channels[c].name, names[c].c_str(), 255);
    pointers.push_back(reinterpret_cast<unsigned char*>(const_cast<std::uint32_t*>(planes[c].data())));
  }
  EXRHeader header;
  InitEXRHeader(&header);
  header.num_channels = static_cast<int>(names.size());
  header.channels = channels.data();
  header.pixel_types = types.data();
  header.requested_pixel_types = types.data();
  header.compression_type = TINYEXR_COMPRESSIONTYPE_NONE;
  EXRImage image;
  InitEXRImage(&image);
  image.num_channels = static_cast<int>(names.size());
  image.images = pointers.data();
  image.width = width;
  image.height = height;
  const char* error = nullptr;
  REQUIRE(SaveEXRImageToFile(&image, &header, path.c_str(), &error) == TINYEXR_SUCCESS);
}

}  // namespace

TEST_CASE("image: sRGB transfer functions and 8-bit quantization", "[io][image]") {
  CHECK(srgb_encode(0.0f) == 0.0f);
  CHECK(srgb_encode(1.0f) == 1.0f);
  // The linear segment: 12.92 * 0.0031308 = 0.04044994; the power segment continues from there.
  CHECK(srgb_encode(0.0031308f) == Approx(0.04044994).epsilon(1e-6));
  CHECK(srgb_encode(0.0031309f) == Approx(0.04044994).epsilon(1e-4));
  // 0.5 -> 1.055 * 0.5^(1/2.4) - 0.055 = 1.055 * 0.749154 - 0.055 = 0.735357 (by hand).
  CHECK(srgb_encode(0.5f) == Approx(0.735357).epsilon(1e-5));
  CHECK(srgb_decode(0.735357f) == Approx(0.5).epsilon(1e-5));
  // 0.735357 * 255 = 187.52 -> code 188; 0.0031308 * 12.92 * 255 = 10.31 -> code 10.
  CHECK(quantize(0.5f) == 188);
  CHECK(quantize(0.0031308f) == 10);
  CHECK(quantize(0.0f) == 0);
  CHECK(quantize(1.0f) == 255);
  // Out of range and NaN clamp to a defined code.
  CHECK(quantize(-3.0f) == 0);
  CHECK(quantize(7.0f) == 255);
  CHECK(quantize(std::numeric_limits<float>::quiet_NaN()) == 0);
  CHECK(quantize(std::numeric_limits<float>::infinity()) == 255);
  // Every code survives decode + quantize, and decoding is strictly increasing.
  for (int code = 0; code < 256; ++code) {
    INFO("code " << code);
    CHECK(quantize(dequantize(static_cast<std::uint8_t>(code))) == code);
    if (code > 0) CHECK(dequantize(static_cast<std::uint8_t>(code)) > dequantize(static_cast<std::uint8_t>(code - 1)));
  }
  // Round to nearest: the encoded value is within half a code of the chosen code.
  Rng rng(1);
  for (int i = 0; i < 10000; ++i) {
    const float linear = rng.next();
    CHECK(std::abs(srgb_encode(linear) * 255.0f - quantize(linear)) <= 0.5f + 1e-4f);  // + float rounding of x*255
  }
}

TEST_CASE("image: the table quantizer equals the transfer function on every sampled float", "[io][image]") {
  // Every 61st bit pattern from 0 to just above 1 (about 17 million floats, so each code's boundary
  // region is sampled many times), then both sides of every threshold.
  std::int64_t mismatches = 0;
  for (std::uint32_t bits = 0; bits <= std::bit_cast<std::uint32_t>(1.001f); bits += 61) {
    const float linear = std::bit_cast<float>(bits);
    mismatches += quantize(linear) != quantize_direct(linear);
  }
  CHECK(mismatches == 0);
  for (const float threshold : image_detail::quantize_thresholds()) {
    const float below = std::nextafter(threshold, 0.0f);
    mismatches += quantize(threshold) != quantize_direct(threshold);
    mismatches += quantize(below) != quantize_direct(below);
    mismatches += quantize(below) == quantize(threshold);  // each threshold starts a new code
  }
  CHECK(mismatches == 0);
}

TEST_CASE("image: the bucket quantizer gives every float from 2^-16 to 1 the code the thresholds give", "[io][image]") {
  // Each bucket holds at most one threshold above its start (what one comparison relies on).
  const image_detail::QuantizeBuckets& buckets = image_detail::quantize_buckets();
  const std::array<float, 255>& thresholds = image_detail::quantize_thresholds();
  int crowded = 0;
  for (std::size_t i = 0; i < image_detail::QuantizeBuckets::count; ++i) {
    const std::uint32_t start = image_detail::QuantizeBuckets::first_bits + (std::uint32_t(i) << image_detail::QuantizeBuckets::shift);
    const float end = std::bit_cast<float>(start + (1u << image_detail::QuantizeBuckets::shift));  // the next bucket's start
    const std::size_t code = buckets.code[i];
    crowded += code + 1 < 255 && thresholds[code + 1] < end;
  }
  CHECK(crowded == 0);
  // Every float in turn, its code the number of thresholds at or below it (the definition the
  // table of thresholds encodes); below 2^-16 every code is 0.
  CHECK(quantize(std::bit_cast<float>(std::bit_cast<std::uint32_t>(0x1p-16f) - 1)) == 0);
  std::int64_t mismatches = 0;
  std::size_t code = 0;
  for (std::uint32_t bits = std::bit_cast<std::uint32_t>(0x1p-16f); bits <= std::bit_cast<std::uint32_t>(1.0f); ++bits) {
    const float linear = std::bit_cast<float>(bits);
    while (code < 255 && thresholds[code] <= linear) ++code;
    mismatches += quantize(linear) != code;
  }
  CHECK(mismatches == 0);
}

TEST_CASE("image: construction, access and quantizing a whole image", "[io][image]") {
  Image image(3, 2, glm::vec3(0.25f));
  CHECK(image.pixels.size() == 6);
  image(2, 1) = glm::vec3(1.0f, 0.0f, 0.5f);
  CHECK(image.at(2, 1) == glm::vec3(1.0f, 0.0f, 0.5f));
  CHECK(image.pixels[5] == glm::vec3(1.0f, 0.0f, 0.5f));  // row-major, top row first
  CHECK_THROWS_AS(image.at(3, 0), std::out_of_range);
  CHECK_THROWS_AS(image.at(0, -1), std::out_of_range);
  CHECK_THROWS_WITH(Image(0, 4), Catch::Contains("0 x 4"));
  CHECK_THROWS_AS(Image(-2, 4), std::invalid_argument);
  CHECK(Image().empty());

  const Rgb8Image rgb8 = quantize(image);
  CHECK(rgb8.width == 3);
  CHECK(rgb8.height == 2);
  CHECK(rgb8.pixel(2, 1)[0] == 255);
  CHECK(rgb8.pixel(2, 1)[1] == 0);
  CHECK(rgb8.pixel(2, 1)[2] == 188);
  CHECK(rgb8.pixel(0, 0)[0] == quantize(0.25f));
  const Image back = dequantize(rgb8);
  CHECK(back(2, 1).b == dequantize(std::uint8_t{188}));

  Image broken(2, 2);
  broken.pixels.pop_back();
  CHECK_THROWS_WITH(quantize(broken), Catch::Contains("3 pixels"));
}

TEST_CASE("image: PNG round trip keeps every value within 8-bit sRGB quantization", "[io][image]") {
  ScratchDirectory directory("png");
  const Image original = random_image(37, 23, 7, -0.1f, 1.2f);  // includes values that clamp
  const fs::path path = directory / "round_trip.png";
  write_image(path, original);
  const Image loaded = read_image(path);
  REQUIRE(loaded.width == 37);
  REQUIRE(loaded.height == 23);
  for (std::size_t i = 0; i < original.pixels.size(); ++i)
    for (int c = 0; c < 3; ++c) {
      INFO("pixel " << i << " channel " << c);
      // Exactly the decode of the nearest code; and within half a code in sRGB space.
      CHECK(loaded.pixels[i][c] == dequantize(quantize(original.pixels[i][c])));
      CHECK(std::abs(srgb_encode(loaded.pixels[i][c]) - srgb_encode(original.pixels[i][c])) <= 0.5f / 255.0f + 1e-6f);
    }

  // The file itself stores the top row first: decode it with stb directly.
  int width = 0, height = 0, channels = 0;
  unsigned char* raw = stbi_load(path.c_str(), &width, &height, &channels, 3);
  REQUIRE(raw != nullptr);
  CHECK(raw[0] == quantize(original(0, 0).r));
  CHECK(raw[(22 * 37 + 36) * 3 + 2] == quantize(original(36, 22).b));  // last pixel of the bottom row
  stbi_image_free(raw);

  // An Rgb8Image is written byte for byte.
  const Rgb8Image codes = quantize(original);
  const fs::path rgb8_path = directory / "codes.PNG";  // the extension's case does not matter
  write_image(rgb8_path, codes);
  CHECK(quantize(read_image(rgb8_path)).bytes == codes.bytes);
}

TEST_CASE("image: grey, grey + alpha and RGBA PNG files read as RGB", "[io][image]") {
  ScratchDirectory directory("png_channels");
  // 2 x 1 images written directly with stb: pixel 0 code 10, pixel 1 code 200 (alpha 77).
  const unsigned char grey[2] = {10, 200};
  const unsigned char grey_alpha[4] = {10, 77, 200, 77};
  const unsigned char rgba[8] = {10, 10, 10, 77, 200, 200, 200, 77};
  REQUIRE(stbi_write_png((directory / "grey.png").c_str(), 2, 1, 1, grey, 2) != 0);
  REQUIRE(stbi_write_png((directory / "grey_alpha.png").c_str(), 2, 1, 2, grey_alpha, 4) != 0);
  REQUIRE(stbi_write_png((directory / "rgba.png").c_str(), 2, 1, 4, rgba, 8) != 0);
  for (const char* name : {"grey.png", "grey_alpha.png", "rgba.png"}) {
    INFO(name);
    const Image image = read_image(directory / name);
    REQUIRE(image.width == 2);
    REQUIRE(image.height == 1);
    CHECK(image(0, 0) == glm::vec3(dequantize(std::uint8_t{10})));  // alpha is dropped, grey replicated
    CHECK(image(1, 0) == glm::vec3(dequantize(std::uint8_t{200})));
  }
}

TEST_CASE("image: EXR and PFM round trips are exact for 32-bit floats", "[io][image]") {
  ScratchDirectory directory("float");
  Image original = random_image(19, 31, 3, -2.0f, 50.0f);  // HDR and negative values
  original(0, 0) = glm::vec3(0.0f, 1e-30f, 3.4e38f);      // tiny and huge magnitudes
  for (const char* name : {"image.exr", "image.pfm"}) {
    INFO(name);
    const fs::path path = directory / name;
    write_image(path, original);
    const Image loaded = read_image(path);
    REQUIRE(loaded.width == original.width);
    REQUIRE(loaded.height == original.height);
    CHECK(loaded.pixels == original.pixels);
  }
}

TEST_CASE("image: half, grey and unsigned int EXR files are read as float RGB", "[io][image]") {
  ScratchDirectory directory("exr_kinds");
  // Half floats (tinyexr's SaveEXR with fp16): values exactly representable in half come back
  // exactly; 0.1 comes back as the nearest half, 0.0999755859375.
  const float rgb[6] = {0.5f, -3.0f, 1024.0f, 1.25f, 0.1f, 0.0f};
  const char* error = nullptr;
  REQUIRE(SaveEXR(rgb, 2, 1, 3, 1, (directory / "half.exr").c_str(), &error) == TINYEXR_SUCCESS);
  const Image half = read_image(directory / "half.exr");
  REQUIRE(half.width == 2);
  CHECK(half(0, 0) == glm::vec3(0.5f, -3.0f, 1024.0f));
  CHECK(half(1, 0) == glm::vec3(1.25f, 0.0999755859375f, 0.0f));

  // One channel of any name is grey.
  const std::vector<std::uint32_t> luminance_plane = {std::bit_cast<std::uint32_t>(0.25f), std::bit_cast<std::uint32_t>(4.0f)};
  write_custom_exr(directory / "grey.exr", 2, 1, {"Y"}, {luminance_plane}, TINYEXR_PIXELTYPE_FLOAT);
  const Image grey = read_image(directory / "grey.exr");
  CHECK(grey(0, 0) == glm::vec3(0.25f));
  CHECK(grey(1, 0) == glm::vec3(4.0f));

  // Unsigned int channels are converted to float values (not reinterpreted bits).
  write_custom_exr(directory / "uint.exr", 1, 1, {"B", "G", "R"}, {{3}, {2}, {70000}}, TINYEXR_PIXELTYPE_UINT);
  CHECK(read_image(directory / "uint.exr")(0, 0) == glm::vec3(70000.0f, 2.0f, 3.0f));

  // RGBA: alpha is ignored.
  const std::vector<std::uint32_t> one = {std::bit_cast<std::uint32_t>(1.0f)}, half_value = {std::bit_cast<std::uint32_t>(0.5f)};
  write_custom_exr(directory / "rgba.exr", 1, 1, {"A", "B", "G", "R"}, {half_value, one, half_value, one}, TINYEXR_PIXELTYPE_FLOAT);
  CHECK(read_image(directory / "rgba.exr")(0, 0) == glm::vec3(1.0f, 0.5f, 1.0f));

  // Two channels that are not R, G, B: an error listing them.
  write_custom_exr(directory / "uv.exr", 1, 1, {"U", "V"}, {one, one}, TINYEXR_PIXELTYPE_FLOAT);
  CHECK_THROWS_WITH(read_image(directory / "uv.exr"), Catch::Contains("uv.exr") && Catch::Contains("channels: U, V"));
}

TEST_CASE("image: PFM files are read in either byte order, grey or colour, bottom row first", "[io][image]") {
  ScratchDirectory directory("pfm");
  // A 2 x 2 colour image, big-endian (positive scale), rows stored bottom row first.
  std::vector<unsigned char> colour;
  for (const char c : std::string("PF\n2 2\n1.0\n")) colour.push_back(static_cast<unsigned char>(c));
  const float bottom_then_top[12] = {1, 2, 3, 4, 5, 6, /* top row: */ 7, 8, 9, 10, 11, 12};
  for (const float v : bottom_then_top) append_float(colour, v, true);
  write_bytes(directory / "colour.pfm", colour);
  const Image image = read_image(directory / "colour.pfm");
  CHECK(image(0, 0) == glm::vec3(7, 8, 9));  // top-left is the first pixel of the last file row
  CHECK(image(1, 0) == glm::vec3(10, 11, 12));
  CHECK(image(0, 1) == glm::vec3(1, 2, 3));
  CHECK(image(1, 1) == glm::vec3(4, 5, 6));

  // A 3 x 1 grey image, little-endian, header split by arbitrary whitespace.
  std::vector<unsigned char> grey;
  for (const char c : std::string("Pf  3\t1\n-2.5\n")) grey.push_back(static_cast<unsigned char>(c));
  for (const float v : {0.5f, -1.0f, 8.0f}) append_float(grey, v, false);
  write_bytes(directory / "grey.pfm", grey);
  const Image grey_image = read_image(directory / "grey.pfm");
  REQUIRE(grey_image.width == 3);
  CHECK(grey_image(1, 0) == glm::vec3(-1.0f));
  CHECK(grey_image(2, 0) == glm::vec3(8.0f));

  // What igi writes has the same layout: "PF", size, -1, then little-endian rows bottom first.
  Image written(1, 2);
  written(0, 0) = glm::vec3(1, 2, 3);  // top
  written(0, 1) = glm::vec3(4, 5, 6);  // bottom
  write_image(directory / "written.pfm", written);
  const std::vector<unsigned char> bytes = file_bytes(directory / "written.pfm");
  const std::string header = "PF\n1 2\n-1\n";
  REQUIRE(bytes.size() == header.size() + 24);
  CHECK(std::string(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(header.size())) == header);
  float first;
  std::memcpy(&first, bytes.data() + header.size(), 4);
  CHECK(first == 4.0f);  // the bottom row comes first
}

TEST_CASE("image: bad paths and unreadable files give errors naming the file", "[io][image]") {
  ScratchDirectory directory("errors");
  const Image image(4, 3, glm::vec3(0.5f));

  CHECK_THROWS_WITH(write_image(directory / "picture.jpg", image), Catch::Contains("picture.jpg") && Catch::Contains("unknown image extension '.jpg'"));
  CHECK_THROWS_WITH(read_image(directory / "noextension"), Catch::Contains("noextension") && Catch::Contains("unknown image extension"));
  CHECK_THROWS_WITH(read_image(directory / "missing.png"), Catch::Contains("missing.png") && Catch::Contains("does not exist"));
  fs::create_directory(directory / "folder.exr");
  CHECK_THROWS_WITH(read_image(directory / "folder.exr"), Catch::Contains("folder.exr") && Catch::Contains("not a regular file"));
  write_bytes(directory / "empty.pfm", {});
  CHECK_THROWS_WITH(read_image(directory / "empty.pfm"), Catch::Contains("empty.pfm") && Catch::Contains("empty"));
  CHECK_THROWS_AS(read_image(directory / "missing.png"), ImageError);

  // Garbage and truncated files of each format.
  write_bytes(directory / "garbage.png", {'n', 'o', 't', ' ', 'p', 'n', 'g'});
  CHECK_THROWS_WITH(read_image(directory / "garbage.png"), Catch::Contains("garbage.png") && Catch::Contains("not a readable PNG"));
  write_image(directory / "good.png", image);
  std::vector<unsigned char> png = file_bytes(directory / "good.png");
  png.resize(png.size() / 2);
  write_bytes(directory / "truncated.png", png);
  CHECK_THROWS_WITH(read_image(directory / "truncated.png"), Catch::Contains("truncated.png") && Catch::Contains("PNG"));

  write_bytes(directory / "garbage.exr", {'v', '/', '1', 0, 0, 0, 0, 0, 9, 9});
  CHECK_THROWS_WITH(read_image(directory / "garbage.exr"), Catch::Contains("garbage.exr") && Catch::Contains("not a readable EXR"));
  write_image(directory / "good.exr", image);
  std::vector<unsigned char> exr = file_bytes(directory / "good.exr");
  exr.resize(exr.size() * 2 / 3);
  write_bytes(directory / "truncated.exr", exr);
  CHECK_THROWS_WITH(read_image(directory / "truncated.exr"), Catch::Contains("truncated.exr") && Catch::Contains("EXR"));

  auto pfm_error = [&](const std::string& name, const std::string& header, std::size_t floats, const std::string& problem) {
    std::vector<unsigned char> bytes(header.begin(), header.end());
    for (std::size_t i = 0; i < floats; ++i) append_float(bytes, 0.25f, false);
    write_bytes(directory / name, bytes);
    INFO(name);
    CHECK_THROWS_WITH(read_image(directory / name), Catch::Contains(name) && Catch::Contains(problem));
  };
  pfm_error("magic.pfm", "P6\n2 2\n-1\n", 12, "not a PFM image");
  pfm_error("width.pfm", "PF\n-2 2\n-1\n", 12, "PFM width '-2'");
  pfm_error("height.pfm", "PF\n2 x\n-1\n", 12, "PFM height 'x'");
  pfm_error("huge.pfm", "PF\n1048576 1048576\n-1\n", 12, "too large");
  pfm_error("scale.pfm", "PF\n2 2\n0\n", 12, "PFM scale '0'");
  pfm_error("header.pfm", "PF\n2", 0, "header is truncated");
  pfm_error("short.pfm", "PF\n2 2\n-1\n", 11, "(truncated)");
  pfm_error("long.pfm", "PF\n2 2\n-1\n", 13, "(trailing bytes)");
  std::vector<unsigned char> nan_pfm;
  for (const char c : std::string("Pf\n2 1\n-1\n")) nan_pfm.push_back(static_cast<unsigned char>(c));
  append_float(nan_pfm, 1.0f, false);
  append_float(nan_pfm, std::numeric_limits<float>::quiet_NaN(), false);
  write_bytes(directory / "nan.pfm", nan_pfm);
  CHECK_THROWS_WITH(read_image(directory / "nan.pfm"), Catch::Contains("nan.pfm") && Catch::Contains("pixel (1, 0) is not finite"));
}

TEST_CASE("image: invalid images are refused before anything is written", "[io][image]") {
  ScratchDirectory directory("invalid");
  Image with_nan(3, 3, glm::vec3(0.5f));
  with_nan(2, 1).g = std::numeric_limits<float>::quiet_NaN();
  for (const char* name : {"nan.png", "nan.exr", "nan.pfm"}) {
    INFO(name);
    CHECK_THROWS_WITH(write_image(directory / name, with_nan), Catch::Contains(name) && Catch::Contains("pixel (2, 1) is not finite"));
  }
  Image wrong_size(3, 3);
  wrong_size.pixels.resize(7);
  CHECK_THROWS_WITH(write_image(directory / "size.exr", wrong_size), Catch::Contains("size.exr") && Catch::Contains("holds 7 pixels instead of 9"));
  CHECK_THROWS_WITH(write_image(directory / "empty.pfm", Image()), Catch::Contains("empty.pfm") && Catch::Contains("empty"));
  Rgb8Image short_codes(2, 2);
  short_codes.bytes.resize(9);
  CHECK_THROWS_AS(write_image(directory / "codes.png", short_codes), ImageError);
  CHECK(directory.entries().empty());  // nothing, not even a temporary file, was created
}

TEST_CASE("image: writes are atomic and leave no temporary files", "[io][image]") {
  ScratchDirectory directory("atomic");
  const fs::path path = directory / "frame.exr";
  const Image first(8, 4, glm::vec3(1.0f, 2.0f, 3.0f)), second(5, 5, glm::vec3(-4.0f));
  write_image(path, first);
  CHECK(read_image(path).pixels == first.pixels);
  write_image(path, second);  // replaces the file as a whole
  CHECK(read_image(path).pixels == second.pixels);
  CHECK(directory.entries() == std::vector<std::string>{"frame.exr"});

  // A failed write leaves the previous file untouched.
  Image bad = first;
  bad(0, 0).r = std::numeric_limits<float>::infinity();
  CHECK_THROWS_AS(write_image(path, bad), ImageError);
  CHECK(read_image(path).pixels == second.pixels);

  // A target that is a directory, or in a directory that does not exist, is refused cleanly.
  fs::create_directory(directory / "taken.pfm");
  CHECK_THROWS_WITH(write_image(directory / "taken.pfm", first), Catch::Contains("taken.pfm") && Catch::Contains("directory"));
  CHECK_THROWS_WITH(write_image(directory / "no_such_dir" / "out.png", first),
                    Catch::Contains("out.png") && Catch::Contains("does not exist"));
  std::vector<std::string> entries = directory.entries();
  std::sort(entries.begin(), entries.end());
  CHECK(entries == std::vector<std::string>{"frame.exr", "taken.pfm"});

  // A relative path with no directory part writes into the working directory.
  const fs::path previous = fs::current_path();
  fs::current_path(directory / "taken.pfm");
  write_image("relative.pfm", first);
  fs::current_path(previous);
  CHECK(read_image(directory / "taken.pfm" / "relative.pfm").pixels == first.pixels);
}
