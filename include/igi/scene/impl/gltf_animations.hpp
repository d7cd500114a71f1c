#pragma once
/// \file
/// glTF motion for the loader (igi/scene/impl/gltf_loader.hpp): the nodes' rest transforms,
/// animations (samplers and channels), skins (joints, inverse bind matrices) and the skinning and
/// morph-target attributes of the primitives that skins and morph targets deform, read into
/// SceneAnimations. Accessors go through AccessorReader (bounds-checked, sparse applied).

#include <cmath>
#include <cstddef>
#include <initializer_list>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/impl/gltf_accessors.hpp"
#include "igi/scene/impl/gltf_diagnostics.hpp"
#include "igi/scene/scene.hpp"

namespace igi::gltf_detail {

/// The one of `values` whose glTF spelling (`name_of`) is `text`, or none.
template <class Enum, class Name>
std::optional<Enum> named(const std::string& text, std::initializer_list<Enum> values, Name name_of) {
  for (const Enum value : values)
    if (text == name_of(value)) return value;
  return std::nullopt;
}

/// A primitive placed by a node whose skin or morph targets deform it.
struct DeformedPrimitive {
  int node = -1;       ///< glTF node holding the mesh.
  int gltf_mesh = -1;  ///< glTF mesh.
  int primitive = -1;  ///< Primitive of that mesh.
  int mesh = -1;       ///< Its own Scene::meshes entry (never shared).
  int instance = -1;   ///< Its Scene::instances entry.
};

/// Reads a parsed glTF model's motion into SceneAnimations.
class AnimationReader {
 public:
  /// Reads from `model` with `accessors`, reporting through `diagnostics`; all must outlive the reader.
  AnimationReader(const tinygltf::Model& model, const AccessorReader& accessors, const Diagnostics& diagnostics)
      : model_(model), accessors_(accessors), diagnostics_(diagnostics) {}

  /// Every node's rest transform and rest morph weights into `data.nodes` (parents and the
  /// visiting order are the loader's, which walks the hierarchy).
  void read_nodes(SceneAnimations& data) const {
    data.nodes.resize(model_.nodes.size());
    for (std::size_t n = 0; n < model_.nodes.size(); ++n) {
      const tinygltf::Node& source = model_.nodes[n];
      SceneNode& node = data.nodes[n];
      node.name = source.name.empty() ? "node " + std::to_string(n) : source.name;
      // Sizes were checked by the loader for the nodes it visits; others keep their defaults.
      if (source.matrix.size() == 16) {
        node.uses_matrix = true;
        node.matrix = glm::mat4(glm::make_mat4(source.matrix.data()));
      }
      if (source.translation.size() == 3)
        node.translation = glm::vec3(float(source.translation[0]), float(source.translation[1]), float(source.translation[2]));
      if (source.rotation.size() == 4) {
        const glm::quat rotation(float(source.rotation[3]), float(source.rotation[0]), float(source.rotation[1]),
                                 float(source.rotation[2]));
        const float length = glm::length(rotation);
        if (length > 0.0f && std::isfinite(length)) {
          const glm::quat unit = rotation / length;
          node.rotation = glm::vec4(unit.x, unit.y, unit.z, unit.w);
        }
      }
      if (source.scale.size() == 3) node.scale = glm::vec3(float(source.scale[0]), float(source.scale[1]), float(source.scale[2]));
      node.weights.assign(source.weights.begin(), source.weights.end());
      if (node.weights.empty() && source.mesh >= 0 && std::size_t(source.mesh) < model_.meshes.size())
        node.weights.assign(model_.meshes[std::size_t(source.mesh)].weights.begin(), model_.meshes[std::size_t(source.mesh)].weights.end());
    }
  }

