// Shadow rays pass alpha cut-outs where they are transparent, as camera rays and the path
// tracer's rays do: through a backend's cut-out test (Embree's occlusion filter functions, the
// reference backend's traversal) or, for a backend without one, by tracing blocked rays again
// (igi::occluded_by_opaque). Before, every shadow ray stopped at a cut-out's triangles, so
// foliage and chains cast solid shadows (Sponza_lit's plants).

#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/shading/cutout_occlusion.hpp"
#include "render_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// A white floor (y = 0, half-size 3) under the sun straight above, and a black stencil sheet
/// 0.5 above it over x, z in [-2, 2], an alpha cut-out transparent where x < 0 (texture u < 0.5)
/// and opaque where x > 0; with `bar`, also an opaque black bar at y = 1 over x in [-0.9, -0.5],
/// above the transparent half. Neither black surface reflects, and the floor's own VPLs lie in
/// its plane, so the floor's light is the sun's alone. The camera sits below the stencil and
/// sees only the floor.
Scene stencil_under_sun(bool bar) {
  Scene scene;
  scene.name = "stencil under the sun";
  add_quad(scene, {0.0f, 0.0f, 0.0f}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 3.0f, add_material(scene, glm::vec3(0.8f)));
  // A second instance of the floor, far below, so that the stencil's mesh (1) and instance (2)
  // have different indices.
  scene.instances.push_back({.name = "floor below", .mesh = 0, .transform = glm::translate(glm::mat4(1.0f), glm::vec3(0, -10, 0))});
  add_stencil_sheet(scene, 0.5f);
  if (bar) {
    Mesh mesh;
    mesh.name = "bar";
    add_quad(mesh, {-0.9f, 1.0f, -1.0f}, {-0.5f, 1.0f, -1.0f}, {-0.5f, 1.0f, 1.0f}, {-0.9f, 1.0f, 1.0f}, {0, 1, 0});
    add_object(scene, std::move(mesh), add_material(scene, glm::vec3(0.0f)));
  }
  scene.lights.push_back({.name = "sun", .kind = PunctualKind::directional, .intensity = 2.0f,
                          .direction = glm::vec3(0.0f, -1.0f, 0.0f)});
  scene.cameras.push_back(look_at({0.0f, 0.3f, 1.6f}, {0.0f, 0.0f, 0.0f}, 1.0f));
  return scene;
}

constexpr int sheet_mesh = 1;      ///< The stencil's mesh in stencil_under_sun.
constexpr int sheet_instance = 2;  ///< Its instance.

/// Whether the sun reaches floor point x of stencil_under_sun(true), the stencil turned half round
/// or not (its transparent half then at x > 0); nullopt within 0.1 of a cut-out edge, where the
/// bilinear alpha blends, and within 0.05 of the bar's edges.
std::optional<bool> sunlit(float x, bool turned) {
  if (std::abs(x) < 0.1f || std::abs(x + 0.9f) < 0.05f || std::abs(x + 0.5f) < 0.05f) return std::nullopt;
  const bool under_bar = x > -0.9f && x < -0.5f;
  return (turned ? x > 0.0f : x < 0.0f) && !under_bar;
}

/// GltfMaterialShader without its opaque_at: test_cutouts_with then shades each candidate whole.
class ShadeOnly {
 public:
  explicit ShadeOnly(const Scene& scene) : shader_(scene) {}
  static constexpr const char* name() noexcept { return "shade only"; }
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const {
    return shader_.shade(hit, mask);
  }

 private:
  GltfMaterialShader shader_;
};
static_assert(CutoutOpacityShader<GltfMaterialShader> && !CutoutOpacityShader<ShadeOnly>);

