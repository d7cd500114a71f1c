#pragma once
/// \file
/// Sampling a scene's animations (SceneAnimations, as a glTF file gives them) at a time into the
/// SceneChanges every renderer applies: instance transforms of rigid nodes, cameras and punctual
/// lights that follow their nodes, and the vertices of skinned and morphed meshes. A frame's
/// changes are a pure function of the scene's animation data, the animation and the time.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "igi/scene/error.hpp"
#include "igi/scene/scene.hpp"
#include "igi/scene/scene_changes.hpp"

namespace igi {

/// Name of an interpolation as glTF spells it, for messages.
inline const char* interpolation_name(Interpolation interpolation) noexcept {
  switch (interpolation) {
    case Interpolation::step: return "STEP";
    case Interpolation::linear: return "LINEAR";
    case Interpolation::cubic_spline: return "CUBICSPLINE";
  }
  return "unknown";
}

/// Name of an animated property as glTF spells it, for messages.
inline const char* property_name(AnimatedProperty property) noexcept {
  switch (property) {
    case AnimatedProperty::translation: return "translation";
    case AnimatedProperty::rotation: return "rotation";
    case AnimatedProperty::scale: return "scale";
    case AnimatedProperty::weights: return "weights";
  }
  return "unknown";
}

namespace animation_sampling_detail {

/// Cosine of the angle between two rotations above which slerp falls back to a normalized lerp:
/// sin(angle) is then below 0.03 and dividing by it would amplify rounding, while the lerp's own
/// error there (angle^3 / 12 < 1e-5 rad) is below float precision of a unit quaternion's components.
inline constexpr float slerp_lerp_threshold = 0.9995f;

/// Vertices per task when deforming a mesh: large enough that a task's cost (~25 us) dwarfs the
/// scheduling, small enough that a 50k-vertex mesh spreads over many threads.
inline constexpr std::size_t vertices_per_task = 4096;

/// Shortest-path spherical interpolation from `a` to `b` by `s` in [0, 1]: `b` is negated when it
/// lies on the far hemisphere (q and -q are the same rotation), so the turn is never the long way.
inline glm::quat shortest_slerp(const glm::quat& a, glm::quat b, float s) noexcept {
  float cosine = glm::dot(a, b);
  if (cosine < 0.0f) {
    b = -b;
    cosine = -cosine;
  }
  if (cosine > slerp_lerp_threshold) return glm::normalize(a * (1.0f - s) + b * s);
  const float angle = std::acos(cosine);
  const float sine = std::sin(angle);
  return a * (std::sin((1.0f - s) * angle) / sine) + b * (std::sin(s * angle) / sine);
}

/// `components` floats of `data` as a glTF quaternion (x, y, z, w).
inline glm::quat quaternion_at(const float* data) noexcept { return glm::quat(data[3], data[0], data[1], data[2]); }

/// `q` written as glTF's x, y, z, w.
inline void store_quaternion(const glm::quat& q, float* out) noexcept {
  out[0] = q.x;
  out[1] = q.y;
  out[2] = q.z;
  out[3] = q.w;
}

/// `q` made unit; a zero quaternion (cubic tangents may cancel) becomes the identity.
inline glm::quat unit_or_identity(const glm::quat& q) noexcept {
  const float length = glm::length(q);
  return length > 0.0f && std::isfinite(length) ? q / length : glm::quat(1.0f, 0.0f, 0.0f, 0.0f);
}

}  // namespace animation_sampling_detail

/// The value of `channel` at `time` seconds into `out` (channel.components floats). Before the
/// first key the first key's value holds, after the last the last's. Rotations come out unit.
inline void sample_channel(const AnimationChannel& channel, float time, float* out) {
  using namespace animation_sampling_detail;
  const std::size_t n = std::size_t(channel.components);
  const bool cubic = channel.interpolation == Interpolation::cubic_spline;
  const std::size_t stride = cubic ? 3 * n : n;
  const std::size_t keys = channel.times.size();
  // A cubic spline key is (in-tangent, value, out-tangent): its value is the middle element.
  const auto value = [&](std::size_t key) { return channel.values.data() + key * stride + (cubic ? n : 0); };
  const bool rotation = channel.property == AnimatedProperty::rotation;
  const auto copy_key = [&](std::size_t key) {
    std::copy_n(value(key), n, out);
    if (rotation) store_quaternion(unit_or_identity(quaternion_at(out)), out);
  };
  if (keys == 0) return;
  if (!(time > channel.times.front())) return copy_key(0);  // also a NaN time: the first key
  if (time >= channel.times.back()) return copy_key(keys - 1);
  const std::size_t key = std::size_t(std::upper_bound(channel.times.begin(), channel.times.end(), time) - channel.times.begin()) - 1;
  const float t0 = channel.times[key], t1 = channel.times[key + 1];
  const float span = t1 - t0;
  const float s = (time - t0) / span;
  switch (channel.interpolation) {
    case Interpolation::step:
      return copy_key(key);
    case Interpolation::linear:
      if (rotation) {
        store_quaternion(shortest_slerp(unit_or_identity(quaternion_at(value(key))), unit_or_identity(quaternion_at(value(key + 1))), s), out);
        return;
      }
      for (std::size_t c = 0; c < n; ++c) out[c] = value(key)[c] + s * (value(key + 1)[c] - value(key)[c]);
      return;
    case Interpolation::cubic_spline: {
      // glTF 2.0 appendix C: p(s) = h00 v_k + h10 span b_k + h01 v_k+1 + h11 span a_k+1, with
      // b_k the out-tangent of key k and a_k+1 the in-tangent of key k + 1.
      const float s2 = s * s, s3 = s2 * s;
      const float h00 = 2.0f * s3 - 3.0f * s2 + 1.0f, h10 = s3 - 2.0f * s2 + s;
      const float h01 = -2.0f * s3 + 3.0f * s2, h11 = s3 - s2;
      const float* out_tangent = channel.values.data() + key * stride + 2 * n;
      const float* in_tangent = channel.values.data() + (key + 1) * stride;
      for (std::size_t c = 0; c < n; ++c)
        out[c] = h00 * value(key)[c] + h10 * span * out_tangent[c] + h01 * value(key + 1)[c] + h11 * span * in_tangent[c];
      if (rotation) store_quaternion(unit_or_identity(quaternion_at(out)), out);
      return;
    }
  }
}

/// The time within `animation` that playing it for `seconds` reaches: with `loop`, `seconds`
/// wrapped into [0, duration); without, `seconds` itself (sampling clamps it to the keys).
inline float animation_time(const NodeAnimation& animation, double seconds, bool loop) noexcept {
  if (!loop || !(animation.duration > 0.0f)) return float(seconds);
  double wrapped = std::fmod(seconds, double(animation.duration));
  if (wrapped < 0.0) wrapped += double(animation.duration);
  return float(wrapped);
}

/// Index of the animation `name_or_index` names in `scene`: an animation name, else a number
/// below the animation count. Throws SceneError naming the choices otherwise.
inline int find_animation(const Scene& scene, std::string_view name_or_index) {
  const std::vector<NodeAnimation>& animations = scene.animations.animations;
  for (std::size_t a = 0; a < animations.size(); ++a)
    if (animations[a].name == name_or_index) return int(a);
  if (!name_or_index.empty() && std::all_of(name_or_index.begin(), name_or_index.end(), [](char c) { return c >= '0' && c <= '9'; }) &&
      name_or_index.size() < 10) {
    const int index = std::stoi(std::string(name_or_index));
    if (std::size_t(index) < animations.size()) return index;
  }
  std::string names;
  for (const NodeAnimation& animation : animations) names += (names.empty() ? "'" : ", '") + animation.name + "'";
  throw SceneError("scene '" + scene.name + "' has no animation '" + std::string(name_or_index) + "' (it has " +
                   (animations.empty() ? std::string("none") : std::to_string(animations.size()) + ": " + names) + ")");
}

/// Throws SceneError naming the problem if `scene`'s animation data cannot be sampled: keys out
/// of order or not finite, value counts that do not match the keys, nodes, skins, joints or
/// meshes that do not exist, or deformation data whose sizes do not match their mesh.
inline void check_animations(const Scene& scene) {
  const SceneAnimations& data = scene.animations;
  const auto node_exists = [&](int node) { return node >= 0 && std::size_t(node) < data.nodes.size(); };
  for (std::size_t a = 0; a < data.animations.size(); ++a) {
    const NodeAnimation& animation = data.animations[a];
    for (std::size_t c = 0; c < animation.channels.size(); ++c) {
      const AnimationChannel& channel = animation.channels[c];
      const std::string label = "animation '" + animation.name + "' channel " + std::to_string(c) + " (node " +
                                std::to_string(channel.node) + " " + property_name(channel.property) + ", " +
                                interpolation_name(channel.interpolation) + ")";
      if (!node_exists(channel.node)) throw SceneError(label + ": node " + std::to_string(channel.node) + " does not exist");
      if (channel.times.empty()) throw SceneError(label + ": sampler has no keys");
      for (std::size_t k = 0; k < channel.times.size(); ++k) {
        if (!std::isfinite(channel.times[k]))
          throw SceneError(label + ": key time " + std::to_string(k) + " is not a finite number");
        if (k > 0 && !(channel.times[k] > channel.times[k - 1]))
          throw SceneError(label + ": key times are not strictly increasing (key " + std::to_string(k) + " at " +
                           std::to_string(channel.times[k]) + " s follows " + std::to_string(channel.times[k - 1]) + " s)");
      }
      if (channel.times.front() < 0.0f)
        throw SceneError(label + ": key time " + std::to_string(channel.times.front()) + " s is negative");
      const std::size_t per_key =
          std::size_t(channel.components) * (channel.interpolation == Interpolation::cubic_spline ? 3 : 1);
      if (channel.components <= 0 || channel.values.size() != channel.times.size() * per_key)
        throw SceneError(label + ": sampler output has " + std::to_string(channel.values.size()) + " values for " +
                         std::to_string(channel.times.size()) + " keys (needs " +
                         std::to_string(channel.times.size() * per_key) + ")");
      for (std::size_t v = 0; v < channel.values.size(); ++v)
        if (!std::isfinite(channel.values[v]))
          throw SceneError(label + ": output value " + std::to_string(v) + " is not a finite number");
    }
  }
  for (std::size_t s = 0; s < data.skins.size(); ++s) {
    const Skin& skin = data.skins[s];
    for (const int joint : skin.joints)
      if (!node_exists(joint))
        throw SceneError("skin '" + skin.name + "': joint node " + std::to_string(joint) + " does not exist");
    if (skin.inverse_bind_matrices.size() != skin.joints.size())
      throw SceneError("skin '" + skin.name + "': " + std::to_string(skin.inverse_bind_matrices.size()) +
                       " inverse bind matrices for " + std::to_string(skin.joints.size()) + " joints");
  }
  for (const DeformableMesh& deformable : data.deformables) {
    if (deformable.mesh < 0 || std::size_t(deformable.mesh) >= scene.meshes.size())
      throw SceneError("deformed mesh " + std::to_string(deformable.mesh) + " does not exist");
    const Mesh& mesh = scene.meshes[std::size_t(deformable.mesh)];
    const std::string label = "mesh '" + mesh.name + "'";
    const std::size_t vertices = deformable.rest_positions.size();
    if (vertices != mesh.positions.size() || deformable.rest_normals.size() != vertices ||
        (!deformable.rest_tangents.empty() && deformable.rest_tangents.size() != vertices))
      throw SceneError(label + ": its rest vertices do not match its " + std::to_string(mesh.positions.size()) + " vertices");
    if (deformable.instance < 0 || std::size_t(deformable.instance) >= scene.instances.size() ||
        !node_exists(deformable.node))
      throw SceneError(label + ": deformed mesh names an instance or node that does not exist");
    for (std::size_t t = 0; t < deformable.targets.size(); ++t) {
      const MorphTarget& target = deformable.targets[t];
      for (const std::vector<glm::vec3>* attribute : {&target.positions, &target.normals, &target.tangents})
        if (!attribute->empty() && attribute->size() != vertices)
          throw SceneError(label + ": morph target " + std::to_string(t) + " has " + std::to_string(attribute->size()) +
                           " elements for " + std::to_string(vertices) + " vertices");
    }
    if (deformable.skin < 0) continue;
    if (std::size_t(deformable.skin) >= data.skins.size())
      throw SceneError(label + ": skin " + std::to_string(deformable.skin) + " does not exist");
    const Skin& skin = data.skins[std::size_t(deformable.skin)];
    if (deformable.influence_sets < 1 || deformable.joints.size() != vertices * std::size_t(deformable.influence_sets) ||
        deformable.weights.size() != deformable.joints.size())
      throw SceneError(label + ": skinned with " + std::to_string(deformable.joints.size()) + " joint and " +
                       std::to_string(deformable.weights.size()) + " weight entries for " + std::to_string(vertices) +
                       " vertices");
    for (std::size_t e = 0; e < deformable.joints.size(); ++e)
      for (int c = 0; c < 4; ++c)
        if (deformable.weights[e][c] != 0.0f && deformable.joints[e][c] >= skin.joints.size())
          throw SceneError(label + ": vertex " + std::to_string(e / std::size_t(deformable.influence_sets)) +
                           " names joint " + std::to_string(deformable.joints[e][c]) + " but skin '" + skin.name +
                           "' has " + std::to_string(skin.joints.size()) + " joints");
  }
}

/// How long the parts of sampling one frame took, for statistics.
struct AnimationTimes {
  double sampling_milliseconds = 0.0;  ///< Channels sampled and node transforms composed.
  double deforming_milliseconds = 0.0; ///< Skinned and morphed vertices computed.
};

/// Samples one of a scene's animations at any time into SceneChanges. It reads the scene's
/// animation data (Scene::animations; borrowed: the scene must outlive it), which applying the changes leaves alone,
/// so it may sample the very scene the renderer changes. What the animation can move (the nodes
/// its channels drive and everything below them) is found once, at construction, and only that
/// appears in the changes: the rest of the scene stays as loaded (and flattened in the backends).
class AnimationPlayer {
 public:
  /// Plays animation `animation` of `scene` (an index into scene.animations.animations; throws
  /// SceneError if it does not exist or the data is bad), wrapping time when `loop`.
  AnimationPlayer(const Scene& scene, int animation, bool loop = false) : scene_(&scene), loop_(loop) {
    const SceneAnimations& data = scene.animations;
    if (animation < 0 || std::size_t(animation) >= data.animations.size())
      throw SceneError("scene '" + scene.name + "' has no animation " + std::to_string(animation) + " (it has " +
                       std::to_string(data.animations.size()) + ")");
    check_animations(scene);
    animation_ = &data.animations[std::size_t(animation)];
    moving_.assign(data.nodes.size(), 0);
    weighted_.assign(data.nodes.size(), 0);
    for (const AnimationChannel& channel : animation_->channels) {
      if (channel.property == AnimatedProperty::weights)
        weighted_[std::size_t(channel.node)] = 1;
      else
        moving_[std::size_t(channel.node)] = 1;
    }
    for (const int node : data.node_order) {  // parents first: motion passes down the hierarchy
      const int parent = data.nodes[std::size_t(node)].parent;
      if (parent >= 0 && moving_[std::size_t(parent)]) moving_[std::size_t(node)] = 1;
    }
    for (std::size_t d = 0; d < data.deformables.size(); ++d) {
      const DeformableMesh& deformable = data.deformables[d];
      bool deformed = weighted_[std::size_t(deformable.node)] != 0;
      // A morphed mesh without a skin moves rigidly with its node, as an instance does.
      if (deformable.skin >= 0)
        for (const int joint : data.skins[std::size_t(deformable.skin)].joints) deformed |= moving_[std::size_t(joint)] != 0;
      if (deformed) deformed_.push_back(d);
    }
  }

