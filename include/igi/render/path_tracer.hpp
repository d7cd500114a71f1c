#pragma once
/// \file
/// The reference path tracer: unbiased ground truth over the same scene, backend, surface shader
/// and BRDF shader as the IGI pipeline.
///
/// Per sample: a camera ray (jittered inside the pixel: a box pixel filter; or through the pixel
/// centre, as the IGI pipeline without anti-aliasing), then at each hit
/// - emission, weighted by the power heuristic against light sampling when a non-delta BRDF
///   sample found it (full weight for camera rays and after mirror / glass bounces); a ray that
///   leaves the scene brings the environment's radiance, weighted the same way;
/// - next-event estimation: one light chosen in proportion to power (LightSampler), a point on
///   area lights with MIS (power heuristic), punctual lights without (delta lights);
/// - the next direction: one of {diffuse + glossy, mirror / glass reflection, glass refraction},
///   chosen in proportion to the largest component of each part's weight; diffuse and glossy
///   sampled by DiffuseGlossySampling, the delta parts taken from the BRDF shader's `spawn`;
/// - Russian roulette from `russian_roulette_depth` bounces on, survival probability
///   min(0.95, largest throughput component).
/// Alpha-mask cut-outs are passed through by camera, bounce and shadow rays alike.
///
/// Determinism: sample s of pixel (x, y) draws its random numbers from Rng(hash(seed, x, y, s))
/// only, and pixel sums run over s in order, so neither the thread count nor splitting a render
/// into progressive passes changes a single bit of the image.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>
#include <oneapi/tbb/task_arena.h>

#include "igi/backends/backend.hpp"
#include "igi/io/image_types.hpp"
#include "igi/lighting/light_sampling.hpp"
#include "igi/render/pipeline.hpp"
#include "igi/render/pixel_layers.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/brdf_sampling.hpp"
#include "igi/shading/brdf_shader.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/cutout_occlusion.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {

/// Settings of the reference path tracer.
struct PathTracerSettings {
  std::uint32_t seed = 0;          ///< Selects the random numbers; the image is a pure function of it.
  int threads = 0;                 ///< Worker threads; 0 means all cores.
  int russian_roulette_depth = 3;  ///< Bounces traced unconditionally before Russian roulette starts.
  int max_depth = 1024;            ///< Safety cap on bounces; with survival <= 0.95 it cuts at most 0.95^1000 ~ 5e-23 of the light.
  bool jitter = true;              ///< Sample the whole pixel (box filter); false: the pixel centre only (or PathTracer::set_pixel_position's point), as IGI with aa 1.
  /// Without jitter: camera rays read textures over a one-pixel footprint, as IGI's do
  /// (RenderSettings::filter_textures), so that a reference through the pixel centres differs
  /// from IGI's frame by the light alone. Jittered samples integrate the pixel's area themselves.
  bool filter_textures = false;
  int tile_size = 16;              ///< Tile edge of the parallel loop (work unit only; no effect on the image).
};

/// Throws SettingsError naming the first path-tracer setting out of range.
inline void validate(const PathTracerSettings& s) {
  if (s.threads < 0 || s.threads > 1024) throw SettingsError("threads " + std::to_string(s.threads) + " is outside 0..1024");
  if (s.russian_roulette_depth < 0 || s.russian_roulette_depth > 1024)
    throw SettingsError("russian roulette depth " + std::to_string(s.russian_roulette_depth) + " is outside 0..1024");
  if (s.max_depth < 1 || s.max_depth > 100000) throw SettingsError("max depth " + std::to_string(s.max_depth) + " is outside 1..100000");
  if (s.tile_size < 1 || s.tile_size > 1024) throw SettingsError("tile size " + std::to_string(s.tile_size) + " is outside 1..1024");
}

/// Power heuristic (beta = 2) weight of a strategy of density `own` against one of density `other`.
inline float power_heuristic(float own, float other) noexcept {
  const float a = own * own, b = other * other;
  return a + b > 0.0f ? a / (a + b) : 0.0f;
}

