#pragma once
/// \file
/// Cameras: a default camera fitted to a scene, lookup by name, and the pinhole projection that
/// turns continuous pixel coordinates into primary-ray directions (scalar and per packet).

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>

#include "igi/scene/error.hpp"
#include "igi/scene/scene.hpp"
#include "igi/simd/vec3.hpp"

namespace igi {

/// A camera for scenes without one: it looks along -Z at the centre of the scene's bounds (glTF assets face +Z) from far enough that the bounding sphere fills the vertical field of view.
inline Camera default_camera(const Scene& scene) {
  const Bounds bounds = scene.bounds();
  if (bounds.empty())
    throw SceneError("scene '" + scene.name + "' has no geometry to fit a default camera to");
  const glm::vec3 center = bounds.center();
  float radius = 0.5f * glm::length(bounds.extent());
  if (!std::isfinite(radius) || !std::isfinite(center.x) || !std::isfinite(center.y) || !std::isfinite(center.z))
    throw SceneError("scene '" + scene.name + "' has non-finite bounds");
  if (radius == 0.0f) radius = 1.0f;  // a single point: any distance shows it; one unit keeps znear sensible
  Camera camera;
  camera.name = "default";
  // Sphere tangent to the top and bottom of the view (images at least as wide as tall see all of it).
  const float distance = radius / std::sin(0.5f * camera.yfov);
  camera.camera_to_world = glm::mat4(1.0f);
  camera.camera_to_world[3] = glm::vec4(center + glm::vec3(0.0f, 0.0f, distance), 1.0f);
  camera.aspect = 0.0f;
  camera.znear = 1e-3f * radius;  // a thousandth of the scene's size: clips nothing of it, keeps depth precision
  return camera;
}

/// The first camera of `scene` named `name`, or nullptr.
inline const Camera* find_camera(const Scene& scene, std::string_view name) noexcept {
  for (const Camera& camera : scene.cameras)
    if (camera.name == name) return &camera;
  return nullptr;
}

/// Primary rays of a pinhole camera for a width x height image: pixel (x, y) covers [x, x+1) x [y, y+1), y grows downwards, row 0 is the top.
struct PinholeProjection {
  /// Projection of `camera` onto a width x height image with square pixels: the camera's vertical
  /// field of view spans the image's height and the width follows from the image's own aspect, as
  /// glTF viewers do, whatever the camera's `aspect` (a glTF aspectRatio other than the image's
  /// would stretch the view). Throws std::invalid_argument on a bad camera or size.
  PinholeProjection(const Camera& camera, int width, int height) : width_(width), height_(height) {
    if (width <= 0 || height <= 0)
      throw std::invalid_argument("PinholeProjection: image size " + std::to_string(width) + "x" +
                                  std::to_string(height) + " must be positive");
    if (!(camera.yfov > 0.0f && camera.yfov < glm::pi<float>()))
      throw std::invalid_argument("PinholeProjection: camera '" + camera.name + "' yfov " +
                                  std::to_string(camera.yfov) + " must be in (0, pi) radians");
    if (!(camera.aspect >= 0.0f) || !std::isfinite(camera.aspect))
      throw std::invalid_argument("PinholeProjection: camera '" + camera.name + "' aspect must be finite and >= 0");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(camera.camera_to_world[c][r]))
          throw std::invalid_argument("PinholeProjection: camera '" + camera.name + "' has a non-finite transform");
    const float aspect = float(width) / float(height);
    const float half_height = std::tan(0.5f * camera.yfov);  // image plane at distance 1
    const float half_width = aspect * half_height;
    const glm::mat3 rotation(camera.camera_to_world);
    eye_ = glm::vec3(camera.camera_to_world[3]);
    // Unnormalized direction = top_left + px * right_step + py * down_step, in world space.
    top_left_ = rotation * glm::vec3(-half_width, half_height, -1.0f);
    right_step_ = rotation * glm::vec3(2.0f * half_width / float(width), 0.0f, 0.0f);
    down_step_ = rotation * glm::vec3(0.0f, -2.0f * half_height / float(height), 0.0f);
    forward_ = rotation * glm::vec3(0.0f, 0.0f, -1.0f);
    // project()'s constants, so that it divides once.
    plane_distance_ = glm::dot(top_left_, forward_);
    right_per_pixel_ = right_step_ / glm::dot(right_step_, right_step_);
    down_per_pixel_ = down_step_ / glm::dot(down_step_, down_step_);
    left_edge_ = glm::dot(top_left_, right_per_pixel_);
    top_edge_ = glm::dot(top_left_, down_per_pixel_);
  }

  /// World-space eye position, the origin of every primary ray.
  glm::vec3 origin() const noexcept { return eye_; }

  /// Unit world-space direction through continuous pixel coordinates (px, py).
  glm::vec3 direction(float px, float py) const noexcept {
    return glm::normalize(top_left_ + px * right_step_ + py * down_step_);
  }

  /// Unit world-space directions through W continuous pixel coordinates, one per lane.
  template <int W>
  vec3<W> direction(const vfloat<W>& px, const vfloat<W>& py) const noexcept {
    return normalize(vec3<W>(top_left_) + vec3<W>(right_step_) * px + vec3<W>(down_step_) * py);
  }

  /// Continuous pixel coordinates (px, py) whose ray passes through world point `point`, the
  /// inverse of direction(); empty for a point not in front of the eye. They may lie outside the image.
  std::optional<glm::vec2> project(const glm::vec3& point) const noexcept {
    const glm::vec3 offset = point - eye_;
    // offset = t (top_left_ + px right_step_ + py down_step_), and only top_left_ has a component
    // along forward_; right_step_ and down_step_ are orthogonal to each other and to forward_ (a
    // rigid camera), so px = dot(offset / t - top_left_, right_step_) / |right_step_|^2, and so for py.
    const float along = glm::dot(offset, forward_);
    if (!(along > 0.0f)) return std::nullopt;  // t > 0, as plane_distance_ > 0; NaN too
    const float inverse_t = plane_distance_ / along;
    return glm::vec2(glm::dot(offset, right_per_pixel_) * inverse_t - left_edge_,
                     glm::dot(offset, down_per_pixel_) * inverse_t - top_edge_);
  }

  /// The side of one pixel on the image plane at distance 1 (2 tan(yfov / 2) / height): how much
  /// wider a primary ray's cone grows per unit of distance.
  float pixel_spread() const noexcept { return glm::length(down_step_); }

  /// Image width in pixels.
  int width() const noexcept { return width_; }
  /// Image height in pixels.
  int height() const noexcept { return height_; }

 private:
  int width_;
  int height_;
  glm::vec3 eye_;
  glm::vec3 top_left_;
  glm::vec3 right_step_;
  glm::vec3 down_step_;
  glm::vec3 forward_;  ///< Viewing direction (the camera's -Z).
  float plane_distance_;        ///< top_left_'s component along forward_ (1 up to rounding).
  glm::vec3 right_per_pixel_;   ///< right_step_ / |right_step_|^2: a world offset's pixels to the right, at t = 1.
  glm::vec3 down_per_pixel_;    ///< down_step_ / |down_step_|^2.
  float left_edge_;             ///< top_left_'s pixels to the right (negative: it is the left edge).
  float top_edge_;              ///< top_left_'s pixels down.
};

}  // namespace igi