/// Shadow rays of `B` from a grid of floor points straight up (length 2) through
/// occluded_by_opaque, against sunlit(); with `test` the backend's cut-out test (of a `Shader`) is set first.
template <class B, class Shader = GltfMaterialShader>
void check_shadow_rays(bool test) {
  Scene scene = stencil_under_sun(true);
  Shader surface(scene);
  B backend(scene);
  if constexpr (CutoutTestingBackend<B>) {
    if (test) test_cutouts_with(backend, scene, surface);
    CHECK(backend.cutout_test_set() == test);
  }
  for (const bool turned : {false, true}) {
    if (turned) {
      // Turned half round the vertical: the backend now traces the stencil as an instance of
      // its own (Embree: a ray in the instance's object space reaches the filter).
      const glm::mat4 half_turn = glm::rotate(glm::mat4(1.0f), 3.14159265f, glm::vec3(0.0f, 1.0f, 0.0f));
      scene.instances[std::size_t(sheet_instance)].transform = half_turn;
      backend.set_instance_transform(sheet_instance, half_turn);
      backend.commit();
    }
    const SceneGeometry geometry(scene);
    const CutoutMeshes cutouts(scene);
    constexpr int W = B::width;
    int checked = 0, failures = 0;
    for (int row = 0; row < 9; ++row) {
      RayPacket<W> rays;
      vec3<W> origin;
      float xs[W];
      for (int lane = 0; lane < W; ++lane) {
        xs[lane] = W == 1 ? -0.7f + 0.17f * float(row) : -1.8f + 3.6f * float(lane) / float(W - 1);
        origin.set(lane, glm::vec3(xs[lane], 1e-3f, -0.8f + 0.2f * float(row)));
      }
      const vmask<W> mask(true);
      rays.set(origin, vec3<W>(glm::vec3(0.0f, 1.0f, 0.0f)), vfloat<W>(0.0f), vfloat<W>(2.0f), mask);
      const vmask<W> blocked = occluded_by_opaque(backend, surface, scene, geometry, cutouts, 1e-4f, rays, Coherence::coherent, mask);
      for (int lane = 0; lane < W; ++lane) {
        const std::optional<bool> lit = sunlit(xs[lane], turned);
        if (!lit) continue;
        ++checked;
        if (blocked[lane] == *lit) {
          ++failures;
          UNSCOPED_INFO(B::name() << (test ? " with" : " without") << " its cut-out test, stencil " << (turned ? "turned" : "as built")
                                  << ": floor x = " << xs[lane] << " should be " << (*lit ? "sunlit" : "shadowed"));
        }
        // Blocked lanes get tfar = -inf, the others keep theirs, as from Backend::occluded.
        CHECK(rays.tfar[lane] == (blocked[lane] ? -std::numeric_limits<float>::infinity() : 2.0f));
      }
    }
    CHECK(checked >= (W == 1 ? 7 : 9 * W / 2));
    CHECK(failures == 0);
  }
}

}  // namespace

TEMPLATE_TEST_CASE("cut-outs: shadow rays pass an alpha cut-out where it is transparent and stop where it is opaque, "
                   "with the backend's cut-out test and without it, also once the cut-out moved",
                   "[render][cutouts]", EmbreeBackend<8>, EmbreeBackend<16>, EmbreeBackend<1>, ReferenceBackend<8>) {
  check_shadow_rays<TestType>(true);
  check_shadow_rays<TestType, ShadeOnly>(true);
  check_shadow_rays<TestType>(false);
}

