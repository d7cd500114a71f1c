#pragma once
/// \file
/// The filters: `DiscontinuityFilter` (the paper's discontinuity buffer: an S x S average over
/// neighbours on the same surface), `BoxFilter` (the same window without the surface test, to
/// show why the test matters) and `NoFilter`. All filter only irradiance and glossy radiance;
/// albedo (textures) is applied afterwards, so texture detail stays sharp.
///
/// The window for interleave S is S x S pixels: offsets -(S/2) .. S-1-(S/2) in x and y, the 3x3
/// neighbourhood around the pixel for S = 3. Any S consecutive pixels hold one pixel of every
/// interleaving set, so the window averages all S^2 VPL sets. Pixels of the window outside the
/// G-buffer (border narrower than the window) are skipped.
///
/// The filters run over the structure-of-arrays G-buffer one row vector of W pixels at a time;
/// each pixel sums its neighbours in the order the scalar loop would, so the images do not depend
/// on W or on the ISA.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "igi/filters/filter.hpp"
#include "igi/simd/lanes.hpp"
#include "igi/simd/vec3.hpp"

namespace igi {

namespace filter_detail {

/// Lanes of the filters' row vectors: one native register of floats of the build's ISA (4 with
/// SSE, 8 with AVX2, 16 with AVX-512), the width at which a row operation costs one instruction.
inline constexpr int row_lanes = detail::native_lanes;

/// Throws std::invalid_argument unless `gbuffer` is consistent and `interleave` >= 1.
inline void check_filter_input(const char* filter, const TileGBuffer& gbuffer, int interleave) {
  const auto fail = [&](const std::string& what) { throw std::invalid_argument(std::string(filter) + ": " + what); };
  if (interleave < 1) fail("interleave must be at least 1, got " + std::to_string(interleave));
  if (gbuffer.width < 0 || gbuffer.height < 0 || gbuffer.border < 0)
    fail("G-buffer size " + std::to_string(gbuffer.width) + "x" + std::to_string(gbuffer.height) + " border " +
         std::to_string(gbuffer.border) + " is negative");
  if (2 * gbuffer.border > gbuffer.width || 2 * gbuffer.border > gbuffer.height)
    fail("G-buffer border " + std::to_string(gbuffer.border) + " does not fit in " + std::to_string(gbuffer.width) +
         "x" + std::to_string(gbuffer.height));
  const std::size_t n = std::size_t(gbuffer.width) * std::size_t(gbuffer.height);
  if (gbuffer.irradiance.size() != n || gbuffer.glossy.size() != n || gbuffer.normal.size() != n ||
      gbuffer.depth.size() != n || gbuffer.hit.size() != n || gbuffer.albedo.size() != n)
    fail("G-buffer arrays do not all hold width x height = " + std::to_string(n) + " entries");
}
/// check_filter_input, then sizes `out` to the interior of `gbuffer`, zeroed.
inline void prepare_filter(const char* filter, const TileGBuffer& gbuffer, int interleave, FilteredTile& out) {
  check_filter_input(filter, gbuffer, interleave);
  out.width = gbuffer.width - 2 * gbuffer.border;
  out.height = gbuffer.height - 2 * gbuffer.border;
  const std::size_t interior = std::size_t(out.width) * std::size_t(out.height);
  out.irradiance.assign(interior);
  out.glossy.assign(interior);
}

/// W pixels of `plane` from pixel `i` on (i may lie up to PixelPlane::padding outside the plane).
template <int W>
[[gnu::always_inline]] inline vfloat<W> load(const PixelPlane& plane, std::ptrdiff_t i) noexcept {
  return vfloat<W>::load(plane.data() + i);
}
/// W pixels of `planes` from pixel `i` on.
template <int W>
[[gnu::always_inline]] inline vec3<W> load(const Vec3Plane& planes, std::ptrdiff_t i) noexcept {
  return {load<W>(planes.x, i), load<W>(planes.y, i), load<W>(planes.z, i)};
}
/// Stores W pixels of `planes` from pixel `i` on (lanes past a row's end land in the next row,
/// written again when that row is filtered, or in the padding after the last row).
template <int W>
[[gnu::always_inline]] inline void store(const vec3<W>& value, Vec3Plane& planes, std::ptrdiff_t i) noexcept {
  value.x.store(planes.x.data() + i);
  value.y.store(planes.y.data() + i);
  value.z.store(planes.z.data() + i);
}
/// The lanes whose column x + lane lies in [0, width).
template <int W>
[[gnu::always_inline]] inline vmask<W> columns_inside(int x, int width) noexcept {
  const vint<W> column = lane_index<W>() + vint<W>(x);
  return (column >= vint<W>(0)) & (column < vint<W>(width));
}
/// `sum / count` component by component where count > 0, else zero (as dividing each glm::vec3 component).
template <int W>
[[gnu::always_inline]] inline vec3<W> average(const vec3<W>& sum, const vfloat<W>& count) noexcept {
  const vmask<W> some = count > vfloat<W>(0.0f);
  return keep(vec3<W>(sum.x / count, sum.y / count, sum.z / count), some);
}

/// Calls `visit(neighbour, take)` for each offset of the S x S window around the W pixels of
/// buffer row `cy` from column `cx` on, row by row: `neighbour` is the index of the offset's
/// first pixel and `take` the lanes inside the buffer that `accept(centre, neighbour)` admits
/// (offsets that admit none are skipped). Rows and columns outside the buffer are never admitted.
template <int W, class Accept, class Visit>
[[gnu::always_inline]] inline void for_each_in_window(const TileGBuffer& g, int interleave, int cx, int cy,
                                                      const Accept& accept, Visit&& visit) {
  const int low = -(interleave / 2), high = interleave - 1 - interleave / 2;
  const auto centre = std::ptrdiff_t(g.index(cx, cy));
  for (int dy = low; dy <= high; ++dy) {
    const int ny = cy + dy;
    if (ny < 0 || ny >= g.height) continue;
    for (int dx = low; dx <= high; ++dx) {
      const std::ptrdiff_t neighbour = centre + std::ptrdiff_t(dy) * g.width + dx;
      const vmask<W> take = columns_inside<W>(cx + dx, g.width) & accept(centre, neighbour);
      if (any(take)) visit(neighbour, take);
    }
  }
}

/// Averages the S x S window around each interior pixel over the neighbours
/// `accept(centre, neighbour)` admits (a vmask<W> for the W pixels from index `centre` on
/// against those from `neighbour` on). W neighbouring pixels of a row are filtered at once, each
/// adding its neighbours in the same order as one pixel alone would, so the result does not
/// depend on W.
template <int W, class Accept>
void window_average(const TileGBuffer& g, int interleave, FilteredTile& out, const Accept& accept) {
  for (int y = 0; y < out.height; ++y)
    for (int x = 0; x < out.width; x += W) {
      vec3<W> irradiance(glm::vec3(0.0f)), glossy(glm::vec3(0.0f));
      vfloat<W> count(0.0f);
      for_each_in_window<W>(g, interleave, x + g.border, y + g.border, accept,
                            [&](std::ptrdiff_t neighbour, const vmask<W>& take) __attribute__((always_inline)) {
                              irradiance.assign(irradiance + load<W>(g.irradiance, neighbour), take);
                              glossy.assign(glossy + load<W>(g.glossy, neighbour), take);
                              count.assign(count + vfloat<W>(1.0f), take);
                            });
      const auto at = std::ptrdiff_t(y) * out.width + x;
      store(average(irradiance, count), out.irradiance, at);
      store(average(glossy, count), out.glossy, at);
    }
}

/// Every neighbour inside the G-buffer.
template <int W>
struct AcceptAll {
  /// All lanes.
  [[gnu::always_inline]] vmask<W> operator()(std::ptrdiff_t, std::ptrdiff_t) const noexcept { return vmask<W>(true); }
};

/// The discontinuity buffer's surface test: both pixels hit, normals within the angle whose
/// cosine is `cos_max_angle`, depths within `max_relative_depth` of the centre's.
template <int W>
struct SameSurface {
  const TileGBuffer* g;         ///< The G-buffer read.
  float cos_max_angle;          ///< Cosine of the largest normal angle admitted.
  float max_relative_depth;     ///< Largest depth difference admitted, relative to the centre's depth.
  /// The lanes of `neighbour` on the surface of `centre`.
  [[gnu::always_inline]] vmask<W> operator()(std::ptrdiff_t centre, std::ptrdiff_t neighbour) const noexcept {
    const vfloat<W> zero(0.0f);
    vmask<W> same = (load<W>(g->hit, centre) != zero) & (load<W>(g->hit, neighbour) != zero);
    const vec3<W> n = load<W>(g->normal, centre), m = load<W>(g->normal, neighbour);
    // Summed in glm::dot's order; a NaN normal fails the >= test and so rejects the neighbour.
    const vfloat<W> cosine = n.x * m.x + n.y * m.y + n.z * m.z;
    same &= cosine >= vfloat<W>(cos_max_angle);
    const vfloat<W> depth = load<W>(g->depth, centre);
    same &= abs(load<W>(g->depth, neighbour) - depth) <= vfloat<W>(max_relative_depth) * abs(depth);
    return same;
  }
};

}  // namespace filter_detail

/// Neighbour tests of DiscontinuityFilter.
struct DiscontinuitySettings {
  /// 25 degrees: curved surfaces (a column, the bunny) change their normal by a few degrees
  /// per pixel and stay smooth, while the 90-degree creases of walls, floors and boxes (and
  /// anything above 25 degrees) keep their edge.
  float max_normal_angle = 0.436332313f;
  /// 5%: neighbouring pixels on one surface differ in depth by well under 5% except at grazing
  /// angles, while an object in front of a wall is usually more than 5% nearer.
  float max_relative_depth = 0.05f;
};

/// The discontinuity buffer: averages irradiance over the S x S window, counting a neighbour
/// only if it hit geometry, its normal is within `max_normal_angle` of the pixel's and its depth
/// within `max_relative_depth` of the pixel's depth. Pixels whose ray missed get zero.
class DiscontinuityFilter {
 public:
  /// Its settings type.
  using Settings = DiscontinuitySettings;
  /// Filter with `settings`; throws std::invalid_argument on a negative or non-finite threshold.
  explicit DiscontinuityFilter(const Settings& settings = {}) : settings_(settings) {
    if (!(settings.max_normal_angle >= 0.0f) || !std::isfinite(settings.max_normal_angle))
      throw std::invalid_argument("DiscontinuityFilter: max_normal_angle must be a finite angle >= 0 (radians)");
    if (!(settings.max_relative_depth >= 0.0f) || !std::isfinite(settings.max_relative_depth))
      throw std::invalid_argument("DiscontinuityFilter: max_relative_depth must be finite and >= 0");
    // Angles beyond pi admit every normal, like pi itself.
    cos_max_angle_ = std::cos(std::min(settings.max_normal_angle, std::numbers::pi_v<float>));
  }
  /// Policy name.
  static constexpr const char* name() noexcept { return "discontinuity"; }
  /// Pixels read around a tile: the S x S window's reach.
  static constexpr int border(int interleave) noexcept { return window_border(interleave); }
  /// The thresholds in use.
  const Settings& settings() const noexcept { return settings_; }
  /// Cosine of max_normal_angle: the smallest cosine between normals admitted.
  float cos_max_angle() const noexcept { return cos_max_angle_; }
  /// Filters the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("DiscontinuityFilter", gbuffer, interleave, out);
    constexpr int W = filter_detail::row_lanes;
    filter_detail::window_average<W>(
        gbuffer, interleave, out,
        filter_detail::SameSurface<W>{&gbuffer, cos_max_angle_, settings_.max_relative_depth});
  }

 private:
  Settings settings_;
  float cos_max_angle_ = 1.0f;
};

/// Plain S x S average of every pixel in the window, hit or not, across any edge.
class BoxFilter {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "box"; }
  /// Pixels read around a tile: the S x S window's reach.
  static constexpr int border(int interleave) noexcept { return window_border(interleave); }
  /// Filters the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("BoxFilter", gbuffer, interleave, out);
    constexpr int W = filter_detail::row_lanes;
    filter_detail::window_average<W>(gbuffer, interleave, out, filter_detail::AcceptAll<W>{});
  }
};

/// Copies the interior unfiltered (the interleaving pattern stays visible).
class NoFilter {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "none"; }
  /// Pixels read around a tile: none (a pixel's rays give the same values whatever tile traces
  /// them, so rendering no border changes no pixel, only saves the border's rays).
  static constexpr int border(int /*interleave*/) noexcept { return 0; }
  /// Copies the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("NoFilter", gbuffer, interleave, out);
    constexpr int W = filter_detail::row_lanes;
    filter_detail::window_average<W>(gbuffer, 1, out, filter_detail::AcceptAll<W>{});
  }
};

}  // namespace igi
