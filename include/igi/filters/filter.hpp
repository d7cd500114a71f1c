#pragma once
/// \file
/// The filter policy and the tile G-buffer it reads. A filter reconstructs irradiance (and the
/// glossy VPL radiance) over a tile whose G-buffer carries a border of `border` pixels on each side.
///
/// The G-buffer is a structure of arrays: every channel is one padded float plane per component,
/// so that W neighbouring pixels of a row load as one `vfloat<W>`. Writers and readers that work
/// pixel by pixel index it like an array of `glm::vec3` (`g.normal[i] = n`, `glm::vec3 a = g.albedo[i]`).

#include <algorithm>
#include <concepts>
#include <cstddef>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace igi {

/// One float per pixel, row-major, with `padding` spare floats before the first pixel and after
/// the last: a SIMD row read that starts up to `padding` pixels before the plane or ends up to
/// `padding` pixels after it stays in memory (its lanes outside the plane are masked by the reader).
class PixelPlane {
 public:
  /// Spare floats on each side: the widest packet (64 lanes) or the farthest filter tap past a
  /// row's end, whichever a reader needs, fits in it.
  static constexpr std::size_t padding = 64;

  /// Sets `pixels` entries (and the padding) to `value`.
  void assign(std::size_t pixels, float value = 0.0f) {
    storage_.assign(pixels + 2 * padding, value);
    size_ = pixels;
  }
  /// Number of pixels.
  std::size_t size() const noexcept { return size_; }
  /// Pixel 0 (padding lies before it and after pixel size()-1).
  float* data() noexcept { return storage_.data() + padding; }
  /// Pixel 0, read-only.
  const float* data() const noexcept { return storage_.data() + padding; }
  /// Pixel `i`.
  float& operator[](std::size_t i) noexcept { return storage_[i + padding]; }
  /// Pixel `i`, read-only.
  float operator[](std::size_t i) const noexcept { return storage_[i + padding]; }

 private:
  std::vector<float> storage_;
  std::size_t size_ = 0;
};

/// A colour or direction per pixel as three planes (x, y, z): structure of arrays.
class Vec3Plane {
 public:
  /// Pixel `i` of a Vec3Plane as an assignable glm::vec3.
  class Reference {
   public:
    /// Pixel `i` of `planes`.
    Reference(Vec3Plane& planes, std::size_t i) noexcept : planes_(&planes), i_(i) {}
    /// Its value.
    operator glm::vec3() const noexcept { return {planes_->x[i_], planes_->y[i_], planes_->z[i_]}; }  // NOLINT: reads as a vec3
    /// Sets it.
    Reference& operator=(const glm::vec3& v) noexcept {
      planes_->x[i_] = v.x;
      planes_->y[i_] = v.y;
      planes_->z[i_] = v.z;
      return *this;
    }
    /// Adds `v` to it, component by component (as glm::vec3's +=).
    Reference& operator+=(const glm::vec3& v) noexcept {
      planes_->x[i_] += v.x;
      planes_->y[i_] += v.y;
      planes_->z[i_] += v.z;
      return *this;
    }

   private:
    Vec3Plane* planes_;
    std::size_t i_;
  };

  PixelPlane x;  ///< First components.
  PixelPlane y;  ///< Second components.
  PixelPlane z;  ///< Third components.

  /// Sets `pixels` entries to `value`.
  void assign(std::size_t pixels, const glm::vec3& value = glm::vec3(0.0f)) {
    x.assign(pixels, value.x);
    y.assign(pixels, value.y);
    z.assign(pixels, value.z);
  }
  /// Number of pixels (that of its smallest plane, so a plane resized alone shows).
  std::size_t size() const noexcept { return std::min(x.size(), std::min(y.size(), z.size())); }
  /// Pixel `i`.
  glm::vec3 operator[](std::size_t i) const noexcept { return {x[i], y[i], z[i]}; }
  /// Pixel `i`, assignable.
  Reference operator[](std::size_t i) noexcept { return {*this, i}; }
  /// All pixels as glm::vec3 (for tests and reports).
  std::vector<glm::vec3> to_vector() const {
    std::vector<glm::vec3> out(size());
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = (*this)[i];
    return out;
  }
};

