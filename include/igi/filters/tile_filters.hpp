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

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>

#include <glm/glm.hpp>

#include "igi/filters/filter.hpp"

namespace igi {

namespace filter_detail {

/// Throws std::invalid_argument unless `gbuffer` is consistent and `interleave` >= 1; sizes `out`.
inline void prepare_filter(const char* filter, const TileGBuffer& gbuffer, int interleave, FilteredTile& out) {
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
      gbuffer.depth.size() != n || gbuffer.hit.size() != n)
    fail("G-buffer arrays do not all hold width x height = " + std::to_string(n) + " entries");
  out.width = gbuffer.width - 2 * gbuffer.border;
  out.height = gbuffer.height - 2 * gbuffer.border;
  const std::size_t interior = std::size_t(out.width) * std::size_t(out.height);
  out.irradiance.assign(interior, glm::vec3(0.0f));
  out.glossy.assign(interior, glm::vec3(0.0f));
}

/// Averages the S x S window around each interior pixel over the neighbours `accept(centre, neighbour)` admits.
template <class Accept>
void window_average(const TileGBuffer& g, int interleave, FilteredTile& out, const Accept& accept) {
  const int low = -(interleave / 2), high = interleave - 1 - interleave / 2;
  for (int y = 0; y < out.height; ++y) {
    for (int x = 0; x < out.width; ++x) {
      const int cx = x + g.border, cy = y + g.border;
      const std::size_t centre = g.index(cx, cy);
      glm::vec3 irradiance(0.0f), glossy(0.0f);
      int count = 0;
      for (int dy = low; dy <= high; ++dy) {
        const int ny = cy + dy;
        if (ny < 0 || ny >= g.height) continue;
        for (int dx = low; dx <= high; ++dx) {
          const int nx = cx + dx;
          if (nx < 0 || nx >= g.width) continue;
          const std::size_t neighbour = g.index(nx, ny);
          if (!accept(centre, neighbour)) continue;
          irradiance += g.irradiance[neighbour];
          glossy += g.glossy[neighbour];
          ++count;
        }
      }
      const std::size_t at = std::size_t(y) * std::size_t(out.width) + std::size_t(x);
      if (count > 0) {
        out.irradiance[at] = irradiance / float(count);
        out.glossy[at] = glossy / float(count);
      }
    }
  }
}

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
  /// The thresholds in use.
  const Settings& settings() const noexcept { return settings_; }
  /// Filters the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("DiscontinuityFilter", gbuffer, interleave, out);
    filter_detail::window_average(gbuffer, interleave, out, [&](std::size_t centre, std::size_t neighbour) {
      if (!gbuffer.hit[centre] || !gbuffer.hit[neighbour]) return false;
      // Written as !(>=) so that a NaN normal rejects the neighbour too.
      if (!(glm::dot(gbuffer.normal[centre], gbuffer.normal[neighbour]) >= cos_max_angle_)) return false;
      const float depth = gbuffer.depth[centre];
      return std::abs(gbuffer.depth[neighbour] - depth) <= settings_.max_relative_depth * std::abs(depth);
    });
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
  /// Filters the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("BoxFilter", gbuffer, interleave, out);
    filter_detail::window_average(gbuffer, interleave, out, [](std::size_t, std::size_t) { return true; });
  }
};

/// Copies the interior unfiltered (the interleaving pattern stays visible).
class NoFilter {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "none"; }
  /// Copies the interior of `gbuffer` into `out`; throws std::invalid_argument on inconsistent input.
  void apply(const TileGBuffer& gbuffer, int interleave, FilteredTile& out) const {
    filter_detail::prepare_filter("NoFilter", gbuffer, interleave, out);
    filter_detail::window_average(gbuffer, 1, out, [](std::size_t, std::size_t) { return true; });
  }
};

}  // namespace igi
