#pragma once
/// \file
/// `find_portals`: where light from infinitely far away (directional lights, the environment)
/// reaches what the camera sees. Camera rays on a jittered grid find the view's points; from each,
/// a ray towards every directional light and a few towards the sky (drawn by the environment's
/// own distribution, above the point's surface) are traced, and those that leave the scene
/// (through glass and blended surfaces too, which let light in) are the openings, whatever shape
/// they have: the window of a room, the gap between slats, or the whole sky over an open yard. The lights then aim a share of their particles along those rays
/// (Portals, lights.hpp), so the light walks of a room lit through a window bounce inside the
/// room instead of on the ground outside, with every particle weighed by the mixture's density.
///
/// Everything here is a pure function of the scene, the view, the seed and the frame, so every
/// backend, thread and process finds the same portals (up to the float rounding of hit points).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/packet.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/lighting/vpl_sampler.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {

/// View points found per frame: 16 x 16 camera rays cover a view's rooms and openings well enough
/// for aiming (each escape ray is widened by the spread) for a few thousand rays a frame.
inline constexpr int portal_view_samples = 256;
/// Rays towards the sky from each view point: 8 find the openings a point sees (a window that
/// fills a tenth of its sky is found by most points) at 2,048 rays a frame.
inline constexpr int portal_sky_rays = 8;
/// Rays from each view point to the surfaces it sees (portals one bounce further): 4 find the
/// ground outside a window from most points that see it, at 1,024 rays a frame.
inline constexpr int portal_bounce_rays = 4;
/// Rays towards the sky from each of those surfaces: 2, as they are four times as many.
inline constexpr int portal_beyond_sky_rays = 2;
/// Most escape rays kept per light: an aimed particle's density sums over them, so 256 bounds
/// that cost (a few ms a frame for thousands of walks) while covering any opening.
inline constexpr std::size_t portal_most_rays = 256;

/// An opaque surface a single ray found, and its BRDF parameters.
struct OpaqueHit {
  SurfaceHit<1> surface;          ///< The hit point.
  BrdfParameters<1> parameters;   ///< The surface shader's output there.
};

/// The first opaque surface along the ray from `origin` along `direction` beyond `start`, passing
/// alpha cut-outs where they are transparent (going on `offset` beyond each) and, with
/// `through_glass`, see-through surfaces (thin glass, alpha blending: Material::see_through) as
/// well; none if the ray leaves the scene or passes more than max_cutout_layers of them.
template <class Tracer, class Shader>
  requires SurfaceShader<Shader, 1>
std::optional<OpaqueHit> first_opaque_hit(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer,
                                          const Shader& shader, glm::vec3 origin, const glm::vec3& direction, float start,
                                          float offset, bool through_glass = false) {
  const vmask<1> one(true);
  for (int layer = 0; layer <= max_cutout_layers; ++layer) {
    RayPacket<1> ray;
    ray.set(vec3<1>(origin), vec3<1>(direction), vfloat<1>(start), vfloat<1>(std::numeric_limits<float>::infinity()), one);
    HitPacket<1> hit;
    hit.clear();
    tracer.intersect(ray, hit, one);
    if (hit.geomID[0] == invalid_id) return std::nullopt;
    OpaqueHit found{.surface = make_surface_hit(scene, geometry, ray, hit, one), .parameters = {}};
    found.parameters = shader.shade(found.surface, one);
    const bool passes = through_glass && scene.material_of(int(hit.geomID[0])).see_through();
    if (found.parameters.opaque[0] && !passes) return found;
    origin = found.surface.position[0];
    start = offset;
  }
  return std::nullopt;
}

/// Calls `visit(cell, direction)` for the camera rays of a grid of about `samples` cells with the
/// image's aspect (at least one each way) over `projection`'s image, each through a point of its
/// cell jittered by `cell` = hash(key, cell index), which the visitor may hash on for its own numbers.
template <class Visit>
void for_each_view_ray(const PinholeProjection& projection, int samples, std::uint32_t key, Visit&& visit) {
  const float width = float(projection.width()), height = float(projection.height());
  const int columns = std::max(1, int(std::lround(std::sqrt(double(samples) * width / height))));
  const int rows = std::max(1, int(std::lround(double(samples) / columns)));
  for (int row = 0; row < rows; ++row)
    for (int column = 0; column < columns; ++column) {
      const std::uint32_t cell = hash(key, std::uint32_t(row * columns + column));
      const float px = (float(column) + to_unit_float(hash(cell, 0u))) * width / float(columns);
      const float py = (float(row) + to_unit_float(hash(cell, 1u))) * height / float(rows);
      visit(cell, projection.direction(px, py));
    }
}

namespace portal_detail {

/// At most `most` of `items`, evenly spaced (all if fewer).
template <class T>
std::vector<T> thinned(const std::vector<T>& items, std::size_t most) {
  if (items.size() <= most) return items;
  std::vector<T> kept;
  kept.reserve(most);
  for (std::size_t i = 0; i < most; ++i) kept.push_back(items[i * items.size() / most]);
  return kept;
}

}  // namespace portal_detail

/// The portals of the frame `settings` describe (its view must be set, else none are found), with
/// `share` of the particles to be aimed through them. Returns empty portals where the scene has
/// no directional light and no environment, or the view sees nothing.
template <class Tracer, class Shader>
  requires SurfaceShader<Shader, 1>
