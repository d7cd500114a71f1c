// SceneBounds keeps Scene::bounds() per instance: bit for bit the same box after any sequence of
// moves and mesh changes, so frames that take their clamp distance and ray offsets from it stay
// identical while the per-frame cost no longer grows with the triangle count.

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

TEST_CASE("scene bounds: an empty scene has empty bounds, and a changed instance count is refused", "[scene]") {
  igi::Scene scene;
  const igi::SceneBounds empty(scene);
  CHECK(empty.bounds().empty());
  igi::Scene cornell = igi::cornell_box();
  igi::SceneBounds bounds(cornell);
  cornell.instances.pop_back();
  CHECK_THROWS_WITH(bounds.instance_moved(cornell, 0), Catch::Contains("made for"));
}
