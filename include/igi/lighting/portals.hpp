#pragma once
/// \file
/// `find_portals`: where light from infinitely far away (directional lights, the environment)
/// reaches what the camera sees. Camera rays on a jittered grid find the view's points; from each,
/// a ray towards every directional light and a few towards the sky (drawn by the environment's
/// own distribution, above the point's surface; without an environment, about its normal) are
/// traced, and those that leave the scene (through glass and blended surfaces too, which let
/// light in) show the openings, whatever shape they have: the window of a room, the gap between
/// slats, or the whole sky over an open yard. Where each such ray passes its opening is found
/// by rays turned from it that meet the opening's frame. The lights then aim a share of their
/// particles along those rays and through those points (Portals, lights.hpp), so the light walks
/// of a room lit through a window bounce inside the room instead of on the ground outside, with
/// every particle weighed by the mixture's density.
///
/// Everything here is a pure function of the scene, the view, the seed and the frame, so every
/// backend, thread and process finds the same portals (up to the float rounding of hit points):
/// the rays of each point are traced as oneTBB tasks (a few thousand single rays a frame, which
/// took 9 ms on one thread at Sponza_lit's 640 x 480), into a slot of their own, and gathered in
/// the points' order.

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "igi/backends/packet.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/lighting/vpl_sampler.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"
#include "igi/simd/float_mode.hpp"
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
/// Angles (radians) by which rays beside an escape ray turn from it to find the frame of its
/// opening, tried in turn until two meet a surface: 0.1 finds the frame of a window an escape
/// ray passes near its edge, 0.5 (29 degrees) that of a 2 m window from 2 m away through its
/// middle; an escape ray with open sky even that far around it starts in the open.
inline constexpr std::array<float, 3> portal_frame_angles = {0.1f, 0.25f, 0.5f};
/// An emitter's opening counts where its frame lies within this share of the way from the view's
/// point to the emitter: a window passed on the way to a panel outside, not the ceiling around a
/// luminaire (whose frame is where the emitter is, up to a few of the turned rays' offsets).
inline constexpr float emitter_frame_share = 0.8f;
/// Fewest of the view's rays that must reach an emitter for it to be aimed: 4, so that "at least
/// half of them through openings" means something, while the window room's panel, reached by
/// 140-160 rays a frame, is far above it.
inline constexpr std::size_t emitter_least_rays = 4;

/// Most of the view's points' rays towards the sky that may leave the scene for the view to
/// count as enclosed, its light coming in through openings (Portals::view_openings, whose
/// bounces outside are aimed back in): 1.9-4.2% leave in the window, blinds and two-window rooms
/// and 2.2% in Sponza's atrium, 35% under the forest's canopy, where the ground around the view
/// is lit where it is and aiming its bounces at the gaps between trunks made the walk's frames
/// worse (median relMSE +10%, worst frames 2.5x). A tenth lies well between.
inline constexpr float enclosed_sky_share = 0.1f;

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

/// `work(i)` for i in [0, count) as oneTBB tasks, each result in slot i of the returned vector:
/// the same results, in the same order, on any number of threads (each task flushes denormals,
/// as the frame's tracing threads do).
template <class Work>
auto in_parallel(std::size_t count, Work&& work) {
  std::vector<decltype(work(std::size_t(0)))> results(count);
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count), [&](const tbb::blocked_range<std::size_t>& range) {
    const FlushDenormals flush;
    for (std::size_t i = range.begin(); i != range.end(); ++i) results[i] = work(i);
  });
  return results;
}

/// Each point's spread: twice the distance to the nearest other point, so the aimed lines of
/// neighbouring points overlap and cover the region between them (once the distance: 3-10x the
/// variance of a window room's sky light, measured; 3 or 5 times: alike), near ones finely, far
/// ones coarsely; at least 10 ray offsets where points coincide, and `alone` for a single point.
inline void set_spreads(std::vector<AimPoint>& points, float offset, float alone) {
  const std::vector<float> spreads = in_parallel(points.size(), [&](std::size_t i) {
    float nearest2 = std::numeric_limits<float>::infinity();
    for (std::size_t j = 0; j < points.size(); ++j) {
      if (j == i) continue;
      const glm::vec3 d = points[j].point - points[i].point;
      nearest2 = std::min(nearest2, glm::dot(d, d));
    }
    return std::isfinite(nearest2) ? std::max(2.0f * std::sqrt(nearest2), 10.0f * offset) : alone;
  });
  for (std::size_t i = 0; i < points.size(); ++i) points[i].spread = spreads[i];
}

