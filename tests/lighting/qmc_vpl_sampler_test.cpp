// QmcVplSampler: normalisation (each set is an unbiased estimate of the light transport),
// placement on lights and surfaces, determinism, and the per-set distribution of walks.

#include <cmath>
#include <cstdio>
#include <numbers>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/backends/reference/reference_backend.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "igi/shading/procedural_shaders.hpp"
#include "lighting/lighting_support.hpp"
#include "scenes.hpp"
#include "scene_builders.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

// Sum of the mean-RGB flux of the VPLs of `set` whose bounce is `bounce` (-1: all).
double set_flux(const VplGeneration& g, std::size_t set, int bounce, float directional_area = 0.0f) {
  double sum = 0.0;
  for (std::size_t i = 0; i < g.vpls.sets[set].size(); ++i) {
    if (bounce >= 0 && g.origins[set][i].bounce != bounce) continue;
    const glm::vec3 f = vpl_flux(g.vpls.sets[set][i], directional_area);
    sum += (double(f.x) + f.y + f.z) / 3.0;
  }
  return sum;
}

double total_flux(const VplGeneration& g, int bounce, float directional_area = 0.0f) {
  double sum = 0.0;
  for (std::size_t s = 0; s < g.vpls.sets.size(); ++s) sum += set_flux(g, s, bounce, directional_area);
  return sum;
}

bool same(const Vpl& a, const Vpl& b) {
  return a.position == b.position && a.normal == b.normal && a.intensity == b.intensity && a.kind == b.kind;
}

}  // namespace

TEST_CASE("QmcVplSampler: satisfies the VplSampler concept", "[lighting][vpl]") {
  STATIC_REQUIRE(VplSampler<QmcVplSampler, ReferenceBackend<4>, GltfMaterialShader, StandardBrdf>);
  STATIC_REQUIRE(VplSampler<QmcVplSampler, ReferenceBackend<16>, ConstantDiffuseShader, LambertBrdf>);
}

TEST_CASE("QmcVplSampler: closed box - light VPLs first, each set carries the light's power, first bounce power x albedo",
          "[lighting][vpl]") {
  const float rho = 0.5f;
  const Scene scene = testing::closed_box_with_light(rho, glm::vec3(1.0f, 0.8f, 0.6f));
  const ReferenceBackend<4> backend(scene);
  const double power = (1.0 + 0.8 + 0.6) / 3.0 * 0.04 * double(pi);  // mean radiance x area x pi
  const VplSettings settings{.sets = 9, .vpls_per_set = 1000, .frame = 3, .seed = 11};
  const VplGeneration g = QmcVplSampler{}.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  REQUIRE(g.vpls.sets.size() == 9);
  // A walk leaves 1 + 1 / (1 - rho) = 3 VPLs in a closed box (light, then a geometric number of
  // bounces); the 256-walk pilot measures that with a standard error of about 1.4 / 16 = 9%
  // at worst (QMC does better), so N = M / m lies within 25% of 333.
  CHECK(g.vpls_per_walk == Approx(3.0).epsilon(0.25));
  CHECK(g.walks_per_set == Approx(333).epsilon(0.25));

  for (std::size_t s = 0; s < 9; ++s) {
    INFO("set " << s);
    const auto& set = g.vpls.sets[s];
    // The first N VPLs sit on the light, facing down, in the light's square.
    for (int i = 0; i < g.walks_per_set; ++i) {
      const Vpl& v = set[std::size_t(i)];
      REQUIRE(g.origins[s][std::size_t(i)].bounce == 0);
      CHECK(v.kind == VplKind::surface);
      CHECK(v.position.y == Approx(testing::box_light_height));
      CHECK(std::abs(v.position.x - 0.5f) <= testing::box_light_half + 1e-6f);
      CHECK(v.normal == glm::vec3(0, -1, 0));
    }
    // Every set alone carries the whole emitted power (exact: one light, every particle
    // carries power / N) and, the box being closed with uniform albedo, exactly power x rho
    // in its first bounce. Tolerance: float rounding of a 500-term sum.
    CHECK(set_flux(g, s, 0) == Approx(power).epsilon(1e-4));
    CHECK(set_flux(g, s, 1) == Approx(power * rho).epsilon(1e-4));
  }
  // Second bounce: a particle survives Russian roulette with probability rho and then deposits
  // power/N x rho, so the expected total is 9 power rho^2; the survivor count is at worst
  // binomial, relative standard deviation sqrt((1 - rho) / (rho K)) with K = 9 N ~ 3000 walks
  // (1.8%); scrambled Halton stratifies it further. Four standard deviations: 8%.
  const double second = total_flux(g, 2) / 9.0;
  const double sigma = std::sqrt((1.0 - rho) / (rho * 9.0 * g.walks_per_set));
  std::printf("closed box: second-bounce power per set %.6f, expected %.6f (binomial sigma %.2f%%)\n", second,
              power * rho * rho, 100.0 * sigma);
  CHECK(second == Approx(power * rho * rho).epsilon(4.0 * sigma));
  // About M VPLs per set: N light VPLs plus N (1 + rho + rho^2 + ...) = 2 N bounce VPLs; the
  // walk count is random like the second-bounce survivors (sigma ~2%), 10% is generous.
  double mean_size = 0.0;
  for (const auto& set : g.vpls.sets) mean_size += double(set.size()) / 9.0;
  CHECK(mean_size == Approx(1000.0).epsilon(0.1));
}

