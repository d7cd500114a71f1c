#pragma once
/// \file
/// Deterministic scene animations for dynamic-scene runs: the scene changes of frame f are a pure
/// function of the initial scene, the initial camera, the kind of animation and f, so igi-render,
/// igi-view and a cluster render the very same frames. Frame 0 is the initial scene.

#include <cmath>
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/render/settings.hpp"
#include "igi/scene/scene.hpp"
#include "igi/scene/scene_changes.hpp"

namespace igi {

/// What moves from frame to frame.
enum class Animation { none, light, camera, object };

/// Parses "none", "light", "camera" or "object"; throws SettingsError naming anything else.
inline Animation parse_animation(std::string_view text) {
  if (text == "none" || text.empty()) return Animation::none;
  if (text == "light") return Animation::light;
  if (text == "camera") return Animation::camera;
  if (text == "object") return Animation::object;
  throw SettingsError("animation '" + std::string(text) + "' is not one of none, light, camera, object");
}

namespace animation_detail {

/// Radians per frame for lights and objects: a full cycle takes about 21 frames, so every frame of
/// a short run moves visibly.
inline constexpr float swing_step = 0.3f;
/// Radians per frame of the camera orbit: about 2.3 degrees, consecutive views overlap as in a walk-through.
inline constexpr float orbit_step = 0.04f;
/// Amplitude of light and object motion as a fraction of the scene diagonal: 5% keeps the Cornell
/// box's luminaire under its ceiling and its boxes on the floor.
inline constexpr float swing_amplitude = 0.05f;

/// World bounds of instance `i`.
inline Bounds instance_bounds(const Scene& scene, std::size_t i) {
  Bounds bounds;
  const Instance& instance = scene.instances[i];
  for (const glm::vec3& p : scene.meshes[std::size_t(instance.mesh)].positions)
    bounds.extend(glm::vec3(instance.transform * glm::vec4(p, 1.0f)));
  return bounds;
}

}  // namespace animation_detail

/// The instance the "object" animation moves: the smallest non-emissive one (a Cornell box's short box), -1 if none.
inline int animated_instance(const Scene& scene) {
  int best = -1;
  float best_size = 0.0f;
  for (std::size_t i = 0; i < scene.instances.size(); ++i) {
    if (scene.emits_light(scene.instances[i].mesh)) continue;
    const Bounds bounds = animation_detail::instance_bounds(scene, i);
    if (bounds.empty()) continue;
    const float size = glm::length(bounds.extent());
    if (best < 0 || size < best_size) {
      best = int(i);
      best_size = size;
    }
  }
  return best;
}

/// An animation of a scene: the changes of each frame, from the initial scene and camera. What it
/// needs of the initial scene (its diagonal and centre, the instance that moves) is found once, at
/// construction, so a frame costs O(lights + instances), not a walk over every vertex.
/// light: punctual lights circle horizontally (directional ones turn about +Y); a scene without
/// punctual lights slides its emissive instances instead. camera: orbit about +Y through the
/// scene centre. object: the animated_instance slides sideways.
class Animator {
 public:
  /// Animation `kind` of `initial` (borrowed: it must outlive the animator) seen from `camera`;
  /// throws SettingsError if the scene has nothing of that kind.
  Animator(const Scene& initial, const Camera& camera, Animation kind) : initial_(&initial), camera_(camera), kind_(kind) {
    using namespace animation_detail;
    if (kind == Animation::none) return;
    const Bounds bounds = initial.bounds();
    amplitude_ = swing_amplitude * (bounds.empty() ? 1.0f : glm::length(bounds.extent()));
    centre_ = bounds.empty() ? glm::vec3(0.0f) : bounds.center();
    if (kind == Animation::light && initial.lights.empty()) {
      for (std::size_t i = 0; i < initial.instances.size(); ++i)
        if (initial.emits_light(initial.instances[i].mesh)) moving_.push_back(int(i));
      if (moving_.empty()) throw SettingsError("--animate light: scene '" + initial.name + "' has no punctual or emissive light");
    }
    if (kind == Animation::object) {
      const int instance = animated_instance(initial);
      if (instance < 0) throw SettingsError("--animate object: scene '" + initial.name + "' has no non-emissive instance");
      moving_.push_back(instance);
    }
  }

  /// The scene changes of frame `frame`.
  SceneChanges operator()(std::uint32_t frame) const {
    using namespace animation_detail;
    SceneChanges changes;
    changes.camera = camera_;
    const float angle = swing_step * float(frame);
    switch (kind_) {
      case Animation::none:
        break;
      case Animation::camera: {
        const glm::mat4 orbit = glm::translate(glm::mat4(1.0f), centre_) *
                                glm::rotate(glm::mat4(1.0f), orbit_step * float(frame), glm::vec3(0.0f, 1.0f, 0.0f)) *
                                glm::translate(glm::mat4(1.0f), -centre_);
        changes.camera.camera_to_world = orbit * camera_.camera_to_world;
        break;
      }
      case Animation::light:
        if (moving_.empty()) {
          const glm::mat3 turn(glm::rotate(glm::mat4(1.0f), angle, glm::vec3(0.0f, 1.0f, 0.0f)));
          for (std::size_t i = 0; i < initial_->lights.size(); ++i) {
            PunctualLight light = initial_->lights[i];
            // A circle through the initial position: offset (cos a - 1, 0, sin a) is zero at frame 0.
            light.position += amplitude_ * glm::vec3(std::cos(angle) - 1.0f, 0.0f, std::sin(angle));
            if (light.kind == PunctualKind::directional) light.direction = glm::normalize(turn * light.direction);
            changes.lights.emplace_back(int(i), light);
          }
          break;
        }
        [[fallthrough]];  // no punctual lights: the emissive instances slide, as objects do
      case Animation::object: {
        const glm::mat4 slide = glm::translate(glm::mat4(1.0f), glm::vec3(amplitude_ * std::sin(angle), 0.0f, 0.0f));
        for (const int instance : moving_)
          changes.instances.emplace_back(instance, slide * initial_->instances[std::size_t(instance)].transform);
        break;
      }
    }
    return changes;
  }

 private:
  const Scene* initial_;     ///< The scene as it was before frame 0.
  Camera camera_;            ///< The camera before frame 0.
  Animation kind_;           ///< What moves.
  float amplitude_ = 0.0f;   ///< swing_amplitude of the initial scene's diagonal.
  glm::vec3 centre_{0.0f};   ///< Centre of the initial scene's bounds (the camera orbit's pivot).
  std::vector<int> moving_;  ///< Instances that slide (the object, or emissive instances of a scene without punctual lights).
};

/// Scene changes of frame `frame` of animation `kind` (one frame of Animator(initial, camera,
/// kind); a loop over frames should keep one Animator). Throws SettingsError if the scene has
/// nothing of that kind.
inline SceneChanges animate(const Scene& initial, const Camera& camera, Animation kind, std::uint32_t frame) {
  return Animator(initial, camera, kind)(frame);
}

}  // namespace igi
