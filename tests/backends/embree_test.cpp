// EmbreeBackend at every width: the common cross-check harness against the reference, plus
// Embree-specific behaviour (errors as exceptions, masked lanes untouched, layout).

#include <catch2/catch.hpp>

#include <glm/gtc/matrix_transform.hpp>

#include "cross_check_cases.hpp"
#include "igi/backends/embree/embree_backend.hpp"

using igi::EmbreeBackend;

TEST_CASE("embree: Embree's errors surface as exceptions carrying Embree's message", "[backends]") {
  EmbreeBackend<4> backend(igi::testing::instanced_scene());
  // An operation Embree rejects: transforms are only for instance geometries.
  RTCGeometry triangles = rtcNewGeometry(backend.device(), RTC_GEOMETRY_TYPE_TRIANGLE);
  const glm::mat4 identity(1.0f);
  rtcSetGeometryTransform(triangles, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &identity[0][0]);
  rtcReleaseGeometry(triangles);
  CHECK_THROWS_AS(backend.check("test operation"), igi::EmbreeError);
  // The error was consumed by the first check; the message is Embree's own text.
  CHECK_NOTHROW(backend.check("nothing wrong"));
  RTCGeometry again = rtcNewGeometry(backend.device(), RTC_GEOMETRY_TYPE_TRIANGLE);
  rtcSetGeometryTransform(again, 0, RTC_FORMAT_FLOAT4X4_COLUMN_MAJOR, &identity[0][0]);
  rtcReleaseGeometry(again);
  CHECK_THROWS_WITH(backend.check("test operation"),
                    Catch::Contains("test operation") && Catch::Contains("RTC_ERROR_INVALID_OPERATION") &&
                        Catch::Contains("not supported for this geometry"));
}

TEST_CASE("embree: bad input is rejected with a message before reaching Embree", "[backends]") {
  igi::Scene scene = igi::testing::instanced_scene();
  {
    igi::Scene broken = scene;
    broken.instances[0].mesh = -1;
    CHECK_THROWS_WITH(EmbreeBackend<8>(broken), Catch::Contains("refers to mesh -1"));
  }
  EmbreeBackend<8> backend(scene);
  CHECK_THROWS_WITH(backend.set_instance_transform(5, glm::mat4(1.0f)), Catch::Contains("instance index 5"));
  glm::mat4 bad(1.0f);
  bad[3][0] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(backend.set_instance_transform(0, bad), Catch::Contains("non-finite"));
  const std::vector<glm::vec3> too_few(2);
  CHECK_THROWS_WITH(backend.set_mesh_positions(1, too_few), Catch::Contains("got 2 positions"));
}

TEMPLATE_TEST_CASE("embree: masked-off lanes are neither traced nor written", "[backends]", EmbreeBackend<4>,
                   EmbreeBackend<8>, EmbreeBackend<16>) {
  constexpr int W = TestType::width;
  const igi::Scene scene = igi::testing::instanced_scene();
  const TestType backend(scene);
  // Every ray aims at the scene centre (all would hit); only the even lanes are in the mask.
  igi::RayPacket<W> rays;
  igi::HitPacket<W> hits;
  const glm::vec3 centre = scene.bounds().center();
  rays.set(igi::vec3<W>(centre + glm::vec3(0.1f, 5.0f, 0.2f)), igi::vec3<W>(glm::vec3(-0.1f, -5.0f, -0.2f)),
           igi::vfloat<W>(0.0f), igi::vfloat<W>(100.0f), igi::vmask<W>(true));
  for (int lane = 0; lane < W; ++lane) {
    hits.primID[lane] = hits.geomID[lane] = hits.instID[lane] = 777u;
    hits.u[lane] = 0.25f;
  }
  igi::vmask<W> even;
  for (int lane = 0; lane < W; lane += 2) even.set(lane, true);
  backend.intersect(rays, hits, even);
  for (int lane = 0; lane < W; ++lane) {
    INFO("lane " << lane);
    if (lane % 2 == 0) {
      CHECK(hits.geomID[lane] != 777u);
      CHECK(hits.geomID[lane] != igi::invalid_id);
      CHECK(rays.tfar[lane] < 100.0f);
    } else {
      CHECK(hits.geomID[lane] == 777u);
      CHECK(hits.primID[lane] == 777u);
      CHECK(hits.instID[lane] == 777u);
      CHECK(hits.u[lane] == 0.25f);
      CHECK(rays.tfar[lane] == 100.0f);
    }
  }
  // Occlusion: odd lanes only this time.
  rays.set(igi::vec3<W>(centre + glm::vec3(0.1f, 5.0f, 0.2f)), igi::vec3<W>(glm::vec3(-0.1f, -5.0f, -0.2f)),
           igi::vfloat<W>(0.0f), igi::vfloat<W>(100.0f), igi::vmask<W>(true));
  const igi::vmask<W> blocked = backend.occluded(rays, !even);
  CHECK(blocked == !even);
  for (int lane = 0; lane < W; lane += 2) CHECK(rays.tfar[lane] == 100.0f);
}

