#pragma once
/// \file
/// `SceneChanges`: the scene state that changes between frames (camera, punctual lights, instance
/// transforms), as absolute values. Animations produce it, renderers apply it, and the tile farm
/// broadcasts it to every rank at the start of a frame.

#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/scene/error.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Scene state that changes between frames. Values are absolute (not deltas), so applying the same
/// changes twice is harmless.
struct SceneChanges {
  Camera camera;                                      ///< The frame's camera.
  std::vector<std::pair<int, PunctualLight>> lights;  ///< Punctual lights replaced, by index.
  std::vector<std::pair<int, glm::mat4>> instances;   ///< Instance transforms replaced, by index.

  /// Throws SceneError if an index does not exist in `scene`.
  void check(const Scene& scene) const {
    for (const auto& [index, light] : lights)
      if (index < 0 || std::size_t(index) >= scene.lights.size())
        throw SceneError("scene change names punctual light " + std::to_string(index) + " but the scene has " +
                         std::to_string(scene.lights.size()));
    for (const auto& [index, transform] : instances)
      if (index < 0 || std::size_t(index) >= scene.instances.size())
        throw SceneError("scene change names instance " + std::to_string(index) + " but the scene has " +
                         std::to_string(scene.instances.size()));
  }
};

}  // namespace igi
