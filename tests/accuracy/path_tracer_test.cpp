// The reference path tracer: analytic closed box, 1/sqrt(spp) convergence, agreement with IGI
// (clamp off, many VPLs) on the Cornell box, determinism and progressive accumulation.
#include <catch2/catch.hpp>

#include "accuracy_support.hpp"
#include "igi/scene/gltf.hpp"
#include "scenes.hpp"

using namespace igi;
using namespace igi::testing;

TEST_CASE("path tracer: closed uniform box has radiance Le / (1 - albedo)", "[accuracy][path][analytic]") {
  for (const float albedo : {0.5f, 0.8f}) {
    const float emission = 1.0f;
    const Scene scene = closed_box(albedo, emission);
    PathTracerStatistics statistics;
    const Image image = path_trace(scene, 24, 24, 16, {}, &statistics);
    REQUIRE(finite(image));
    CHECK(statistics.invalid_samples == 0);
    // Pixels are independent estimates (own random numbers), so the image mean's standard error
    // is the pixels' standard deviation / sqrt(pixel count); 4 standard errors leave a 6e-5
    // chance of a false failure while any bias above ~1% (e.g. a missing MIS weight, which would
    // double-count light) stands out by far more.
    std::vector<double> pixels;
    for (const glm::vec3& p : image.pixels) pixels.push_back((double(p.r) + double(p.g) + double(p.b)) / 3.0);
    const Estimate e = estimate(pixels);
    const double expected = emission / (1.0 - albedo);
    INFO("albedo " << albedo << ": mean " << e.mean << " +- " << e.standard_error << ", expected " << expected);
    CHECK(std::abs(e.mean - expected) < 4.0 * e.standard_error);
    CHECK(e.standard_error < 0.02 * expected);  // the estimate is tight enough for the check to mean something
  }
}

TEST_CASE("path tracer: RMSE falls like 1/sqrt(spp)", "[accuracy][path][convergence]") {
  const Scene scene = cornell_box();
  // Pixel centres only: a jittered pixel that partly covers the 18-unit-bright light is a
  // Bernoulli variable whose rare hits dominate a 32 x 32 RMSE at low spp and make the estimate
  // of the RMSE itself unstable; the law under test is that of the light transport.
  PathTracerSettings reference_settings;
  reference_settings.jitter = false;
  reference_settings.seed = 1;
  const Image reference = path_trace(scene, 32, 32, 1024, reference_settings);
  PathTracerSettings test_settings = reference_settings;
  test_settings.seed = 2;  // independent of the reference's random numbers
  std::vector<double> spp{4, 16, 64}, errors;
  for (const double k : spp) errors.push_back(igi::rmse(path_trace(scene, 32, 32, int(k), test_settings), reference));
  const double slope = log_log_slope(spp, errors);
  INFO("rmse at 4/16/64 spp: " << errors[0] << " " << errors[1] << " " << errors[2] << ", slope " << slope);
  // An unbiased estimator with finite variance has RMSE = sigma / sqrt(spp): slope -1/2. The
  // reference's own noise (1024 spp) adds sigma^2 / 1024 to every squared error, which flattens
  // the 4..64 fit to -0.49; the RMSE over 1024 pixels fluctuates by a few percent, moving the
  // slope by about +-0.03. A biased estimator would level off (slope towards 0) and a broken
  // sampler could not fall faster than -1/2, so [-0.6, -0.4] separates both from the truth.
  CHECK(slope < -0.4);
  CHECK(slope > -0.6);
  CHECK(errors[2] < errors[1]);
  CHECK(errors[1] < errors[0]);
}

