// Use igi in your renderer, a tutorial: this renderer builds its own scene and camera, shades with
// its own scalar function and light source, and lets igi compute the global illumination.
// CMakeLists.txt beside it finds igi with find_package(igi) and links igi::igi and igi::embree,
// or with MY_RENDERER_COMPILED igi::compiled, whose renderer comes compiled (README.md).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <utility>
#include <glm/gtc/matrix_transform.hpp>
#include <igi/io/image_files.hpp>
#include <igi/lighting/qmc_vpl_sampler.hpp>
#if defined(MY_RENDERER_COMPILED)
#include <igi/render/scalar_surface_renderer.hpp>
#else
#include <igi/backends/embree/embree_backend.hpp>
#include <igi/filters/tile_filters.hpp>
#include <igi/render/renderer.hpp>
#include <igi/shading/brdf_shaders.hpp>
#include <igi/shading/scalar_shader_adapter.hpp>
#endif

// Step 1, geometry. An igi::Scene is plain data: meshes (one material each) placed by instances.
// Here every object is a box given by its centre and half size; faces wind counter-clockwise
// seen from outside, each face a quad of two triangles with its own flat normal.
void add_box(igi::Scene& scene, glm::vec3 center, glm::vec3 half, int material) {
  igi::Mesh mesh{.name = "box", .material = material};
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.0f, 1.0f}) {
      glm::vec3 normal(0.0f), u(0.0f), v(0.0f);
      normal[axis] = side;
      u[(axis + 1) % 3] = half[(axis + 1) % 3];
      v[(axis + 2) % 3] = half[(axis + 2) % 3];
      if (side < 0.0f) std::swap(u, v);  // keeps the winding counter-clockwise from outside
      const glm::vec3 face = center + normal * half[axis];
      const unsigned first = unsigned(mesh.positions.size());
      mesh.positions.insert(mesh.positions.end(), {face - u - v, face + u - v, face + u + v, face - u + v});
      mesh.normals.insert(mesh.normals.end(), 4, normal);
      mesh.triangles.push_back({first, first + 1, first + 2});
      mesh.triangles.push_back({first, first + 2, first + 3});
    }
  scene.instances.push_back({.name = "box", .mesh = int(scene.meshes.size())});
  scene.meshes.push_back(std::move(mesh));
}

// Step 2, surfaces. A plain function of one hit point; igi::ScalarShaderAdapter runs it on every
// lane of a SIMD packet. Material 0 is a chequered floor (10 cm squares), 1 red, 2 white.
struct MySurface {
  igi::ScalarBrdfParameters operator()(const igi::SurfacePoint& hit) const {
    igi::ScalarBrdfParameters brdf;  // grey Lambertian unless set otherwise
    const bool odd = (int(std::floor(hit.position.x * 10.0f)) + int(std::floor(hit.position.z * 10.0f))) & 1;
    if (hit.material == 0) brdf.albedo = odd ? glm::vec3(0.75f) : glm::vec3(0.25f);
    if (hit.material == 1) brdf.albedo = {0.7f, 0.1f, 0.08f};
    return brdf;
  }
};

// Step 3, a programmable light source: any type with power() and sample_emission(u1..u4), the
// igi::EmitterModel concept. This one is a glowing ball of radius 5 cm, uniform radiance 40.
struct BallLamp {
  glm::vec3 center{0.0f, 0.8f, 0.1f}, radiance{40.0f, 36.0f, 30.0f};  float radius = 0.05f;
  glm::vec3 power() const { return radiance * (4.0f * std::numbers::pi_v<float> * radius * radius) * std::numbers::pi_v<float>; }
  igi::EmissionSample sample_emission(float u1, float u2, float u3, float u4) const {
    const float z = 1.0f - 2.0f * u1, r = std::sqrt(std::max(0.0f, 1.0f - z * z)), phi = 2.0f * std::numbers::pi_v<float> * u2;
    const glm::vec3 normal(r * std::cos(phi), r * std::sin(phi), z);  // uniform point on the ball
    igi::EmissionSample sample{.origin = center + radius * normal};
    sample.direction = igi::sample_cosine_hemisphere(normal, u3, u4);  // Lambertian emission
    sample.flux = power();  // each sample stands for the whole lamp; the sampler divides by the count
    sample.vpl = {.position = sample.origin, .normal = normal, .intensity = power() / std::numbers::pi_v<float>};
    return sample;
  }
};

int main(int argc, char** argv) try {
  igi::Scene scene{.name = "my scene"};
  // Materials only name the surfaces here: MySurface gives their colours, to the camera and to the
  // VPL random walks alike (the light bouncing off the chequered floor is chequered too).
  scene.materials = {{.name = "floor"}, {.name = "red"}, {.name = "white"}};
  add_box(scene, {0.0f, -0.01f, 0.0f}, {1.0f, 0.01f, 1.0f}, 0);     // floor slab
  add_box(scene, {0.0f, 0.5f, -0.6f}, {1.0f, 0.5f, 0.01f}, 2);      // back wall
  add_box(scene, {-0.3f, 0.15f, 0.0f}, {0.15f, 0.15f, 0.15f}, 1);   // red cube
  add_box(scene, {0.3f, 0.35f, -0.2f}, {0.12f, 0.35f, 0.12f}, 2);   // white pillar
  // The camera looks down its -Z with +Y up, like glTF's; glm::lookAt gives the inverse transform.
  const igi::Camera camera{.camera_to_world = glm::inverse(glm::lookAt(glm::vec3(0, 0.6f, 1.6f), glm::vec3(0, 0.3f, -0.2f), glm::vec3(0, 1, 0)))};

  // Step 4, put it together: backend (Embree, 8-ray packets), the four policies, the settings.
  igi::QmcVplSampler sampler;
  sampler.add_emitter(BallLamp{});
  igi::RenderSettings settings;  // 640 x 480, 16 VPLs per pixel, 3 x 3 interleaving; all cores
#if defined(MY_RENDERER_COMPILED)  // the same policies, compiled in igi::compiled at its ISA's width
  igi::ScalarSurfaceRenderer renderer(scene, settings, MySurface{}, sampler);
#else
  const igi::ScalarShaderAdapter<MySurface> surface{MySurface{}};
  const igi::StandardBrdf brdf;           // Lambert + glossy + mirror + glass, SIMD
  const igi::DiscontinuityFilter filter;  // smooths the interleaving pattern, keeps edges
  igi::Renderer<igi::EmbreeBackend<8>, igi::ScalarShaderAdapter<MySurface>, igi::StandardBrdf, igi::QmcVplSampler,
                igi::DiscontinuityFilter> renderer(scene, settings, surface, brdf, sampler, filter);
#endif
  // Step 5, render (frame 0: the frame index picks the VPL sets) and write the tone-mapped image.
  const igi::Frame frame = renderer.render(camera, 0);
  const char* path = argc > 1 ? argv[1] : "my_renderer.png";
  igi::write_image(path, frame.rgb8);
  std::printf("%s: %.1f ms, %d VPLs\n", path, frame.statistics.milliseconds, frame.statistics.vpls);
} catch (const std::exception& error) {  // igi reports bad input with exceptions naming the problem
  std::fprintf(stderr, "my_renderer: %s\n", error.what());
  return 1;
}