TEST_CASE("cut-outs: GltfMaterialShader's opaque_at is shade()'s alpha test, on cut-outs and other meshes",
          "[render][cutouts]") {
  Scene scene = stencil_under_sun(true);
  const GltfMaterialShader surface(scene);
  const SceneGeometry geometry(scene);
  std::uint32_t state = 12345u;
  const auto uniform = [&state] {
    state = state * 1664525u + 1013904223u;  // a plain LCG: any spread of points will do
    return float(state >> 8) / float(1u << 24);
  };
  int opaque = 0, transparent = 0;
  for (int k = 0; k < 4000; ++k) {
    OcclusionCandidate candidate;
    candidate.instance = std::uint32_t(k % 3 == 0 ? 0 : k % 3 == 1 ? sheet_instance : 3);
    candidate.mesh = std::uint32_t(scene.instances[candidate.instance].mesh);
    candidate.primitive = std::uint32_t(k % 2);
    candidate.u = uniform();
    candidate.v = uniform() * (1.0f - candidate.u);
    candidate.origin = glm::vec3(0.0f, -1.0f, 0.0f);
    candidate.direction = glm::vec3(0.1f, 1.0f, 0.2f);
    candidate.distance = 1.0f;
    const vmask<1> one(true);
    const CandidateHit traced = candidate_hit(candidate);
    const bool shaded = surface.shade(make_surface_hit(scene, geometry, traced.ray, traced.hit, one), one).opaque[0];
    CHECK(surface.opaque_at(candidate) == shaded);
    (shaded ? opaque : transparent) += 1;
  }
  CHECK(transparent > 500);
  CHECK(opaque > 2000);
  OcclusionCandidate outside;
  outside.mesh = std::uint32_t(scene.meshes.size());
  CHECK_THROWS_AS(surface.opaque_at(outside), std::out_of_range);
  Scene broken = scene;
  broken.meshes[std::size_t(sheet_mesh)].material = 99;  // a material the scene lacks
  const GltfMaterialShader broken_surface(broken);
  OcclusionCandidate on_sheet;
  on_sheet.mesh = std::uint32_t(sheet_mesh);
  on_sheet.instance = std::uint32_t(sheet_instance);
  CHECK_THROWS_AS(broken_surface.opaque_at(on_sheet), std::out_of_range);
}

TEMPLATE_TEST_CASE("cut-outs: a backend's cut-out test sees each candidate in world space, with its mesh, instance and "
                   "triangle, also through a moved instance", "[render][cutouts]", EmbreeBackend<8>, EmbreeBackend<1>,
                   ReferenceBackend<8>) {
  Scene scene = stencil_under_sun(false);
  TestType backend(scene);
  std::vector<OcclusionCandidate> seen;
  backend.set_cutout_test([&seen](const OcclusionCandidate& candidate) {
    seen.push_back(candidate);
    return false;  // transparent: every candidate on the way is reported
  });
  for (const bool moved : {false, true}) {
    // Moved: lifted by 0.25 and turned a quarter round the vertical (Embree then traces it as an
    // instance, and hands the filter the ray in the instance's object space).
    const glm::mat4 transform = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(0.0f, 0.25f, 0.0f)), 1.5707963f,
                                            glm::vec3(0.0f, 1.0f, 0.0f));
    if (moved) {
      scene.instances[std::size_t(sheet_instance)].transform = transform;
      backend.set_instance_transform(sheet_instance, transform);
      backend.commit();
    }
    seen.clear();
    constexpr int W = TestType::width;
    RayPacket<W> rays;
    vec3<W> origin;
    for (int lane = 0; lane < W; ++lane) origin.set(lane, glm::vec3(-0.6f + 0.1f * float(lane), 0.01f, 0.3f));
    const glm::vec3 direction(0.2f, 2.0f, -0.1f);  // not unit length: distances are in its units
    rays.set(origin, vec3<W>(direction), vfloat<W>(0.0f), vfloat<W>(1.0f), vmask<W>(true));
    CHECK(none(backend.occluded(rays, vmask<W>(true))));
    REQUIRE(seen.size() >= std::size_t(W));
    const float height = moved ? 0.75f : 0.5f;
    for (const OcclusionCandidate& candidate : seen) {
      CHECK(candidate.mesh == std::uint32_t(sheet_mesh));
      CHECK(candidate.instance == std::uint32_t(sheet_instance));
      CHECK(candidate.primitive < 2u);
      CHECK(candidate.direction.x == Approx(direction.x).margin(1e-5));
      CHECK(candidate.direction.y == Approx(direction.y).margin(1e-5));
      CHECK(candidate.direction.z == Approx(direction.z).margin(1e-5));
      CHECK(candidate.origin.y == Approx(0.01f).margin(1e-5));
      // The candidate lies on the stencil, at its barycentrics' point of the world-space triangle.
      const glm::vec3 point = candidate.origin + candidate.distance * candidate.direction;
      CHECK(point.y == Approx(height).margin(1e-4));
      const Mesh& mesh = scene.meshes[std::size_t(sheet_mesh)];
      const glm::uvec3 triangle = mesh.triangles[candidate.primitive];
      const glm::mat4& to_world = scene.instances[std::size_t(sheet_instance)].transform;
      const glm::vec3 on_triangle = glm::vec3(to_world * glm::vec4((1.0f - candidate.u - candidate.v) * mesh.positions[triangle.x] +
                                                                       candidate.u * mesh.positions[triangle.y] +
                                                                       candidate.v * mesh.positions[triangle.z],
                                                                   1.0f));
      CHECK(glm::length(on_triangle - point) < 1e-4f);
    }
  }
}