/// Work of the path tracer so far, by ray kind.
struct PathTracerStatistics {
  RayCounts rays;                 ///< primary: camera rays; shadow: light-sample visibility; secondary: bounces.
  std::uint64_t paths = 0;        ///< Samples traced.
  std::uint64_t invalid_samples = 0;  ///< Samples whose radiance was NaN or infinite (counted, then dropped as 0; should stay 0).
};

/// Progressive, multithreaded, unbiased reference path tracer over Backend B, surface shader Surface and BRDF shader Brdf.
// Any backend width works: single rays go through the backend's width-1 calls. Scene, backend
// and policies are borrowed and must outlive the tracer.
template <class B, class Surface, class Brdf>
  requires Backend<B> && SurfaceShader<Surface, 1> && BrdfShader<Brdf, 1>
class PathTracer {
 public:
  /// A path tracer over `scene` traced by `backend` (built from that scene).
  // Throws std::invalid_argument for a scene without geometry or with broken lights, SettingsError for bad settings.
  PathTracer(const Scene& scene, const B& backend, const Surface& surface, const Brdf& brdf,
             const PathTracerSettings& settings = {})
      : scene_(&scene),
        backend_(&backend),
        surface_(&surface),
        brdf_(&brdf),
        settings_((validate(settings), settings)),
        lights_(scene),
        geometry_(scene),
        arena_(settings.threads > 0 ? settings.threads : tbb::task_arena::automatic) {
    if (scene.instances.empty() || scene.triangle_count() == 0)
      throw std::invalid_argument("PathTracer: scene '" + scene.name + "' has no geometry");
    ray_epsilon_ = ray_offset(scene.bounds());
    if (!std::isfinite(ray_epsilon_) || !(ray_epsilon_ > 0.0f))
      throw std::invalid_argument("PathTracer: scene '" + scene.name + "' has non-finite or empty bounds");
    has_cutouts_ = CutoutMeshes(scene).any();
    see_through_ = SeeThroughMeshes(scene);
    if (see_through_.any()) cutouts_ = CutoutMeshes(scene);
  }

  /// Starts a new image of `camera` at width x height (zero samples). Throws SettingsError on a bad size.
  void reset(const Camera& camera, int width, int height) {
    if (width < 1 || height < 1 || width > max_image_edge || height > max_image_edge)
      throw SettingsError("size " + std::to_string(width) + "x" + std::to_string(height) + " is outside 1.." +
                          std::to_string(max_image_edge) + " per side");
    projection_.emplace(camera, width, height);
    sums_.assign(std::size_t(width) * std::size_t(height), glm::dvec3(0.0));
    samples_ = 0;
    statistics_ = {};
  }

  // Defined after the class, so not inline: a program that declares the path tracer's
  // instantiation extern does not compile its paths again (as Renderer::render).
  /// Adds `spp` samples per pixel to the current image (after reset); SettingsError if spp < 0 or nothing was reset.
  void add_samples(int spp);

  /// The running mean of all samples so far (black before the first sample).
  Image image() const {
    if (!projection_) throw SettingsError("PathTracer::image before reset(camera, width, height)");
    Image result(projection_->width(), projection_->height());
    const double scale = samples_ > 0 ? 1.0 / double(samples_) : 0.0;
    for (std::size_t i = 0; i < sums_.size(); ++i) result.pixels[i] = glm::vec3(sums_[i] * scale);
    return result;
  }