/// Whether instance `instance` of `scene` emits light.
inline bool emits(const Scene& scene, std::size_t instance) {
  const int mesh = scene.instances[instance].mesh;
  return mesh >= 0 && std::size_t(mesh) < scene.meshes.size() && scene.material_of(mesh).emissive();
}

/// Where the escape ray from `start` along unit `to_sky` passes its opening: rays turned from it
/// four ways around by each of portal_frame_angles in turn, until at least two of them meet a
/// surface (a frame surrounds an opening; furniture beside the ray is on one side), and of
/// those the farthest along the escape ray (the frame lies beyond what the ray passed on its
/// way). Measured in the two-window room, 9 in 10 of the points so found lie within 0.5 m of a
/// window (with the nearest hit of the first angle that meets any surface, 8 in 10). None where
/// no angle does (open sky all around).
template <class Tracer, class Shader>
  requires SurfaceShader<Shader, 1>
std::optional<glm::vec3> opening_point(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer,
                                       const Shader& shader, const glm::vec3& start, const glm::vec3& to_sky, float offset) {
  glm::vec3 side1, side2;
  orthonormal_basis(to_sky, side1, side2);
  for (const float angle : portal_frame_angles) {
    int hits = 0;
    float farthest = 0.0f;
    for (const glm::vec3& side : {side1, -side1, side2, -side2}) {
      const glm::vec3 direction = to_sky * std::cos(angle) + side * std::sin(angle);
      const std::optional<OpaqueHit> hit = first_opaque_hit(scene, geometry, tracer, shader, start, direction, 0.0f, offset, true);
      // An emitter beyond the opening (a sky panel) is not its frame.
      if (!hit || emits(scene, std::size_t(hit->surface.instance[0]))) continue;
      ++hits;
      farthest = std::max(farthest, glm::dot(hit->surface.position[0] - start, to_sky));
    }
    if (hits >= 2) return start + to_sky * farthest;
  }
  return std::nullopt;
}

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
  // Only where light comes from far away: a scene lit by its emitters alone (a lamp in a room, the
  // Cornell box) would pay a few thousand rays a frame (a fifth of a 320 x 240 Cornell frame) to
  // find that they light the view from where they are.
  const VplView* view = settings.portal_view ? settings.portal_view : settings.view;
  if (!view || !(share > 0.0f) || (!sky && !directional)) return portals;

  // The emissive triangles, drawn by power: rays from the view's points towards them find the
  // openings an emitter outside shines in by (a sky panel seen through a window fills too little
  // of a point's sky for its rays about the normal to find it often: 1-5 openings a frame in the
  // window room, against 140-160 with these rays).
  struct EmissiveTriangle {
    glm::vec3 corner, edge1, edge2;
    std::size_t instance;
  };
  std::vector<EmissiveTriangle> emitters;
  std::vector<float> emitter_cdf;
  float emitter_power = 0.0f;
  for (std::size_t instance = 0; instance < scene.instances.size(); ++instance) {
    if (!portal_detail::emits(scene, instance)) continue;
    const Instance& placed = scene.instances[instance];
    const Mesh& mesh = scene.meshes[std::size_t(placed.mesh)];
    const float radiance = light_detail::largest_component(scene.material_of(placed.mesh).emission);
    for (const glm::uvec3& t : mesh.triangles) {
      if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size()) continue;
      const auto world = [&](unsigned i) { return glm::vec3(placed.transform * glm::vec4(mesh.positions[i], 1.0f)); };
      const glm::vec3 corner = world(t.x), edge1 = world(t.y) - corner, edge2 = world(t.z) - corner;
      const float power = 0.5f * glm::length(glm::cross(edge1, edge2)) * radiance;
      if (!(power > 0.0f) || !std::isfinite(power)) continue;
      emitters.push_back({corner, edge1, edge2, instance});
      emitter_power += power;
      emitter_cdf.push_back(emitter_power);
    }
  }

  const PinholeProjection& projection = view->projection;
  // An arbitrary salt that separates the portals' numbers from the walks' and the view points'.
  constexpr std::uint32_t portal_salt = 0x706f7274u;
  const float offset = ray_offset(settings.scene_bounds);
  // The view points: the first opaque hit of each cell's camera ray, its normal turned towards
  // the camera (the side light reaches it from), and the cell's key for its sky rays.
  struct Seen {
    glm::vec3 point, normal;
    std::uint32_t cell;
  };
  std::vector<std::pair<std::uint32_t, glm::vec3>> view_rays;
  for_each_view_ray(projection, portal_view_samples, hash(hash(settings.seed, settings.frame), portal_salt),
                    [&](std::uint32_t cell, const glm::vec3& direction) { view_rays.emplace_back(cell, direction); });
  std::vector<Seen> seen;
  for (const std::optional<Seen>& point : portal_detail::in_parallel(view_rays.size(), [&](std::size_t i) -> std::optional<Seen> {
         const auto& [cell, direction] = view_rays[i];
         const std::optional<OpaqueHit> hit =
             first_opaque_hit(scene, geometry, tracer, shader, projection.origin(), direction, 0.0f, offset);
         if (!hit) return std::nullopt;
         glm::vec3 normal = hit->surface.geometric_normal[0];
         if (glm::dot(normal, direction) > 0.0f) normal = -normal;
         return Seen{hit->surface.position[0], normal, cell};
       }))
    if (point) seen.push_back(*point);
  // Where light from far away reaches `points` (the view's, or those they see): each point's
  // rays towards the directional lights and `sky_rays` towards the sky that leave the scene (by
  // the environment's own distribution; without one, about the point's normal, which finds the
  // openings a directional light's particles are also aimed through).
  struct Escape {
    AimPoint aim;         // The point the ray starts from, with its spread.
    glm::vec3 start;      // The ray's origin: the point lifted off its surface.
    glm::vec3 direction;  // Towards the sky.
    float reach = 0.0f;   // Distance to the emitter it met (rays that reach one instead of the sky).
    bool from_view = false;  // Whether it starts at one of the view's points (not one they see).
  };
  std::vector<Escape> escapes;
  // The same rays where they met an emitter instead (a sky panel, an emissive dome), by instance.
  std::vector<std::vector<Escape>> emitter_escapes(scene.instances.size());
  const float alone = glm::length(settings.scene_bounds.extent());
  // What one point's rays found: the directional lights that reach it, its rays that left the
  // scene, and those that met an emitter first (with the emitter's instance).
  struct PointFindings {
    std::vector<std::size_t> sunlit;
    std::vector<Escape> escapes;
    std::vector<std::pair<std::size_t, Escape>> emitters;
  };
  const auto add_openings = [&](const std::vector<Seen>& points, int sky_rays, bool from_view) {
    std::vector<AimPoint> aims(points.size());
    for (std::size_t i = 0; i < points.size(); ++i) aims[i].point = points[i].point;
    portal_detail::set_spreads(aims, offset, alone);
    const std::vector<PointFindings> found = portal_detail::in_parallel(points.size(), [&](std::size_t i) {
      PointFindings findings;
      // Records a ray from `start` that met an emitter first.
      const auto reach_emitter = [&](const AimPoint& aim, const glm::vec3& start, const glm::vec3& direction, const OpaqueHit& hit) {
        const auto instance = std::size_t(hit.surface.instance[0]);
        if (instance < scene.instances.size() && portal_detail::emits(scene, instance))
          findings.emitters.emplace_back(instance, Escape{aim, start, direction, glm::length(hit.surface.position[0] - start)});
      };
      const glm::vec3 start_point = points[i].point + points[i].normal * offset;
      for (std::size_t l = 0; l < scene.lights.size(); ++l) {
        const PunctualLight& light = scene.lights[l];
        if (light.kind != PunctualKind::directional) continue;
        const float length = glm::length(light.direction);
        if (!(length > 0.0f) || !std::isfinite(length)) continue;
        const glm::vec3 to_light = -light.direction / length;
        if (glm::dot(to_light, points[i].normal) > 0.0f &&
            !first_opaque_hit(scene, geometry, tracer, shader, start_point, to_light, 0.0f, offset, true))
          findings.sunlit.push_back(l);
      }
      for (int k = 0; k < sky_rays; ++k) {
        const std::uint32_t cell = points[i].cell;
        const float u1 = to_unit_float(hash(cell, std::uint32_t(2 + 2 * k)));
        const float u2 = to_unit_float(hash(cell, std::uint32_t(3 + 2 * k)));
        glm::vec3 direction = sample_cosine_hemisphere(points[i].normal, u1, u2);
        if (sky) {
          const EnvironmentSample s = scene.environment->sample(u1, u2);
          if (!(s.pdf > 0.0f) || !(glm::dot(s.direction, points[i].normal) > 0.0f)) continue;
          direction = s.direction;
        }
        const std::optional<OpaqueHit> hit =
            first_opaque_hit(scene, geometry, tracer, shader, start_point, direction, 0.0f, offset, true);
        if (!hit)
          findings.escapes.push_back({aims[i], start_point, direction, 0.0f, from_view});
        else
          reach_emitter(aims[i], start_point, direction, *hit);
        if (emitters.empty()) continue;
        // A ray towards a point of an emitter drawn by power.
        const float pick = to_unit_float(hash(cell, std::uint32_t(0x200 + 3 * k))) * emitter_power;
        const auto chosen = std::size_t(std::upper_bound(emitter_cdf.begin(), emitter_cdf.end(), pick) - emitter_cdf.begin());
        const EmissiveTriangle& triangle = emitters[std::min(chosen, emitters.size() - 1)];
        const glm::vec3 towards =
            light_detail::triangle_point(triangle.corner, triangle.edge1, triangle.edge2,
                                         to_unit_float(hash(cell, std::uint32_t(0x201 + 3 * k))),
                                         to_unit_float(hash(cell, std::uint32_t(0x202 + 3 * k)))) -
            start_point;
        const float length = glm::length(towards);
        if (!(length > 0.0f) || !(glm::dot(towards, points[i].normal) > 0.0f)) continue;
        if (const std::optional<OpaqueHit> met =
                first_opaque_hit(scene, geometry, tracer, shader, start_point, towards / length, 0.0f, offset, true))
          reach_emitter(aims[i], start_point, towards / length, *met);
      }
      return findings;
    });
    for (std::size_t i = 0; i < points.size(); ++i) {
      for (const std::size_t light : found[i].sunlit) portals.sunlit[light].push_back(aims[i]);
      escapes.insert(escapes.end(), found[i].escapes.begin(), found[i].escapes.end());
      for (const auto& [instance, escape] : found[i].emitters) emitter_escapes[instance].push_back(escape);
    }
  };
  add_openings(seen, portal_sky_rays, true);
  // Whether the view is enclosed, its light coming in through openings: its points' rays
  // towards the sky leave the scene rarely (enclosed_sky_share).
  const bool enclosed = double(escapes.size()) <= double(enclosed_sky_share) * double(seen.size() * portal_sky_rays);
  // One bounce further: the surfaces the view's points see (through a window, the ground and the
  // walls outside), whose sunlit and sky-lit parts send their reflected light back into the
  // view's room. Measured in the sunlit window room, that light is a third of the room's
  // indirect light, and without these targets only the unaimed share of the walks carries it.
  std::vector<Seen> beyond;
  for (const std::optional<Seen>& point :
       portal_detail::in_parallel(seen.size() * portal_bounce_rays, [&](std::size_t ray) -> std::optional<Seen> {
         const Seen& view_point = seen[ray / portal_bounce_rays];
         const std::uint32_t ray_key = hash(view_point.cell, std::uint32_t(0x100 + ray % portal_bounce_rays));
         const glm::vec3 direction =
             sample_cosine_hemisphere(view_point.normal, to_unit_float(hash(ray_key, 0u)), to_unit_float(hash(ray_key, 1u)));
         const std::optional<OpaqueHit> hit = first_opaque_hit(scene, geometry, tracer, shader,
                                                               view_point.point + view_point.normal * offset, direction, 0.0f, offset, true);
         if (!hit) return std::nullopt;
         glm::vec3 normal = hit->surface.geometric_normal[0];
         if (glm::dot(normal, direction) > 0.0f) normal = -normal;
         return Seen{hit->surface.position[0], normal, ray_key};
       }))
    if (point) beyond.push_back(*point);
  add_openings(beyond, portal_beyond_sky_rays, false);
  portals.share = share;
  for (auto& points : portals.sunlit) points = portal_detail::thinned(points, portal_most_rays);
  // The escape rays, and where each passes its opening: the sky's light enters a room through
  // the whole opening from every direction it admits, so particles aimed at the points of the
  // opening with the sky's own directions pass it far more often than those aimed at the view's
  // points, which reach most of them only through walls and ceilings (measured in the window,
  // blinds and two-window rooms: 3-4x more enter, and the room's sky light per particle has a
  // tenth of the variance).
  const std::vector<Escape> kept_escapes = portal_detail::thinned(escapes, portal_most_rays);
  const std::vector<std::optional<glm::vec3>> kept_openings = portal_detail::in_parallel(kept_escapes.size(), [&](std::size_t i) {
    return portal_detail::opening_point(scene, geometry, tracer, shader, kept_escapes[i].start, kept_escapes[i].direction, offset);
  });
  std::vector<std::size_t> view_framed;  // which of the framed openings the view's own points found, if enclosed
  for (std::size_t i = 0; i < kept_escapes.size(); ++i) {
    const Escape& escape = kept_escapes[i];
    if (sky) {
      portals.sky_points.push_back(escape.aim);
      portals.sky_directions.push_back(escape.direction);
    }
    const std::optional<glm::vec3>& opening = kept_openings[i];
    portals.openings.push_back({.point = opening.value_or(escape.start)});
    if (opening) {
      if (escape.from_view && enclosed) {
        view_framed.push_back(portals.framed_openings.size());
        portals.view_opening_directions.push_back(escape.direction);
      }
      portals.framed_openings.push_back({.point = *opening});
    }
  }
  portal_detail::set_spreads(portals.openings, offset, alone);
  portal_detail::set_spreads(portals.framed_openings, offset, alone);
  for (const std::size_t i : view_framed) portals.view_openings.push_back(portals.framed_openings[i]);
  // An emitter's openings: framed well before the emitter (a window 3 m away, the panel 9 m: a
  // luminaire on a ceiling has its frame, the ceiling, where it is). Only an emitter the view's
  // points see mostly through openings is aimed: one they see in the open (a luminaire in the
  // room, seen past a gap between two boxes now and then) lights them from where it is.
  // Each opening costs up to 12 rays, so the rays looked at are portal_most_rays in all, shared
  // by the emitters in proportion to how often the view's rays reached them (most first); an
  // emitter reached fewer than emitter_least_rays times lights too little of the view to aim.
  portals.emitter_openings.resize(scene.instances.size());
  std::size_t reached_in_all = 0;
  std::vector<std::size_t> by_reach;
  for (std::size_t instance = 0; instance < scene.instances.size(); ++instance) {
    reached_in_all += emitter_escapes[instance].size();
    if (emitter_escapes[instance].size() >= emitter_least_rays) by_reach.push_back(instance);
  }
  std::stable_sort(by_reach.begin(), by_reach.end(), [&](std::size_t a, std::size_t b) {
    return emitter_escapes[a].size() > emitter_escapes[b].size();
  });
  std::size_t budget = portal_most_rays;
  for (const std::size_t instance : by_reach) {
    if (budget < emitter_least_rays) break;
    const std::size_t share_of_rays = portal_most_rays * emitter_escapes[instance].size() / std::max<std::size_t>(reached_in_all, 1);
    const std::size_t kept = std::min({emitter_escapes[instance].size(), std::max(emitter_least_rays, share_of_rays), budget});
    budget -= kept;
    const std::vector<Escape> reached = portal_detail::thinned(emitter_escapes[instance], kept);
    std::vector<AimPoint>& openings = portals.emitter_openings[instance];
    const std::vector<std::optional<glm::vec3>> found = portal_detail::in_parallel(reached.size(), [&](std::size_t i) {
      return portal_detail::opening_point(scene, geometry, tracer, shader, reached[i].start, reached[i].direction, offset);
    });
    for (std::size_t i = 0; i < reached.size(); ++i)
      if (found[i] && glm::length(*found[i] - reached[i].start) < emitter_frame_share * reached[i].reach)
        openings.push_back({.point = *found[i]});
    if (2 * openings.size() < reached.size()) openings.clear();
    portal_detail::set_spreads(openings, offset, alone);
  }
  return portals;
}

}  // namespace igi
