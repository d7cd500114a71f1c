// BRDF shaders: VPL contributions against the formula, energy of the lobes by numerical
// integration, mirror and glass directions and weights; then every BRDF shader of
// policy_lists.hpp through the properties all must have: energy at most 1 for every lobe setting
// (white furnace), packets equal to single lanes at W = 4, 8 and 16, and no NaN or Inf on
// grazing and degenerate input.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <type_traits>

#include <catch2/catch.hpp>

#include "igi/shading/brdf_shaders.hpp"
#include "igi/simd/sampling.hpp"
#include "policy_lists.hpp"
#include "shading/shading_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

// A flat surface at the origin facing +z, seen from direction `wo` (all lanes alike).
SurfaceHit<W> flat_hit(const glm::vec3& wo, bool front = true) {
  SurfaceHit<W> hit;
  hit.position = vec3<W>(glm::vec3(0.0f));
  hit.geometric_normal = vec3<W>(glm::vec3(0, 0, 1));
  hit.shading_normal = hit.geometric_normal;
  hit.wo = vec3<W>(glm::normalize(wo));
  hit.distance = vfloat<W>(1.0f);
  hit.front_face = vmask<W>(front);
  return hit;
}

BrdfParameters<W> parameters(const glm::vec3& albedo, const glm::vec3& glossy, float shininess) {
  BrdfParameters<W> p;
  p.albedo = vec3<W>(albedo);
  p.glossy = vec3<W>(glossy);
  p.shininess = vfloat<W>(shininess);
  p.ior = vfloat<W>(1.5f);
  p.normal = vec3<W>(glm::vec3(0, 0, 1));
  p.opaque = vmask<W>(true);
  return p;
}

// Integral over the hemisphere of evaluate(wi) on an n x n midpoint grid in (cos theta, phi):
// dw = d(cos theta) d(phi), so the sum times the cell area is the integral.
glm::vec3 hemisphere_integral(const auto& brdf, const SurfaceHit<W>& hit, const BrdfParameters<W>& p, int n) {
  glm::dvec3 sum(0.0);
  for (int a = 0; a < n; ++a) {
    const float cos_theta = (float(a) + 0.5f) / float(n);
    const float sin_theta = std::sqrt(1.0f - cos_theta * cos_theta);
    for (int b = 0; b < n; b += W) {
      vec3<W> wi;
      for (int i = 0; i < W; ++i) {
        const float phi = 2.0f * std::numbers::pi_v<float> * (float(b + i) + 0.5f) / float(n);
        wi.set(i, {sin_theta * std::cos(phi), sin_theta * std::sin(phi), cos_theta});
      }
      sum += glm::dvec3(reduce_add(brdf.evaluate(hit, p, wi, vmask<W>(true))));
    }
  }
  return glm::vec3(sum * (2.0 * std::numbers::pi / (double(n) * double(n))));
}

}  // namespace

TEST_CASE("BRDF: add_vpl adds intensity x falloff x cos on visible lanes only", "[shading][brdf]") {
  const SurfaceHit<W> hit = flat_hit({0, 0, 1});
  const BrdfParameters<W> p = parameters(glm::vec3(0.5f), glm::vec3(0.0f), 1.0f);
  Vpl vpl{.position = {1.0f, 0.0f, 2.0f}, .normal = glm::normalize(glm::vec3(-1, 0, -1)), .intensity = {2.0f, 1.0f, 0.5f}};
  vmask<W> mask(true);
  mask.set(2, false);
  const VplGeometry<W> g = connect(vpl, hit.position, hit.geometric_normal, 0.0f, mask);
  VplAccumulator<W> acc;
  LambertBrdf{}.add_vpl(hit, p, g, vpl.intensity, acc, g.reaches);
  // By hand: d^2 = 5, cos at receiver 2/sqrt5, cos at the VPL (1*1 + 1*2)/(sqrt2 sqrt5).
  const float cos_x = 2.0f / std::sqrt(5.0f), cos_vpl = 3.0f / (std::sqrt(2.0f) * std::sqrt(5.0f));
  const glm::vec3 expected = vpl.intensity * (cos_vpl * cos_x / 5.0f);
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    if (i == 2) {
      CHECK(acc.irradiance[i] == glm::vec3(0.0f));
    } else {
      CHECK(glm::length(acc.irradiance[i] - expected) < 1e-6f);
    }
    CHECK(acc.glossy[i] == glm::vec3(0.0f));
  }
  // StandardBrdf gathers the same irradiance.
  VplAccumulator<W> standard;
  StandardBrdf{}.add_vpl(hit, p, g, vpl.intensity, standard, g.reaches);
  CHECK(standard.irradiance[0] == acc.irradiance[0]);
}

