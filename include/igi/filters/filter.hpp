#pragma once
/// \file
/// The filter policy and the tile G-buffer it reads. A filter reconstructs irradiance (and the
/// glossy VPL radiance) over a tile whose G-buffer carries a border of `border` pixels on each side.

#include <concepts>
#include <cstdint>
#include <vector>

#include <glm/glm.hpp>

namespace igi {

/// Per-pixel buffers of one tile plus its border, row-major, `width x height` including border.
/// With anti-aliasing each entry is the average over the pixel's primary rays.
struct TileGBuffer {
  int width = 0;                        ///< Pixels per row, border included.
  int height = 0;                       ///< Rows, border included.
  int border = 1;                       ///< Border pixels on each side (what the filter may read).
  std::vector<glm::vec3> irradiance;    ///< Unfiltered VPL irradiance (before albedo/pi).
  std::vector<glm::vec3> glossy;        ///< Unfiltered glossy VPL radiance.
  std::vector<glm::vec3> albedo;        ///< Diffuse albedo of the first hit (after texturing).
  std::vector<glm::vec3> normal;        ///< Unit shading normal of the first hit; zero on a miss.
  std::vector<float> depth;             ///< Distance of the first hit; 0 on a miss.
  std::vector<glm::vec3> radiance;      ///< Unfiltered rest: emission and mirror/glass paths.
  std::vector<std::uint8_t> hit;        ///< 1 where the first ray hit geometry.

  /// Sets every buffer to `w x h` zeros.
  void resize(int w, int h) {
    width = w;
    height = h;
    const std::size_t n = std::size_t(w) * std::size_t(h);
    irradiance.assign(n, glm::vec3(0.0f));
    glossy.assign(n, glm::vec3(0.0f));
    albedo.assign(n, glm::vec3(0.0f));
    normal.assign(n, glm::vec3(0.0f));
    depth.assign(n, 0.0f);
    radiance.assign(n, glm::vec3(0.0f));
    hit.assign(n, 0);
  }
  /// Index of pixel (x, y) in the buffers.
  std::size_t index(int x, int y) const noexcept { return std::size_t(y) * std::size_t(width) + std::size_t(x); }
};

/// Filtered irradiance and glossy radiance of a tile's interior (border excluded).
struct FilteredTile {
  int width = 0;                      ///< Interior pixels per row.
  int height = 0;                     ///< Interior rows.
  std::vector<glm::vec3> irradiance;  ///< Filtered irradiance.
  std::vector<glm::vec3> glossy;      ///< Filtered glossy radiance.
};

/// A filter reconstructs the interior of a tile from its G-buffer. `interleave` is S: the window
/// that removes the interleaving pattern is S x S.
template <class F>
concept Filter = requires(const F& filter, const TileGBuffer& gbuffer, int interleave, FilteredTile& out) {
  { F::name() } -> std::convertible_to<const char*>;
  { filter.apply(gbuffer, interleave, out) } -> std::same_as<void>;
};

}  // namespace igi