  /// The file's skins into `data.skins`.
  void read_skins(SceneAnimations& data) const {
    for (std::size_t s = 0; s < model_.skins.size(); ++s) {
      const tinygltf::Skin& source = model_.skins[s];
      Skin skin;
      skin.name = source.name.empty() ? "skin " + std::to_string(s) : source.name;
      const std::string label = "skin " + std::to_string(s) + " '" + source.name + "'";
      if (source.joints.empty()) fail(label + " has no joints");
      for (const int joint : source.joints)
        if (joint < 0 || std::size_t(joint) >= model_.nodes.size())
          fail(label + ": joint node " + std::to_string(joint) + " does not exist (the file has " +
               std::to_string(model_.nodes.size()) + " nodes)");
      skin.joints = source.joints;
      skin.skeleton = source.skeleton;
      if (source.inverseBindMatrices >= 0) {
        const std::vector<float> values =
            accessors_.read_floats(source.inverseBindMatrices, 16, {TINYGLTF_COMPONENT_TYPE_FLOAT}, label + " inverseBindMatrices");
        if (values.size() / 16 < skin.joints.size())
          fail(label + ": inverseBindMatrices has " + std::to_string(values.size() / 16) + " matrices for " +
               std::to_string(skin.joints.size()) + " joints");
        for (std::size_t j = 0; j < skin.joints.size(); ++j) {
          for (std::size_t v = 0; v < 16; ++v)
            if (!std::isfinite(values[16 * j + v])) fail(label + ": inverse bind matrix " + std::to_string(j) + " is not finite");
          skin.inverse_bind_matrices.push_back(glm::make_mat4(values.data() + 16 * j));
        }
      } else {
        skin.inverse_bind_matrices.assign(skin.joints.size(), glm::mat4(1.0f));  // glTF: identity matrices when absent
      }
      data.skins.push_back(std::move(skin));
    }
  }