TEST_CASE("BRDF: Phong glossy VPL radiance follows the lobe", "[shading][brdf]") {
  const glm::vec3 wo = glm::normalize(glm::vec3(1, 0, 1));
  const SurfaceHit<W> hit = flat_hit(wo);
  const float s = 20.0f;
  const BrdfParameters<W> p = parameters(glm::vec3(0.0f), glm::vec3(0.5f), s);
  // A VPL straight along the mirror direction and one 30 degrees off it.
  const glm::vec3 mirror = glm::normalize(glm::vec3(-1, 0, 1));
  for (const float off : {0.0f, 0.5235988f}) {
    const glm::vec3 dir(-std::sin(0.7853982f + off), 0.0f, std::cos(0.7853982f + off));
    const Vpl vpl{.position = dir * 2.0f, .normal = {0, 0, 1}, .intensity = glm::vec3(1.0f), .kind = VplKind::omni};
    const VplGeometry<W> g = connect(vpl, hit.position, hit.geometric_normal, 0.0f, vmask<W>(true));
    VplAccumulator<W> acc;
    PhongBrdf{}.add_vpl(hit, p, g, vpl.intensity, acc, g.reaches);
    const float lobe = (s + 2.0f) / (2.0f * std::numbers::pi_v<float>) * std::pow(glm::dot(mirror, dir), s);
    const float expected = 0.5f * lobe * dir.z / 4.0f;
    CHECK(acc.glossy[0].x == Approx(expected).epsilon(1e-4));
    CHECK(acc.irradiance[0].x == Approx(dir.z / 4.0f).epsilon(1e-5));
  }
}

TEST_CASE("BRDF: Lambert and normalised Phong conserve energy at normal incidence", "[shading][brdf]") {
  const SurfaceHit<W> hit = flat_hit({0, 0, 1});
  // A 512^2 midpoint grid integrates these smooth integrands to better than 1e-3.
  const glm::vec3 lambert = hemisphere_integral(LambertBrdf{}, hit, parameters(glm::vec3(0.7f), glm::vec3(0.0f), 1.0f), 512);
  CHECK(lambert.x == Approx(0.7f).epsilon(1e-3));
  for (const float s : {1.0f, 10.0f, 50.0f}) {
    INFO("shininess " << s);
    // At normal incidence the modified Phong lobe times cos integrates to exactly 1.
    const glm::vec3 phong = hemisphere_integral(PhongBrdf{}, hit, parameters(glm::vec3(0.0f), glm::vec3(1.0f), s), 512);
    CHECK(phong.x == Approx(1.0f).epsilon(2e-3));
  }
  // At oblique incidence part of the lobe falls below the horizon: less, never more.
  const SurfaceHit<W> oblique = flat_hit({1, 0, 0.3f});
  const glm::vec3 phong = hemisphere_integral(PhongBrdf{}, oblique, parameters(glm::vec3(0.0f), glm::vec3(1.0f), 10.0f), 512);
  CHECK(phong.x < 1.0f);
  CHECK(phong.x > 0.3f);
  // Light from below the surface contributes nothing.
  vec3<W> below(glm::vec3(0, 0.3f, -1));
  CHECK(reduce_add(StandardBrdf{}.evaluate(hit, parameters(glm::vec3(1.0f), glm::vec3(1.0f), 5.0f), below, vmask<W>(true))) ==
        glm::vec3(0.0f));
}

TEST_CASE("BRDF: mirror reflects about the normal with weight `mirror`", "[shading][brdf]") {
  const glm::vec3 wo = glm::normalize(glm::vec3(0.3f, -0.4f, 0.8f));
  const SurfaceHit<W> hit = flat_hit(wo);
  BrdfParameters<W> p = parameters(glm::vec3(0.0f), glm::vec3(0.0f), 1.0f);
  p.mirror = vec3<W>(glm::vec3(0.9f, 0.5f, 0.1f));
  SecondaryRays<W> reflection, refraction;
  vmask<W> mask(true);
  mask.set(5, false);
  const vmask<W> spawned = MirrorBrdf{}.spawn(hit, p, reflection, refraction, mask);
  CHECK(spawned == mask);
  CHECK(none(refraction.active));
  const glm::vec3 expected(-wo.x, -wo.y, wo.z);
  CHECK(glm::length(reflection.direction[0] - expected) < 1e-6f);
  CHECK(reflection.weight[0] == glm::vec3(0.9f, 0.5f, 0.1f));
  CHECK(reflection.weight[5] == glm::vec3(0.0f));
  CHECK(MirrorBrdf{}.evaluate(hit, p, vec3<W>(expected), mask)[0] == glm::vec3(0.0f));
}

