// Emitters and LightSet: power formulas, emission sampling against them, consistency with
// connect()'s profiles, the power CDF, and errors on bad lights.

#include <cmath>
#include <numbers>

#include <catch2/catch.hpp>

#include "igi/lighting/lights.hpp"
#include "igi/simd/sampling.hpp"
#include "lighting/lighting_support.hpp"
#include "scene_builders.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

// Mean flux of n stratified emission samples (u3, u4 on an n x n grid, u1, u2 from Halton).
glm::dvec3 mean_flux(const Emitter& e, int n) {
  glm::dvec3 sum(0.0);
  for (int a = 0; a < n; ++a)
    for (int b = 0; b < n; ++b) {
      const std::uint64_t k = std::uint64_t(a * n + b);
      sum += glm::dvec3(e.sample_emission(radical_inverse(0, k), radical_inverse(1, k), (float(a) + 0.5f) / float(n),
                                          (float(b) + 0.5f) / float(n))
                            .flux);
    }
  return sum / double(n * n);
}

}  // namespace

TEST_CASE("lights: a scene's emissive triangles and punctual lights, with their powers", "[lighting]") {
  Scene scene = testing::closed_box_with_light(0.5f, {2.0f, 1.0f, 0.5f});
  scene.lights.push_back({.name = "bulb", .kind = PunctualKind::point, .color = {1, 1, 1}, .intensity = 3.0f});
  scene.lights.push_back({.name = "sun",
                          .kind = PunctualKind::directional,
                          .color = {1, 1, 1},
                          .intensity = 2.0f,
                          .direction = glm::normalize(glm::vec3(0.3f, -1.0f, 0.2f))});
  const LightSet lights(scene);
  REQUIRE(lights.size() == 4);  // two light triangles, the bulb, the sun
  // Area light: radiance x area x pi, the quad being 0.2 x 0.2.
  const glm::vec3 area_power = glm::vec3(2.0f, 1.0f, 0.5f) * (0.04f * pi);
  CHECK(glm::length(lights.emitter(0).power() + lights.emitter(1).power() - area_power) < 1e-5f);
  CHECK(lights.emitter(2).power().x == Approx(4.0f * pi * 3.0f));
  // The sun's disc covers the unit cube's bounding sphere: radius sqrt(3)/2.
  CHECK(lights.emitter(3).power().x == Approx(2.0f * pi * 0.75f).epsilon(1e-5));
  CHECK(glm::length(lights.total_power() - (area_power + glm::vec3(12.0f * pi) + glm::vec3(1.5f * pi))) < 1e-3f);
}

TEST_CASE("lights: choosing follows the power CDF and rescales u", "[lighting]") {
  LightSet lights;
  lights.add(PointEmitter({0, 0, 0}, glm::vec3(1.0f)));
  lights.add(PointEmitter({0, 0, 0}, glm::vec3(0.0f)));  // no power: ignored
  lights.add(PointEmitter({1, 0, 0}, glm::vec3(3.0f)));
  REQUIRE(lights.size() == 2);
  const LightSet::Choice a = lights.choose(0.2f), b = lights.choose(0.4f);
  CHECK(a.index == 0);
  CHECK(a.probability == Approx(0.25f));
  CHECK(a.u == Approx(0.8f));
  CHECK(b.index == 1);
  CHECK(b.probability == Approx(0.75f));
  CHECK(b.u == Approx((0.4f - 0.25f) / 0.75f));
  CHECK(lights.choose(0.0f).index == 0);
  CHECK(lights.choose(0.99999994f).index == 1);
  CHECK(lights.choose(0.99999994f).u < 1.0f);
  CHECK_THROWS_AS(LightSet{}.choose(0.5f), std::logic_error);
}

