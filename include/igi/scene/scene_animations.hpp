#pragma once
/// \file
/// What a glTF file says about motion: its node hierarchy (the rest transforms), its animations
/// (keyframed translation, rotation, scale and morph weights of nodes), its skins and the meshes
/// that skins and morph targets deform, and which node places each instance, camera and light.
/// Plain data: sampling it at a time is igi/scene/animation_sampling.hpp.

#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

namespace igi {

/// How an animation channel interpolates between its keys (glTF sampler `interpolation`).
enum class Interpolation {
  step,         ///< The value of the last key at or before the time.
  linear,       ///< Linear between keys; rotations by shortest-path spherical interpolation.
  cubic_spline  ///< Cubic Hermite spline with the keys' in- and out-tangents.
};

/// The node property an animation channel drives (glTF channel `target.path`).
enum class AnimatedProperty { translation, rotation, scale, weights };

/// One keyframed property of one node: a glTF channel together with its sampler.
struct AnimationChannel {
  int node = -1;                                     ///< Index into SceneAnimations::nodes.
  AnimatedProperty property = AnimatedProperty::translation;  ///< What it drives.
  Interpolation interpolation = Interpolation::linear;        ///< How it interpolates.
  std::vector<float> times;                          ///< Key times in seconds, strictly increasing.
  /// Key values, `components` floats per element: one element per key, or three per key with
  /// cubic_spline (in-tangent, value, out-tangent). Rotations are quaternions x, y, z, w.
  std::vector<float> values;
  int components = 3;                                ///< 3 (translation, scale), 4 (rotation) or the morph target count.
};

/// A glTF animation: channels played together.
struct NodeAnimation {
  std::string name;                        ///< glTF name, or "animation N".
  std::vector<AnimationChannel> channels;  ///< Its channels.
  float duration = 0.0f;                   ///< Time of its last key over all channels (it starts at time 0).
};

/// A glTF node as animations see it: its rest transform and place in the hierarchy.
struct SceneNode {
  std::string name;                        ///< glTF name, or "node N".
  int parent = -1;                         ///< Index of its parent, -1 for a root.
  glm::vec3 translation{0.0f};             ///< Rest translation.
  glm::quat rotation{1.0f, 0.0f, 0.0f, 0.0f};  ///< Rest rotation (unit).
  glm::vec3 scale{1.0f};                   ///< Rest scale.
  /// True if the file gave a `matrix` (then `matrix` is the local transform and no channel may move it).
  bool uses_matrix = false;
  glm::mat4 matrix{1.0f};                  ///< Local transform when uses_matrix.
  std::vector<float> weights;              ///< Rest morph weights (node.weights, else its mesh's).
};

/// A glTF skin: the joints whose motion deforms a mesh.
struct Skin {
  std::string name;                              ///< glTF name, or "skin N".
  std::vector<int> joints;                       ///< Joint nodes; JOINTS_n values index this list.
  std::vector<glm::mat4> inverse_bind_matrices;  ///< Per joint: mesh space to the joint's space at bind time.
  int skeleton = -1;                             ///< The skeleton's root node (informative), -1 if unnamed.
};

/// A morph target's displacements of a mesh's vertices (empty where the target leaves the attribute alone).
struct MorphTarget {
  std::vector<glm::vec3> positions;  ///< POSITION displacement per vertex.
  std::vector<glm::vec3> normals;    ///< NORMAL displacement per vertex.
  std::vector<glm::vec3> tangents;   ///< TANGENT xyz displacement per vertex.
};

/// A mesh that a skin or morph targets deform: its undeformed vertices and what deforms them.
/// Such a mesh belongs to one instance only, whose node it follows.
struct DeformableMesh {
  int mesh = -1;      ///< Index into Scene::meshes.
  int instance = -1;  ///< Index into Scene::instances of its one instance.
  int node = -1;      ///< The node that holds it (its morph weights; with a skin, its transform is ignored).
  int skin = -1;      ///< Index into SceneAnimations::skins, -1 if only morphed.
  std::vector<glm::vec3> rest_positions;  ///< Mesh-space positions before morphing and skinning.
  std::vector<glm::vec3> rest_normals;    ///< Unit normals before deformation.
  std::vector<glm::vec4> rest_tangents;   ///< Tangents before deformation (empty if the mesh has none).
  /// Joint influences, `influence_sets` entries of four per vertex (JOINTS_0/WEIGHTS_0, then _1):
  /// entry v * influence_sets + s. Empty without a skin.
  std::vector<glm::uvec4> joints;
  std::vector<glm::vec4> weights;  ///< Weights matching `joints`, normalized to sum 1 per vertex.
  int influence_sets = 0;          ///< 1 or 2 with a skin, 0 without.
  std::vector<MorphTarget> targets;  ///< Morph targets, in the file's order.
};

/// Everything about a scene's motion that its file gives (empty for scenes built in code).
struct SceneAnimations {
  std::vector<SceneNode> nodes;           ///< Every node of the file, by glTF index.
  std::vector<int> node_order;            ///< Nodes of the rendered scene, each after its parent.
  std::vector<NodeAnimation> animations;  ///< The file's animations.
  std::vector<Skin> skins;                ///< The file's skins.
  std::vector<DeformableMesh> deformables;  ///< Skinned or morphed meshes.
  std::vector<int> instance_nodes;        ///< Per Scene::instances entry: the node placing it (-1: none).
  std::vector<int> camera_nodes;          ///< Per Scene::cameras entry: its node (-1: none).
  std::vector<int> light_nodes;           ///< Per Scene::lights entry: its node (-1: none).

  /// True if nothing ever moves: no animation (deformables at rest are already in the scene).
  bool empty() const noexcept { return animations.empty(); }
};

}  // namespace igi