TEST_CASE("BRDF: glass follows Snell and Fresnel, conserves energy and reflects totally inside", "[shading][brdf]") {
  // Tolerances: float rounding of a few dozen operations (1e-4 relative is ~1000 ulps).
  BrdfParameters<W> p = parameters(glm::vec3(0.0f), glm::vec3(0.0f), 1.0f);
  SecondaryRays<W> reflection, refraction;

  SECTION("normal incidence from outside: F = ((n-1)/(n+1))^2 = 0.04") {
    const SurfaceHit<W> hit = flat_hit({0, 0, 1}, true);
    GlassBrdf{}.spawn(hit, p, reflection, refraction, vmask<W>(true));
    CHECK(reflection.weight[0].x == Approx(0.04f).epsilon(1e-4));
    CHECK(refraction.weight[0].x == Approx(0.96f).epsilon(1e-4));
    CHECK(glm::length(refraction.direction[0] - glm::vec3(0, 0, -1)) < 1e-6f);
  }
  SECTION("oblique entry: Snell's law and exact Fresnel") {
    const float theta_i = 0.9f;
    const SurfaceHit<W> hit = flat_hit({std::sin(theta_i), 0.0f, std::cos(theta_i)}, true);
    GlassBrdf{}.spawn(hit, p, reflection, refraction, vmask<W>(true));
    const glm::vec3 t = refraction.direction[0];
    CHECK(glm::length(t) == Approx(1.0f).epsilon(1e-6));
    const float sin_t = std::sqrt(t.x * t.x + t.y * t.y);
    CHECK(sin_t == Approx(std::sin(theta_i) / 1.5f).epsilon(1e-5));
    CHECK(t.x < 0.0f);  // continues across the normal
    const float cos_i = std::cos(theta_i), cos_t = std::sqrt(1.0f - sin_t * sin_t);
    const float rs = (cos_i - 1.5f * cos_t) / (cos_i + 1.5f * cos_t), rp = (1.5f * cos_i - cos_t) / (1.5f * cos_i + cos_t);
    CHECK(reflection.weight[0].x == Approx(0.5f * (rs * rs + rp * rp)).epsilon(1e-4));
    CHECK(reflection.weight[0].x + refraction.weight[0].x == Approx(1.0f).epsilon(1e-6));
  }
  SECTION("leaving the glass beyond the critical angle: total internal reflection") {
    const float critical = std::asin(1.0f / 1.5f);
    const float theta = critical + 0.05f;
    const SurfaceHit<W> hit = flat_hit({std::sin(theta), 0.0f, std::cos(theta)}, false);
    GlassBrdf{}.spawn(hit, p, reflection, refraction, vmask<W>(true));
    CHECK(none(refraction.active));
    CHECK(reflection.weight[0].x == Approx(1.0f));
  }
  SECTION("StandardBrdf splits by transmission and adds the mirror") {
    const SurfaceHit<W> hit = flat_hit({0, 0, 1}, true);
    p.transmission = vfloat<W>(0.5f);
    p.mirror = vec3<W>(glm::vec3(0.1f));
    StandardBrdf{}.spawn(hit, p, reflection, refraction, vmask<W>(true));
    CHECK(reflection.weight[0].x == Approx(0.1f + 0.5f * 0.04f).epsilon(1e-4));
    CHECK(refraction.weight[0].x == Approx(0.5f * 0.96f).epsilon(1e-4));
  }
}

namespace {

// Random-looking but fixed hit geometry for lane i: a receiver with a tilted normal, a view
// direction and BRDF parameters mixing all lobes.
template <int N>
void fill_lane(SurfaceHit<N>& hit, BrdfParameters<N>& p, int lane, int i) {
  const float a = 0.37f * float(i), b = 0.91f * float(i);
  const glm::vec3 n = glm::normalize(glm::vec3(std::sin(a) * 0.4f, 1.0f, std::cos(b) * 0.4f));
  const glm::vec3 wo = glm::normalize(glm::vec3(std::cos(a), 0.6f + 0.3f * std::sin(b), std::sin(a + b)));
  hit.position.set(lane, {0.1f * float(i), 0.0f, -0.05f * float(i)});
  hit.geometric_normal.set(lane, {0, 1, 0});
  hit.shading_normal.set(lane, n);
  hit.wo.set(lane, wo);
  hit.front_face.set(lane, i % 3 != 0);
  p.albedo.set(lane, glm::vec3(0.2f + 0.01f * float(i)));
  p.glossy.set(lane, glm::vec3(0.3f));
  p.shininess.set(lane, 1.0f + float(i));
  p.mirror.set(lane, glm::vec3(0.1f * float(i % 2)));
  p.transmission.set(lane, float(i % 4) / 4.0f);
  p.ior.set(lane, 1.2f + 0.05f * float(i));
  p.normal.set(lane, n);
  p.opaque.set(lane, i % 7 != 6);
}

}  // namespace

TEST_CASE("BRDF: the packet pow matches std::pow on 0..1 for exponents up to 1e4", "[shading][brdf]") {
  double worst = 0.0;
  for (const float s : {0.0f, 0.5f, 1.0f, 2.0f, 7.3f, 30.0f, 200.0f, 1e3f, 1e4f}) {
    for (int k = 0; k <= 4096; k += 16) {
      vfloat<16> x;
      for (int i = 0; i < 16; ++i) x.set(i, std::min(1.0f, float(k + i) / 4096.0f));
      const vfloat<16> fast = brdf_detail::pow_unit(x, vfloat<16>(s));
      for (int i = 0; i < 16; ++i) {
        const double exact = std::pow(double(x[i]), double(s));
        INFO("x = " << x[i] << ", s = " << s);
        CHECK(std::isfinite(fast[i]));
        // Relative accuracy where the result is a normal float (the documented bound, with the
        // float rounding of s ln x added: 1e-7 x s |ln x|); below 2^-64 (5.4e-20) it is
        // flushed to zero by design.
        if (exact > 1e-19) {
          const double log_term = x[i] > 0.0f ? double(s) * std::abs(std::log(double(x[i]))) : 0.0;
          const double bound = 2e-6 * (1.0 + log_term) + 1e-7 * log_term;
          const double error = std::abs(double(fast[i]) - exact) / exact;
          worst = std::max(worst, error);
          CHECK(error <= bound);
        } else {
          CHECK(fast[i] <= 1e-19f);
        }
      }
    }
  }
  std::printf("pow_unit: worst relative error %.2e\n", worst);
  CHECK(brdf_detail::pow_unit(vfloat<1>(0.0f), vfloat<1>(0.0f))[0] == 1.0f);
  CHECK(brdf_detail::pow_unit(vfloat<1>(0.0f), vfloat<1>(3.0f))[0] == 0.0f);
}