  /// The animation played.
  const NodeAnimation& animation() const noexcept { return *animation_; }

  /// The scene's changes at `seconds` into the animation, seen by `camera` (returned as the
  /// changes' camera, moved with its node when `camera_index` names one of scene.cameras that the
  /// animation moves; -1 for a camera of one's own). `times`, if given, receives what it cost.
  SceneChanges operator()(double seconds, const Camera& camera, int camera_index = -1, AnimationTimes* times = nullptr) const {
    using clock = std::chrono::steady_clock;
    const auto start = clock::now();
    const SceneAnimations& data = scene_->animations;
    const float time = animation_time(*animation_, seconds, loop_);
    Pose pose = rest_pose();
    std::vector<float> scratch;
    for (const AnimationChannel& channel : animation_->channels) {
      scratch.resize(std::size_t(channel.components));
      sample_channel(channel, time, scratch.data());
      NodeState& node = pose.nodes[std::size_t(channel.node)];
      switch (channel.property) {
        case AnimatedProperty::translation: node.translation = glm::vec3(scratch[0], scratch[1], scratch[2]); break;
        case AnimatedProperty::rotation: node.rotation = animation_sampling_detail::quaternion_at(scratch.data()); break;
        case AnimatedProperty::scale: node.scale = glm::vec3(scratch[0], scratch[1], scratch[2]); break;
        case AnimatedProperty::weights: node.weights = scratch; break;
      }
    }
    compose(pose);

    SceneChanges changes;
    changes.camera = camera;
    if (camera_index >= 0 && std::size_t(camera_index) < data.camera_nodes.size()) {
      const int node = data.camera_nodes[std::size_t(camera_index)];
      if (node >= 0 && moving_[std::size_t(node)]) changes.camera.camera_to_world = rigid(pose.world[std::size_t(node)]);
    }
    for (std::size_t l = 0; l < data.light_nodes.size() && l < scene_->lights.size(); ++l) {
      const int node = data.light_nodes[l];
      if (node < 0 || !moving_[std::size_t(node)]) continue;
      PunctualLight light = scene_->lights[l];
      place_light(pose.world[std::size_t(node)], light);
      changes.lights.emplace_back(int(l), light);
    }
    std::vector<char> skinned(scene_->instances.size(), 0);
    for (const DeformableMesh& deformable : data.deformables)
      if (deformable.skin >= 0) skinned[std::size_t(deformable.instance)] = 1;
    for (std::size_t i = 0; i < data.instance_nodes.size() && i < scene_->instances.size(); ++i) {
      const int node = data.instance_nodes[i];
      if (node >= 0 && moving_[std::size_t(node)] && !skinned[i]) changes.instances.emplace_back(int(i), pose.world[std::size_t(node)]);
    }
    const auto sampled = clock::now();
    for (const std::size_t d : deformed_) changes.meshes.push_back(deform(data.deformables[d], pose));
    if (times != nullptr) {
      times->sampling_milliseconds = std::chrono::duration<double, std::milli>(sampled - start).count();
      times->deforming_milliseconds = std::chrono::duration<double, std::milli>(clock::now() - sampled).count();
    }
    return changes;
  }

