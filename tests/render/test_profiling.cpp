// Renderer::set_profiling: every pipeline stage timed, the image unchanged, the times within the
// frame's own.

#include <catch2/catch.hpp>

#include <cstring>

#include "render_support.hpp"

TEST_CASE("profiling: stage times change nothing in the image and add up to at most the frame", "[render]") {
  igi::Scene scene = igi::cornell_box();
  igi::RenderSettings settings;
  settings.width = 96;
  settings.height = 72;
  settings.vpls_per_pixel = 8;
  settings.threads = 1;  // one thread: its stages run one after another inside the frame's wall time
  const igi::GltfMaterialShader surface(scene);
  const igi::StandardBrdf brdf;
  const igi::QmcVplSampler sampler;
  const igi::DiscontinuityFilter filter;
  igi::Renderer<igi::EmbreeBackend<8>, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                igi::DiscontinuityFilter>
      renderer(scene, settings, surface, brdf, sampler, filter);
  const igi::Camera camera = scene.cameras.front();
  const igi::Frame plain = renderer.render(camera, 1);
  CHECK(plain.statistics.stages.total() == 0);  // not asked for: nothing timed

  renderer.set_profiling(true);
  const igi::Frame profiled = renderer.render(camera, 1);
  REQUIRE(plain.hdr.pixels.size() == profiled.hdr.pixels.size());
  CHECK(std::memcmp(plain.hdr.pixels.data(), profiled.hdr.pixels.data(), plain.hdr.pixels.size() * sizeof(glm::vec3)) == 0);

  const igi::StageTimes& t = profiled.statistics.stages;
  // Every stage the Cornell box exercises took some time (it has no mirrors: no spawned rays).
  CHECK(t.primary > 0);
  CHECK(t.closest > 0);
  CHECK(t.surface > 0);
  CHECK(t.connect > 0);
  CHECK(t.shadow > 0);
  CHECK(t.gbuffer > 0);
  CHECK(t.filter > 0);
  CHECK(t.compose > 0);
  CHECK(t.compensate == 0);  // bias compensation is off by default
  const double stages_ms = double(t.total()) * 1e-6;
  INFO("stages " << stages_ms << " ms, frame " << profiled.statistics.milliseconds << " ms");
  CHECK(stages_ms <= profiled.statistics.milliseconds);
  int named = 0;
  t.each([&](const char*, std::uint64_t) { ++named; });
  CHECK(named == 10);

  renderer.set_profiling(false);
  CHECK(renderer.render(camera, 1).statistics.stages.total() == 0);
}