/// A rectangle of `columns x rows` pixels copied from (source_x, source_y) of one row-major tile
/// buffer to (x, y) of another.
struct BlockCopy {
  int source_x = 0;  ///< First column read.
  int source_y = 0;  ///< First row read.
  int x = 0;         ///< First column written.
  int y = 0;         ///< First row written.
  int columns = 0;   ///< Pixels per row.
  int rows = 0;      ///< Rows.
};

/// Copies `block` from `from`, `from_width` pixels a row, into `to`, `to_width` pixels a row.
inline void copy_block(const PixelPlane& from, int from_width, PixelPlane& to, int to_width, const BlockCopy& block) {
  for (int row = 0; row < block.rows; ++row) {
    const float* in = from.data() + std::size_t(block.source_y + row) * std::size_t(from_width) + std::size_t(block.source_x);
    float* out = to.data() + std::size_t(block.y + row) * std::size_t(to_width) + std::size_t(block.x);
    // A border's columns are a pixel or a few wide: a call to memmove per row would cost more than the copy.
    if (block.columns <= 8)
      for (int column = 0; column < block.columns; ++column) out[column] = in[column];
    else
      std::copy_n(in, block.columns, out);
  }
}
/// copy_block on each of the three planes.
inline void copy_block(const Vec3Plane& from, int from_width, Vec3Plane& to, int to_width, const BlockCopy& block) {
  copy_block(from.x, from_width, to.x, to_width, block);
  copy_block(from.y, from_width, to.y, to_width, block);
  copy_block(from.z, from_width, to.z, to_width, block);
}

/// The delta lights' (point, spot, directional) shadow-ray answers at a pixel's first hit, one bit
/// per light as FrameState::delta_lights numbers them: what temporal reuse keeps so that the next
/// frame need not trace them again where its first hits see the same lights.
struct ShadowBits {
  std::uint32_t known = 0;    ///< Lights whose visibility is known.
  std::uint32_t visible = 0;  ///< Of those, the ones nothing blocks.
};

/// Per-pixel buffers of one tile plus its border, row-major, `width x height` including border.
/// With anti-aliasing each entry is the average over the pixel's primary rays.
struct TileGBuffer {
  int width = 0;          ///< Pixels per row, border included.
  int height = 0;         ///< Rows, border included.
  int border = 1;         ///< Border pixels on each side (what the filter may read).
  Vec3Plane irradiance;   ///< Unfiltered VPL irradiance (before albedo/pi), the delta lights' only with RenderSettings::filter_delta_lights.
  Vec3Plane glossy;       ///< Unfiltered glossy VPL radiance.
  Vec3Plane albedo;       ///< Diffuse albedo of the first hit (after texturing).
  Vec3Plane normal;       ///< Unit shading normal of the first hit; zero on a miss.
  PixelPlane depth;       ///< Distance of the first hit; 0 on a miss.
  Vec3Plane radiance;     ///< Unfiltered rest: emission, the delta lights' direct light, mirror/glass paths.
  PixelPlane hit;         ///< 1 where the first ray hit geometry, else 0 (floats, so a row loads as a SIMD mask).
  std::vector<ShadowBits> shadows;  ///< The delta lights' shadow answers at sub-sample 0's first hit (none known on a miss).