  /// The rest pose of `scene` (no animation): its deformable meshes' vertices with their rest
  /// morph weights and skins at the nodes' rest transforms, and the skinned instances' transform
  /// (the identity: skinned vertices are in world space). The loader puts these into the scene.
  static SceneChanges rest(const Scene& scene) {
    check_animations(scene);
    const Pose pose = rest_pose(scene.animations);
    SceneChanges changes;
    for (const DeformableMesh& deformable : scene.animations.deformables) {
      changes.meshes.push_back(deform(scene.animations, deformable, pose));
      if (deformable.skin >= 0) changes.instances.emplace_back(deformable.instance, glm::mat4(1.0f));
    }
    return changes;
  }

 private:
  /// One node's local transform and morph weights at the sampled time.
  struct NodeState {
    glm::vec3 translation{0.0f};                 ///< Translation.
    glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  ///< Rotation.
    glm::vec3 scale{1.0f};                       ///< Scale.
    std::vector<float> weights;                  ///< Morph weights.
  };
  /// Every node's state and world transform.
  struct Pose {
    std::vector<NodeState> nodes;   ///< Local states.
    std::vector<glm::mat4> world;   ///< World transforms (after compose).
  };

  /// The nodes at rest, their world transforms composed.
  static Pose rest_pose(const SceneAnimations& data) {
    Pose pose;
    pose.nodes.resize(data.nodes.size());
    for (std::size_t n = 0; n < data.nodes.size(); ++n) {
      const SceneNode& node = data.nodes[n];
      pose.nodes[n] = {node.translation, glm::quat(node.rotation.w, node.rotation.x, node.rotation.y, node.rotation.z), node.scale, node.weights};
    }
    compose(data, pose);
    return pose;
  }
  /// The nodes of this player's scene at rest.
  Pose rest_pose() const { return rest_pose(scene_->animations); }

