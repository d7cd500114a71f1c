#pragma once
/// \file
/// Tiles, interleaving sets and the grouping of primary rays into packets per set (the paper's
/// Figure 2): a packet holds W pixels of ONE set that are neighbours in that set's sub-grid, so
/// every ray of a packet connects to the same VPLs and its shadow rays stay coherent.

#include <algorithm>
#include <vector>

#include <glm/glm.hpp>

namespace igi {

/// A rectangle of pixels, [x0, x1) x [y0, y1).
struct PixelRect {
  ///@{
  int x0 = 0, y0 = 0, x1 = 0, y1 = 0;  ///< Corners.
  ///@}
  /// Pixels per row.
  int width() const noexcept { return x1 - x0; }
  /// Rows.
  int height() const noexcept { return y1 - y0; }
  /// True if no pixel is inside.
  bool empty() const noexcept { return x1 <= x0 || y1 <= y0; }
};

/// The tiles of a `width x height` image, row by row, each at most `tile_size` on a side.
inline std::vector<PixelRect> make_tiles(int width, int height, int tile_size) {
  std::vector<PixelRect> tiles;
  for (int y = 0; y < height; y += tile_size)
    for (int x = 0; x < width; x += tile_size)
      tiles.push_back({x, y, std::min(x + tile_size, width), std::min(y + tile_size, height)});
  return tiles;
}

/// The interleaving set of pixel (x, y): sets are numbered row-major over the S x S pattern, and
/// the pattern is anchored at the image origin so it continues seamlessly across tiles.
inline int interleaving_set(int x, int y, int interleave) noexcept {
  return (y % interleave) * interleave + (x % interleave);
}

/// Width and height, in sub-grid pixels, of a W-ray packet: as square as W allows.
template <int W>
struct PacketShape {
  static constexpr int width = W >= 64 ? 8 : W >= 16 ? 4 : W >= 4 ? 2 : 1;  ///< Columns.
  static constexpr int height = W / width;                                 ///< Rows.
  static_assert(width * height == W, "packet widths are powers of two");
};

/// The pixels of one packet: up to W of them, in lane order, `count` valid.
template <int W>
struct PixelPacket {
  int x[W];       ///< Pixel columns (image coordinates); lanes past `count` repeat lane 0's (make_set_packets).
  int y[W];       ///< Pixel rows; lanes past `count` repeat lane 0's.
  int count = 0;  ///< Valid lanes 0..count-1; the rest are masked off, never traced as rays.
};

/// Splits the pixels of set `set` inside `region` into packets of W sub-grid neighbours (blocks of
/// PacketShape<W> in the set's sub-grid, which has stride S in the image).
template <int W>
void make_set_packets(const PixelRect& region, int interleave, int set, std::vector<PixelPacket<W>>& packets) {
  packets.clear();
  const int sx = set % interleave;
  const int sy = set / interleave;
  // First pixel of the set at or after the region's corner.
  auto first = [interleave](int start, int offset) {
    const int r = ((start % interleave) + interleave) % interleave;
    return start + ((offset - r + interleave) % interleave);
  };
  const int fx = first(region.x0, sx);
  const int fy = first(region.y0, sy);
  if (fx >= region.x1 || fy >= region.y1) return;
  const int columns = (region.x1 - 1 - fx) / interleave + 1;  // sub-grid size
  const int rows = (region.y1 - 1 - fy) / interleave + 1;
  using Shape = PacketShape<W>;
  for (int by = 0; by < rows; by += Shape::height)
    for (int bx = 0; bx < columns; bx += Shape::width) {
      PixelPacket<W> p;
      for (int j = 0; j < Shape::height; ++j)
        for (int i = 0; i < Shape::width; ++i) {
          const int gx = bx + i, gy = by + j;
          if (gx >= columns || gy >= rows) continue;
          p.x[p.count] = fx + gx * interleave;
          p.y[p.count] = fy + gy * interleave;
          ++p.count;
        }
      // Lanes past the count repeat the first pixel, so whole packets of coordinates can be
      // loaded and used as indices (masked off afterwards).
      for (int i = p.count; i < W; ++i) {
        p.x[i] = p.x[0];
        p.y[i] = p.y[0];
      }
      packets.push_back(p);
    }
}

/// Position inside the pixel of anti-aliasing sub-sample `k` of `n`: a stratified grid of
/// ceil(sqrt(n))^2 cells, the point `within` of cell k (in [0, 1)^2; the default, the cell's
/// centre, gives the pixel centre for n = 1).
inline void subsample_offset(int k, int n, float& dx, float& dy, glm::vec2 within = glm::vec2(0.5f)) noexcept {
  int side = 1;
  while (side * side < n) ++side;
  dx = (float(k % side) + within.x) / float(side);
  dy = (float(k / side) + within.y) / float(side);
}

}  // namespace igi