  /// The G-buffer of the current image (after reset; SettingsError before): for each pixel, row by
  /// row from the top, the first opaque hit of the camera ray through its centre (or where
  /// set_pixel_position put the rays), as the IGI pipeline's PixelLayers give it with one camera
  /// ray per pixel: albedo, shading normal, distance and hit (all zero on a miss), and in `rest`
  /// the hit's emission (what the camera sees of it directly, which a denoiser keeps out of the
  /// light it filters); the other radiance terms stay zero. What a denoiser or compositing reads.
  std::vector<PixelLayers> first_hits() {
    if (!projection_) throw SettingsError("PathTracer::first_hits before reset(camera, width, height)");
    const int width = projection_->width(), height = projection_->height();
    std::vector<PixelLayers> layers(std::size_t(width) * std::size_t(height));
    arena_.execute([&] {
      tbb::parallel_for(0, height, [&](int y) {
        for (int x = 0; x < width; ++x) {
          RayPacket<1> ray;
          ray.set(vec3<1>(projection_->origin()),
                  vec3<1>(projection_->direction(float(x) + pixel_position_.x, float(y) + pixel_position_.y)),
                  vfloat<1>(0.0f), vfloat<1>(std::numeric_limits<float>::infinity()), vmask<1>(true));
          std::uint64_t rays = 0;
          const Vertex v = trace(ray, rays, camera_cone_spread());
          if (!v.found) continue;
          PixelLayers& pixel = layers[std::size_t(y) * std::size_t(width) + std::size_t(x)];
          pixel.albedo = v.parameters.albedo[0];
          pixel.normal = v.parameters.normal[0];
          pixel.depth = v.hit.distance[0];
          pixel.hit = true;
          pixel.rest = v.parameters.emission[0];
        }
      });
    });
    return layers;
  }

  /// reset + add_samples(spp) + image: a width x height image of `camera` at `spp` samples per pixel.
  Image render(const Camera& camera, int width, int height, int spp) {
    reset(camera, width, height);
    add_samples(spp);
    return image();
  }

  /// Draws the samples added from now on from `seed` instead of PathTracerSettings::seed, so that
  /// each frame of a sequence has noise of its own (DenoisedPathTracer seeds it by frame index).
  void set_seed(std::uint32_t seed) noexcept { settings_.seed = seed; }
  /// Where in its pixel (0..1 on each axis) the camera ray of every sample added from now on
  /// passes without jitter, and first_hits' ray: the centre (0.5, 0.5) unless set. A still view's
  /// frames move it to cover the pixel (TemporalReuse::pixel_jitter).
  void set_pixel_position(glm::vec2 position) noexcept { pixel_position_ = position; }

  /// Samples per pixel so far.
  int samples() const noexcept { return samples_; }
  /// Rays and paths traced since the last reset.
  const PathTracerStatistics& statistics() const noexcept { return statistics_; }
  /// The settings.
  const PathTracerSettings& settings() const noexcept { return settings_; }

 private:
  /// Radiance of sample `s` of pixel (x, y) (a pure function of seed, x, y, s); counts its rays into `counts`.
  glm::vec3 sample(int x, int y, int s, PathTracerStatistics& counts) const {
    Rng rng(hash(hash(hash(settings_.seed, std::uint32_t(x)), std::uint32_t(y)), std::uint32_t(s)));
    float dx = pixel_position_.x, dy = pixel_position_.y;
    if (settings_.jitter) {
      dx = rng.next();
      dy = rng.next();
    }
    ++counts.paths;
    const glm::vec3 radiance = trace_path(projection_->origin(), projection_->direction(float(x) + dx, float(y) + dy), rng, counts);
    if (!std::isfinite(radiance.x) || !std::isfinite(radiance.y) || !std::isfinite(radiance.z)) {
      ++counts.invalid_samples;
      return glm::vec3(0.0f);
    }
    return radiance;
  }

  /// A shaded hit of one ray.
  struct Vertex {
    SurfaceHit<1> hit;
    BrdfParameters<1> parameters;
    bool found = false;
  };

  /// Largest component.
  static float largest(const glm::vec3& v) noexcept { return std::max(v.x, std::max(v.y, v.z)); }

  /// How much a camera ray's texture footprint widens per unit of distance (0: none, point lookups).
  float camera_cone_spread() const noexcept {
    return settings_.filter_textures && !settings_.jitter ? projection_->pixel_spread() : 0.0f;
  }

