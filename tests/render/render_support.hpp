#pragma once
// Shared helpers of the render tests: frames through any backend and BRDF, a closed box.

#include <cmath>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

namespace igi::testing {

/// One frame of `scene` through backend B, BRDF shader Brdf and filter F.
template <class B, class Brdf = StandardBrdf, class F = DiscontinuityFilter>
Frame render_once(Scene& scene, const RenderSettings& settings, std::uint32_t index = 0, const Brdf& brdf = Brdf(),
                  const F& filter = F()) {
  const GltfMaterialShader surface(scene);
  const QmcVplSampler sampler;
  Renderer<B, GltfMaterialShader, Brdf, QmcVplSampler, F> renderer(scene, settings, surface, brdf, sampler, filter);
  const Camera camera = scene.cameras.empty() ? default_camera(scene) : scene.cameras.front();
  return renderer.render(camera, index);
}

/// Mean of all channels of all pixels.
inline double mean_radiance(const Frame& frame) {
  double sum = 0.0;
  for (const glm::vec3& p : frame.hdr.pixels) sum += double(p.r) + double(p.g) + double(p.b);
  return sum / (3.0 * double(frame.hdr.pixels.size()));
}

/// Root-mean-square difference of two frames' HDR pixels.
inline double rmse(const Frame& a, const Frame& b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.hdr.pixels.size(); ++i) {
    const glm::vec3 d = a.hdr.pixels[i] - b.hdr.pixels[i];
    sum += double(glm::dot(d, d));
  }
  return std::sqrt(sum / (3.0 * double(a.hdr.pixels.size())));
}

/// True if every channel of every pixel is finite.
inline bool all_finite(const Frame& frame) {
  for (const glm::vec3& p : frame.hdr.pixels)
    if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) return false;
  return true;
}

/// A closed unit cube seen from inside: every face emits `emission` and reflects `albedo`
/// diffusely, so radiance is emission / (1 - albedo) everywhere.
inline Scene closed_box(float albedo, float emission) {
  Scene scene;
  scene.name = "closed box";
  Material material;
  material.name = "uniform";
  material.base_color = glm::vec4(albedo, albedo, albedo, 1.0f);
  material.metallic = 0.0f;
  material.roughness = 1.0f;
  material.emission = glm::vec3(emission);
  scene.materials.push_back(material);
  Mesh mesh;
  mesh.name = "box";
  mesh.material = 0;
  // Each face: inward normal n, two tangent axes; corners at +-1/2 around the centre.
  const glm::vec3 normals[6] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  for (const glm::vec3& n : normals) {
    const glm::vec3 a = std::abs(n.x) > 0.5f ? glm::vec3(0, 1, 0) : glm::vec3(1, 0, 0);
    const glm::vec3 b = glm::cross(n, a);
    const glm::vec3 centre = -0.5f * n;  // the face opposite its inward normal
    const auto base = std::uint32_t(mesh.positions.size());
    for (const glm::vec2& c : {glm::vec2(-0.5f, -0.5f), glm::vec2(0.5f, -0.5f), glm::vec2(0.5f, 0.5f), glm::vec2(-0.5f, 0.5f)}) {
      mesh.positions.push_back(centre + c.x * a + c.y * b);
      mesh.normals.push_back(n);
    }
    // Counter-clockwise seen from inside (from the side n points to).
    mesh.triangles.push_back({base, base + 1, base + 2});
    mesh.triangles.push_back({base, base + 2, base + 3});
    const glm::vec3 e1 = mesh.positions[base + 1] - mesh.positions[base];
    const glm::vec3 e2 = mesh.positions[base + 2] - mesh.positions[base];
    if (glm::dot(glm::cross(e1, e2), n) < 0.0f) {
      mesh.triangles[mesh.triangles.size() - 2] = {base, base + 2, base + 1};
      mesh.triangles[mesh.triangles.size() - 1] = {base, base + 3, base + 2};
    }
  }
  scene.meshes.push_back(mesh);
  scene.instances.push_back({.name = "box", .mesh = 0});
  Camera camera;
  camera.name = "inside";
  camera.yfov = 1.2f;  // wide: sees walls, edges and corners
  scene.cameras.push_back(camera);  // at the centre, looking down -z
  return scene;
}

}  // namespace igi::testing
