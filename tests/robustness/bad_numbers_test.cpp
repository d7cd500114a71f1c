// Bad numbers through the whole path (scene -> backend -> IGI frame): each gives a clear error
// naming the problem or a documented clamp, never NaN pixels, a crash or a hang. Every case runs
// through each backend. Covered elsewhere and not repeated here: validate_scene and the glTF
// loader on NaN/Inf positions (tests/scene/validate_test.cpp, gltf_malformed_test.cpp), zero-area
// triangles dropped by validation (validate_test.cpp), PinholeProjection's own checks
// (tests/scene/camera_test.cpp), LightSet on a negative intensity (tests/lighting/lights_test.cpp).

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/scene/validate.hpp"
#include "render/render_support.hpp"

namespace {

using namespace igi;
using Catch::Contains;

constexpr float not_a_number = std::numeric_limits<float>::quiet_NaN();
constexpr float infinity = std::numeric_limits<float>::infinity();

/// Small frames: enough pixels to see every wall of the Cornell box, few VPLs to stay quick under the sanitizers.
RenderSettings small_settings() {
  RenderSettings settings;
  settings.width = 24;
  settings.height = 24;
  settings.vpls_per_pixel = 2;
  settings.tile_size = 8;
  return settings;
}

/// The message of the exception one frame of `scene` throws through backend B; fails if it throws none.
template <class B>
std::string render_error(Scene scene, const RenderSettings& settings = small_settings()) {
  try {
    testing::render_once<B>(scene, settings);
  } catch (const std::exception& error) {
    return error.what();
  }
  FAIL("no error from " << B::name());
  return {};
}

/// Runs `check.template operator()<B>()` for each backend: Embree W=16, Reference W=8, SaarCOR.
template <class Check>
void for_each_backend(const Check& check) {
  check.template operator()<EmbreeBackend<16>>();
  check.template operator()<ReferenceBackend<8>>();
  check.template operator()<SaarcorBackend>();
}

/// Index of the Cornell box's mesh named `name`.
int mesh_named(const Scene& scene, const std::string& name) {
  for (std::size_t m = 0; m < scene.meshes.size(); ++m)
    if (scene.meshes[m].name == name) return int(m);
  FAIL("no mesh " << name);
  return -1;
}

}  // namespace

TEST_CASE("bad numbers: NaN and infinite vertex positions reaching a backend are errors naming the mesh", "[robustness]") {
  for (const float bad : {not_a_number, infinity, -infinity}) {
    Scene scene = cornell_box();
    scene.meshes[0].positions[1].y = bad;
    for_each_backend([&]<class B>() {
      INFO(B::name() << " with " << bad);
      CHECK_THAT(render_error<B>(scene), Contains("non-finite vertex position") && Contains(scene.meshes[0].name));
    });
  }
}

/// The Cornell box plus a triangle `far` with corners at +-`reach` (placed by a unit instance, or by `scale`).
Scene cornell_with_far_triangle(float reach, float scale = 1.0f) {
  Scene scene = cornell_box();
  Mesh far;
  far.name = "far";
  far.positions = {{reach, 0, 0}, {reach, reach, 0}, {-reach, 0, reach}};
  far.triangles = {{0, 1, 2}};
  far.material = 0;
  scene.meshes.push_back(far);
  scene.instances.push_back({.name = "far away", .mesh = int(scene.meshes.size()) - 1,
                             .transform = glm::scale(glm::mat4(1.0f), glm::vec3(scale))});
  return scene;
}

TEST_CASE("bad numbers: vertices at 1e30, in object or world space, are errors naming the instance and mesh", "[robustness]") {
  // Before this check Debian's Embree (built with assertions) aborted the process on the shadow
  // rays to VPLs on such a triangle: their squared length overflows float.
  for (const Scene& scene : {cornell_with_far_triangle(1e30f), cornell_with_far_triangle(1.0f, 1e30f)}) {
    Scene loaded = scene;
    CHECK_THROWS_WITH(validate_scene(loaded), Contains("instance 'far away' places mesh 'far' vertex 0") &&
                                                  Contains("beyond +-1e12"));
    for_each_backend([&]<class B>() {
      INFO(B::name());
      CHECK_THAT(render_error<B>(scene), Contains("'far'") && Contains("beyond +-1e12"));
    });
  }
}

TEST_CASE("bad numbers: a triangle at 0.9e12, just inside the limit, renders finite pixels", "[robustness]") {
  Scene scene = cornell_with_far_triangle(0.9f * max_scene_coordinate);
  validate_scene(scene);
  for_each_backend([&]<class B>() {
    INFO(B::name());
    const Frame frame = testing::render_once<B>(scene, small_settings());
    CHECK(testing::all_finite(frame));
    CHECK(testing::mean_radiance(frame) > 0.0);  // the box is still lit
  });
}