TEST_CASE("path tracer and IGI (clamp 0, many VPLs) agree on the Cornell box within noise", "[accuracy][path][igi]") {
  Scene scene = cornell_box();
  constexpr int size = 48, block = 8, runs = 6;
  // IGI without its biases: no clamp, one interleaving set, no filter, long walks, pixel centres.
  RenderSettings igi_settings;
  igi_settings.width = igi_settings.height = size;
  igi_settings.interleave = 1;
  igi_settings.vpls_per_pixel = 512;
  igi_settings.clamp_distance = 0.0f;
  igi_settings.max_bounces = 64;
  PathTracerSettings path_settings;
  path_settings.jitter = false;  // the same pixel-centre rays as IGI without anti-aliasing
  // Independent runs of both (seeds differ) give means and standard errors of every block.
  std::vector<std::vector<double>> igi_blocks, path_blocks;
  std::vector<double> igi_means, path_means;
  for (int run = 0; run < runs; ++run) {
    igi_settings.seed = std::uint32_t(100 + run);
    const Frame frame = render_once<EmbreeBackend<8>, StandardBrdf, NoFilter>(scene, igi_settings);
    REQUIRE(all_finite(frame));
    igi_blocks.push_back(block_means(frame.hdr, block));
    igi_means.push_back(mean_of(frame.hdr));
    path_settings.seed = std::uint32_t(200 + run);
    const Image path = path_trace(scene, size, size, 64, path_settings);
    REQUIRE(finite(path));
    path_blocks.push_back(block_means(path, block));
    path_means.push_back(mean_of(path));
  }
  const Estimate igi_mean = estimate(igi_means), path_mean = estimate(path_means);
  const double mean_sigma = std::hypot(igi_mean.standard_error, path_mean.standard_error);
  INFO("image mean: IGI " << igi_mean.mean << " +- " << igi_mean.standard_error << ", path " << path_mean.mean << " +- "
                          << path_mean.standard_error);
  // Within noise: the difference of the two means in units of its standard error. With 6 runs
  // each the standard errors are themselves uncertain (t with ~10 degrees of freedom), so 4
  // sigma still leaves a false-failure chance below 0.3%.
  CHECK(std::abs(igi_mean.mean - path_mean.mean) < 4.0 * mean_sigma);
  // The low-pass: 8 x 8 block means (36 blocks). Each block's z = difference / combined standard
  // error; if both converge to the same image the z^2 average about 1 (t-distributed z with 10
  // degrees of freedom: E z^2 = 1.25, and the mean over 36 blocks has a standard deviation of
  // about 0.4), so a mean z^2 below 2.5 is what agreement looks like, while a bias of one
  // standard error in every block would already give 2.25 + 1.25.
  double z2 = 0.0, worst = 0.0;
  const std::size_t blocks = igi_blocks.front().size();
  for (std::size_t b = 0; b < blocks; ++b) {
    std::vector<double> a, c;
    for (int run = 0; run < runs; ++run) {
      a.push_back(igi_blocks[std::size_t(run)][b]);
      c.push_back(path_blocks[std::size_t(run)][b]);
    }
    const Estimate ea = estimate(a), ec = estimate(c);
    const double sigma = std::hypot(ea.standard_error, ec.standard_error);
    const double z = sigma > 0.0 ? (ea.mean - ec.mean) / sigma : 0.0;
    z2 += z * z;
    worst = std::max(worst, std::abs(z));
  }
  z2 /= double(blocks);
  INFO("blocks " << blocks << ": mean z^2 " << z2 << ", worst |z| " << worst);
  CHECK(z2 < 2.5);
  // The two are also close in absolute terms: means within 2% of each other.
  CHECK(std::abs(igi_mean.mean - path_mean.mean) < 0.02 * path_mean.mean);
}

TEST_CASE("path tracer: threads and progressive passes do not change a bit", "[accuracy][path][determinism]") {
  const Scene scene = cornell_box();
  PathTracerSettings one, two;
  one.threads = 1;
  two.threads = 2;
  one.seed = two.seed = 7;
  const Image a = path_trace(scene, 40, 30, 8, one);
  const Image b = path_trace(scene, 40, 30, 8, two);
  CHECK(a.pixels == b.pixels);
  CHECK(mean_of(a) > 0.0);

  const EmbreeBackend<1> backend(scene);
  const GltfMaterialShader surface(scene);
  const StandardBrdf brdf;
  PathTracer<EmbreeBackend<1>, GltfMaterialShader, StandardBrdf> tracer(scene, backend, surface, brdf, two);
  tracer.reset(scene.cameras.front(), 40, 30);
  tracer.add_samples(3);
  tracer.add_samples(5);
  CHECK(tracer.samples() == 8);
  CHECK(tracer.image().pixels == a.pixels);
  CHECK(tracer.statistics().rays.primary >= 40u * 30u * 8u);
  CHECK(tracer.statistics().invalid_samples == 0);

  PathTracerSettings other = one;
  other.seed = 8;
  CHECK(path_trace(scene, 40, 30, 8, other).pixels != a.pixels);
}

TEST_CASE("path tracer: bad input is a clear error", "[accuracy][path][errors]") {
  const Scene scene = cornell_box();
  const EmbreeBackend<1> backend(scene);
  const GltfMaterialShader surface(scene);
  const StandardBrdf brdf;
  using Tracer = PathTracer<EmbreeBackend<1>, GltfMaterialShader, StandardBrdf>;
  PathTracerSettings bad;
  bad.max_depth = 0;
  CHECK_THROWS_WITH(Tracer(scene, backend, surface, brdf, bad), Catch::Contains("max depth"));
  Tracer tracer(scene, backend, surface, brdf);
  CHECK_THROWS_WITH(tracer.add_samples(1), Catch::Contains("reset"));
  CHECK_THROWS_WITH(tracer.render(scene.cameras.front(), 0, 10, 1), Catch::Contains("size"));
  tracer.reset(scene.cameras.front(), 8, 8);
  CHECK_THROWS_WITH(tracer.add_samples(-1), Catch::Contains("spp"));
}

namespace {

/// The shared scene `file` path-traces to a finite, non-black image with every sample valid.
void check_path_traced_scene(const char* file) {
  const auto path = scene_path(file);
  IGI_REQUIRE_SCENE(path);
  const Scene scene = load_gltf(path);
  PathTracerStatistics statistics;
  const Image image = path_trace(scene, 32, 24, 4, {}, &statistics);
  CHECK(finite(image));
  CHECK(statistics.invalid_samples == 0);
  CHECK(mean_of(image) > 0.0);
  CHECK(statistics.rays.shadow > 0);
}

}  // namespace

// One test case per scene, so that a missing scene skips only its own case.
TEST_CASE("path tracer: alpha-mask foliage, textures and punctual lights render finite, every sample valid "
          "(shared scene Sponza_lit.gltf)", "[accuracy][path][scenes]") {
  // Cut-outs in camera, bounce and shadow rays.
  check_path_traced_scene("sponza/Sponza_lit.gltf");
}

TEST_CASE("path tracer: the Mitsuba comparison's Cornell box renders finite, every sample valid "
          "(shared scene cornell_box.gltf)", "[accuracy][path][scenes]") {
  check_path_traced_scene("cornell/cornell_box.gltf");
}