// ---------------------------------------------------------------------------------------------
// Properties of every BRDF shader.

TEMPLATE_TEST_CASE("BRDF: every shader satisfies the BrdfShader concept at every width", "[shading][brdf]",
                   IGI_ALL_BRDF_SHADERS) {
  STATIC_REQUIRE(BrdfShader<TestType, 1>);
  STATIC_REQUIRE(BrdfShader<TestType, 4>);
  STATIC_REQUIRE(BrdfShader<TestType, 8>);
  STATIC_REQUIRE(BrdfShader<TestType, 16>);
  STATIC_REQUIRE(BrdfShader<TestType, 64>);
}

namespace {

/// One physically possible material: reflectances that sum to at most 1.
struct LobeSetting {
  const char* name;       // For messages.
  glm::vec3 albedo;       // Diffuse.
  glm::vec3 glossy;       // Phong lobe.
  float shininess;        // Phong exponent.
  glm::vec3 mirror;       // Perfect mirror.
  float transmission;     // Glass.
};

/// The lobe settings of the white-furnace test: each lobe alone at full white, and mixtures.
const LobeSetting lobe_settings[] = {
    {"white diffuse", glm::vec3(1.0f), glm::vec3(0.0f), 1.0f, glm::vec3(0.0f), 0.0f},
    {"white glossy s=0", glm::vec3(0.0f), glm::vec3(1.0f), 0.0f, glm::vec3(0.0f), 0.0f},
    {"white glossy s=1", glm::vec3(0.0f), glm::vec3(1.0f), 1.0f, glm::vec3(0.0f), 0.0f},
    {"white glossy s=10", glm::vec3(0.0f), glm::vec3(1.0f), 10.0f, glm::vec3(0.0f), 0.0f},
    {"white glossy s=50", glm::vec3(0.0f), glm::vec3(1.0f), 50.0f, glm::vec3(0.0f), 0.0f},
    {"half diffuse, half glossy s=10", glm::vec3(0.5f), glm::vec3(0.5f), 10.0f, glm::vec3(0.0f), 0.0f},
    {"white mirror", glm::vec3(0.0f), glm::vec3(0.0f), 1.0f, glm::vec3(1.0f), 0.0f},
    {"clear glass", glm::vec3(0.0f), glm::vec3(0.0f), 1.0f, glm::vec3(0.0f), 1.0f},
    {"half mirror, half glass", glm::vec3(0.0f), glm::vec3(0.0f), 1.0f, glm::vec3(0.5f), 0.5f},
    {"diffuse, glossy, mirror and glass", glm::vec3(0.25f), glm::vec3(0.25f), 20.0f, glm::vec3(0.25f), 0.25f},
};

/// Grid cells per side of hemisphere_integral in the furnace test: 512^2 = 262,144 directions.
/// On this grid the exactly known integrals (Lambert and Phong at normal incidence, both 1)
/// come out within 2e-3 (the energy test above), so an excess of 2e-3 is quadrature error and
/// anything beyond it a BRDF that creates energy: a lobe scaled by 1.01 already fails.
constexpr int furnace_grid = 512;
/// Allowed excess of the furnace energy over 1: the quadrature error of furnace_grid (see there).
constexpr double furnace_tolerance = 2e-3;

}  // namespace

TEMPLATE_TEST_CASE("BRDF: white furnace - no lobe setting reflects more energy than arrives", "[shading][brdf]",
                   IGI_ALL_BRDF_SHADERS) {
  // Energy reflected for light arriving from wo = the hemisphere integral of f_r x cos (what
  // evaluate returns, by reciprocity the same integral over wi) plus the weights of the
  // spawned mirror and glass rays, which carry the delta lobes.
  double most = 0.0;
  for (const LobeSetting& lobe : lobe_settings) {
    BrdfParameters<W> p = parameters(lobe.albedo, lobe.glossy, lobe.shininess);
    p.mirror = vec3<W>(lobe.mirror);
    p.transmission = vfloat<W>(lobe.transmission);
    for (const float view_angle : {0.0f, 0.7853982f, 1.3962634f, 1.5690509f}) {  // 0, 45, 80 and 89.9 degrees
      for (const bool front : {true, false}) {
        INFO(TestType::name() << ": " << lobe.name << ", view " << view_angle << " rad from the normal, "
                              << (front ? "front" : "back") << " face");
        const SurfaceHit<W> hit = flat_hit({std::sin(view_angle), 0.0f, std::cos(view_angle)}, front);
        const TestType brdf{};
        const glm::vec3 lobes = hemisphere_integral(brdf, hit, p, furnace_grid);
        SecondaryRays<W> reflection, refraction;
        brdf.spawn(hit, p, reflection, refraction, vmask<W>(true));
        const glm::vec3 delta = reflection.weight[0] + refraction.weight[0];
        const glm::vec3 energy = lobes + delta;
        const double largest = std::max(energy.x, std::max(energy.y, energy.z));
        INFO("energy " << largest << " (lobes " << lobes.x << ", mirror and glass rays " << delta.x << ")");
        CHECK(std::isfinite(largest));
        CHECK(largest <= 1.0 + furnace_tolerance);
        most = std::max(most, largest);
      }
    }
  }
  // Every shader reflects something under some setting, so the check above is not met by a
  // shader that returns nothing: its white lobe at normal incidence reflects all (1 - 2e-3).
  INFO(TestType::name() << ": most energy over all settings " << most);
  CHECK(most >= 1.0 - furnace_tolerance);
}