  /// Traces `ray` to its first opaque hit (passing alpha cut-outs) and shades it, reading
  /// textures over a cone that widens by `cone_spread` per unit of distance.
  Vertex trace(RayPacket<1>& ray, std::uint64_t& count, float cone_spread = 0.0f) const {
    Vertex v;
    const vmask<1> one(true);
    for (int layer = 0; layer < max_cutout_layers; ++layer) {
      HitPacket<1> hits;
      hits.clear();
      backend_->intersect(ray, hits, one);
      ++count;
      if (hits.geomID[0] == invalid_id) return v;
      v.hit = make_surface_hit(*scene_, geometry_, ray, hits, one, cone_spread);
      v.parameters = surface_->shade(v.hit, one);
      if (v.parameters.opaque[0]) {
        v.found = true;
        return v;
      }
      ray.tnear[0] = ray.tfar[0] + ray_epsilon_;
      ray.tfar[0] = std::numeric_limits<float>::infinity();
    }
    return v;  // gave up: treated as a miss, as the pipeline does
  }

  /// True if nothing opaque lies on the segment from `origin` along unit `direction` up to `distance`.
  bool visible(const glm::vec3& origin, const glm::vec3& direction, float distance, std::uint64_t& count) const {
    RayPacket<1> ray;
    ray.set(vec3<1>(origin), vec3<1>(direction), vfloat<1>(0.0f), vfloat<1>(distance), vmask<1>(true));
    const vmask<1> one(true);
    if (!has_cutouts_) {
      ++count;
      return !backend_->occluded(ray, one)[0];
    }
    for (int layer = 0; layer < max_cutout_layers; ++layer) {
      HitPacket<1> hits;
      hits.clear();
      backend_->intersect(ray, hits, one);
      ++count;
      if (hits.geomID[0] == invalid_id) return true;
      const Material& material = scene_->material_of(int(hits.geomID[0]));
      if (material.alpha_mode != AlphaMode::mask) return false;
      const SurfaceHit<1> hit = make_surface_hit(*scene_, geometry_, ray, hits, one);
      if (surface_->shade(hit, one).opaque[0]) return false;
      ray.tnear[0] = ray.tfar[0] + ray_epsilon_;
      ray.tfar[0] = distance;
    }
    return false;
  }

  /// Per colour, the light that gets from `origin` along unit `direction` up to `distance`: 0 or
  /// 1 as visible() says, and in a scene with see-through surfaces (thin-walled glass, alpha
  /// blending) dimmed by each one crossed (shadow_transmittance; counted as one shadow ray).
  glm::vec3 transmittance(const glm::vec3& origin, const glm::vec3& direction, float distance, std::uint64_t& count) const {
    if (!see_through_.any()) return glm::vec3(visible(origin, direction, distance, count) ? 1.0f : 0.0f);
    RayPacket<1> ray;
    const vmask<1> one(true);
    ray.set(vec3<1>(origin), vec3<1>(direction), vfloat<1>(0.0f), vfloat<1>(distance), one);
    ++count;
    return shadow_transmittance(*backend_, *surface_, *scene_, geometry_, cutouts_, see_through_, ray_epsilon_, ray,
                                Coherence::incoherent, one)[0];
  }

