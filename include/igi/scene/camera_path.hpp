#pragma once
/// \file
/// `CameraPath`: a glTF file's animated camera played over any scene, so that a walkthrough is a
/// file anyone can open, edit (in Blender, say) and replay over the scene it was made for, or
/// over a built-in one. The file needs a camera node and an animation that moves it (or one of
/// its parents); meshes, lights and other nodes in it are ignored.

#include <filesystem>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/error.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// The first camera of a glTF file, moved by one of the file's animations.
class CameraPath {
 public:
  /// Loads `file` and the animation `animation` (its name or index) that moves the file's first
  /// camera; with `loop`, time wraps around the animation. Throws SceneError naming the file if it
  /// cannot be read, has no camera, or the animation does not move that camera.
  explicit CameraPath(const std::filesystem::path& file, std::string_view animation = "0", bool loop = false)
      : file_(std::make_unique<Scene>(load_gltf(file, &warnings_))) {
    const Scene& scene = *file_;
    const std::string where = "camera path '" + file.string() + "'";
    if (scene.cameras.empty() || scene.animations.camera_nodes.empty() || scene.animations.camera_nodes.front() < 0)
      throw SceneError(where + ": the file has no camera node to follow");
    try {
      player_ = std::make_unique<AnimationPlayer>(scene, find_animation(scene, animation), loop);
    } catch (const SceneError& e) {
      throw SceneError(where + ": " + e.what());
    }
    if (!moves_camera())
      throw SceneError(where + ": animation '" + player_->animation().name + "' does not move camera '" +
                       scene.cameras.front().name + "' (nor any node above it)");
  }

  /// The camera at `seconds` into the path (before its first key the first pose, after its last
  /// the last one, unless the path loops).
  Camera at(double seconds) const { return (*player_)(seconds, file_->cameras.front(), 0).camera; }

  /// The path's length in seconds (its animation's last key).
  float duration() const noexcept { return player_->animation().duration; }
  /// The animation's name.
  const std::string& name() const noexcept { return player_->animation().name; }
  /// What loading the file reported but did not refuse.
  const std::vector<std::string>& warnings() const noexcept { return warnings_; }

 private:
  /// True if a channel of the animation moves the camera's node or a node above it.
  bool moves_camera() const {
    const SceneAnimations& data = file_->animations;
    for (int node = data.camera_nodes.front(); node >= 0; node = data.nodes[std::size_t(node)].parent)
      for (const AnimationChannel& channel : player_->animation().channels)
        if (channel.node == node && channel.property != AnimatedProperty::weights) return true;
    return false;
  }

  std::vector<std::string> warnings_;         ///< Filled while loading, so declared before file_.
  std::unique_ptr<const Scene> file_;         ///< The file's nodes and animations (the player borrows them: a stable address).
  std::unique_ptr<AnimationPlayer> player_;   ///< Samples them.
};

}  // namespace igi
