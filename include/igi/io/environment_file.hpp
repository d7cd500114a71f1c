#pragma once
/// \file
/// Environment maps from files: an equirectangular image of linear radiance (.exr, .hdr, .pfm;
/// a .png is read as sRGB and lights dimly), +Y up, its top row the zenith (scene/environment.hpp).

#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "igi/io/image_files.hpp"
#include "igi/scene/environment.hpp"

namespace igi {

/// The environment in the image at `path`, its radiance times `scale`, turned by
/// `rotation_degrees` about +Y. Throws ImageError naming the file for one that is missing,
/// unreadable, or holds a negative or non-finite texel, or a bad scale or rotation.
inline std::shared_ptr<const Environment> read_environment(const std::filesystem::path& path, float scale = 1.0f,
                                                           float rotation_degrees = 0.0f) {
  Image image = read_image(path);
  try {
    return std::make_shared<const Environment>(path.filename().string(), image.width, image.height, std::move(image.pixels),
                                               scale, rotation_degrees * (std::numbers::pi_v<float> / 180.0f));
  } catch (const std::invalid_argument& error) {
    throw ImageError(path.string() + ": " + error.what());
  }
}

}  // namespace igi
