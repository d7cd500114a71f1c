// SceneBounds keeps Scene::bounds() per mesh and instance: bit for bit the same box after any
// sequence of moves and mesh changes, so frames that take their clamp distance and ray offsets
// from it stay identical while a moved instance costs the same whatever its triangle count. The
// placed boxes they are made of hold every vertex, and are exact where nothing rotates.

#include <catch2/catch.hpp>

#include <cstring>

#include <glm/gtc/matrix_transform.hpp>

#include "igi/scene/cornell.hpp"
#include "igi/scene/scene_bounds.hpp"

namespace {

/// True if the two boxes have the same bits (so +0 and -0 differ, and nothing is compared with a tolerance).
bool same_bits(const igi::Bounds& a, const igi::Bounds& b) {
  return std::memcmp(&a.lower, &b.lower, sizeof a.lower) == 0 && std::memcmp(&a.upper, &b.upper, sizeof a.upper) == 0;
}

/// The Cornell box plus two more instances of its tallest block, one of them with a zero
/// coordinate of either sign at the box's lower corner (ties between +0 and -0 must resolve as
/// Scene::bounds() resolves them).
igi::Scene scene_with_shared_mesh() {
  igi::Scene scene = igi::cornell_box();
  const int mesh = scene.instances.back().mesh;
  scene.instances.push_back({"copy", mesh, glm::translate(glm::mat4(1.0f), glm::vec3(0.3f, 0.0f, -0.2f))});
  igi::Mesh signed_zero;
  signed_zero.name = "signed zero";
  signed_zero.positions = {{-0.0f, 0.0f, -0.0f}, {0.0f, -0.0f, 0.0f}, {0.1f, 0.1f, 0.1f}};
  signed_zero.normals = {{0, 1, 0}, {0, 1, 0}, {0, 1, 0}};
  signed_zero.triangles = {{0, 1, 2}};
  scene.meshes.push_back(signed_zero);
  scene.instances.push_back({"signed zero", int(scene.meshes.size()) - 1, glm::mat4(1.0f)});
  return scene;
}

}  // namespace

TEST_CASE("scene bounds: the same box as Scene::bounds(), bit for bit, through moves and mesh changes", "[scene]") {
  igi::Scene scene = scene_with_shared_mesh();
  igi::SceneBounds bounds(scene);
  REQUIRE_FALSE(bounds.bounds().empty());
  CHECK(same_bits(bounds.bounds(), scene.bounds()));

  // Moves, each followed by the update a renderer makes.
  const std::size_t copy = scene.instances.size() - 2;
  for (const glm::vec3 shift : {glm::vec3(5.0f, 0.0f, 0.0f), glm::vec3(-7.5f, 2.0f, 1.0f), glm::vec3(0.0f)}) {
    scene.instances[copy].transform = glm::translate(glm::mat4(1.0f), shift);
    bounds.instance_moved(scene, int(copy));
    INFO("copy moved to " << shift.x << ", " << shift.y << ", " << shift.z);
    CHECK(same_bits(bounds.bounds(), scene.bounds()));
  }
  // Turned and moved far out, then several moves before the box is asked for again.
  scene.instances[copy].transform = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(-30.0f, 0.0f, 3.0f)), 0.7f,
                                                glm::vec3(0.3f, 1.0f, 0.2f));
  bounds.instance_moved(scene, int(copy));
  CHECK(same_bits(bounds.bounds(), scene.bounds()));
  CHECK(bounds.bounds().lower.x < -29.0f);
  scene.instances[0].transform = glm::scale(glm::mat4(1.0f), glm::vec3(1.5f));
  bounds.instance_moved(scene, 0);
  scene.instances[copy].transform = glm::mat4(1.0f);
  bounds.instance_moved(scene, int(copy));
  CHECK(same_bits(bounds.bounds(), scene.bounds()));
  // The moved copy far outside: the box grows; back inside: it shrinks again.
  scene.instances[copy].transform = glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 40.0f, 0.0f));
  bounds.instance_moved(scene, int(copy));
  CHECK(bounds.bounds().upper.y > 40.0f);
  CHECK(same_bits(bounds.bounds(), scene.bounds()));

  // A change to the shared mesh moves both of its instances.
  igi::Mesh& shared = scene.meshes[std::size_t(scene.instances[copy].mesh)];
  for (glm::vec3& p : shared.positions) p = 2.0f * p - glm::vec3(1.0f);
  bounds.mesh_changed(scene, scene.instances[copy].mesh);
  CHECK(same_bits(bounds.bounds(), scene.bounds()));
}

TEST_CASE("placed boxes: every vertex inside, and exact bit for bit under translations and scales of either sign", "[scene]") {
  const igi::Scene cornell = igi::cornell_box();
  const igi::Mesh& block = cornell.meshes[std::size_t(cornell.instances.back().mesh)];
  const igi::Bounds box = igi::mesh_bounds(block);
  REQUIRE_FALSE(box.empty());
  /// The box of the transformed vertices themselves, the definition the placed box stands for.
  const auto walked = [&](const glm::mat4& transform) {
    igi::Bounds world;
    for (const glm::vec3& p : block.positions) world.extend(glm::vec3(transform * glm::vec4(p, 1.0f)));
    return world;
  };
  const glm::mat4 moved = glm::translate(glm::mat4(1.0f), glm::vec3(0.37f, -12.5f, 1e3f));
  for (const glm::mat4& transform : {glm::mat4(1.0f), moved, glm::scale(moved, glm::vec3(2.5f, 0.3f, 7.0f)),
                                     glm::scale(moved, glm::vec3(-1.0f, 1.0f, -3.1f))}) {
    CHECK(same_bits(igi::placed(box, transform), walked(transform)));
  }
  // Under a rotation the placed box holds the walked one and is no more than the box of the rotated box.
  const glm::mat4 turned = glm::rotate(moved, 0.9f, glm::vec3(1.0f, 2.0f, -0.5f));
  const igi::Bounds loose = igi::placed(box, turned);
  const igi::Bounds tight = walked(turned);
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(loose.lower[axis] <= tight.lower[axis]);
    CHECK(loose.upper[axis] >= tight.upper[axis]);
  }
  // and no more than the cube around the sphere through the box's corners (a rotation keeps
  // their distance from the centre; 1e-4 of it is float rounding in the transform).
  const glm::vec3 center(turned * glm::vec4(box.center(), 1.0f));
  const float radius = 0.5f * glm::length(box.extent()) * (1.0f + 1e-4f);
  for (int axis = 0; axis < 3; ++axis) {
    CHECK(loose.lower[axis] >= center[axis] - radius);
    CHECK(loose.upper[axis] <= center[axis] + radius);
  }
  CHECK(igi::placed(igi::Bounds{}, turned).empty());
}

TEST_CASE("scene bounds: an empty scene has empty bounds, and a changed instance count is refused", "[scene]") {
  igi::Scene scene;
  const igi::SceneBounds empty(scene);
  CHECK(empty.bounds().empty());
  igi::Scene cornell = igi::cornell_box();
  igi::SceneBounds bounds(cornell);
  cornell.instances.pop_back();
  CHECK_THROWS_WITH(bounds.instance_moved(cornell, 0), Catch::Contains("made for"));
}
