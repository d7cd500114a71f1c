// The VPL walks shade with the frame's own surface shader: a shader that paints the Cornell box's
// floor green must colour the light the floor reflects, in the VPLs and in the rendered ceiling.
#include <string>
#include <type_traits>

#include <catch2/catch.hpp>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "render/test_renderers.hpp"

using namespace igi;

namespace {

/// The glTF materials, with one mesh's albedo replaced: a user's procedural surface shader.
class PaintedMeshShader {
 public:
  /// Paints mesh `mesh` of `scene` with `albedo`.
  PaintedMeshShader(const Scene& scene, int mesh, glm::vec3 albedo) : materials_(scene), mesh_(mesh), albedo_(albedo) {}
  /// Policy name.
  static constexpr const char* name() noexcept { return "painted mesh"; }
  /// The glTF material's parameters, the painted mesh's albedo replaced.
  template <int W>
  BrdfParameters<W> shade(const SurfaceHit<W>& hit, const vmask<W>& mask) const {
    BrdfParameters<W> parameters = materials_.shade(hit, mask);
    parameters.albedo.assign(vec3<W>(albedo_), mask & (hit.mesh == vint<W>(mesh_)));
    return parameters;
  }

 private:
  GltfMaterialShader materials_;
  int mesh_;
  glm::vec3 albedo_;
};

/// Index of the mesh called `name`.
int mesh_named(const Scene& scene, const std::string& name) {
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    if (scene.meshes[i].name == name) return int(i);
  FAIL("the Cornell box has no mesh '" << name << "'");
  return -1;
}

/// Sum of the red channel over the image's top quarter: ceiling, upper walls and the luminaire,
/// no floor in view there.
double top_red(const Frame& frame) {
  double red = 0.0;
  for (int y = 0; y < frame.height / 4; ++y)
    for (int x = 0; x < frame.width; ++x) red += frame.hdr(x, y).r;
  return red;
}

// Green paint: the Cornell white's green albedo (0.699) kept, its red (0.886) and blue taken away.
const glm::vec3 painted_green{0.05f, 0.7f, 0.05f};

}  // namespace

TEST_CASE("VPL walks take their albedo from the frame's surface shader", "[lighting][qmc][shaders]") {
  const Scene scene = cornell_box();
  const EmbreeBackend<8> backend(scene);
  const int floor = mesh_named(scene, "floor");
  const VplSettings settings{.sets = 9, .vpls_per_set = 64};
  const VplGeneration plain =
      QmcVplSampler{}.generate_with_origins(scene, backend, GltfMaterialShader(scene), StandardBrdf{}, settings);
  const VplGeneration painted = QmcVplSampler{}.generate_with_origins(
      scene, backend, PaintedMeshShader(scene, floor, painted_green), StandardBrdf{}, settings);
  // The first bounce of each walk lands where the light's particles first hit, mostly the floor
  // under the luminaire; count those VPLs (floor at y = 0 in the box's own coordinates) by colour.
  const auto floor_vpls = [&](const VplGeneration& g, int& greenish, int& total) {
    greenish = total = 0;
    for (std::size_t s = 0; s < g.vpls.sets.size(); ++s)
      for (std::size_t i = 0; i < g.vpls.sets[s].size(); ++i) {
        const Vpl& vpl = g.vpls.sets[s][i];
        if (g.origins[s][i].bounce != 1 || !(vpl.normal.y > 0.99f) || !(vpl.position.y < 1e-3f)) continue;
        ++total;
        // A VPL left on the painted floor carries flux x green albedo: green over red is 0.7 / 0.05 = 14
        // times the light's own ratio, while the white floor's is about 0.79.
        if (vpl.intensity.g > 4.0f * vpl.intensity.r) ++greenish;
      }
  };
  int plain_green = 0, plain_total = 0, painted_green_count = 0, painted_total = 0;
  floor_vpls(plain, plain_green, plain_total);
  floor_vpls(painted, painted_green_count, painted_total);
  INFO("floor VPLs: glTF materials " << plain_green << " green of " << plain_total << ", painted " << painted_green_count
                                     << " green of " << painted_total);
  // 9 sets x 64 VPLs leave about 20 first-bounce VPLs on the floor under the luminaire.
  REQUIRE(plain_total >= 10);
  REQUIRE(painted_total >= 10);
  CHECK(plain_green == 0);
  CHECK(painted_green_count == painted_total);
}

TEST_CASE("Indirect light in the frame has the colours the surface shader paints", "[lighting][qmc][shaders][render]") {
  Scene scene = cornell_box();
  const int floor = mesh_named(scene, "floor");
  RenderSettings settings;
  settings.width = 64;
  settings.height = 48;
  settings.vpls_per_pixel = 32;
  settings.threads = 1;
  const StandardBrdf brdf;
  const QmcVplSampler sampler;
  const DiscontinuityFilter filter;
  const Camera camera = scene.cameras.front();
  const GltfMaterialShader plain(scene);
  const PaintedMeshShader painted(scene, floor, painted_green);
  const auto red_of = [&](const auto& surface, int max_bounces) {
    RenderSettings s = settings;
    s.max_bounces = max_bounces;
    Renderer<EmbreeBackend<8>, std::decay_t<decltype(surface)>, StandardBrdf, QmcVplSampler, DiscontinuityFilter> renderer(
        scene, s, surface, brdf, sampler, filter);
    return top_red(renderer.render(camera, 0));
  };
  // Walks of no bounce leave VPLs on the luminaire only: the direct light, which the floor's
  // paint cannot change in the top quarter. What the full frame has beyond it is bounce light.
  const double direct = red_of(plain, 0);
  const double plain_indirect = red_of(plain, settings.max_bounces) - direct;
  const double painted_indirect = red_of(painted, settings.max_bounces) - direct;
  INFO("indirect red in the top quarter: glTF materials " << plain_indirect << ", floor painted green " << painted_indirect
                                                            << " (direct " << direct << ")");
  REQUIRE(plain_indirect > 0.0);
  // The floor is not in the top quarter, so only its bounce light can change those pixels: if the
  // VPL walks ignored the frame's shader the two would be equal (the same VPLs). The floor is the
  // largest reflector under the luminaire; without its red the top quarter's red bounce light
  // drops by 14% (the red wall and the boxes still give the rest), so 5% is far outside rounding.
  CHECK(painted_indirect < 0.95 * plain_indirect);
}
