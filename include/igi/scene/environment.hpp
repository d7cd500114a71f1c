#pragma once
/// \file
/// The environment: light arriving from infinitely far away in every direction (a sky, an HDR
/// photograph of one), as an equirectangular map of radiance. It is what camera rays that miss
/// the scene see and what lights scenes from outside, and it carries the distribution by which
/// its directions are sampled in proportion to their light (a bound of each texel's radiance times
/// its solid angle), built once when the environment is made.
///
/// Mapping: +Y is up; the map's top row looks at the zenith, its bottom row at the nadir; its
/// left edge looks along -Z and u grows towards +X (u = atan2(x, -z) / 2 pi, v = acos(y) / pi,
/// the convention of Mitsuba 3's `envmap` emitter, so a map lights both renderers alike). A
/// rotation turns the map about +Y; a scale multiplies its radiance.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

namespace igi {

/// A direction sampled from an environment.
struct EnvironmentSample {
  glm::vec3 direction{0.0f, 1.0f, 0.0f};  ///< Unit world direction towards the sky.
  glm::vec3 radiance{0.0f};               ///< Radiance arriving from it (scale applied).
  float pdf = 0.0f;                       ///< Solid-angle density of the sample; 0 if it carries no light.
};

/// An equirectangular environment map of radiance with its importance-sampling distribution.
class Environment {
 public:
  /// The environment of `width` x `height` linear RGB radiance texels (row-major, top row the
  /// zenith), times `scale`, turned by `rotation` radians about +Y; `name` is for messages.
  /// Throws std::invalid_argument on an empty map, a size mismatch, a texel that is negative or
  /// not finite, or a scale or rotation that is not finite or a negative scale.
  Environment(std::string name, int width, int height, std::vector<glm::vec3> texels, float scale = 1.0f,
              float rotation = 0.0f)
      : name_(std::move(name)), width_(width), height_(height), texels_(std::move(texels)), scale_(scale), rotation_(rotation) {
    if (width < 1 || height < 1 || std::size_t(width) * std::size_t(height) != texels_.size())
      throw std::invalid_argument("environment '" + name_ + "': " + std::to_string(width) + " x " + std::to_string(height) +
                                  " map with " + std::to_string(texels_.size()) + " texels");
    if (!std::isfinite(scale) || scale < 0.0f)
      throw std::invalid_argument("environment '" + name_ + "': scale " + std::to_string(scale) + " is not a finite number >= 0");
    if (!std::isfinite(rotation)) throw std::invalid_argument("environment '" + name_ + "': rotation is not finite");
    for (std::size_t i = 0; i < texels_.size(); ++i)
      for (int c = 0; c < 3; ++c)
        if (!std::isfinite(texels_[i][c]) || texels_[i][c] < 0.0f)
          throw std::invalid_argument("environment '" + name_ + "': texel (" + std::to_string(i % std::size_t(width)) + ", " +
                                      std::to_string(i / std::size_t(width)) + ") is " +
                                      (std::isfinite(texels_[i][c]) ? "negative" : "not finite"));
    cos_rotation_ = std::cos(rotation);
    sin_rotation_ = std::sin(rotation);
    build_distribution();
  }

  /// The name given (a file name, or "neutral sky").
  const std::string& name() const noexcept { return name_; }
  /// Texels per row.
  int width() const noexcept { return width_; }
  /// Rows.
  int height() const noexcept { return height_; }
  /// The factor on the map's radiance.
  float scale() const noexcept { return scale_; }
  /// The turn about +Y, radians.
  float rotation() const noexcept { return rotation_; }
  /// Texel (x, y) of the map, without the scale.
  const glm::vec3& texel(int x, int y) const noexcept { return texels_[std::size_t(y) * std::size_t(width_) + std::size_t(x)]; }

  /// Radiance arriving from unit world direction `direction` (bilinear between texel centres,
  /// wrapping around in u), scale applied.
  glm::vec3 radiance(const glm::vec3& direction) const noexcept {
    const glm::vec2 uv = to_map(direction);
    // Texel centres sit at (i + 0.5) / size.
    const float x = uv.x * float(width_) - 0.5f, y = uv.y * float(height_) - 0.5f;
    const float x0 = std::floor(x), y0 = std::floor(y);
    const float fx = x - x0, fy = y - y0;
    const int column = int(x0), row = int(y0);
    const auto at = [&](int i, int j) {
      i = ((i % width_) + width_) % width_;
      j = std::clamp(j, 0, height_ - 1);
      return texel(i, j);
    };
    const glm::vec3 top = at(column, row) * (1.0f - fx) + at(column + 1, row) * fx;
    const glm::vec3 bottom = at(column, row + 1) * (1.0f - fx) + at(column + 1, row + 1) * fx;
    return (top * (1.0f - fy) + bottom * fy) * scale_;
  }

