#pragma once
/// \file
/// Texture lookups for surface shaders: sRGB decoding through a 256-entry table, bilinear
/// filtering with repeat wrapping (glTF's default sampler), and mip chains (`TextureMips`) read
/// trilinearly at a hit's footprint (`sample_filtered`), so a single ray per pixel sees the
/// texture averaged over the pixel instead of one point of it.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/parallel_for.h>

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

/// glm::mix(a, b, t) (the same arithmetic, a (1 - t) + b t), always inlined.
// The lookups below are always inlined, down to this mix: with the mip chains' callers GCC 12
// stopped inlining texel, sample_bilinear, glm::mix's helper and sample_filtered into the
// shader's lane loop, which cost Sponza_lit's frames 3-5% (perf: 12.7% of the samples in those
// calls against 9.9% in the inlined loop before).
[[gnu::always_inline]] inline glm::vec4 mix_texels(const glm::vec4& a, const glm::vec4& b, float t) noexcept {
  const float s = 1.0f - t;  // per component: GCC left glm's vec4 operators out of line here
  return {a.x * s + b.x * t, a.y * s + b.y * t, a.z * s + b.z * t, a.w * s + b.w * t};
}

/// RGBA of texel (x, y), linear (colour decoded from sRGB if the texture is sRGB; alpha never is).
[[gnu::always_inline]] inline glm::vec4 texel(const Texture& texture, int x, int y) noexcept {
  const std::uint8_t* p = &texture.texels[(std::size_t(y) * std::size_t(texture.width) + std::size_t(x)) * 4];
  if (texture.srgb) {
    const auto& table = srgb_to_linear_table();
    return {table[p[0]], table[p[1]], table[p[2]], float(p[3]) / 255.0f};
  }
  return {float(p[0]) / 255.0f, float(p[1]) / 255.0f, float(p[2]) / 255.0f, float(p[3]) / 255.0f};
}

/// Bilinear lookup at texture coordinates `uv` with repeat wrapping; texel centres sit at
/// (i + 0.5) / size and v = 0 is the top row (glTF). Non-finite coordinates read texel (0, 0);
/// an empty or malformed texture reads opaque white, so a broken file cannot crash shading.
[[gnu::always_inline]] inline glm::vec4 sample_bilinear(const Texture& texture, glm::vec2 uv) noexcept {
  if (texture.width <= 0 || texture.height <= 0 ||
      texture.texels.size() < std::size_t(texture.width) * std::size_t(texture.height) * 4)
    return glm::vec4(1.0f);
  if (!std::isfinite(uv.x)) uv.x = 0.0f;
  if (!std::isfinite(uv.y)) uv.y = 0.0f;
  // Wrap first so that huge coordinates never overflow the integer texel index.
  uv.x -= std::floor(uv.x);
  uv.y -= std::floor(uv.y);
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
  const glm::vec4 top = mix_texels(texel(texture, x0, y0), texel(texture, x1, y0), fx);
  const glm::vec4 bottom = mix_texels(texel(texture, x0, y1), texel(texture, x1, y1), fx);
  return mix_texels(top, bottom, fy);
}

namespace texture_detail {

/// What nearest_srgb_code looks up: the midpoints between consecutive codes' linear values, and
/// per bin of [0, 1] (4096 bins) the number of midpoints below the bin's start.
struct SrgbEncoding {
  /// 4096 bins: narrower than the closest codes' spacing (3e-4 at the dark end), so a bin holds
  /// at most one midpoint and a lookup takes at most one step past its start.
  static constexpr int bins = 4096;
  std::array<float, 255> midpoint{};           ///< Between code c and c + 1.
  std::array<std::uint8_t, bins + 1> start{};  ///< Midpoints below bin b's lower end.
};

/// The tables of nearest_srgb_code, built once.
inline const SrgbEncoding& srgb_encoding() noexcept {
  static const SrgbEncoding encoding = [] {
    SrgbEncoding e;
    const auto& table = srgb_to_linear_table();
    for (std::size_t c = 0; c < 255; ++c) e.midpoint[c] = 0.5f * (table[c] + table[c + 1]);
    std::size_t below = 0;
    for (int b = 0; b <= SrgbEncoding::bins; ++b) {
      const float lower = float(b) / float(SrgbEncoding::bins);
      while (below < 255 && e.midpoint[below] < lower) ++below;
      e.start[std::size_t(b)] = std::uint8_t(below);
    }
    return e;
  }();
  return encoding;
}

}  // namespace texture_detail

/// The 8-bit sRGB code whose linear value (srgb_to_linear_table) lies nearest `linear` (the lower
/// code on a tie), so a box-filtered texel keeps its linear mean as well as 8 bits can: the
/// number of midpoints between codes below `linear`, counted from its bin's start.
inline std::uint8_t nearest_srgb_code(float linear) noexcept {
  if (!(linear > 0.0f)) return 0;  // NaN too
  if (linear >= 1.0f) return 255;
  const texture_detail::SrgbEncoding& e = texture_detail::srgb_encoding();
  int code = e.start[std::size_t(linear * float(texture_detail::SrgbEncoding::bins))];
  while (code < 255 && e.midpoint[std::size_t(code)] < linear) ++code;
  return std::uint8_t(code);
}