TEST_CASE("bad numbers: a scene of 1e30 extent has no default camera, with an error naming the bounds", "[robustness]") {
  Scene scene = cornell_box();
  for (Mesh& mesh : scene.meshes)
    for (glm::vec3& position : mesh.positions) position *= 1e30f;  // extent ~1e30: its length overflows float
  scene.cameras.clear();
  CHECK_THROWS_WITH(default_camera(scene), Contains("non-finite bounds"));
}

TEST_CASE("bad numbers: zero-length vertex normals fall back to the face normal, pixels stay finite", "[robustness]") {
  Scene scene = cornell_box();
  Scene reference = scene;
  for (Mesh& mesh : scene.meshes) mesh.normals.assign(mesh.positions.size(), glm::vec3(0.0f));
  for (Mesh& mesh : reference.meshes) mesh.normals.clear();  // no normals: the face normal by definition
  for_each_backend([&]<class B>() {
    INFO(B::name());
    const Frame frame = testing::render_once<B>(scene, small_settings());
    CHECK(testing::all_finite(frame));
    // The Cornell box is flat-shaded: zero normals must give exactly the image without normals.
    CHECK(testing::rmse(frame, testing::render_once<B>(reference, small_settings())) == 0.0);
  });
}

TEST_CASE("bad numbers: zero-area and sliver triangles that skip validation render finite pixels", "[robustness]") {
  Scene scene = cornell_box();
  Mesh& floor = scene.meshes[std::size_t(mesh_named(scene, "floor"))];
  const auto base = std::uint32_t(floor.positions.size());
  const glm::vec3 corner = floor.positions[0];
  const glm::vec3 along = floor.positions[1] - corner;
  // Above the floor, in view: a repeated vertex, three collinear vertices, a 1e-7-thin sliver.
  const glm::vec3 lift(0.0f, 0.05f, 0.0f);
  floor.positions.insert(floor.positions.end(), {corner + lift, corner + lift + 0.5f * along, corner + lift + along,
                                                 corner + lift + 0.5f * along + glm::vec3(0.0f, 1e-7f, 0.0f)});
  if (!floor.normals.empty()) floor.normals.resize(floor.positions.size(), glm::vec3(0.0f, 1.0f, 0.0f));
  floor.triangles.insert(floor.triangles.end(), {{base, base, base + 2}, {base, base + 1, base + 2}, {base, base + 2, base + 3}});
  for_each_backend([&]<class B>() {
    INFO(B::name());
    CHECK(testing::all_finite(testing::render_once<B>(scene, small_settings())));
  });
}

TEST_CASE("bad numbers: negative, NaN or infinite light intensities and colours are errors naming the light", "[robustness]") {
  for (const float bad : {-1.0f, not_a_number, infinity}) {
    Scene scene = cornell_box();
    scene.lights.push_back({.name = "lamp", .kind = PunctualKind::point, .intensity = bad, .position = glm::vec3(0.3f)});
    Scene colour = cornell_box();
    colour.lights.push_back({.name = "tinted", .kind = PunctualKind::point, .color = glm::vec3(1.0f, bad, 1.0f),
                             .position = glm::vec3(0.3f)});
    Scene emission = cornell_box();
    emission.materials.back().emission.g = bad;
    for_each_backend([&]<class B>() {
      INFO(B::name() << " with " << bad);
      CHECK_THAT(render_error<B>(scene), Contains("lamp"));
      CHECK_THAT(render_error<B>(colour), Contains("tinted"));
      CHECK_THAT(render_error<B>(emission), Contains("emission"));
    });
  }
}

TEST_CASE("bad numbers: zero, negative, NaN or straight-angle camera fov is an error naming yfov", "[robustness]") {
  for (const float bad : {0.0f, -0.5f, not_a_number, infinity, glm::pi<float>()}) {
    Scene scene = cornell_box();
    scene.cameras.front().yfov = bad;
    for_each_backend([&]<class B>() {
      INFO(B::name() << " with yfov " << bad);
      CHECK_THAT(render_error<B>(scene), Contains("yfov"));
    });
  }
}

TEST_CASE("bad numbers: resolution 0, negative or 100000 is a settings error naming the size", "[robustness]") {
  for (const auto& [width, height] : {std::pair{0, 24}, std::pair{24, 0}, std::pair{-3, 24}, std::pair{100000, 24},
                                      std::pair{24, 100000}, std::pair{100000, 100000}}) {
    RenderSettings settings = small_settings();
    settings.width = width;
    settings.height = height;
    INFO(width << "x" << height);
    Scene scene = cornell_box();
    CHECK_THROWS_AS(testing::render_once<EmbreeBackend<16>>(scene, settings), SettingsError);
    CHECK_THAT(render_error<ReferenceBackend<8>>(cornell_box(), settings),
               Contains(std::to_string(width) + "x" + std::to_string(height)));
  }
}

TEST_CASE("bad numbers: 0 VPLs and interleave 0 are settings errors naming the setting", "[robustness]") {
  RenderSettings no_vpls = small_settings();
  no_vpls.vpls_per_pixel = 0;
  RenderSettings no_pattern = small_settings();
  no_pattern.interleave = 0;
  for_each_backend([&]<class B>() {
    INFO(B::name());
    CHECK_THAT(render_error<B>(cornell_box(), no_vpls), Contains("vpls 0"));
    CHECK_THAT(render_error<B>(cornell_box(), no_pattern), Contains("interleave 0"));
  });
}