  /// A direction in proportion to its light from (u1, u2) in [0, 1): a texel by the map's
  /// distribution, then a direction uniformly over the texel's solid angle (uniform in
  /// azimuth and in cos theta), so the density is constant over each texel.
  EnvironmentSample sample(float u1, float u2) const noexcept {
    EnvironmentSample s;
    if (!(total_weight_ > 0.0)) return s;
    // The row from the marginal distribution, the column from that row's conditional one.
    const auto pick = [](const std::vector<double>& cumulative, std::size_t first, std::size_t count, double target) {
      const auto begin = cumulative.begin() + std::ptrdiff_t(first), end = begin + std::ptrdiff_t(count);
      auto it = std::upper_bound(begin, end, target);
      if (it == end) --it;
      return std::size_t(it - begin);
    };
    const double row_target = double(u1) * total_weight_;
    const std::size_t row = pick(row_cumulative_, 0, std::size_t(height_), row_target);
    const double row_low = row == 0 ? 0.0 : row_cumulative_[row - 1];
    const double row_weight = row_cumulative_[row] - row_low;
    const double column_target = double(u2) * row_weight;
    const std::size_t first = row * std::size_t(width_);
    const std::size_t column = pick(texel_cumulative_, first, std::size_t(width_), column_target);
    const double column_low = column == 0 ? 0.0 : texel_cumulative_[first + column - 1];
    const double texel_weight = texel_cumulative_[first + column] - column_low;
    if (!(texel_weight > 0.0)) return s;
    // Where inside the texel: the numbers' remainders, reused (uniform in [0, 1) again).
    const double fy = std::clamp((row_target - row_low) / row_weight, 0.0, 1.0);
    const double fx = std::clamp((column_target - column_low) / texel_weight, 0.0, 1.0);
    const double cos_top = std::cos(std::numbers::pi * double(row) / double(height_));
    const double cos_bottom = std::cos(std::numbers::pi * double(row + 1) / double(height_));
    const double cos_theta = cos_top - fy * (cos_top - cos_bottom);
    const glm::vec2 uv(float((double(column) + fx) / double(width_)),
                       float(std::acos(std::clamp(cos_theta, -1.0, 1.0)) * std::numbers::inv_pi));
    s.direction = from_map(uv);
    s.pdf = float(texel_weight / band_solid_angle_[row] / total_weight_);
    s.radiance = radiance(s.direction);
    return s;
  }

  /// The solid-angle density with which sample() returns unit world direction `direction`.
  float pdf(const glm::vec3& direction) const noexcept {
    if (!(total_weight_ > 0.0)) return 0.0f;
    const glm::vec2 uv = to_map(direction);
    const int column = std::min(int(uv.x * float(width_)), width_ - 1);
    const int row = std::min(int(uv.y * float(height_)), height_ - 1);
    const double weight = texel_weights_[std::size_t(row) * std::size_t(width_) + std::size_t(column)];
    return float(weight / band_solid_angle_[std::size_t(row)] / total_weight_);
  }

  /// The integral of radiance over the sphere of directions (W / m^2 per unit of area facing
  /// each direction), scale applied, the texels' values times their solid angles (the bilinear
  /// lookups' integral differs by the blur of sharp edges; it serves as the light's power for
  /// choosing among lights, where any close value is unbiased).
  glm::vec3 integral() const noexcept { return integral_ * scale_; }
  /// Mean radiance over the sphere of directions, scale applied.
  glm::vec3 mean_radiance() const noexcept { return integral() / (4.0f * std::numbers::pi_v<float>); }
  /// True if some direction carries light (a positive scale and a texel that is not black).
  bool emits() const noexcept { return total_weight_ > 0.0 && scale_ > 0.0f; }

  /// Unit world direction of map coordinates `uv` in [0, 1]^2.
  glm::vec3 from_map(const glm::vec2& uv) const noexcept {
    const float theta = uv.y * std::numbers::pi_v<float>, phi = 2.0f * std::numbers::pi_v<float> * uv.x;
    const float sin_theta = std::sin(theta);
    const glm::vec3 local(sin_theta * std::sin(phi), std::cos(theta), -sin_theta * std::cos(phi));
    // Map to world: turned by +rotation about +Y.
    return {cos_rotation_ * local.x + sin_rotation_ * local.z, local.y, -sin_rotation_ * local.x + cos_rotation_ * local.z};
  }
  /// Map coordinates in [0, 1)^2 x [0, 1] of unit world direction `direction`.
  glm::vec2 to_map(const glm::vec3& direction) const noexcept {
    // World to map: turned by -rotation about +Y.
    const float x = cos_rotation_ * direction.x - sin_rotation_ * direction.z;
    const float z = sin_rotation_ * direction.x + cos_rotation_ * direction.z;
    float u = std::atan2(x, -z) * (0.5f * std::numbers::inv_pi_v<float>);
    if (u < 0.0f) u += 1.0f;
    const float v = std::acos(std::clamp(direction.y, -1.0f, 1.0f)) * std::numbers::inv_pi_v<float>;
    return {std::min(u, one_below_one), v};
  }