  /// World transforms of `pose`'s nodes, parents before children.
  static void compose(const SceneAnimations& data, Pose& pose) {
    pose.world.assign(data.nodes.size(), glm::mat4(1.0f));
    for (const int index : data.node_order) {
      const SceneNode& node = data.nodes[std::size_t(index)];
      const NodeState& state = pose.nodes[std::size_t(index)];
      glm::mat4 local = node.matrix;
      if (!node.uses_matrix) {
        local = glm::mat4_cast(state.rotation);
        local[0] *= state.scale.x;
        local[1] *= state.scale.y;
        local[2] *= state.scale.z;
        local[3] = glm::vec4(state.translation, 1.0f);
      }
      pose.world[std::size_t(index)] = node.parent >= 0 ? pose.world[std::size_t(node.parent)] * local : local;
    }
  }
  /// World transforms of `pose`'s nodes in this player's scene.
  void compose(Pose& pose) const { compose(scene_->animations, pose); }

  /// `world` with unit axes (a camera's view must not stretch).
  static glm::mat4 rigid(glm::mat4 world) {
    for (int axis = 0; axis < 3; ++axis) {
      const float length = glm::length(glm::vec3(world[axis]));
      if (length > 0.0f) world[axis] /= length;
    }
    return world;
  }

  /// Places `light` at the origin of `world`, shining along its -Z.
  static void place_light(const glm::mat4& world, PunctualLight& light) {
    light.position = glm::vec3(world[3]);
    const glm::vec3 direction = -glm::vec3(world[2]);
    const float length = glm::length(direction);
    if (length > 0.0f) light.direction = direction / length;
  }