  /// Sets every buffer to `w x h` zeros.
  void resize(int w, int h) {
    width = w;
    height = h;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    irradiance.assign(n);
    glossy.assign(n);
    albedo.assign(n);
    normal.assign(n);
    depth.assign(n);
    radiance.assign(n);
    hit.assign(n);
    shadows.assign(n, ShadowBits{});
  }
  /// Index of pixel (x, y) in the buffers.
  std::size_t index(int x, int y) const noexcept { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
  /// Copies `block` of every buffer from `source` into this one (both rectangles must lie inside
  /// their buffers). `with_radiance` false leaves `radiance` and `shadows` out: a border needs
  /// only what the filters read.
  void copy_from(const TileGBuffer& source, const BlockCopy& block, bool with_radiance = true) {
    for (Vec3Plane TileGBuffer::*planes :
         {&TileGBuffer::irradiance, &TileGBuffer::glossy, &TileGBuffer::albedo, &TileGBuffer::normal, &TileGBuffer::radiance}) {
      if (planes == &TileGBuffer::radiance && !with_radiance) continue;
      copy_block(source.*planes, source.width, this->*planes, width, block);
    }
    copy_block(source.depth, source.width, depth, width, block);
    copy_block(source.hit, source.width, hit, width, block);
    if (with_radiance)
      for (int row = 0; row < block.rows; ++row)
        std::copy_n(source.shadows.begin() + std::ptrdiff_t(source.index(block.source_x, block.source_y + row)), block.columns,
                    shadows.begin() + std::ptrdiff_t(index(block.x, block.y + row)));
  }
};

/// Filtered irradiance and glossy radiance of a tile's interior (border excluded), row-major.
struct FilteredTile {
  int width = 0;         ///< Interior pixels per row.
  int height = 0;        ///< Interior rows.
  Vec3Plane irradiance;  ///< Filtered irradiance.
  Vec3Plane glossy;      ///< Filtered glossy radiance.
};

/// Border of the S x S window around a pixel: offsets -(S/2) .. S-1-(S/2), so S/2 pixels (1 for
/// the paper's 3 x 3). What the window filters need rendered around a tile.
inline constexpr int window_border(int interleave) noexcept { return interleave / 2; }

/// A filter reconstructs the interior of a tile from its G-buffer. `interleave` is S: the window
/// that removes the interleaving pattern is S x S. `border(S)` is how many pixels around a tile
/// the filter reads: the pipeline renders that many, and with them the filtered image does not
/// depend on the tile size.
template <class F>
concept Filter = requires(const F& filter, const TileGBuffer& gbuffer, int interleave, FilteredTile& out) {
  { F::name() } -> std::convertible_to<const char*>;
  { filter.border(interleave) } -> std::convertible_to<int>;
  { filter.apply(gbuffer, interleave, out) } -> std::same_as<void>;
};

/// A Filter that can also run as a cascade of `stage_count()` stages over the tiles of one
/// process, which share their borders (TileEngine::render_frame), each stage computing only the
/// tile's own pixels: `run_stage(0, ...)` reads the tile's G-buffer, border included;
/// `run_stage(k, ...)` for k > 0 reads stage k-1's output within `stage_reach(k)` pixels of the
/// tile, which the caller first copies into the tile's border from its neighbours' own stage k-1
/// output with `copy_stage(k - 1, neighbour, block, tile)`; `finish` writes the last stage's
/// result. A stage leaves the border of its own output for the next stage's copies to fill (and
/// zero outside the image), so the result is `apply`'s, pixel for pixel, with no pixel filtered
/// again for every tile whose border holds it. `staged_border(S)` is the border such a tile
/// needs (of its G-buffer and of each stage's output): the farthest any one stage reads, at most
/// `border(S)`, which is what all stages read together when they run over one tile alone.
template <class F>
concept StagedFilter =
    Filter<F> && std::default_initializable<typename F::TileStages> &&
    requires(const F& filter, const TileGBuffer& gbuffer, int interleave, int stage, typename F::TileStages& tile,
             const typename F::TileStages& neighbour, const BlockCopy& block, FilteredTile& out) {
      { filter.stage_count() } -> std::convertible_to<int>;
      { filter.stage_reach(stage) } -> std::convertible_to<int>;
      { filter.staged_border(interleave) } -> std::convertible_to<int>;
      { filter.run_stage(stage, gbuffer, interleave, tile) } -> std::same_as<void>;
      { filter.copy_stage(stage, neighbour, block, tile) } -> std::same_as<void>;
      { filter.finish(gbuffer, tile, out) } -> std::same_as<void>;
    };

/// What a tile keeps between the stages of filter `F`: `F::TileStages` for a StagedFilter,
/// an empty type for the others (which run whole, Filter::apply).
template <class F>
struct FilterStages {
  struct type {};  ///< Nothing.
};
/// A StagedFilter's tile stages.
template <StagedFilter F>
struct FilterStages<F> {
  using type = typename F::TileStages;  ///< Its type.
};

}  // namespace igi