TEST_CASE("QmcVplSampler: point light in a cube of six albedos - first bounce = power x mean albedo",
          "[lighting][vpl]") {
  const float albedo[6] = {0.1f, 0.3f, 0.5f, 0.7f, 0.9f, 0.2f};
  Scene scene = testing::closed_cube({glm::vec3(albedo[0]), glm::vec3(albedo[1]), glm::vec3(albedo[2]),
                                      glm::vec3(albedo[3]), glm::vec3(albedo[4]), glm::vec3(albedo[5])});
  scene.lights.push_back({.name = "bulb", .kind = PunctualKind::point, .color = {1, 1, 1}, .intensity = 2.0f,
                          .position = glm::vec3(0.5f)});
  const ReferenceBackend<4> backend(scene);
  const VplSettings settings{.sets = 9, .vpls_per_set = 400, .frame = 0, .seed = 1};
  const VplGeneration g = QmcVplSampler{}.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  const double power = 4.0 * double(pi) * 2.0;
  double mean_albedo = 0.0, variance = 0.0;
  for (const float a : albedo) mean_albedo += a / 6.0;
  for (const float a : albedo) variance += (a - mean_albedo) * (a - mean_albedo) / 6.0;
  // From the centre every face gets 1/6 of the directions. One particle's first-bounce albedo
  // has standard deviation sqrt(variance); over K = 9 N particles the mean's is that / sqrt(K).
  const double k = 9.0 * g.walks_per_set;
  const double relative_sigma = std::sqrt(variance / k) / mean_albedo;
  const double first = total_flux(g, 1) / 9.0;
  std::printf("point light in cube: first-bounce power per set %.5f, expected %.5f (sigma %.2f%%)\n", first,
              power * mean_albedo, 100.0 * relative_sigma);
  CHECK(first == Approx(power * mean_albedo).epsilon(4.0 * relative_sigma));
  for (std::size_t s = 0; s < 9; ++s) {
    CHECK(g.vpls.sets[s][0].kind == VplKind::omni);
    CHECK(set_flux(g, s, 0) == Approx(power).epsilon(1e-4));
  }
}

TEST_CASE("QmcVplSampler: directional light - disc particles that hit the floor carry its irradiance x area",
          "[lighting][vpl]") {
  Scene scene;
  const float rho = 0.6f;
  testing::add_quad(scene, {0, 0, 0}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 1.0f, testing::add_material(scene, glm::vec3(rho)));
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .color = {1, 1, 1}, .intensity = 1.5f,
                          .direction = {0, -1, 0}});
  const ReferenceBackend<4> backend(scene);
  const VplSettings settings{.sets = 9, .vpls_per_set = 400, .frame = 2, .seed = 0};
  const VplGeneration g = QmcVplSampler{}.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  for (std::size_t s = 0; s < 9; ++s) {
    // The light VPLs are directional and share the irradiance: their sum per set is E.
    double irradiance = 0.0;
    for (std::size_t i = 0; i < g.vpls.sets[s].size(); ++i)
      if (g.origins[s][i].bounce == 0) {
        CHECK(g.vpls.sets[s][i].kind == VplKind::directional);
        CHECK(g.vpls.sets[s][i].normal == glm::vec3(0, -1, 0));
        irradiance += g.vpls.sets[s][i].intensity.x;
      }
    CHECK(irradiance == Approx(1.5).epsilon(1e-4));
  }
  // The floor (area 4) intercepts E x 4 of the disc's E pi R^2 (R = sqrt 2): fraction p = 2/pi
  // of the particles, binomial: relative sigma sqrt((1 - p) / (p K)).
  const double p = 2.0 / std::numbers::pi, k = 9.0 * g.walks_per_set;
  const double sigma = std::sqrt((1.0 - p) / (p * k));
  const double first = total_flux(g, 1) / 9.0;
  std::printf("directional light on floor: first-bounce power per set %.5f, expected %.5f (sigma %.2f%%)\n", first,
              1.5 * 4.0 * rho, 100.0 * sigma);
  CHECK(first == Approx(1.5 * 4.0 * rho).epsilon(4.0 * sigma));
}