TEST_CASE("lights: emission samples carry the emitter's power and their VPLs its light", "[lighting]") {
  const Bounds bounds{.lower = {-1, -1, -1}, .upper = {1, 1, 1}};
  const Emitter triangle = TriangleEmitter({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, glm::vec3(2.0f), true);
  const Emitter point = PointEmitter({0, 0, 0}, glm::vec3(1.5f));
  const Emitter spot = SpotEmitter({0, 0, 0}, {0, -1, 0}, glm::vec3(2.0f), 0.3f, 0.6f);
  const Emitter sun = DirectionalEmitter({0, -1, 0}, glm::vec3(3.0f), bounds);
  for (const Emitter* e : {&triangle, &point, &spot, &sun}) {
    // The spot's profile-weighted flux is the only non-constant one: a 256^2 grid integrates its
    // smooth t^2 ramp to well below 1e-3.
    const glm::dvec3 flux = mean_flux(*e, 256);
    CHECK(flux.x == Approx(e->power().x).epsilon(1e-3));
  }
  // Double-sided triangle: both faces emit, directions in the emitting face's hemisphere.
  int front = 0;
  for (int k = 0; k < 64; ++k) {
    const EmissionSample s = triangle.sample_emission(0.3f, 0.6f, (float(k) + 0.5f) / 64.0f, 0.7f);
    CHECK(glm::dot(s.direction, s.vpl.normal) > 0.0f);
    CHECK(s.vpl.kind == VplKind::surface);
    CHECK(s.vpl.intensity.x == Approx(triangle.power().x / pi));
    CHECK(s.origin.z == 0.0f);
    CHECK(s.origin.x + s.origin.y <= 1.0f + 1e-6f);
    if (s.vpl.normal.z > 0.0f) ++front;
  }
  CHECK(front == 32);
  // The sun starts outside the bounding sphere, travelling along its direction.
  const EmissionSample s = sun.sample_emission(0.99f, 0.1f, 0.0f, 0.0f);
  CHECK(s.origin.y == Approx(std::sqrt(3.0f)));
  CHECK(s.vpl.kind == VplKind::directional);
  CHECK(s.vpl.intensity == glm::vec3(3.0f));
}

TEST_CASE("lights: a spot's power is connect()'s profile integrated over the sphere", "[lighting]") {
  // connect() evaluates the profile the pipeline uses; integrate falloff x d^2 over a unit
  // sphere of receivers facing the light (midpoint grid in cos theta, phi: 2048 x 64 cells).
  const SpotEmitter spot({0, 0, 0}, {0, 0, 1}, glm::vec3(1.0f), 0.4f, 0.9f);
  const Vpl vpl = spot.sample_emission(0, 0, 0.1f, 0.2f).vpl;
  const int n_theta = 2048, n_phi = 64;
  double sum = 0.0;
  for (int a = 0; a < n_theta; ++a) {
    const float cos_theta = -1.0f + 2.0f * (float(a) + 0.5f) / float(n_theta);
    const float sin_theta = std::sqrt(1.0f - cos_theta * cos_theta);
    vec3<16> position, normal;
    for (int b = 0; b < 16; ++b) {
      const float phi = 2.0f * pi * (float(b) + 0.5f) / 16.0f;
      const glm::vec3 d(sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta);
      position.set(b, d);
      normal.set(b, -d);
    }
    const VplGeometry<16> g = connect(vpl, position, normal, 0.0f, vmask<16>(true));
    // Unit distance: falloff is the profile itself; 16 lanes stand for the n_phi = 64 cells.
    sum += double(reduce_add(g.falloff)) * (double(n_phi) / 16.0);
  }
  const double integral = sum * (2.0 / n_theta) * (2.0 * std::numbers::pi / n_phi);
  // The profile does not depend on phi, so only the cos-theta midpoint rule errs: at the ramp's
  // two kinks, by about a cell width (1e-3) squared relative; 2e-3 also covers float sums.
  CHECK(spot.power().x == Approx(integral).epsilon(2e-3));
  CHECK(vpl_flux(vpl, 0.0f).x == Approx(spot.power().x));
}

TEST_CASE("lights: bad lights are errors naming them", "[lighting]") {
  Scene scene = testing::closed_box_with_light(0.5f, glm::vec3(1.0f));
  scene.lights.push_back({.name = "broken", .kind = PunctualKind::point, .intensity = -1.0f});
  CHECK_THROWS_WITH(LightSet(scene), Catch::Contains("broken"));
  scene.lights.back() = {.name = "aimless", .kind = PunctualKind::directional, .direction = glm::vec3(0.0f)};
  CHECK_THROWS_WITH(LightSet(scene), Catch::Contains("direction"));
  scene.lights.clear();
  scene.materials.back().emission = glm::vec3(1.0f, -2.0f, 0.0f);
  CHECK_THROWS_WITH(LightSet(scene), Catch::Contains("emission"));
  CHECK_THROWS_AS(SpotEmitter({0, 0, 0}, {0, 0, 1}, glm::vec3(1.0f), 0.1f, 0.0f), std::invalid_argument);
}