 private:
  /// The largest float below 1, which keeps map coordinates inside the last texel.
  static constexpr float one_below_one = 0x1.fffffep-1f;

  /// Texel weights, their cumulative sums per row and over rows, and the integral. A texel's
  /// weight is the largest mean RGB radiance of it and its eight neighbours, times its solid
  /// angle: radiance() blends each direction's four nearest texel centres, all among those
  /// nine, so the weight bounds the light anywhere in the texel. Every direction that brings
  /// light can then be drawn (a black texel beside a bright one is not dark all over), and no
  /// sample's light over its density exceeds the map's integral of those bounds: no fireflies
  /// where a small sun's light spills into its neighbours.
  void build_distribution() {
    const std::size_t count = texels_.size();
    texel_weights_.resize(count);
    texel_cumulative_.resize(count);
    row_cumulative_.resize(std::size_t(height_));
    band_solid_angle_.resize(std::size_t(height_));
    glm::dvec3 integral(0.0);
    double rows = 0.0;
    for (int y = 0; y < height_; ++y) {
      // The exact solid angle of a row's band divided among its texels: 2 pi (cos theta0 - cos theta1) / width.
      const double theta0 = std::numbers::pi * double(y) / double(height_), theta1 = std::numbers::pi * double(y + 1) / double(height_);
      const double solid_angle = 2.0 * std::numbers::pi * (std::cos(theta0) - std::cos(theta1)) / double(width_);
      band_solid_angle_[std::size_t(y)] = solid_angle;
      double row = 0.0;
      for (int x = 0; x < width_; ++x) {
        const std::size_t i = std::size_t(y) * std::size_t(width_) + std::size_t(x);
        integral += glm::dvec3(texels_[i]) * solid_angle;
        double bound = 0.0;
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const glm::vec3& value = texel((x + dx + width_) % width_, std::clamp(y + dy, 0, height_ - 1));
            bound = std::max(bound, (double(value.x) + double(value.y) + double(value.z)) / 3.0);
          }
        const double weight = bound * solid_angle;
        texel_weights_[i] = weight;
        row += weight;
        texel_cumulative_[i] = row;
      }
      rows += row;
      row_cumulative_[std::size_t(y)] = rows;
    }
    total_weight_ = rows;
    integral_ = glm::vec3(integral);
  }

  std::string name_;
  int width_ = 0, height_ = 0;
  std::vector<glm::vec3> texels_;
  float scale_ = 1.0f, rotation_ = 0.0f, cos_rotation_ = 1.0f, sin_rotation_ = 0.0f;
  std::vector<double> texel_weights_, texel_cumulative_, row_cumulative_;
  std::vector<double> band_solid_angle_;  ///< Solid angle of one texel of each row.
  double total_weight_ = 0.0;
  glm::vec3 integral_{0.0f};
};

/// A neutral, colourless sky for scenes that bring no light of their own: the CIE standard
/// overcast sky above the horizon (radiance rising from the horizon to three times that at the
/// zenith, L = Lz (1 + 2 cos theta) / 3) and below it a grey ground of albedo 0.2 that it lights.
/// Lz = 9/7 makes the irradiance on an open horizontal surface pi, so such a white surface has
/// radiance 1 and a surface of albedo a shows a; multiply by `scale` for other exposures.
inline Environment neutral_sky(float scale = 1.0f) {
  // 256 x 128 texels: 1.4 degrees each, far finer than the sky's smooth gradient; the horizon's
  // step from sky to ground is blurred by half a texel.
  constexpr int width = 256, height = 128;
  constexpr float zenith = 9.0f / 7.0f;
  constexpr float ground_albedo = 0.2f;  // a common value for open ground (grass, soil, asphalt)
  std::vector<glm::vec3> texels(std::size_t(width) * std::size_t(height));
  for (int y = 0; y < height; ++y) {
    const float cos_theta = std::cos(std::numbers::pi_v<float> * (float(y) + 0.5f) / float(height));
    // The ground reflects the pi x 1 of irradiance the sky gives an open surface: radiance albedo x 1.
    const float value = cos_theta > 0.0f ? zenith * (1.0f + 2.0f * cos_theta) / 3.0f : ground_albedo;
    for (int x = 0; x < width; ++x) texels[std::size_t(y) * std::size_t(width) + std::size_t(x)] = glm::vec3(value);
  }
  return Environment("neutral sky", width, height, std::move(texels), scale);
}

}  // namespace igi
