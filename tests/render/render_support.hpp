#pragma once
// Shared helpers of the render tests: frames through any backend and BRDF, and their statistics
// (the scenes they render are built by scene_builders.hpp).

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include <glm/gtc/matrix_transform.hpp>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "render/test_renderers.hpp"
#include "scene_builders.hpp"

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

/// Pixels of `other` whose largest channel difference from `reference` exceeds `relative` times
/// the reference pixel's largest channel (floored at 1e-6, so black pixels must match to 1e-6 x relative).
inline std::size_t differing_pixels(const Frame& reference, const Frame& other, float relative) {
  std::size_t count = 0;
  for (std::size_t i = 0; i < reference.hdr.pixels.size(); ++i) {
    const glm::vec3 d = glm::abs(reference.hdr.pixels[i] - other.hdr.pixels[i]);
    const glm::vec3& p = reference.hdr.pixels[i];
    if (std::max(d.r, std::max(d.g, d.b)) > relative * std::max(1e-6f, std::max(p.r, std::max(p.g, p.b)))) ++count;
  }
  return count;
}

/// Calls `visit(i, floor)` for each pixel of a `settings`-sized frame seen by `camera` whose ray
/// through the pixel's centre hits the plane y = 0 below it: `i` the pixel's index, `floor` the hit.
template <class Visit>
void for_each_floor_pixel(const Camera& camera, const RenderSettings& settings, Visit&& visit) {
  const PinholeProjection projection(camera, settings.width, settings.height);
  for (int y = 0; y < settings.height; ++y)
    for (int x = 0; x < settings.width; ++x) {
      const glm::vec3 direction = projection.direction(float(x) + 0.5f, float(y) + 0.5f);
      if (!(direction.y < 0.0f)) continue;
      visit(std::size_t(y) * std::size_t(settings.width) + std::size_t(x),
            projection.origin() - direction * (projection.origin().y / direction.y));
    }
}

/// True if every channel of every pixel is finite.
inline bool all_finite(const Frame& frame) {
  for (const glm::vec3& p : frame.hdr.pixels)
    if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) return false;
  return true;
}

/// `start` moved `index` steps of a walk: each `metres` sideways (along world x) and turned
/// `degrees` about its own vertical axis.
inline Camera walked_camera(const Camera& start, std::uint32_t index, float metres, float degrees) {
  Camera camera = start;
  const float step = float(index);
  camera.camera_to_world = glm::translate(glm::mat4(1.0f), glm::vec3(metres * step, 0.0f, 0.0f)) * camera.camera_to_world *
                           glm::rotate(glm::mat4(1.0f), glm::radians(degrees * step), glm::vec3(0.0f, 1.0f, 0.0f));
  return camera;
}

/// A renderer of `scene` through Embree with its glTF materials, the paper's VPL walks and the
/// discontinuity filter: what the programs render a glTF scene with.
struct RoomRenderer {
  GltfMaterialShader surface;
  StandardBrdf brdf;
  QmcVplSampler sampler;
  DiscontinuityFilter filter;
  Renderer<EmbreeBackend<8>, GltfMaterialShader, StandardBrdf, QmcVplSampler, DiscontinuityFilter> renderer;
  RoomRenderer(Scene& scene, const RenderSettings& settings) : surface(scene), renderer(scene, settings, surface, brdf, sampler, filter) {}
  /// Frame `index` seen by `camera`.
  Frame render(const Camera& camera, std::uint32_t index) { return renderer.render(camera, index); }
};

}  // namespace igi::testing