namespace {

/// Width of a packet test, as a type (for a templated lambda).
template <int N>
using Width = std::integral_constant<int, N>;

/// Lane i of a packet of test directions wi: spread over the upper and a little of the lower hemisphere.
glm::vec3 test_wi(int i) {
  const float a = 0.53f * float(i) + 0.2f, b = 0.29f * float(i);
  return glm::normalize(glm::vec3(std::cos(a), 0.9f * std::sin(b) + 0.05f, std::sin(a)));
}

/// Relative distance of two vectors: |a - b| / (1 + |b|).
float relative_distance(const glm::vec3& a, const glm::vec3& b) { return glm::length(a - b) / (1.0f + glm::length(b)); }

}  // namespace

TEMPLATE_TEST_CASE("BRDF: a packet of 4, 8, 16 or 64 lanes gives what single-lane calls give", "[shading][brdf]",
                   IGI_ALL_BRDF_SHADERS) {
  const TestType brdf{};
  const Vpl vpl{.position = {0.3f, 1.2f, -0.4f}, .normal = glm::normalize(glm::vec3(0.2f, -1, 0.1f)), .intensity = {1, 2, 3}};
  const auto check_width = [&]<int N>(Width<N>) {
    SurfaceHit<N> hit;
    BrdfParameters<N> p;
    vec3<N> wi;
    for (int i = 0; i < N; ++i) {
      fill_lane(hit, p, i, i);
      wi.set(i, test_wi(i));
    }
    vmask<N> mask(true);
    mask.set(N - 1, false);
    const VplGeometry<N> g = connect(vpl, hit.position, hit.geometric_normal, 0.1f, mask);
    VplAccumulator<N> accumulator;
    brdf.add_vpl(hit, p, g, vpl.intensity, accumulator, g.reaches);
    SecondaryRays<N> reflection, refraction;
    const vmask<N> spawned = brdf.spawn(hit, p, reflection, refraction, mask);
    const vec3<N> evaluated = brdf.evaluate(hit, p, wi, mask);
    for (int i = 0; i < N; ++i) {
      SurfaceHit<1> hit1;
      BrdfParameters<1> p1;
      fill_lane(hit1, p1, 0, i);
      const vmask<1> mask1(i != N - 1);
      const VplGeometry<1> g1 = connect(vpl, hit1.position, hit1.geometric_normal, 0.1f, mask1);
      VplAccumulator<1> accumulator1;
      brdf.add_vpl(hit1, p1, g1, vpl.intensity, accumulator1, g1.reaches);
      SecondaryRays<1> reflection1, refraction1;
      const vmask<1> spawned1 = brdf.spawn(hit1, p1, reflection1, refraction1, mask1);
      const vec3<1> evaluated1 = brdf.evaluate(hit1, p1, vec3<1>(test_wi(i)), mask1);
      INFO(TestType::name() << ", width " << N << ", lane " << i);
      // Packet and scalar code run the same operations; only fused multiply-adds the compiler
      // may contract differently separate them: 1e-6 relative.
      constexpr float tolerance = 1e-6f;
      CHECK(relative_distance(accumulator.irradiance[i], accumulator1.irradiance[0]) <= tolerance);
      CHECK(relative_distance(accumulator.glossy[i], accumulator1.glossy[0]) <= tolerance);
      CHECK(spawned[i] == spawned1[0]);
      CHECK(reflection.active[i] == reflection1.active[0]);
      CHECK(refraction.active[i] == refraction1.active[0]);
      CHECK(relative_distance(reflection.direction[i], reflection1.direction[0]) <= tolerance);
      CHECK(relative_distance(reflection.weight[i], reflection1.weight[0]) <= tolerance);
      CHECK(relative_distance(refraction.direction[i], refraction1.direction[0]) <= tolerance);
      CHECK(relative_distance(refraction.weight[i], refraction1.weight[0]) <= tolerance);
      CHECK(relative_distance(evaluated[i], evaluated1[0]) <= tolerance);
    }
    // The lanes are not all alike, so the comparison above sees lane mix-ups: some lane differs
    // from lane 0 in what the shader computed (the masked-off last lane aside).
    bool lanes_differ = false;
    for (int i = 1; i < N - 1; ++i)
      lanes_differ = lanes_differ || accumulator.irradiance[i] != accumulator.irradiance[0] ||
                     reflection.weight[i] != reflection.weight[0] || refraction.weight[i] != refraction.weight[0] ||
                     evaluated[i] != evaluated[0];
    CHECK(lanes_differ);
  };
  check_width(Width<4>{});
  check_width(Width<8>{});
  check_width(Width<16>{});
  check_width(Width<64>{});  // the SaarCOR backend's width
}