  /// Radiance arriving at `origin` from `direction`.
  glm::vec3 trace_path(const glm::vec3& origin, const glm::vec3& direction, Rng& rng, PathTracerStatistics& counts) const {
    glm::vec3 radiance(0.0f), throughput(1.0f);
    RayPacket<1> ray;
    ray.set(vec3<1>(origin), vec3<1>(direction), vfloat<1>(0.0f), vfloat<1>(std::numeric_limits<float>::infinity()),
            vmask<1>(true));
    bool delta_bounce = true;     // camera rays and specular bounces see emission with full weight
    float previous_pdf = 0.0f;    // density of the non-delta BRDF sample that made this ray
    glm::vec3 previous_position(0.0f);
    const vmask<1> one(true);
    for (int depth = 0;; ++depth) {
      const Vertex v = depth == 0 ? trace(ray, counts.rays.primary, camera_cone_spread()) : trace(ray, counts.rays.secondary);
      if (!v.found) {
        // Left the scene: the environment's light, weighted against light sampling's density
        // after a non-delta bounce (as emission found by BRDF sampling is).
        if (lights_.has_environment()) {
          const glm::vec3 wi = glm::normalize(glm::vec3(ray.dir_x[0], ray.dir_y[0], ray.dir_z[0]));
          const float weight = delta_bounce ? 1.0f : power_heuristic(previous_pdf, lights_.environment_pdf(wi));
          radiance += throughput * lights_.environment_radiance(wi) * weight;
        }
        break;
      }
      const SurfaceHit<1>& hit = v.hit;
      const BrdfParameters<1>& parameters = v.parameters;
      const glm::vec3 position = hit.position[0];

      const glm::vec3 emission = parameters.emission[0];
      if (largest(emission) > 0.0f) {
        float weight = 1.0f;
        if (!delta_bounce) {
          const float light_pdf =
              lights_.pdf(std::size_t(hit.instance[0]), std::size_t(hit.triangle[0]), previous_position, position);
          weight = power_heuristic(previous_pdf, light_pdf);
        }
        radiance += throughput * emission * weight;
      }
      if (depth >= settings_.max_depth) break;

      // Lobe choice: non-delta (diffuse + glossy) against the delta rays of the BRDF shader.
      const DiffuseGlossySampling lobes(hit, parameters);
      SecondaryRays<1> reflection, refraction;
      brdf_->spawn(hit, parameters, reflection, refraction, one);
      const float smooth = lobes.weight();
      const float reflect = reflection.active[0] ? largest(reflection.weight[0]) : 0.0f;
      const float refract = refraction.active[0] ? largest(refraction.weight[0]) : 0.0f;
      const float total = smooth + reflect + refract;
      if (!(total > 0.0f)) break;

      // Next-event estimation at non-delta vertices.
      if (smooth > 0.0f && !lights_.empty()) {
        const float u_choice = rng.next(), u1 = rng.next(), u2 = rng.next();
        const LightSample light = lights_.sample(position, u_choice, u1, u2);
        if (light.usable()) {
          const glm::vec3 f = brdf_->evaluate(hit, parameters, vec3<1>(light.wi), one)[0];
          if (largest(f) > 0.0f) {
            const glm::vec3 shadow_origin = position + hit.geometric_normal[0] * ray_epsilon_;
            // Stop short of the light by two offsets so the emitter's own surface does not block it.
            const float length = std::isfinite(light.distance) ? std::max(light.distance - 2.0f * ray_epsilon_, 0.0f)
                                                               : std::numeric_limits<float>::infinity();
            const glm::vec3 passed = transmittance(shadow_origin, light.wi, length, counts.rays.shadow);
            if (largest(passed) > 0.0f) {
              const float weight =
                  light.delta ? 1.0f : power_heuristic(light.pdf, smooth / total * lobes.pdf(light.wi));
              radiance += throughput * f * light.incident * passed * (weight / light.pdf);
            }
          }
        }
      }

      // Next direction.
      const float u_lobe = rng.next() * total;
      if (u_lobe < smooth) {
        const float u_inner = rng.next(), u1 = rng.next(), u2 = rng.next();
        const glm::vec3 wi = lobes.sample(u_inner, u1, u2);
        const float pdf = smooth / total * lobes.pdf(wi);
        const glm::vec3 f = brdf_->evaluate(hit, parameters, vec3<1>(wi), one)[0];
        if (!(pdf > 0.0f) || !(largest(f) > 0.0f)) break;
        throughput *= f / pdf;
        ray.set(vec3<1>(position + hit.geometric_normal[0] * ray_epsilon_), vec3<1>(wi), vfloat<1>(0.0f),
                vfloat<1>(std::numeric_limits<float>::infinity()), one);
        delta_bounce = false;
        previous_pdf = pdf;
      } else {
        const SecondaryRays<1>& chosen = u_lobe < smooth + reflect ? reflection : refraction;
        const float probability = (u_lobe < smooth + reflect ? reflect : refract) / total;
        throughput *= chosen.weight[0] / probability;
        ray.set(leave_surface(hit.position, hit.geometric_normal, chosen.direction, ray_epsilon_), chosen.direction, vfloat<1>(0.0f), vfloat<1>(std::numeric_limits<float>::infinity()), one);
        delta_bounce = true;
        previous_pdf = 0.0f;
      }
      previous_position = position;

      if (depth + 1 >= settings_.russian_roulette_depth) {
        // Survival at most 0.95 so that white, lossless scenes still end (expected 20 more bounces).
        const float survive = std::min(0.95f, largest(throughput));
        if (!(survive > 0.0f) || rng.next() >= survive) break;
        throughput /= survive;
      }
    }
    return radiance;
  }

