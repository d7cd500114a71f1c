#pragma once
/// \file
/// The parts of igi-view that do not need a window, kept apart so tests can check them: the
/// orbit / fly camera, the progressive accumulator that converges a still image over new VPL
/// sets, and the movable light (a punctual light or an emissive instance) with its scripted orbit.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/io/srgb.hpp"
#include "igi/render/tone_mapping.hpp"
#include "igi/scene/scene.hpp"

namespace igi_view {

/// A camera that orbits a target point (mouse) and flies with it (keys).
class OrbitCamera {
 public:
  /// Starts where `camera` is, looking where it looks; the target lies `target_distance` ahead.
  OrbitCamera(const igi::Camera& camera, float target_distance) : yfov_(camera.yfov), znear_(camera.znear) {
    if (!(target_distance > 0.0f) || !std::isfinite(target_distance))
      throw std::invalid_argument("OrbitCamera: target distance must be positive and finite, got " +
                                  std::to_string(target_distance));
    const glm::vec3 eye = camera.position();
    const glm::vec3 forward = glm::normalize(-glm::vec3(camera.camera_to_world[2]));
    distance_ = target_distance;
    target_ = eye + forward * distance_;
    yaw_ = std::atan2(forward.x, -forward.z);
    pitch_ = std::asin(std::clamp(forward.y, -1.0f, 1.0f));
    clamp_pitch();
  }

  /// The igi camera for the current state (aspect 0: the image's).
  igi::Camera camera() const {
    igi::Camera camera;
    camera.name = "igi-view";
    camera.yfov = yfov_;
    camera.znear = znear_;
    camera.aspect = 0.0f;
    // lookAt gives world-to-camera with the camera looking down -Z and +Y up, glTF's convention.
    camera.camera_to_world = glm::inverse(glm::lookAt(eye(), target_, glm::vec3(0.0f, 1.0f, 0.0f)));
    return camera;
  }

  /// Unit direction the camera looks in.
  glm::vec3 forward() const noexcept {
    return {std::cos(pitch_) * std::sin(yaw_), std::sin(pitch_), -std::cos(pitch_) * std::cos(yaw_)};
  }
  /// Unit direction to the camera's right, horizontal.
  glm::vec3 right() const noexcept { return {std::cos(yaw_), 0.0f, std::sin(yaw_)}; }
  /// World position of the eye.
  glm::vec3 eye() const noexcept { return target_ - forward() * distance_; }
  /// The point orbited around.
  const glm::vec3& target() const noexcept { return target_; }

  /// Turns around the target by `yaw` and `pitch` radians (pitch stays short of straight up or down).
  void orbit(float yaw, float pitch) noexcept {
    yaw_ += yaw;
    pitch_ += pitch;
    clamp_pitch();
  }
  /// Moves eye and target together: `along` the view, to the `side` (right) and `up` (world +Y).
  void fly(float along, float side, float up) noexcept {
    target_ += forward() * along + right() * side + glm::vec3(0.0f, up, 0.0f);
  }
  /// Multiplies the distance to the target by `factor` (> 0).
  void zoom(float factor) noexcept {
    // 0.1 mm: closer than any scene needs, yet the eye never reaches the target (lookAt would fail).
    if (factor > 0.0f && std::isfinite(factor)) distance_ = std::max(distance_ * factor, 1e-4f);
  }

 private:
  void clamp_pitch() noexcept {
    // 1.5 rad (86 degrees) keeps lookAt's up vector away from the view direction.
    pitch_ = std::clamp(pitch_, -1.5f, 1.5f);
  }
  glm::vec3 target_{0.0f};
  float distance_ = 1.0f;
  float yaw_ = 0.0f;
  float pitch_ = 0.0f;
  float yfov_;
  float znear_;
};

/// Sums HDR frames of a still scene rendered with new frame indices (new VPL sets) into their converging mean.
class ProgressiveAccumulator {
  // Any change to scene, camera or settings must reset it: the frames would mean different images.
 public:
  /// Forgets every frame.
  void reset() noexcept { count_ = 0; }
  /// Adds one frame; a frame of another size restarts the sum.
  void add(const igi::Image& frame) {
    if (frame.width != width_ || frame.height != height_) {
      width_ = frame.width;
      height_ = frame.height;
      count_ = 0;
    }
    if (count_ == 0) sum_.assign(frame.pixels.size(), glm::dvec3(0.0));
    for (std::size_t i = 0; i < frame.pixels.size(); ++i) sum_[i] += glm::dvec3(frame.pixels[i]);
    ++count_;
  }
  /// Frames summed since the last reset.
  int count() const noexcept { return count_; }
  /// The mean of the frames added (an empty image before the first).
  igi::Image mean() const {
    if (count_ == 0) return {};
    igi::Image image(width_, height_);
    for (std::size_t i = 0; i < sum_.size(); ++i) image.pixels[i] = glm::vec3(sum_[i] / double(count_));
    return image;
  }