TEMPLATE_TEST_CASE("BRDF: grazing and degenerate input never yields NaN or Inf", "[shading][brdf]",
                   IGI_ALL_BRDF_SHADERS) {
  constexpr float nan = std::numeric_limits<float>::quiet_NaN();
  constexpr float infinity = std::numeric_limits<float>::infinity();
  const TestType brdf{};
  const auto finite = [](const vec3<W>& v) { return all(isfinite(v.x) & isfinite(v.y) & isfinite(v.z)); };
  // Views: exactly grazing, almost grazing, and from just below the surface; front and back faces.
  for (const glm::vec3& view : {glm::vec3(1, 0, 0), glm::vec3(1, 0, 1e-7f), glm::vec3(1, 0.2f, -1e-3f)}) {
    for (const bool front : {true, false}) {
      SurfaceHit<W> hit = flat_hit(view, front);
      BrdfParameters<W> p = parameters(glm::vec3(0.8f), glm::vec3(0.5f), 0.0f);
      p.mirror = vec3<W>(glm::vec3(0.5f));
      p.transmission = vfloat<W>(0.5f);
      // One broken input per lane: zero normal, NaN normal, zero ior, NaN shininess, zero wo,
      // infinite shininess and ior, shading normal facing into the surface, NaN transmission.
      p.normal.set(0, glm::vec3(0.0f));
      p.normal.set(1, glm::vec3(nan));
      p.ior.set(2, 0.0f);
      p.shininess.set(3, nan);
      hit.wo.set(4, glm::vec3(0.0f));
      p.shininess.set(5, infinity);
      p.ior.set(5, infinity);
      p.normal.set(6, glm::vec3(0, 0, -1));
      p.transmission.set(7, nan);
      INFO(TestType::name() << ": view " << view.x << ", " << view.y << ", " << view.z << (front ? ", front" : ", back"));
      // VPLs straight above, grazing, and at the hit point itself (distance 0).
      for (const glm::vec3 vpl_position : {glm::vec3(0, 0, 1), glm::vec3(1, 0, 1e-7f), glm::vec3(0.0f)}) {
        const Vpl vpl{.position = vpl_position, .normal = {0, 0, -1}, .intensity = glm::vec3(1.0f)};
        const VplGeometry<W> g = connect(vpl, hit.position, hit.geometric_normal, 0.0f, vmask<W>(true));
        VplAccumulator<W> accumulator;
        brdf.add_vpl(hit, p, g, vpl.intensity, accumulator, g.reaches);
        CHECK(finite(accumulator.irradiance));
        CHECK(finite(accumulator.glossy));
      }
      SecondaryRays<W> reflection, refraction;
      brdf.spawn(hit, p, reflection, refraction, vmask<W>(true));
      CHECK(finite(reflection.direction));
      CHECK(finite(reflection.weight));
      CHECK(finite(refraction.direction));
      CHECK(finite(refraction.weight));
      // Incident directions: zero, in the surface plane, and from below.
      for (const glm::vec3& wi : {glm::vec3(0.0f), glm::vec3(1, 0, 0), glm::vec3(0, 0.3f, -1)})
        CHECK(finite(brdf.evaluate(hit, p, vec3<W>(wi), vmask<W>(true))));
    }
  }
}

TEMPLATE_TEST_CASE("BRDF: one VPL adds at most intensity x (albedo + glossy) / (pi clamp^2) to a pixel", "[shading][brdf]",
                   IGI_ALL_BRDF_SHADERS) {
  const TestType brdf{};
  constexpr float clamp_distance = 0.1f;
  const float limit = std::numbers::inv_pi_v<float> / (clamp_distance * clamp_distance);
  Rng rng(7u);
  double largest_share = 0.0;  // the largest contribution seen, as a fraction of the bound
  // Receivers at 0.001 to 10 clamp distances from a surface, omni or spot VPL, views all round,
  // lobes from dull to sharper than any material (shininess 1e6): the sharp lobe close to its
  // VPL is the firefly the bound exists for.
  for (int trial = 0; trial < 2000; ++trial) {
    const float shininess = std::pow(10.0f, 6.0f * rng.next());
    const glm::vec3 albedo(rng.next(), rng.next(), rng.next()), glossy(rng.next(), rng.next(), rng.next());
    const float phi = 6.2831853f * rng.next(), cos_theta = rng.next();
    const float sin_theta = std::sqrt(1.0f - cos_theta * cos_theta);
    const SurfaceHit<W> hit = flat_hit({sin_theta * std::cos(phi), sin_theta * std::sin(phi), std::max(cos_theta, 1e-3f)});
    const BrdfParameters<W> p = parameters(albedo, glossy, shininess);
    const float distance = clamp_distance * std::pow(10.0f, -3.0f + 4.0f * rng.next());
    // The VPL where the lobe points half of the time (the worst case), anywhere above the rest.
    glm::vec3 direction = glm::reflect(-hit.wo[0], glm::vec3(0, 0, 1));
    if (rng.next() < 0.5f) direction = glm::normalize(glm::vec3(rng.next() - 0.5f, rng.next() - 0.5f, rng.next() + 1e-3f));
    const Vpl vpl{.position = direction * distance, .normal = -direction, .intensity = glm::vec3(2.0f, 1.0f, 0.5f),
                  .kind = rng.next() < 0.5f ? VplKind::omni : VplKind::surface};
    const VplGeometry<W> g = connect(vpl, hit.position, hit.geometric_normal, clamp_distance, vmask<W>(true));
    REQUIRE(g.transfer_limit == Approx(limit));
    VplAccumulator<W> accumulator;
    brdf.add_vpl(hit, p, g, vpl.intensity, accumulator, g.reaches);
    for (int c = 0; c < 3; ++c) {
      const float radiance = albedo[c] * std::numbers::inv_pi_v<float> * accumulator.irradiance[0][c] + accumulator.glossy[0][c];
      const float bound = vpl.intensity[c] * (albedo[c] + glossy[c]) * limit;
      INFO(TestType::name() << ": trial " << trial << ", shininess " << shininess << ", distance " << distance);
      // 1e-5: float rounding of the products (the bound itself is exact arithmetic on the same values).
      CHECK(radiance <= bound * (1.0f + 1e-5f));
      largest_share = std::max(largest_share, double(radiance) / double(bound));
    }
  }
  // The gathering shaders come close to the bound (so the check above saw contributions that
  // could break it); the delta shaders gather nothing.
  if constexpr (std::is_same_v<TestType, MirrorBrdf> || std::is_same_v<TestType, GlassBrdf>)
    CHECK(largest_share == 0.0);
  else
    CHECK(largest_share > 0.5);
}

