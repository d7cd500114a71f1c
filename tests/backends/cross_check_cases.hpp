#pragma once
// The cross-check test cases, stamped out once per backend family by IGI_CROSS_CHECK_CASES(prefix, types...).

#include "cross_check.hpp"

namespace igi::testing {

/// Builds B over `scene` and cross-checks every ray kind.
template <class B>
void check_scene(const Scene& scene) {
  static_assert(Backend<B>);
  const B backend(scene);
  cross_check_all_kinds(scene, backend);
}

/// instanced_scene() with instance 2 moved through the backend's update path (not a rebuild):
/// the reference is built from the moved scene directly.
template <class B>
void check_moved_instance() {
  Scene scene = instanced_scene();
  B backend(scene);
  {
    // Trace once before moving, so a backend that forgets the update is caught with stale state.
    const ReferenceBackend<1> reference(scene);
    cross_check(scene, backend, reference, random_rays(scene, 1024, 5));
  }
  scene.instances[2].transform = moved_transform();
  backend.set_instance_transform(2, moved_transform());
  backend.commit();
  cross_check_all_kinds(scene, backend);
}

/// instanced_scene() with the sphere mesh (used by three instances) deformed through set_mesh_positions.
template <class B>
void check_changed_vertices() {
  Scene scene = instanced_scene();
  B backend(scene);
  const std::vector<glm::vec3> positions = deformed_sphere_positions(scene);
  scene.meshes[1].positions = positions;
  backend.set_mesh_positions(1, positions);
  backend.commit();
  cross_check_all_kinds(scene, backend);
}

/// An empty scene, and one whose only instance places a mesh without triangles: every ray misses.
template <class B>
void check_empty_scenes() {
  Scene hollow;
  Mesh no_triangles;
  no_triangles.name = "no triangles";
  no_triangles.positions = {glm::vec3(0.0f)};
  hollow.meshes.push_back(no_triangles);
  hollow.instances.push_back({"hollow", 0, glm::mat4(1.0f)});
  for (const Scene& scene : {Scene{}, hollow}) {
    const B backend(scene);
    constexpr int W = B::width;
    RayPacket<W> rays;
    HitPacket<W> hits;
    rays.set(vec3<W>(glm::vec3(0.0f, 0.0f, -1.0f)), vec3<W>(glm::vec3(0.0f, 0.0f, 1.0f)), vfloat<W>(0.0f),
             vfloat<W>(1e30f), vmask<W>(true));
    for (int lane = 0; lane < W; ++lane) hits.geomID[lane] = 5u;
    backend.intersect(rays, hits, vmask<W>(true));
    CHECK(none(hits.valid()));
    CHECK(rays.tfar[0] == 1e30f);
    CHECK(none(backend.occluded(rays, vmask<W>(true))));
  }
}

}  // namespace igi::testing

/// Every cross-check case for the backend types given.
#define IGI_CROSS_CHECK_CASES(prefix, ...)                                                        \
  TEMPLATE_TEST_CASE(prefix " cross-check: random triangle soup", "[backends]", __VA_ARGS__) {    \
    igi::testing::check_scene<TestType>(igi::testing::soup_scene());                              \
  }                                                                                               \
  TEMPLATE_TEST_CASE(prefix " cross-check: instanced scene", "[backends]", __VA_ARGS__) {         \
    igi::testing::check_scene<TestType>(igi::testing::instanced_scene());                         \
  }                                                                                               \
  TEMPLATE_TEST_CASE(prefix " cross-check: instanced scene after an instance moved", "[backends]", \
                     __VA_ARGS__) {                                                               \
    igi::testing::check_moved_instance<TestType>();                                               \
  }                                                                                               \
  TEMPLATE_TEST_CASE(prefix " cross-check: instanced scene after mesh vertices changed",          \
                     "[backends]", __VA_ARGS__) {                                                 \
    igi::testing::check_changed_vertices<TestType>();                                             \
  }                                                                                               \
  TEMPLATE_TEST_CASE(prefix " empty scenes miss everything", "[backends]", __VA_ARGS__) {          \
    igi::testing::check_empty_scenes<TestType>();                                                 \
  }                                                                                               \
  TEMPLATE_TEST_CASE(prefix " cross-check: Cornell box", "[backends]", __VA_ARGS__) {             \
    igi::testing::check_scene<TestType>(igi::cornell_box());                                      \
  }                                                                                               \
  TEMPLATE_TEST_CASE(prefix " cross-check: bunny (shared scene stanford-bunny.glb)", "[backends]", \
                     __VA_ARGS__) {                                                               \
    const auto path = igi::testing::scene_path("bunny/stanford-bunny.glb");                      \
    IGI_REQUIRE_SCENE(path);                                                                      \
    igi::testing::check_scene<TestType>(igi::load_gltf(path));                                    \
  }