TEST_CASE("QmcVplSampler: Cornell box - deterministic, frame- and seed-dependent, on surfaces, finite (shared scene cornell_box.gltf)",
          "[lighting][vpl]") {
  const auto path = testing::scene_path("cornell/cornell_box.gltf");
  IGI_REQUIRE_SCENE(path);
  const Scene scene = load_gltf(path);
  const ReferenceBackend<8> backend(scene);
  const QmcVplSampler sampler;
  const VplSettings settings{.sets = 9, .vpls_per_set = 16, .frame = 5, .seed = 42};
  const VplSets a = sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  const VplSets b = sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  VplSettings next_frame = settings;
  next_frame.frame = 6;
  VplSettings other_seed = settings;
  other_seed.seed = 43;
  const VplSets c = sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, next_frame);
  const VplSets d = sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, other_seed);
  REQUIRE(a.sets.size() == 9);
  std::size_t total = 0;
  for (std::size_t s = 0; s < 9; ++s) {
    REQUIRE(a.sets[s].size() == b.sets[s].size());
    for (std::size_t i = 0; i < a.sets[s].size(); ++i) CHECK(same(a.sets[s][i], b.sets[s][i]));
    CHECK_FALSE(same(a.sets[s][0], c.sets[s][0]));
    CHECK_FALSE(same(a.sets[s][0], d.sets[s][0]));
    if (s > 0) CHECK_FALSE(same(a.sets[s][0], a.sets[0][0]));
    total += a.sets[s].size();
  }
  const double mean_size = double(total) / 9.0;
  std::printf("cornell: %.1f VPLs per set for M = 16\n", mean_size);
  // About M: the pilot sizes N to M within its few-percent error, the frame's own walks vary
  // by a similar amount; 30% either way is loose for both.
  CHECK(mean_size > 0.7 * 16.0);
  CHECK(mean_size < 1.3 * 16.0);

  // Every VPL is finite with a unit normal and lies on a surface: a short ray from just above it
  // back along -normal hits within twice the offset. The offset, 1e-4 of the scene's diagonal
  // (0.1 mm in the 0.55 m box), is far above float rounding of the hit points and far below
  // the 0.5 mm gap between the luminaire and the ceiling.
  const float size = glm::length(scene.bounds().extent());
  const float offset = 1e-4f * size;
  const LightSet lights(scene);
  for (std::size_t s = 0; s < 9; ++s)
    for (const Vpl& v : a.sets[s]) {
      CHECK(finite(v.position));
      CHECK(finite(v.intensity));
      CHECK(glm::length(v.normal) == Approx(1.0f).epsilon(1e-5));
      CHECK(v.intensity.x >= 0.0f);
      RayPacket<1> ray;
      ray.set(vec3<1>(v.position + v.normal * offset), vec3<1>(-v.normal), vfloat<1>(0.0f), vfloat<1>(2.0f * offset),
              vmask<1>(true));
      HitPacket<1> hit;
      hit.clear();
      backend.intersect(ray, hit, vmask<1>(true));
      CHECK(hit.geomID[0] != invalid_id);
    }
}