TEST_CASE("cut-outs: a backend without a cut-out test (SaarCOR) gets the same shadows from the pipeline's re-tracing",
          "[render][cutouts]") {
  static_assert(!CutoutTestingBackend<SaarcorBackend>);
  check_shadow_rays<SaarcorBackend>(false);
}

TEST_CASE("cut-outs: without a cut-out test a backend's own occlusion query stops at every cut-out triangle",
          "[render][cutouts]") {
  // What the pipeline had before: occluded() alone, so the transparent half cast a shadow too.
  Scene scene = stencil_under_sun(true);
  const EmbreeBackend<8> backend(scene);
  RayPacket<8> rays;
  vec3<8> origin;
  for (int lane = 0; lane < 8; ++lane) origin.set(lane, glm::vec3(-0.4f + 0.01f * float(lane), 1e-3f, 0.0f));
  const vmask<8> mask(true);
  rays.set(origin, vec3<8>(glm::vec3(0.0f, 1.0f, 0.0f)), vfloat<8>(0.0f), vfloat<8>(2.0f), mask);
  CHECK(all(backend.occluded(rays, mask)));
}

TEST_CASE("cut-outs: a frame's floor is sunlit through the stencil's transparent half exactly as with no stencil, "
          "and dark under its opaque half, on every backend", "[render][cutouts]") {
  RenderSettings settings;
  settings.width = 48;
  settings.height = 36;
  settings.vpls_per_pixel = 4;
  settings.threads = 2;
  Scene scene = stencil_under_sun(false);
  Scene open = scene;
  open.materials[std::size_t(open.meshes[std::size_t(sheet_mesh)].material)].base_color.a = 0.0f;  // transparent everywhere
  const Frame unshaded = render_once<EmbreeBackend<8>>(open, settings);
  const Frame embree = render_once<EmbreeBackend<8>>(scene, settings);
  const Frame reference = render_once<ReferenceBackend<8>>(scene, settings);
  const Frame saarcor = render_once<SaarcorBackend>(scene, settings);
  // Each pixel's floor point, from its camera ray: sunlit where x < 0 (the transparent half),
  // black where x > 0, a margin of 0.2 left out around the cut-out's edges.
  int sunlit = 0, shadowed = 0, as_open = 0, black = 0;
  for_each_floor_pixel(scene.cameras.front(), settings, [&](std::size_t i, const glm::vec3& floor) {
    if (std::abs(floor.x) < 0.2f || std::abs(floor.x) > 1.8f || std::abs(floor.z) > 1.8f) return;
    const float open_light = unshaded.hdr.pixels[i].g, light = embree.hdr.pixels[i].g;
    REQUIRE(open_light > 0.0f);
    if (floor.x < 0.0f) {
      ++sunlit;
      as_open += light == Approx(open_light).epsilon(1e-4) ? 1 : 0;
    } else {
      ++shadowed;
      black += light == 0.0f ? 1 : 0;
    }
  });
  INFO(as_open << " of " << sunlit << " pixels under the transparent half as with no stencil, " << black << " of "
               << shadowed << " under the opaque half black");
  CHECK(sunlit > 100);
  CHECK(shadowed > 100);
  CHECK(as_open == sunlit);
  CHECK(black == shadowed);
  // The backends agree: the cut-out test in Embree's and the reference's traversal, the
  // pipeline's re-tracing for SaarCOR.
  CHECK(differing_pixels(embree, reference, 1e-3f) == 0);
  CHECK(differing_pixels(embree, saarcor, 1e-3f) == 0);
}