TEST_CASE("BRDF: the glossy bound cuts only lobes sharper than the clamp admits", "[shading][brdf]") {
  // Head-on VPL at distance 1 with clamp 0.1 (bound 1 / (pi 0.01) = 31.8): a lobe of peak
  // (s + 2) / (2 pi) stays whole while that is below the bound (s = 100: 16.2), and is cut to it
  // above (s = 1000: 159.5).
  const SurfaceHit<W> hit = flat_hit({0, 0, 1});
  const Vpl vpl{.position = {0, 0, 1}, .normal = {0, 0, -1}, .intensity = glm::vec3(1.0f), .kind = VplKind::omni};
  const VplGeometry<W> g = connect(vpl, hit.position, hit.geometric_normal, 0.1f, vmask<W>(true));
  const float bound = std::numbers::inv_pi_v<float> / 0.01f;
  for (const float s : {100.0f, 1000.0f}) {
    VplAccumulator<W> accumulator;
    PhongBrdf{}.add_vpl(hit, parameters(glm::vec3(0.0f), glm::vec3(1.0f), s), g, vpl.intensity, accumulator, g.reaches);
    const float peak = (s + 2.0f) / (2.0f * std::numbers::pi_v<float>);
    CHECK(accumulator.glossy[0].x == Approx(std::min(peak, bound)).epsilon(1e-4));
  }
}

TEST_CASE("BRDF: a VPL spread over a sphere widens the glossy lobe and keeps it normalised", "[shading][brdf]") {
  // Phong exponent 1000 seen from straight above; a VPL at distance 1 in the mirror direction and
  // one 10 degrees off it (about 5 lobe widths, 1/sqrt(1000) rad): as a point the first gets the
  // peak and the second almost nothing; spread over a sphere of radius 0.3 (sin^2 of its half-angle
  // 0.083, exponent 1000 / (1 + 41.3) = 23.7) the peak drops and the lobe reaches the second.
  const SurfaceHit<W> hit = flat_hit({0, 0, 1});
  const BrdfParameters<W> p = parameters(glm::vec3(0.0f), glm::vec3(1.0f), 1000.0f);
  const auto glossy_from = [&](float angle, float radius) {
    const glm::vec3 direction(std::sin(angle), 0.0f, std::cos(angle));
    const Vpl vpl{.position = direction, .normal = -direction, .intensity = glm::vec3(1.0f), .radius = radius};
    const VplGeometry<W> g = connect(vpl, hit.position, hit.geometric_normal, 0.0f, vmask<W>(true));
    VplAccumulator<W> accumulator;
    PhongBrdf{}.add_vpl(hit, p, g, vpl.intensity, accumulator, g.reaches);
    return accumulator.glossy[0].x;
  };
  const float off = 10.0f * std::numbers::pi_v<float> / 180.0f;
  const float spread = 0.09f / 1.09f, exponent = 1000.0f / (1.0f + 500.0f * spread);
  const float cos_off = std::cos(off);
  CHECK(glossy_from(0.0f, 0.0f) == Approx(1002.0f / (2.0f * std::numbers::pi_v<float>)).epsilon(1e-4));
  CHECK(glossy_from(0.0f, 0.3f) == Approx((exponent + 2.0f) / (2.0f * std::numbers::pi_v<float>)).epsilon(1e-4));
  // The surface VPL's own cosine is 1 towards the receiver; the receiver's is cos(off).
  CHECK(glossy_from(off, 0.3f) ==
        Approx((exponent + 2.0f) / (2.0f * std::numbers::pi_v<float>) * std::pow(cos_off, exponent) * cos_off).epsilon(1e-4));
  CHECK(glossy_from(off, 0.0f) < 1e-3f * glossy_from(off, 0.3f));
}

namespace {

/// Lane `i` of a packet of 16 as fill_lane writes it, with the surface shader's normal spoiled
/// on some lanes the way the shading frame must repair: zero, NaN, three times too long, facing
/// away from wo; and no glossy reflectance on one.
void fill_spoiled_lanes(SurfaceHit<16>& hit, BrdfParameters<16>& p) {
  for (int i = 0; i < 16; ++i) fill_lane(hit, p, i, i);
  p.normal.set(1, glm::vec3(0.0f));
  p.normal.set(2, glm::vec3(std::numeric_limits<float>::quiet_NaN()));
  p.normal.set(3, p.normal[3] * 3.0f);
  p.normal.set(4, -hit.wo[4]);
  p.glossy.set(5, glm::vec3(0.0f));
}

}  // namespace