TEST_CASE("QmcVplSampler: every set has the same expected power (shared scene cornell_box.gltf)", "[lighting][vpl]") {
  const auto path = testing::scene_path("cornell/cornell_box.gltf");
  IGI_REQUIRE_SCENE(path);
  const Scene scene = load_gltf(path);
  const ReferenceBackend<8> backend(scene);
  const QmcVplSampler sampler;
  const int frames = 24;
  std::vector<std::vector<double>> per_set(9);
  for (int f = 0; f < frames; ++f) {
    const VplGeneration g = sampler.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.sets = 9, .vpls_per_set = 32, .frame = std::uint32_t(f), .seed = 7});
    for (std::size_t s = 0; s < 9; ++s) {
      // The emitted power is the same in every set exactly; the bounced power varies.
      CHECK(set_flux(g, s, 0) == Approx(set_flux(g, 0, 0)).epsilon(1e-4));
      per_set[s].push_back(set_flux(g, s, -1) - set_flux(g, s, 0));
    }
  }
  // Each set's mean bounced power over the frames against the mean of all sets: within four
  // standard errors of the per-set mean (the sets are independent randomizations).
  double grand = 0.0, spread = 0.0;
  for (const auto& v : per_set)
    for (const double x : v) grand += x / (9.0 * frames);
  for (const auto& v : per_set)
    for (const double x : v) spread += (x - grand) * (x - grand) / (9.0 * frames - 1.0);
  const double standard_error = std::sqrt(spread / frames);
  CHECK(spread > 0.0);  // sets really differ
  for (std::size_t s = 0; s < 9; ++s) {
    double mean = 0.0;
    for (const double x : per_set[s]) mean += x / frames;
    INFO("set " << s << " mean " << mean << " grand " << grand << " standard error " << standard_error);
    CHECK(std::abs(mean - grand) < 4.0 * standard_error);
  }
}

TEST_CASE("QmcVplSampler: user emitters, no lights, bad settings", "[lighting][vpl]") {
  // A user-defined emitter: a "light bar" emitting straight down from a segment.
  struct LightBar {
    glm::vec3 power() const { return glm::vec3(3.0f); }
    EmissionSample sample_emission(float u1, float, float, float) const {
      EmissionSample s;
      s.origin = {0.2f + 0.6f * u1, 0.9f, 0.5f};
      s.direction = {0, -1, 0};
      s.flux = power();
      s.vpl = {.position = s.origin, .normal = {0, -1, 0}, .intensity = power() / pi, .kind = VplKind::surface};
      return s;
    }
  };
  STATIC_REQUIRE(EmitterModel<LightBar>);
  const Scene scene = testing::closed_cube({glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f), glm::vec3(0.5f),
                                            glm::vec3(0.5f), glm::vec3(0.5f)});
  const ReferenceBackend<4> backend(scene);
  QmcVplSampler sampler;
  const VplSettings settings{.sets = 4, .vpls_per_set = 20};
  // No lights: empty sets, not an error.
  const VplSets empty = sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  REQUIRE(empty.sets.size() == 4);
  for (const auto& set : empty.sets) CHECK(set.empty());
  sampler.add_emitter(LightBar{});
  const VplGeneration g = sampler.generate_with_origins(scene, backend, ConstantDiffuseShader(glm::vec3(0.5f)), StandardBrdf{}, settings);
  for (std::size_t s = 0; s < 4; ++s) {
    CHECK(set_flux(g, s, 0) == Approx(3.0).epsilon(1e-4));
    CHECK(set_flux(g, s, 1) == Approx(1.5).epsilon(1e-4));  // the floor below, albedo 0.5
  }
  CHECK_THROWS_WITH(sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.sets = 0}), Catch::Contains("sets"));
  CHECK_THROWS_WITH(sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.vpls_per_set = 0}), Catch::Contains("vpls_per_set"));
  CHECK_THROWS_WITH(sampler.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.max_bounces = -1}), Catch::Contains("max_bounces"));
}