  const Scene* scene_;
  const B* backend_;
  const Surface* surface_;
  const Brdf* brdf_;
  PathTracerSettings settings_;
  LightSampler lights_;
  SceneGeometry geometry_;
  tbb::task_arena arena_;
  float ray_epsilon_ = 1e-4f;
  bool has_cutouts_ = false;
  CutoutMeshes cutouts_;          ///< The alpha cut-out meshes, kept only where see-through ones are too (transmittance).
  SeeThroughMeshes see_through_;  ///< Thin-walled glass and alpha-blended meshes, which shadow rays pass attenuated.
  std::optional<PinholeProjection> projection_;
  glm::vec2 pixel_position_{0.5f};  ///< Where unjittered camera rays pass in their pixels (set_pixel_position).
  std::vector<glm::dvec3> sums_;
  int samples_ = 0;
  PathTracerStatistics statistics_;
};

template <class B, class Surface, class Brdf>
void PathTracer<B, Surface, Brdf>::add_samples(int spp) {
  if (spp < 0) throw SettingsError("spp " + std::to_string(spp) + " is negative");
  if (spp > std::numeric_limits<int>::max() - samples_)
    throw SettingsError("spp " + std::to_string(spp) + " would take the sample count past " +
                        std::to_string(std::numeric_limits<int>::max()));
  if (!projection_) throw SettingsError("PathTracer::add_samples before reset(camera, width, height)");
  const int width = projection_->width(), height = projection_->height(), tile = settings_.tile_size;
  const int tiles_x = (width + tile - 1) / tile, tiles_y = (height + tile - 1) / tile;
  const int first = samples_, last = samples_ + spp;
  std::mutex merge;
  arena_.execute([&] {
    tbb::parallel_for(tbb::blocked_range<int>(0, tiles_x * tiles_y, 1), [&](const tbb::blocked_range<int>& range) {
      PathTracerStatistics local;
      for (int t = range.begin(); t != range.end(); ++t) {
        const int x0 = (t % tiles_x) * tile, y0 = (t / tiles_x) * tile;
        for (int y = y0; y < std::min(y0 + tile, height); ++y)
          for (int x = x0; x < std::min(x0 + tile, width); ++x) {
            glm::dvec3& sum = sums_[std::size_t(y) * std::size_t(width) + std::size_t(x)];
            for (int s = first; s < last; ++s) sum += glm::dvec3(sample(x, y, s, local));
          }
      }
      std::lock_guard lock(merge);
      statistics_.rays.merge(local.rays);
      statistics_.paths += local.paths;
      statistics_.invalid_samples += local.invalid_samples;
    }, tbb::simple_partitioner());
  });
  samples_ = last;
}

}  // namespace igi