  /// The vertices of `deformable` in `pose` (see the static deform).
  MeshVertices deform(const DeformableMesh& deformable, const Pose& pose) const {
    return deform(scene_->animations, deformable, pose);
  }
  /// The vertices of `deformable` of `data` in `pose`: morphed by its node's weights, then skinned
  /// by its skin's joints (into world space), else left in mesh space.
  static MeshVertices deform(const SceneAnimations& data, const DeformableMesh& deformable, const Pose& pose) {
    const std::size_t vertices = deformable.rest_positions.size();
    MeshVertices out;
    out.mesh = deformable.mesh;
    out.positions.resize(vertices);
    out.normals.resize(vertices);
    if (!deformable.rest_tangents.empty()) out.tangents.resize(vertices);
    const std::vector<float>& weights = pose.nodes[std::size_t(deformable.node)].weights;
    std::vector<std::pair<float, const MorphTarget*>> active;  // targets with a non-zero weight
    for (std::size_t t = 0; t < deformable.targets.size() && t < weights.size(); ++t)
      if (weights[t] != 0.0f) active.emplace_back(weights[t], &deformable.targets[t]);
    std::vector<glm::mat4> joints;
    if (deformable.skin >= 0) {
      const Skin& skin = data.skins[std::size_t(deformable.skin)];
      joints.resize(skin.joints.size());
      for (std::size_t j = 0; j < joints.size(); ++j)
        joints[j] = pose.world[std::size_t(skin.joints[j])] * skin.inverse_bind_matrices[j];
    }
    const int sets = deformable.influence_sets;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, vertices, animation_sampling_detail::vertices_per_task),
                      [&](const tbb::blocked_range<std::size_t>& range) {
      for (std::size_t v = range.begin(); v != range.end(); ++v) {
        glm::vec3 position = deformable.rest_positions[v];
        glm::vec3 normal = deformable.rest_normals[v];
        glm::vec3 tangent = out.tangents.empty() ? glm::vec3(0.0f) : glm::vec3(deformable.rest_tangents[v]);
        for (const auto& [weight, target] : active) {
          if (!target->positions.empty()) position += weight * target->positions[v];
          if (!target->normals.empty()) normal += weight * target->normals[v];
          if (!target->tangents.empty()) tangent += weight * target->tangents[v];
        }
        if (!joints.empty()) {
          glm::mat4 skinning(0.0f);
          for (int s = 0; s < sets; ++s) {
            const std::size_t entry = v * std::size_t(sets) + std::size_t(s);
            for (int c = 0; c < 4; ++c)
              if (const float w = deformable.weights[entry][c]; w != 0.0f) skinning += w * joints[deformable.joints[entry][c]];
          }
          position = glm::vec3(skinning * glm::vec4(position, 1.0f));
          // Normals map by the cofactor matrix (the inverse transpose times the determinant): no
          // inverse per vertex, and the determinant's sign keeps them facing out under mirroring.
          const glm::vec3 x(skinning[0]), y(skinning[1]), z(skinning[2]);
          const glm::mat3 cofactor(glm::cross(y, z), glm::cross(z, x), glm::cross(x, y));
          normal = cofactor * normal * (glm::dot(x, glm::cross(y, z)) < 0.0f ? -1.0f : 1.0f);
          tangent = glm::mat3(skinning) * tangent;
        }
        out.positions[v] = position;
        const float length = glm::length(normal);
        out.normals[v] = length > 0.0f && std::isfinite(length) ? normal / length : deformable.rest_normals[v];
        if (!out.tangents.empty()) {
          const float tangent_length = glm::length(tangent);
          out.tangents[v] = tangent_length > 0.0f && std::isfinite(tangent_length) && deformable.rest_tangents[v].w != 0.0f
                                ? glm::vec4(tangent / tangent_length, deformable.rest_tangents[v].w)
                                : glm::vec4(0.0f);
        }
      }
    });
    return out;
  }

  const Scene* scene_;                    ///< The scene whose animation data is sampled.
  const NodeAnimation* animation_ = nullptr;  ///< The animation played.
  bool loop_ = false;                     ///< Whether time wraps around the animation's duration.
  std::vector<char> moving_;              ///< Per node: its transform may change (driven, or below a driven node).
  std::vector<char> weighted_;            ///< Per node: its morph weights are driven.
  std::vector<std::size_t> deformed_;     ///< Deformable meshes whose vertices may change.
};

}  // namespace igi
