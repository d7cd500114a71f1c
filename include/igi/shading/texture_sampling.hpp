#pragma once
/// \file
/// Texture lookups for surface shaders: sRGB decoding through a 256-entry table and bilinear
/// filtering with repeat wrapping (glTF's default sampler).

#include <array>
#include <cmath>
#include <cstdint>

#include <glm/glm.hpp>

#include "igi/scene/scene.hpp"

namespace igi {

/// Linear value of every 8-bit sRGB code (IEC 61966-2-1 transfer curve), built once.
inline const std::array<float, 256>& srgb_to_linear_table() noexcept {
  static const std::array<float, 256> table = [] {
    std::array<float, 256> t{};
    for (int code = 0; code < 256; ++code) {
      const float c = float(code) / 255.0f;
      // The standard's constants: linear segment below 0.04045, gamma 2.4 curve above.
      t[std::size_t(code)] = c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
    }
    return t;
  }();
  return table;
}

/// RGBA of texel (x, y), linear (colour decoded from sRGB if the texture is sRGB; alpha never is).
inline glm::vec4 texel(const Texture& texture, int x, int y) noexcept {
  const std::uint8_t* p = &texture.texels[(std::size_t(y) * std::size_t(texture.width) + std::size_t(x)) * 4];
  if (texture.srgb) {
    const auto& table = srgb_to_linear_table();
    return {table[p[0]], table[p[1]], table[p[2]], float(p[3]) / 255.0f};
  }
  return glm::vec4(p[0], p[1], p[2], p[3]) / 255.0f;
}

/// Bilinear lookup at texture coordinates `uv` with repeat wrapping; texel centres sit at
/// (i + 0.5) / size and v = 0 is the top row (glTF). Non-finite coordinates read texel (0, 0);
/// an empty or malformed texture reads opaque white, so a broken file cannot crash shading.
inline glm::vec4 sample_bilinear(const Texture& texture, glm::vec2 uv) noexcept {
  if (texture.width <= 0 || texture.height <= 0 ||
      texture.texels.size() < std::size_t(texture.width) * std::size_t(texture.height) * 4)
    return glm::vec4(1.0f);
  if (!std::isfinite(uv.x)) uv.x = 0.0f;
  if (!std::isfinite(uv.y)) uv.y = 0.0f;
  // Wrap first so that huge coordinates never overflow the integer texel index.
  uv -= glm::floor(uv);
  const float x = uv.x * float(texture.width) - 0.5f;
  const float y = uv.y * float(texture.height) - 0.5f;
  const float x_floor = std::floor(x), y_floor = std::floor(y);
  const float fx = x - x_floor, fy = y - y_floor;
  // The wrapped uv lies in [0, 1] (1 where a tiny negative coordinate rounds up), so x and y lie
  // in [-0.5, size - 0.5] (a few units more only where float(size) rounds, above 2^24 texels):
  // the neighbours lie within one period of the texture, and one addition or subtraction wraps
  // them. (Integer division here, two per neighbour, cost a tenth of the surface stage.)
  const auto wrap = [](int i, int size) { return i < 0 ? i + size : i >= size ? i - size : i; };
  const int x0 = wrap(int(x_floor), texture.width), x1 = wrap(int(x_floor) + 1, texture.width);
  const int y0 = wrap(int(y_floor), texture.height), y1 = wrap(int(y_floor) + 1, texture.height);
  const glm::vec4 top = glm::mix(texel(texture, x0, y0), texel(texture, x1, y0), fx);
  const glm::vec4 bottom = glm::mix(texel(texture, x0, y1), texel(texture, x1, y1), fx);
  return glm::mix(top, bottom, fy);
}

}  // namespace igi
