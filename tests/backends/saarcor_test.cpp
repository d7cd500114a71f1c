// SaarcorBackend: the common cross-check harness against the reference, and its hardware counters.

#include <thread>

#include <catch2/catch.hpp>

#include "cross_check_cases.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"

using igi::SaarcorBackend;

TEST_CASE("saarcor: the kd-tree is a real SAH tree with 8-byte nodes", "[backends]") {
  const igi::Scene scene = igi::testing::soup_scene();
  const SaarcorBackend backend(scene);
  // 3000 small triangles: a useful tree has many leaves and few references per triangle.
  CHECK(backend.node_count() > 500);
  CHECK(backend.depth() >= 8);
  CHECK(backend.reference_count() >= scene.unique_triangle_count());
  // The tree must cull: random rays through the soup test a small fraction of the triangles
  // (a flat list would test all 3000; 5% = 150 is generous for a tree ~20 levels deep).
  const auto random = igi::testing::random_rays(scene, 1024, 21);
  for (std::size_t first = 0; first < random.rays.size(); first += 64) {
    igi::RayPacket<64> ray_packet;
    igi::HitPacket<64> hit_packet;
    const igi::vmask<64> mask = igi::testing::load_packet<64>(random, first, ray_packet, hit_packet);
    backend.intersect(ray_packet, hit_packet, mask);
  }
  const igi::SaarcorStats stats = backend.stats();
  const double tests_per_ray = double(stats.ray_triangle_tests) / double(stats.rays);
  INFO("ray-triangle tests per ray: " << tests_per_ray << ", references per triangle: "
       << double(backend.reference_count()) / double(scene.unique_triangle_count()));
  CHECK(tests_per_ray < 0.05 * double(scene.unique_triangle_count()));
}

TEST_CASE("saarcor: counters count packets, steps, tests and bytes, and reset", "[backends]") {
  const igi::Scene scene = igi::testing::instanced_scene();
  const SaarcorBackend backend(scene);
  const igi::ReferenceBackend<1> reference(scene);
  const igi::Bounds b = scene.bounds();
  const auto camera = igi::testing::camera_rays(b.center() + glm::vec3(0.3f, 0.4f, 1.2f) * glm::length(b.extent()),
                                                b.center(), 0.8f, 64);
  CHECK(backend.stats().packets == 0);

  int packets = 0, rays = 0;
  for (std::size_t first = 0; first < camera.rays.size(); first += 64) {
    igi::RayPacket<64> ray_packet;
    igi::HitPacket<64> hit_packet;
    const igi::vmask<64> mask = igi::testing::load_packet<64>(camera, first, ray_packet, hit_packet);
    backend.intersect(ray_packet, hit_packet, mask);
    ++packets;
    rays += igi::popcount(mask);
  }
  const igi::SaarcorStats coherent = backend.stats();
  CHECK(coherent.packets == std::uint64_t(packets));
  CHECK(coherent.rays == std::uint64_t(rays));
  CHECK(coherent.traversal_steps > 0);
  CHECK(coherent.leaf_visits > 0);
  CHECK(coherent.triangle_tests > 0);
  // Every fetched triangle is tested against at least one and at most 64 active rays.
  CHECK(coherent.ray_triangle_tests >= coherent.triangle_tests);
  CHECK(coherent.ray_triangle_tests <= 64 * coherent.triangle_tests);
  // Byte counts follow the record sizes: 8-byte nodes, 4-byte references + 48-byte triangles.
  CHECK(coherent.kd_node_bytes == 8 * (coherent.traversal_steps + coherent.leaf_visits));
  CHECK(coherent.triangle_bytes == (4 + sizeof(igi::WorldTriangle)) * coherent.triangle_tests);
  CHECK(coherent.active_lane_ratio() > 0.0);
  CHECK(coherent.active_lane_ratio() <= 1.0);

  // Incoherent rays in 64-ray packets leave more lanes idle per step than camera tiles do.
  backend.reset_stats();
  CHECK(backend.stats().packets == 0);
  CHECK(backend.stats().traversal_steps == 0);
  const auto random = igi::testing::random_rays(scene, 4096, 77);
  for (std::size_t first = 0; first < random.rays.size(); first += 64) {
    igi::RayPacket<64> ray_packet;
    igi::HitPacket<64> hit_packet;
    const igi::vmask<64> mask = igi::testing::load_packet<64>(random, first, ray_packet, hit_packet);
    backend.intersect(ray_packet, hit_packet, mask);
  }
  const igi::SaarcorStats incoherent = backend.stats();
  INFO("coherent ratio " << coherent.active_lane_ratio() << ", incoherent ratio " << incoherent.active_lane_ratio());
  CHECK(incoherent.active_lane_ratio() < coherent.active_lane_ratio());
}

TEST_CASE("saarcor: counters add up exactly across threads", "[backends]") {
  const igi::Scene scene = igi::testing::soup_scene();
  const SaarcorBackend backend(scene);
  const auto random = igi::testing::random_rays(scene, 2048, 8);
  const auto run_all = [&] {
    for (std::size_t first = 0; first < random.rays.size(); first += 64) {
      igi::RayPacket<64> ray_packet;
      igi::HitPacket<64> hit_packet;
      const igi::vmask<64> mask = igi::testing::load_packet<64>(random, first, ray_packet, hit_packet);
      backend.intersect(ray_packet, hit_packet, mask);
    }
  };
  run_all();
  const igi::SaarcorStats once = backend.stats();
  backend.reset_stats();
  std::thread a(run_all), b(run_all);
  a.join();
  b.join();
  const igi::SaarcorStats twice = backend.stats();
  // Tracing is deterministic, so two concurrent runs count exactly twice one run.
  CHECK(twice.packets == 2 * once.packets);
  CHECK(twice.traversal_steps == 2 * once.traversal_steps);
  CHECK(twice.triangle_tests == 2 * once.triangle_tests);
  CHECK(twice.ray_triangle_tests == 2 * once.ray_triangle_tests);
  CHECK(twice.kd_node_bytes == 2 * once.kd_node_bytes);
}

TEST_CASE("saarcor: bad input is rejected with a message", "[backends]") {
  igi::Scene scene = igi::testing::instanced_scene();
  {
    igi::Scene broken = scene;
    broken.meshes[2].positions[0].x = std::numeric_limits<float>::infinity();
    CHECK_THROWS_WITH(SaarcorBackend(broken), Catch::Contains("non-finite vertex"));
  }
  SaarcorBackend backend(scene);
  CHECK_THROWS_WITH(backend.set_instance_transform(5, glm::mat4(1.0f)), Catch::Contains("instance index 5"));
  CHECK_THROWS_WITH(backend.set_mesh_positions(7, {}), Catch::Contains("mesh index 7"));
}

IGI_CROSS_CHECK_CASES("saarcor:", SaarcorBackend)