 private:
  std::vector<glm::dvec3> sum_;
  int width_ = 0;
  int height_ = 0;
  int count_ = 0;
};

/// `image` tone mapped with its own luminance statistics and quantized to sRGB.
inline igi::Rgb8Image tone_map(const igi::Image& image) {
  igi::LuminanceStatistics statistics;
  for (const glm::vec3& p : image.pixels) statistics.add(p);
  const igi::ToneMapping mapping = igi::ToneMapping::from(statistics);
  igi::Rgb8Image out(image.width, image.height);
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const glm::u8vec3 rgb = igi::quantize_srgb(mapping.apply(image(x, y)));
      std::uint8_t* p = out.pixel(x, y);
      p[0] = rgb.r;
      p[1] = rgb.g;
      p[2] = rgb.b;
    }
  return out;
}

/// What the light keys move: the scene's first punctual light, else its first emissive instance.
struct MovableLight {
  /// Which kind of thing moves.
  enum class Kind { punctual, instance } kind = Kind::punctual;
  int index = 0;                           ///< Light or instance index.
  igi::PunctualLight light;                ///< The punctual light as loaded (kind punctual).
  glm::mat4 transform{1.0f};               ///< The instance's transform as loaded (kind instance).

  /// The light with its loaded placement shifted by the world-space `offset`.
  igi::PunctualLight moved_light(const glm::vec3& offset) const {
    igi::PunctualLight moved = light;
    moved.position += offset;
    return moved;
  }
  /// The instance transform with its loaded placement shifted by the world-space `offset`.
  glm::mat4 moved_transform(const glm::vec3& offset) const { return glm::translate(glm::mat4(1.0f), offset) * transform; }
};

/// The light the viewer moves in `scene`: its first point or spot light, else its first emissive instance, else nothing.
inline std::optional<MovableLight> find_movable_light(const igi::Scene& scene) {
  // Directional lights have no position to move, so they are passed over.
  for (std::size_t i = 0; i < scene.lights.size(); ++i)
    if (scene.lights[i].kind != igi::PunctualKind::directional)
      return MovableLight{.kind = MovableLight::Kind::punctual, .index = int(i), .light = scene.lights[i]};
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    const igi::Instance& instance = scene.instances[i];
    if (instance.mesh >= 0 && std::size_t(instance.mesh) < scene.meshes.size() && scene.material_of(instance.mesh).emissive())
      return MovableLight{.kind = MovableLight::Kind::instance, .index = int(i), .light = {}, .transform = instance.transform};
  }
  return std::nullopt;
}

/// Offset of the scripted light orbit at frame `frame`: a horizontal circle of `radius`, one turn every `period` frames.
inline glm::vec3 light_orbit_offset(std::uint32_t frame, float radius, int period) {
  // A function of the frame alone, so a run is reproducible whatever the frame rate.
  if (period < 1) throw std::invalid_argument("light orbit period must be >= 1 frame, got " + std::to_string(period));
  const float angle = glm::two_pi<float>() * float(frame % std::uint32_t(period)) / float(period);
  return radius * glm::vec3(std::cos(angle), 0.0f, std::sin(angle));
}

/// Radius of the scripted light orbit: a quarter of the scene's smaller horizontal extent.
inline float light_orbit_radius(const igi::Bounds& bounds) noexcept {
  // A quarter keeps a ceiling light of a closed room (the Cornell box) inside the room.
  if (bounds.empty()) return 0.0f;
  const glm::vec3 extent = bounds.extent();
  return 0.25f * std::min(extent.x, extent.z);
}

}  // namespace igi_view