TEST_CASE("embree: moving an instance re-commits only the instance level", "[backends]") {
  // A ray that hits instance 1 before the move and the floor after it.
  igi::Scene scene = igi::testing::instanced_scene();
  EmbreeBackend<1> backend(scene);
  const glm::vec3 target(scene.instances[1].transform[3]);
  igi::RayPacket<1> ray;
  igi::HitPacket<1> hit;
  const auto shoot = [&] {
    ray.set(igi::vec3<1>(target + glm::vec3(0.0f, 3.0f, 0.0f)), igi::vec3<1>(glm::vec3(0.0f, -1.0f, 0.0f)),
            igi::vfloat<1>(0.0f), igi::vfloat<1>(100.0f), igi::vmask<1>(true));
    hit.clear();
    backend.intersect(ray, hit, igi::vmask<1>(true));
  };
  shoot();
  CHECK(hit.instID[0] == 1u);
  backend.set_instance_transform(1, glm::translate(glm::mat4(1.0f), glm::vec3(10.0f, 0.0f, 0.0f)));
  shoot();
  CHECK(hit.instID[0] == 1u);  // Not committed yet: the old placement is still traced.
  backend.commit();
  shoot();
  CHECK(hit.instID[0] == 0u);  // The floor below.
}

TEMPLATE_TEST_CASE("embree: the coherence hint changes speed, not results", "[backends]", EmbreeBackend<4>,
                   EmbreeBackend<16>) {
  constexpr int W = TestType::width;
  const igi::Scene scene = igi::testing::instanced_scene();
  const TestType backend(scene);
  const igi::testing::Tolerances tol = igi::testing::tolerances(scene);
  const auto set = igi::testing::random_rays(scene, 2048, 31);
  int hits = 0;
  for (std::size_t first = 0; first < set.rays.size(); first += W) {
    igi::RayPacket<W> coherent_rays, incoherent_rays;
    igi::HitPacket<W> coherent_hits, incoherent_hits;
    const igi::vmask<W> mask = igi::testing::load_packet<W>(set, first, coherent_rays, coherent_hits);
    igi::testing::load_packet<W>(set, first, incoherent_rays, incoherent_hits);
    backend.intersect(coherent_rays, coherent_hits, igi::Coherence::coherent, mask);
    backend.intersect(incoherent_rays, incoherent_hits, igi::Coherence::incoherent, mask);
    std::vector<igi::testing::Result> coherent_results, incoherent_results;
    for (int lane = 0; lane < W; ++lane) {
      coherent_results.push_back(igi::testing::result_of(coherent_rays, coherent_hits, lane));
      incoherent_results.push_back(igi::testing::result_of(incoherent_rays, incoherent_hits, lane));
    }
    // Fresh intervals for occlusion: one ending exactly at a hit would be a tie either way.
    igi::testing::load_packet<W>(set, first, coherent_rays, coherent_hits);
    igi::testing::load_packet<W>(set, first, incoherent_rays, incoherent_hits);
    const igi::vmask<W> blocked_coherent = backend.occluded(coherent_rays, igi::Coherence::coherent, mask);
    const igi::vmask<W> blocked_incoherent = backend.occluded(incoherent_rays, igi::Coherence::incoherent, mask);
    for (int lane = 0; lane < W; ++lane) {
      if (!mask[lane]) continue;
      const igi::testing::Result& a = coherent_results[std::size_t(lane)];
      const igi::testing::Result& b = incoherent_results[std::size_t(lane)];
      hits += a.hit;
      INFO("ray " << first + std::size_t(lane) << "\n  coherent: " << a.describe() << "\n  incoherent: " << b.describe());
      REQUIRE(igi::testing::compare_hits(scene, set.rays[first + std::size_t(lane)], a, b, tol).empty());
      REQUIRE(blocked_coherent[lane] == blocked_incoherent[lane]);
    }
  }
  CHECK(hits > 100);
}

/// EmbreeBackend flattening only meshes with one instance (as for a scene above the flattening
/// limit): the shared sphere mesh of the instanced scene is traced through Embree instances.
template <int W>
struct InstancingEmbree : EmbreeBackend<W> {
  /// Builds over `scene` with a flattening limit of 0 triangles.
  explicit InstancingEmbree(const igi::Scene& scene) : EmbreeBackend<W>(scene, "", 0) {}
};

TEMPLATE_TEST_CASE("embree: flattened instances that move twice, then deform, stay in step with the reference",
                   "[backends]", EmbreeBackend<16>, InstancingEmbree<16>) {
  // The first move takes an instance out of the flattened scene, the second moves the Embree
  // instance it became; the vertex change then refits the mesh scene it now uses.
  igi::Scene scene = igi::testing::instanced_scene();
  TestType backend(scene);
  for (const float shift : {0.5f, -1.25f}) {
    const glm::mat4 moved = glm::translate(scene.instances[2].transform, glm::vec3(shift, 0.0f, 0.0f));
    scene.instances[2].transform = moved;
    backend.set_instance_transform(2, moved);
    backend.commit();
    igi::testing::cross_check_all_kinds(scene, backend);
  }
  const std::vector<glm::vec3> positions = igi::testing::deformed_sphere_positions(scene);
  scene.meshes[1].positions = positions;
  backend.set_mesh_positions(1, positions);
  backend.commit();
  igi::testing::cross_check_all_kinds(scene, backend);
}

IGI_CROSS_CHECK_CASES("embree:", EmbreeBackend<1>, EmbreeBackend<4>, EmbreeBackend<8>, EmbreeBackend<16>)
IGI_CROSS_CHECK_CASES("embree instancing:", InstancingEmbree<4>, InstancingEmbree<16>)