TEST_CASE("BRDF: a VPL receiver holds the packet's resolved shading frame and lobe axis", "[shading][brdf]") {
  SurfaceHit<16> hit;
  BrdfParameters<16> p;
  fill_spoiled_lanes(hit, p);
  const VplReceiver<16> receiver = make_vpl_receiver(hit, p);
  const vec3<16> resolved = shading_frame_normal(hit, p);
  for (int i = 0; i < 16; ++i) {
    INFO("lane " << i);
    const glm::vec3 n = receiver.normal[i];
    CHECK(n == resolved[i]);
    // Unit up to float rounding of a normalisation.
    CHECK(glm::length(n) == Approx(1.0f).epsilon(1e-6));
    CHECK(glm::dot(n, hit.wo[i]) > 0.0f);
    // The mirror direction by hand: 2 (n.wo) n - wo, unit since n and wo are; 1e-6 for rounding.
    const glm::vec3 axis = 2.0f * glm::dot(n, hit.wo[i]) * n - hit.wo[i];
    CHECK(glm::length(receiver.lobe_axis[i] - axis) <= 1e-6f);
    CHECK(receiver.half_shininess[i] == 0.5f * p.shininess[i]);
    CHECK(receiver.glossy[i] == (p.opaque[i] && i != 5));
  }
  // Lanes 1, 2 and 4 fall back to the geometric normal, lane 3 is normalised.
  for (const int i : {1, 2, 4}) CHECK(receiver.normal[i] == hit.geometric_normal[i]);
  CHECK(glm::length(receiver.normal[3] - glm::normalize(p.normal[3] / 3.0f)) <= 1e-6f);
  // Without glossy lanes the lobe's parts stay zero: nothing reads them.
  p.glossy = vec3<16>();
  const VplReceiver<16> matte = make_vpl_receiver(hit, p);
  CHECK(none(matte.glossy));
  CHECK(reduce_add(matte.lobe_axis) == glm::vec3(0.0f));
}

TEMPLATE_TEST_CASE("BRDF: add_vpl on a receiver adds what add_vpl on the unresolved hit adds", "[shading][brdf]",
                   IGI_ALL_BRDF_SHADERS) {
  // igi's own shaders all have the receiver form, so the pipeline skips their per-VPL frame.
  if constexpr (std::is_same_v<TestType, LambertBrdf> || std::is_same_v<TestType, PhongBrdf> ||
                std::is_same_v<TestType, StandardBrdf>)
    STATIC_REQUIRE(ReceiverBrdfShader<TestType, 16>);
  const TestType brdf{};
  SurfaceHit<16> hit;
  BrdfParameters<16> p;
  fill_spoiled_lanes(hit, p);
  const vmask<16> all(true);
  for (const Vpl& vpl : {Vpl{.position = {0.3f, 1.2f, -0.4f}, .normal = glm::normalize(glm::vec3(0.2f, -1, 0.1f)), .intensity = {1, 2, 3}},
                         Vpl{.position = {-0.5f, 0.4f, 0.2f}, .normal = glm::normalize(glm::vec3(0.5f, -1, 0)), .intensity = {3, 1, 1}, .radius = 0.2f}}) {
    const VplGeometry<16> g = connect(vpl, hit.position, hit.geometric_normal, 0.1f, all);
    REQUIRE(popcount(g.reaches) > 8);  // the comparison below sees most lanes
    VplAccumulator<16> from_hit;
    brdf.add_vpl(hit, p, g, vpl.intensity, from_hit, g.reaches);
    // The receiver form is optional (the pipeline calls the hit form of shaders without one).
    if constexpr (ReceiverBrdfShader<TestType, 16>) {
      VplAccumulator<16> from_receiver;
      brdf.add_vpl(make_vpl_receiver(hit, p), p, g, vpl.intensity, from_receiver, g.reaches);
      for (int i = 0; i < 16; ++i) {
        INFO(TestType::name() << ", lane " << i);
        // Both forms run the same operations; only fused multiply-adds the compiler may contract
        // differently in the two call sites separate them: 1e-6 relative.
        constexpr float tolerance = 1e-6f;
        CHECK(relative_distance(from_receiver.irradiance[i], from_hit.irradiance[i]) <= tolerance);
        CHECK(relative_distance(from_receiver.glossy[i], from_hit.glossy[i]) <= tolerance);
      }
    }
    // The hit form resolves the spoiled normals itself: lane 3's long normal gathers what its
    // unit normal gathers, and the zero, NaN and back-facing ones what the geometric normal does.
    BrdfParameters<16> repaired = p;
    repaired.normal.set(3, glm::normalize(p.normal[3]));
    for (const int i : {1, 2, 4}) repaired.normal.set(i, hit.geometric_normal[i]);
    VplAccumulator<16> from_repaired;
    brdf.add_vpl(hit, repaired, g, vpl.intensity, from_repaired, g.reaches);
    for (const int i : {1, 2, 3, 4}) {
      INFO(TestType::name() << ", spoiled lane " << i);
      constexpr float tolerance = 1e-6f;  // the same operations on one normal, normalised once or twice
      CHECK(relative_distance(from_hit.irradiance[i], from_repaired.irradiance[i]) <= tolerance);
      CHECK(relative_distance(from_hit.glossy[i], from_repaired.glossy[i]) <= tolerance);
    }
  }
}