  /// The file's animations into `data.animations`; channels igi cannot play are named once each in a warning.
  void read_animations(SceneAnimations& data) const {
    std::set<std::string> ignored;  // channel kinds already warned about
    for (const std::string& name : model_.extensionsUsed)
      if (name == "KHR_animation_pointer")
        ignored.insert("KHR_animation_pointer channels (igi animates node translation, rotation, scale and morph weights)");
    for (std::size_t a = 0; a < model_.animations.size(); ++a) {
      const tinygltf::Animation& source = model_.animations[a];
      NodeAnimation animation;
      animation.name = source.name.empty() ? "animation " + std::to_string(a) : source.name;
      const std::string label = "animation " + std::to_string(a) + " '" + source.name + "'";
      for (std::size_t c = 0; c < source.channels.size(); ++c) {
        const tinygltf::AnimationChannel& channel = source.channels[c];
        const std::string channel_label = label + " channel " + std::to_string(c);
        if (channel.target_extensions.count("KHR_animation_pointer") != 0) {
          ignored.insert("KHR_animation_pointer channels (igi animates node translation, rotation, scale and morph weights)");
          continue;
        }
        AnimationChannel read;
        const std::optional<AnimatedProperty> property =
            named(channel.target_path, {AnimatedProperty::translation, AnimatedProperty::rotation, AnimatedProperty::scale,
                                        AnimatedProperty::weights}, property_name);
        if (!property) {
          ignored.insert("channels with target path '" + channel.target_path + "'");
          continue;
        }
        read.property = *property;
        if (channel.target_node < 0 || std::size_t(channel.target_node) >= model_.nodes.size())
          fail(channel_label + ": target node " + std::to_string(channel.target_node) + " does not exist (the file has " +
               std::to_string(model_.nodes.size()) + " nodes)");
        read.node = channel.target_node;
        if (model_.nodes[std::size_t(read.node)].matrix.size() == 16 && read.property != AnimatedProperty::weights)
          fail(channel_label + ": animates the " + channel.target_path + " of node " + std::to_string(read.node) +
               ", which has a matrix (glTF allows only nodes with translation, rotation and scale to be animated)");
        if (channel.sampler < 0 || std::size_t(channel.sampler) >= source.samplers.size())
          fail(channel_label + ": sampler " + std::to_string(channel.sampler) + " does not exist (the animation has " +
               std::to_string(source.samplers.size()) + " samplers)");
        const tinygltf::AnimationSampler& sampler = source.samplers[std::size_t(channel.sampler)];
        const std::optional<Interpolation> interpolation =
            sampler.interpolation.empty()  // glTF's default
                ? Interpolation::linear
                : named(sampler.interpolation, {Interpolation::linear, Interpolation::step, Interpolation::cubic_spline},
                        interpolation_name);
        if (!interpolation)
          fail(channel_label + ": interpolation '" + sampler.interpolation + "' is not LINEAR, STEP or CUBICSPLINE");
        read.interpolation = *interpolation;
        read.times = accessors_.read_floats(sampler.input, 1, {TINYGLTF_COMPONENT_TYPE_FLOAT}, channel_label + " input");
        read.components = components_of(read, channel_label);
        // Rotations and weights may be normalized integers (glTF 2.0 section 3.11); the rest are floats.
        const std::initializer_list<int> floats{TINYGLTF_COMPONENT_TYPE_FLOAT};
        const std::initializer_list<int> normalized{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                                                    TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
        const bool vector = read.property != AnimatedProperty::weights;
        read.values = accessors_.read_floats(sampler.output, vector ? read.components : 1,
                                             read.property == AnimatedProperty::rotation || !vector ? normalized : floats,
                                             channel_label + " output");
        for (const float time : read.times)
          if (std::isfinite(time)) animation.duration = std::max(animation.duration, time);
        animation.channels.push_back(std::move(read));
      }
      data.animations.push_back(std::move(animation));
    }
    for (const std::string& what : ignored) warn("animations: " + what + " are ignored");
  }

  /// The deformation data of `primitive` (its skin's joint influences, its morph targets) into a
  /// DeformableMesh over `mesh`, its rest vertices taken from `mesh` as loaded.
  DeformableMesh read_deformable(const DeformedPrimitive& primitive, const Mesh& mesh, const SceneAnimations& data) const {
    const tinygltf::Node& node = model_.nodes[std::size_t(primitive.node)];
    const tinygltf::Primitive& source = model_.meshes[std::size_t(primitive.gltf_mesh)].primitives[std::size_t(primitive.primitive)];
    const std::string label = "node " + std::to_string(primitive.node) + " '" + node.name + "' mesh '" + mesh.name + "'";
    DeformableMesh deformable;
    deformable.mesh = primitive.mesh;
    deformable.instance = primitive.instance;
    deformable.node = primitive.node;
    deformable.rest_positions = mesh.positions;
    deformable.rest_normals = mesh.normals;
    deformable.rest_tangents = mesh.tangents;
    const std::size_t vertices = mesh.positions.size();
    if (node.skin >= 0) {
      if (std::size_t(node.skin) >= model_.skins.size())
        fail(label + ": skin " + std::to_string(node.skin) + " does not exist (the file has " +
             std::to_string(model_.skins.size()) + " skins)");
      deformable.skin = node.skin;
      read_influences(source, label, vertices, data.skins[std::size_t(node.skin)], deformable);
    }
    const std::vector<float>& weights = data.nodes[std::size_t(primitive.node)].weights;
    if (!weights.empty() && weights.size() != source.targets.size())
      fail(label + ": " + std::to_string(weights.size()) + " morph weights for " + std::to_string(source.targets.size()) +
           " morph targets");
    for (std::size_t t = 0; t < source.targets.size(); ++t) {
      MorphTarget target;
      for (const auto& [attribute, accessor] : source.targets[t]) {
        std::vector<glm::vec3>* into = attribute == "POSITION" ? &target.positions
                                       : attribute == "NORMAL" ? &target.normals
                                       : attribute == "TANGENT" ? &target.tangents
                                                                : nullptr;
        if (into == nullptr) {
          warn(label + ": morph target attribute " + attribute + " is ignored (igi morphs POSITION, NORMAL and TANGENT)");
          continue;
        }
        const std::vector<float> values = accessors_.read_floats(
            accessor, 3,
            {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT},
            label + " morph target " + std::to_string(t) + " " + attribute);
        if (values.size() / 3 != vertices)
          fail(label + ": morph target " + std::to_string(t) + " " + attribute + " has " + std::to_string(values.size() / 3) +
               " elements for " + std::to_string(vertices) + " vertices");
        into->resize(vertices);
        for (std::size_t v = 0; v < vertices; ++v) {
          (*into)[v] = glm::vec3(values[3 * v], values[3 * v + 1], values[3 * v + 2]);
          if (!std::isfinite((*into)[v].x) || !std::isfinite((*into)[v].y) || !std::isfinite((*into)[v].z))
            fail(label + ": morph target " + std::to_string(t) + " " + attribute + " element " + std::to_string(v) +
                 " is not finite");
        }
      }
      deformable.targets.push_back(std::move(target));
    }
    return deformable;
  }

  /// True if glTF mesh `mesh`'s primitives have morph targets.
  bool has_targets(int mesh) const {
    if (mesh < 0 || std::size_t(mesh) >= model_.meshes.size()) return false;
    for (const tinygltf::Primitive& primitive : model_.meshes[std::size_t(mesh)].primitives)
      if (!primitive.targets.empty()) return true;
    return false;
  }

 private:
  const tinygltf::Model& model_;        ///< The parsed file.
  const AccessorReader& accessors_;     ///< Reads its accessors.
  const Diagnostics& diagnostics_;      ///< Where failures and warnings go.

  /// Throws SceneError naming the file and `problem`.
  [[noreturn]] void fail(const std::string& problem) const { diagnostics_.fail(problem); }
  /// Reports a recoverable problem of the file.
  void warn(const std::string& message) const { diagnostics_.warn(message); }

  /// Floats per output element of `channel`: 3, 4, or the morph target count of its node's mesh.
  int components_of(const AnimationChannel& channel, const std::string& label) const {
    switch (channel.property) {
      case AnimatedProperty::rotation: return 4;
      case AnimatedProperty::weights: {
        const tinygltf::Node& node = model_.nodes[std::size_t(channel.node)];
        if (node.mesh < 0 || std::size_t(node.mesh) >= model_.meshes.size() ||
            model_.meshes[std::size_t(node.mesh)].primitives.empty() ||
            model_.meshes[std::size_t(node.mesh)].primitives.front().targets.empty())
          fail(label + ": animates the morph weights of node " + std::to_string(channel.node) +
               ", whose mesh has no morph targets");
        return int(model_.meshes[std::size_t(node.mesh)].primitives.front().targets.size());
      }
      default: return 3;
    }
  }

  /// JOINTS_n and WEIGHTS_n (n = 0, 1) of `source` into `deformable`, weights normalized to sum 1.
  void read_influences(const tinygltf::Primitive& source, const std::string& label, std::size_t vertices, const Skin& skin,
                       DeformableMesh& deformable) const {
    std::vector<std::vector<float>> joints, weights;
    for (const char* set : {"0", "1"}) {
      const auto joint = source.attributes.find(std::string("JOINTS_") + set);
      const auto weight = source.attributes.find(std::string("WEIGHTS_") + set);
      if (joint == source.attributes.end() && weight == source.attributes.end()) break;
      if (joint == source.attributes.end() || weight == source.attributes.end())
        fail(label + ": JOINTS_" + set + " and WEIGHTS_" + set + " must come together");
      joints.push_back(accessors_.read_floats(joint->second, 4,
                                              {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                                              label + " JOINTS_" + set));
      weights.push_back(accessors_.read_floats(weight->second, 4,
                                               {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE,
                                                TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT},
                                               label + " WEIGHTS_" + set));
      for (const std::vector<float>* values : {&joints.back(), &weights.back()})
        if (values->size() / 4 != vertices)
          fail(label + ": JOINTS_" + set + "/WEIGHTS_" + set + " has " + std::to_string(values->size() / 4) +
               " elements for " + std::to_string(vertices) + " vertices");
    }
    if (joints.empty()) fail(label + ": is skinned but has no JOINTS_0 and WEIGHTS_0");
    const std::size_t sets = joints.size();
    deformable.influence_sets = int(sets);
    deformable.joints.resize(vertices * sets);
    deformable.weights.resize(vertices * sets);
    std::size_t unweighted = 0;
    for (std::size_t v = 0; v < vertices; ++v) {
      float sum = 0.0f;
      for (std::size_t s = 0; s < sets; ++s)
        for (std::size_t c = 0; c < 4; ++c) {
          const float w = weights[s][4 * v + c];
          if (!(w >= 0.0f) || !std::isfinite(w))
            fail(label + ": vertex " + std::to_string(v) + " has joint weight " + std::to_string(w) +
                 " (weights must be finite and >= 0)");
          const float joint = joints[s][4 * v + c];
          if (w != 0.0f && joint >= float(skin.joints.size()))
            fail(label + ": vertex " + std::to_string(v) + " names joint " + std::to_string(std::size_t(joint)) +
                 " but skin '" + skin.name + "' has " + std::to_string(skin.joints.size()) + " joints");
          deformable.joints[v * sets + s][int(c)] = unsigned(joint);
          deformable.weights[v * sets + s][int(c)] = w;
          sum += w;
        }
      if (sum > 0.0f) {
        for (std::size_t s = 0; s < sets; ++s) deformable.weights[v * sets + s] /= sum;
      } else {
        // A vertex no joint moves: it follows its first joint entry alone, rather than collapse to the origin.
        ++unweighted;
        deformable.weights[v * sets] = glm::vec4(1.0f, 0.0f, 0.0f, 0.0f);
        if (deformable.joints[v * sets].x >= skin.joints.size()) deformable.joints[v * sets].x = 0;
        for (std::size_t s = 1; s < sets; ++s) deformable.weights[v * sets + s] = glm::vec4(0.0f);
      }
    }
    if (unweighted > 0)
      warn(label + ": " + std::to_string(unweighted) + " vertices have no joint weight; they follow their first joint");
  }
};

}  // namespace igi::gltf_detail