namespace texture_detail {

/// Source texels and weights of one output texel of a box downsampling along one axis.
struct BoxTaps {
  int first = 0;              ///< First source texel.
  int count = 0;              ///< Source texels (at most 3: an output texel spans below 3 source ones).
  float weight[3] = {0, 0, 0};  ///< Their weights, summing to 1.
};

/// The box filter from `size` texels to `reduced` (<= size): output texel i covers the source
/// interval [i size / reduced, (i + 1) size / reduced), each source texel weighted by its overlap.
inline std::vector<BoxTaps> box_taps(int size, int reduced) {
  std::vector<BoxTaps> taps(static_cast<std::size_t>(reduced));
  const double span = double(size) / double(reduced);
  for (int i = 0; i < reduced; ++i) {
    const double start = i * span, end = (i + 1) * span;
    BoxTaps& t = taps[std::size_t(i)];
    t.first = int(std::floor(start));
    for (int j = t.first; j < size && double(j) < end && t.count < 3; ++j)
      t.weight[t.count++] = float((std::min(end, double(j + 1)) - std::max(start, double(j))) / span);
  }
  return taps;
}

/// `texture` box-filtered to half its size (rounded down, at least 1), in linear space: sRGB
/// colour is decoded, averaged and encoded again (alpha is linear).
inline Texture half_size(const Texture& texture) {
  Texture out;
  out.name = texture.name;
  out.srgb = texture.srgb;
  out.width = std::max(1, texture.width / 2);
  out.height = std::max(1, texture.height / 2);
  out.texels.resize(std::size_t(out.width) * std::size_t(out.height) * 4);
  const std::vector<BoxTaps> columns = box_taps(texture.width, out.width), rows = box_taps(texture.height, out.height);
  // Rows on oneTBB's threads (a 4096^2 texture's first level is 4 M texels); each texel alone.
  tbb::parallel_for(0, out.height, [&](int y) {
    for (int x = 0; x < out.width; ++x) {
      glm::vec4 sum(0.0f);
      const BoxTaps& row = rows[std::size_t(y)];
      const BoxTaps& column = columns[std::size_t(x)];
      for (int b = 0; b < row.count; ++b)
        for (int a = 0; a < column.count; ++a)
          sum += column.weight[a] * row.weight[b] * texel(texture, column.first + a, row.first + b);
      std::uint8_t* p = &out.texels[(std::size_t(y) * std::size_t(out.width) + std::size_t(x)) * 4];
      for (int c = 0; c < 3; ++c)
        p[c] = texture.srgb ? nearest_srgb_code(sum[c]) : std::uint8_t(std::lround(std::clamp(sum[c], 0.0f, 1.0f) * 255.0f));
      p[3] = std::uint8_t(std::lround(std::clamp(sum.w, 0.0f, 1.0f) * 255.0f));
    }
  });
  return out;
}

}  // namespace texture_detail

/// A texture's mip chain: level 0 is the texture itself (borrowed: it must outlive the chain),
/// each further level half the one before (rounded down, at least one texel) down to 1 x 1,
/// box-filtered in linear space. An empty or malformed texture has level 0 alone.
class TextureMips {
 public:
  /// The chain of `texture`.
  explicit TextureMips(const Texture& texture) : base_(&texture) {
    if (texture.width <= 0 || texture.height <= 0 ||
        texture.texels.size() < std::size_t(texture.width) * std::size_t(texture.height) * 4)
      return;
    for (;;) {
      const Texture& last = smaller_.empty() ? texture : smaller_.back();
      if (last.width == 1 && last.height == 1) break;
      Texture next = texture_detail::half_size(last);  // before push_back, which may move `last`
      smaller_.push_back(std::move(next));
    }
  }
  /// Levels, level 0 included.
  int count() const noexcept { return 1 + int(smaller_.size()); }
  /// Level `k` in [0, count()).
  const Texture& level(int k) const noexcept { return k == 0 ? *base_ : smaller_[std::size_t(k - 1)]; }

 private:
  const Texture* base_;
  std::vector<Texture> smaller_;
};

/// Trilinear lookup at `uv` for a footprint `footprint` texture coordinates wide: the average of
/// the texture over a box that wide, as well as mip levels give it. A level's texel of side s is
/// a box of that side, and bilinear interpolation between texels adds a tent of half-width s:
/// variance s^2 / 12 + s^2 / 6 = s^2 / 4, which equals the footprint box's f^2 / 12 at s = f /
/// sqrt(3). So the levels read are the two whose texels are nearest f / sqrt(3), bilinear in
/// each, blended by log2 of it (texels of f itself blurred a textured floor seen at 64 x 48 and
/// Sponza_lit more: RMSE against the pixels' averages 0.050 against 0.041, Sponza_lit's 0.0726
/// against 0.0724). A footprint of at most sqrt(3) texels of level 0 (magnification), zero or
/// not finite reads level 0 alone, exactly as sample_bilinear.
[[gnu::always_inline]] inline glm::vec4 sample_filtered(const TextureMips& mips, glm::vec2 uv, float footprint) noexcept {
  const Texture& base = mips.level(0);
  // The level-0 texels of the level whose kernel matches the footprint's box; the geometric mean
  // of the sides sizes a non-square texture's texel.
  constexpr float inverse_sqrt3 = 0.577350269f;
  const float texels = footprint * inverse_sqrt3 * std::sqrt(float(base.width) * float(base.height));
  if (!(texels > 1.0f) || !std::isfinite(texels) || mips.count() == 1) return sample_bilinear(base, uv);
  const float level = std::min(std::log2(texels), float(mips.count() - 1));
  const int lower = int(level);
  const float fraction = level - float(lower);
  const glm::vec4 near = sample_bilinear(mips.level(lower), uv);
  if (lower + 1 >= mips.count() || fraction == 0.0f) return near;
  return mix_texels(near, sample_bilinear(mips.level(lower + 1), uv), fraction);
}

}  // namespace igi