Portals find_portals(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer, const Shader& shader,
                     const VplSettings& settings, float share) {
  Portals portals;
  portals.sunlit.resize(scene.lights.size());
  const bool sky = scene.environment && scene.environment->emits();
  bool directional = false;
  for (const PunctualLight& light : scene.lights) directional |= light.kind == PunctualKind::directional;
  if (!settings.view || !(share > 0.0f) || (!sky && !directional)) return portals;

  const PinholeProjection& projection = settings.view->projection;
  // An arbitrary salt that separates the portals' numbers from the walks' and the view points'.
  constexpr std::uint32_t portal_salt = 0x706f7274u;
  const float offset = ray_offset(settings.scene_bounds);
  // The view points: the first opaque hit of each cell's camera ray, its normal turned towards
  // the camera (the side light reaches it from), and the cell's key for its sky rays.
  struct Seen {
    glm::vec3 point, normal;
    std::uint32_t cell;
  };
  std::vector<Seen> seen;
  for_each_view_ray(projection, portal_view_samples, hash(hash(settings.seed, settings.frame), portal_salt),
                    [&](std::uint32_t cell, const glm::vec3& direction) {
                      const std::optional<OpaqueHit> hit =
                          first_opaque_hit(scene, geometry, tracer, shader, projection.origin(), direction, 0.0f, offset);
                      if (!hit) return;
                      glm::vec3 normal = hit->surface.geometric_normal[0];
                      if (glm::dot(normal, direction) > 0.0f) normal = -normal;
                      seen.push_back({hit->surface.position[0], normal, cell});
                    });
  // Where light from far away reaches `points` (the view's, or those they see): each point's
  // rays towards the directional lights and `sky_rays` towards the sky that leave the scene.
  const auto add_openings = [&](const std::vector<Seen>& points, int sky_rays) {
    for (std::size_t i = 0; i < points.size(); ++i) {
      // The spread: twice the distance to the nearest other point, so the aimed lines of
      // neighbouring points overlap and light the region between them, near ones in a room
      // finely, far ones on the ground outside coarsely; at least 10 ray offsets where points coincide.
      float nearest2 = std::numeric_limits<float>::infinity();
      for (std::size_t j = 0; j < points.size(); ++j) {
        if (j == i) continue;
        const glm::vec3 d = points[j].point - points[i].point;
        nearest2 = std::min(nearest2, glm::dot(d, d));
      }
      const float spread = std::isfinite(nearest2) ? std::max(2.0f * std::sqrt(nearest2), 10.0f * offset)
                                                   : glm::length(settings.scene_bounds.extent());
      const AimPoint aim{.point = points[i].point, .spread = spread};
      const glm::vec3 start_point = points[i].point + points[i].normal * offset;
      for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        const PunctualLight& light = scene.lights[l];
        if (light.kind != PunctualKind::directional) continue;
        const float length = glm::length(light.direction);
        if (!(length > 0.0f) || !std::isfinite(length)) continue;
        const glm::vec3 to_light = -light.direction / length;
        if (glm::dot(to_light, points[i].normal) > 0.0f &&
            !first_opaque_hit(scene, geometry, tracer, shader, start_point, to_light, 0.0f, offset, true))
          portals.sunlit[l].push_back(aim);
      }
      if (!sky) continue;
      for (int k = 0; k < sky_rays; ++k) {
        const std::uint32_t cell = points[i].cell;
        const EnvironmentSample s = scene.environment->sample(to_unit_float(hash(cell, std::uint32_t(2 + 2 * k))),
                                                              to_unit_float(hash(cell, std::uint32_t(3 + 2 * k))));
        if (!(s.pdf > 0.0f) || !(glm::dot(s.direction, points[i].normal) > 0.0f)) continue;
        if (!first_opaque_hit(scene, geometry, tracer, shader, start_point, s.direction, 0.0f, offset, true)) {
          portals.sky_points.push_back(aim);
          portals.sky_directions.push_back(s.direction);
        }
      }
    }
  };
  add_openings(seen, portal_sky_rays);
  // One bounce further: the surfaces the view's points see (through a window, the ground and the
  // walls outside), whose sunlit and sky-lit parts send their reflected light back into the
  // view's room. Measured in the sunlit window room, that light is a third of the room's
  // indirect light, and without these targets only the unaimed share of the walks carries it.
  std::vector<Seen> beyond;
  for (const Seen& view_point : seen)
    for (int k = 0; k < portal_bounce_rays; ++k) {
      const std::uint32_t ray_key = hash(view_point.cell, std::uint32_t(0x100 + k));
      const glm::vec3 direction = sample_cosine_hemisphere(view_point.normal, to_unit_float(hash(ray_key, 0u)), to_unit_float(hash(ray_key, 1u)));
      const std::optional<OpaqueHit> hit = first_opaque_hit(scene, geometry, tracer, shader, view_point.point + view_point.normal * offset,
                                                            direction, 0.0f, offset, true);
      if (!hit) continue;
      glm::vec3 normal = hit->surface.geometric_normal[0];
      if (glm::dot(normal, direction) > 0.0f) normal = -normal;
      beyond.push_back({hit->surface.position[0], normal, ray_key});
    }
  add_openings(beyond, portal_beyond_sky_rays);
  portals.share = share;
  for (auto& points : portals.sunlit) points = portal_detail::thinned(points, portal_most_rays);
  portals.sky_points = portal_detail::thinned(portals.sky_points, portal_most_rays);
  portals.sky_directions = portal_detail::thinned(portals.sky_directions, portal_most_rays);
  return portals;
}

}  // namespace igi