TEST_CASE("QmcVplSampler: closed emitting box - the VPL sum is the analytic irradiance pi Le / (1 - rho)",
          "[lighting][vpl]") {
  // Every wall emits Le and reflects rho: radiance is Le / (1 - rho) everywhere, so the
  // irradiance at the floor's centre is pi Le / (1 - rho). Seen from there every VPL is visible
  // (convex box) and the ones on the floor itself contribute cos = 0, so the plain sum of
  // connect() without clamp estimates it; 20 bounces leave out rho^21 ~ 5e-7 of it.
  const float rho = 0.5f, le = 1.0f;
  Scene scene = testing::closed_cube({glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho), glm::vec3(rho),
                                      glm::vec3(rho)});
  for (Material& m : scene.materials) m.emission = glm::vec3(le);
  const ReferenceBackend<4> backend(scene);
  const vec3<1> receiver(glm::vec3(0.5f, 0.0f, 0.5f)), normal(glm::vec3(0, 1, 0));
  const int seeds = 8;
  std::vector<double> estimates;
  for (int seed = 0; seed < seeds; ++seed) {
    const VplSets vpls =
        QmcVplSampler{}.generate(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.sets = 9, .vpls_per_set = 200, .seed = std::uint32_t(seed), .max_bounces = 20});
    double irradiance = 0.0;
    for (const auto& set : vpls.sets)
      for (const Vpl& v : set) {
        const VplGeometry<1> g = connect(v, receiver, normal, 0.0f, vmask<1>(true));
        irradiance += double(v.intensity.x) * g.falloff[0] * std::max(0.0f, g.wi[0].y) / 9.0;
      }
    estimates.push_back(irradiance);
  }
  double mean = 0.0, spread = 0.0;
  for (const double e : estimates) mean += e / seeds;
  for (const double e : estimates) spread += (e - mean) * (e - mean) / (seeds - 1);
  const double standard_error = std::sqrt(spread / seeds);
  const double expected = double(pi) * le / (1.0 - rho);
  std::printf("emitting box: irradiance %.4f +- %.4f (standard error over %d seeds), analytic %.4f\n", mean,
              standard_error, seeds, expected);
  // Four standard errors of the seed average; the estimate must also be useful (error < 10%).
  CHECK(std::abs(mean - expected) < 4.0 * standard_error);
  CHECK(standard_error < 0.1 * expected);
}

TEST_CASE("QmcVplSampler: Sponza_lit - sun and lamp VPLs, finite, about M per set (shared scene Sponza_lit.gltf)", "[lighting][vpl][sponza]") {
  const auto path = testing::scene_path("sponza/Sponza_lit.gltf");
  IGI_REQUIRE_SCENE(path);
  const Scene scene = load_gltf(path);
  const ReferenceBackend<8> backend(scene);
  const VplGeneration g = QmcVplSampler{}.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.sets = 9, .vpls_per_set = 16, .frame = 1});
  std::size_t total = 0, directional = 0, omni = 0;
  for (std::size_t s = 0; s < 9; ++s) {
    total += g.vpls.sets[s].size();
    for (std::size_t i = 0; i < g.vpls.sets[s].size(); ++i) {
      const Vpl& v = g.vpls.sets[s][i];
      CHECK(finite(v.position));
      CHECK(finite(v.intensity));
      CHECK(glm::length(v.normal) == Approx(1.0f).epsilon(1e-5));
      // VPLs on the lights (the exact ones of the delta lights first) come before the bounces.
      if (i > 0 && g.origins[s][i - 1].bounce > 0) CHECK(g.origins[s][i].bounce > 0);
      if (v.kind == VplKind::directional) ++directional;
      if (v.kind == VplKind::omni) ++omni;
    }
  }
  std::printf("sponza_lit: %.1f VPLs per set for M = 16 (%zu sun, %zu lamp VPLs in 9 sets)\n", double(total) / 9.0,
              directional, omni);
  CHECK(directional > 0);
  CHECK(omni > 0);
  CHECK(double(total) / 9.0 > 0.7 * 16.0);
  CHECK(double(total) / 9.0 < 1.3 * 16.0);
}

TEST_CASE("QmcVplSampler: particles pass through alpha cut-outs", "[lighting][vpl]") {
  const float rho = 0.5f;
  Scene scene = testing::closed_box_with_light(rho, glm::vec3(1.0f));
  // A fully cut-out sheet across the box (alpha 0 < cutoff 0.5) of a very different albedo:
  // a particle that stopped on it would change the first-bounce power and leave a VPL on it.
  const int sheet = testing::add_material(scene, glm::vec3(0.9f));
  scene.materials[std::size_t(sheet)].base_color.a = 0.0f;
  scene.materials[std::size_t(sheet)].alpha_mode = AlphaMode::mask;
  testing::add_quad(scene, {0.5f, 0.5f, 0.5f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 0.45f, sheet);
  const ReferenceBackend<4> backend(scene);
  const VplGeneration g = QmcVplSampler{}.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, {.sets = 4, .vpls_per_set = 64});
  const double power = 0.04 * double(pi);
  for (std::size_t s = 0; s < 4; ++s) {
    CHECK(set_flux(g, s, 1) == Approx(power * rho).epsilon(1e-4));
    for (const Vpl& v : g.vpls.sets[s]) CHECK(std::abs(v.position.y - 0.5f) > 1e-3f);
  }
}