TEST_CASE("bad numbers: a shadow roulette outside 0..1 or NaN is a settings error naming the setting", "[robustness]") {
  for (const float fraction : {-0.1f, 1.5f, std::numeric_limits<float>::quiet_NaN()}) {
    RenderSettings settings = small_settings();
    settings.shadow_roulette = fraction;
    CHECK_THAT(render_error<EmbreeBackend<8>>(cornell_box(), settings), Contains("shadow roulette"));
  }
}

TEST_CASE("bad numbers: compensation rays outside 0..64 are a settings error naming the setting", "[robustness]") {
  for (const int rays : {-1, max_compensation_rays + 1}) {
    RenderSettings settings = small_settings();
    settings.compensation_rays = rays;
    CHECK_THAT(render_error<EmbreeBackend<8>>(cornell_box(), settings), Contains("compensation rays " + std::to_string(rays)));
  }
}

TEST_CASE("bad numbers: runtime updates placing a vertex beyond 1e12 are refused and change nothing", "[robustness]") {
  // validate_scene holds the limit at load time; a moved instance or deformed mesh must hold it too,
  // or the next frame's shadow rays overflow as in the 1e30 case above.
  Scene scene = cornell_box();
  validate_scene(scene);
  const int box = scene.instances[0].mesh;  // a mesh the moved instance places
  const glm::mat4 too_far = glm::scale(glm::mat4(1.0f), glm::vec3(1e13f));  // box corners at ~1e13
  std::vector<glm::vec3> stretched = scene.meshes[std::size_t(box)].positions;
  stretched[0] *= 2e12f;
  const RenderSettings settings = small_settings();
  const Camera camera = scene.cameras.front();
  for_each_backend([&]<class B>() {
    INFO(B::name());
    Scene copy = scene;
    const GltfMaterialShader surface(copy);
    const StandardBrdf brdf;
    const QmcVplSampler sampler;
    const DiscontinuityFilter filter;
    Renderer<B, GltfMaterialShader, StandardBrdf, QmcVplSampler, DiscontinuityFilter> renderer(copy, settings, surface,
                                                                                             brdf, sampler, filter);
    const Frame before = renderer.render(camera, 0);
    CHECK_THROWS_WITH(renderer.set_instance_transform(0, too_far),
                      Contains("instance '" + scene.instances[0].name + "'") && Contains("beyond +-1e12"));
    CHECK_THROWS_WITH(renderer.set_mesh_positions(box, stretched),
                      Contains("mesh '" + scene.meshes[std::size_t(box)].name + "' vertex 0") && Contains("beyond +-1e12"));
    CHECK(renderer.scene().instances[0].transform == scene.instances[0].transform);
    CHECK(renderer.scene().meshes[std::size_t(box)].positions == scene.meshes[std::size_t(box)].positions);
    const Frame after = renderer.render(camera, 0);
    CHECK(after.hdr.pixels == before.hdr.pixels);  // the refused updates reached neither the scene nor the backend
  });
}

TEST_CASE("bad numbers: a move is checked by its mesh's box, and by the vertices only where the box reaches the limit", "[robustness]") {
  // Three vertices 0.9e12 from the origin along the axes: their box's far corner (0.9e12 each
  // way) turned onto the x axis lies 1.56e12 out, beyond the limit, while every vertex stays
  // 0.9e12 out. The box alone would refuse this move; the vertices decide.
  const float reach = 0.9e12f;
  const std::vector<glm::vec3> vertices = {{reach, 0.0f, 0.0f}, {0.0f, reach, 0.0f}, {0.0f, 0.0f, reach}};
  const Bounds box = bounds_of(vertices);
  const glm::vec3 diagonal = glm::normalize(glm::vec3(1.0f));
  const glm::vec3 axis = glm::normalize(glm::cross(diagonal, glm::vec3(1.0f, 0.0f, 0.0f)));
  const glm::mat4 turned = glm::rotate(glm::mat4(1.0f), std::acos(diagonal.x), axis);
  REQUIRE(placed(box, turned).upper.x > max_scene_coordinate);
  CHECK_NOTHROW(check_extent(turned, box, vertices, "turned", "tripod", "test"));
  // A translation past the limit is refused at once by the box, naming the first vertex beyond it.
  const glm::mat4 shifted = glm::translate(glm::mat4(1.0f), glm::vec3(0.5e12f, 0.0f, 0.0f));
  CHECK_THROWS_WITH(check_extent(shifted, box, vertices, "shifted", "tripod", "test"),
                    Contains("instance 'shifted'") && Contains("vertex 0") && Contains("beyond +-1e12"));
  // The box within the limit: accepted without a look at the vertices (an empty list shows it).
  CHECK_NOTHROW(check_extent(glm::mat4(1.0f), box, {}, "still", "tripod", "test"));
}
