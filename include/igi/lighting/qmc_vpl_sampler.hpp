#pragma once
/// \file
/// `QmcVplSampler`: the paper's VPLs, from random walks of light particles driven by a
/// randomized (scrambled) Halton sequence.
///
/// Every set starts with one exact VPL per delta light (point, spot, directional) at its full
/// intensity: such a light has a single VPL whatever the sample, so each set gets its direct
/// light exactly. The environment's direct light comes as VplSettings::environment_directions
/// directional VPLs that every set shares too (EnvironmentLight::directional_vpls, a frame's
/// own directions), outside the budget M; its particles walk like any light's. Then N walks start on the lights. N = max(1, round((M - D) / m)) with
/// M = vpls_per_set, D the number of delta lights, and m the mean number of VPLs one walk leaves
/// in this scene (walks from delta lights leave none on the light), measured by a
/// pilot of 256 walks on an independent scrambling of the sequence that depends on the seed but
/// not on the frame (so N is steady while the scene is, and independent of the frame's walks,
/// which keeps every set unbiased whatever N is). A set then holds about M VPLs: D exact ones,
/// those of walks on area lights, the rest where the walks bounced. Walk j of set s uses Halton index s N + j, so the
/// sets take consecutive, disjoint blocks of one sequence; the sequence is scrambled by
/// hash(seed, frame), so VPLs are a pure function of (scene, settings, frame, seed). Dimensions: 0 picks the light
/// (in proportion to power), 1-2 place the particle, 3-4 direct it, then three per bounce
/// (Russian roulette / lobe choice, two for the direction); past Halton's 32 dimensions a
/// counter-based hash of (scrambling seed, index, dimension) continues.
///
/// Normalisation: a particle from light l, chosen with probability p_l, carries flux
/// power_l / (p_l N). After the exact VPLs come the particles' origins on area lights (surface
/// VPLs of intensity flux / pi), so direct light comes out of the same sum. At each
/// diffuse hit the particle leaves a surface VPL of intensity flux x albedo / pi; it continues
/// with probability q_d = max(albedo) (diffusely, flux x albedo / q_d), or through the mirror /
/// glass lobes with probability max(weight) (flux x weight / that), or stops. A heavy particle
/// of a light outside the view's openings (one that landed on the ground far outside a window:
/// LightSet::heavy_flux) has a share of its first bounce's diffuse continuations aimed back in
/// through them, each weighed by the cosine lobe's density over the mixture's (BounceOpenings,
/// lights.hpp). Every weight is an unbiased estimate, so each set alone sums (in expectation) to the full light transport, and
/// any average of sets does too; that is what lets interleaving give each pixel one set. The
/// 1/d^2 clamp lives in connect(); nothing is clamped here. Walks end after `max_bounces`
/// scattering events (a bias: light reflected more often than that is missing, a fraction
/// rho^(max_bounces + 1) of the total for albedo rho). A glossy lobe as wide as a diffuse one
/// (exponent at most `wide_lobe_shininess`, e.g. glTF's metallic with roughness 1, Sponza's
/// curtains) reflects particles as a diffuse surface would: its VPL and its diffuse continuation
/// count albedo plus the lobe's reflectance towards the continuation's direction (the BRDF's
/// f x cos / pdf, an unbiased estimate of the lobe's directional albedo, at most 1). Sharper
/// glossy lobes do not scatter particles (their energy ends the walk: the light a polished
/// surface reflects onto others is missing), and an alpha cut-out lets the particle through
/// unchanged.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/packet.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/lighting/portals.hpp"
#include "igi/lighting/vpl_sampler.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/brdf_shader.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {

/// Where a VPL came from, parallel to VplSets::sets (for tests and statistics).
struct VplOrigin {
  int walk = 0;    ///< Walk index within the set; -1 for the exact VPL of a delta light.
  int bounce = 0;  ///< 0 on a light, k after k scattering events.
};

/// VPLs with their origins.
struct VplGeneration {
  VplSets vpls;                                ///< The VPL sets.
  std::vector<std::vector<VplOrigin>> origins; ///< origins[s][i] describes vpls.sets[s][i].
  int walks_per_set = 0;                       ///< N: walks (particles) per set.
  double vpls_per_walk = 0.0;                  ///< m: the pilot's mean VPLs per walk, which sized N.
};

/// Phong exponents up to which a glossy lobe scatters light particles as a diffuse surface does:
/// cos^2 falls to half 45 degrees off the mirror direction, a lobe as wide as the cosine lobe of
/// a diffuse surface (whose light also halves at 60 degrees), so a diffuse VPL shows it as well as
/// it can show anything; a sharper lobe's reflected light would be put where it does not go.
inline constexpr float wide_lobe_shininess = 2.0f;

/// QMC random-walk VPL sampler (instant radiosity with randomized Halton), the paper's default.
class QmcVplSampler {
 public:
  /// Policy name.
  static constexpr const char* name() noexcept { return "qmc"; }

  /// Adds a user-defined emitter, lit along with the scene's lights in every frame.
  void add_emitter(Emitter emitter) { user_emitters_.push_back(std::move(emitter)); }

  /// The frame's VPL sets; `shader` gives the albedo of hit surfaces, `brdf` their mirror and
  /// glass lobes (the frame's own policies, so bounce light has the colours the camera sees).
  template <class Tracer, class Shader, class Brdf>
    requires SurfaceShader<Shader, 1> && BrdfShader<Brdf, 1>
  VplSets generate(const Scene& scene, const Tracer& tracer, const Shader& shader, const Brdf& brdf,
                   const VplSettings& settings) const {
    return generate_with_origins(scene, tracer, shader, brdf, settings).vpls;
  }

  /// The frame's VPL sets and where each came from, as generate. Throws std::invalid_argument on bad settings.
  template <class Tracer, class Shader, class Brdf>
    requires SurfaceShader<Shader, 1> && BrdfShader<Brdf, 1>
  VplGeneration generate_with_origins(const Scene& scene, const Tracer& tracer, const Shader& shader, const Brdf& brdf,
                                      const VplSettings& frame_settings) const {
    check(frame_settings);
    VplSettings settings = frame_settings;  // with the scene's bounds, which lights at infinity and ray offsets need
    if (settings.scene_bounds.empty()) settings.scene_bounds = scene.bounds();
    const SceneGeometry geometry(scene);
    LightSet lights = frame_lights(scene, geometry, tracer, shader, settings);
    for (const Emitter& e : user_emitters_) lights.add(e);
    VplGeneration out;
    out.vpls.sets.resize(std::size_t(settings.sets));
    out.origins.resize(std::size_t(settings.sets));
    if (lights.empty()) return out;

    // Delta lights (point, spot, directional) have one VPL whatever the sample, so instead of a
    // random share of the walks they light every set exactly: their direct light, hard shadows
    // included, is then the same in all S^2 sets and neither flickers nor shows the pattern.
    std::vector<Vpl> exact = exact_vpls(lights);
    const std::size_t delta_lights = exact.size();
    const std::uint32_t scramble = hash(settings.seed, settings.frame);
    const std::vector<Vpl> sky = environment_vpls(scene, settings, scramble);
    exact.insert(exact.end(), sky.begin(), sky.end());
    out.vpls_per_walk = pilot(scene, geometry, tracer, shader, brdf, settings, lights);
    // The walks fill what the delta lights' exact VPLs leave of M (the environment's directions
    // have their own count, VplSettings::environment_directions); at least one walk carries the
    // indirect light, and at most 16 M walks are spent where particles rarely leave a VPL (mostly escaping).
    const double budget = std::max(1.0, double(settings.vpls_per_set) - double(delta_lights));
    const double walks = out.vpls_per_walk > 0.0 ? budget / out.vpls_per_walk : 1.0;
    out.walks_per_set = int(std::clamp(std::lround(walks), 1L, 16L * long(settings.vpls_per_set)));
    const Halton halton(scramble);
    const int n = out.walks_per_set;
    for (int s = 0; s < settings.sets; ++s) {
      std::vector<Vpl>& set = out.vpls.sets[std::size_t(s)];
      std::vector<VplOrigin>& origins = out.origins[std::size_t(s)];
      for (const Vpl& vpl : exact) {
        set.push_back(vpl);
        origins.push_back({-1, 0});
      }
      std::vector<Vpl> bounced;
      std::vector<VplOrigin> bounced_origins;
      for (int j = 0; j < n; ++j) {
        const std::uint64_t index = std::uint64_t(s) * std::uint64_t(n) + std::uint64_t(j);
        const auto u = [&](int dimension) { return sample(halton, scramble, dimension, index); };
        if (const std::optional<Vpl> on_light =
                start_walk(scene, geometry, tracer, shader, brdf, settings, lights, n, u, j, bounced, bounced_origins)) {
          set.push_back(*on_light);
          origins.push_back({j, 0});
        }
      }
      set.insert(set.end(), bounced.begin(), bounced.end());
      origins.insert(origins.end(), bounced_origins.begin(), bounced_origins.end());
    }
    return out;
  }

 private:
  friend class ImportanceVplSampler;  // proposes its candidates with these walks

  /// The frame's lights: the scene's, their particles aimed through the portals the frame's view
  /// finds (find_portals, a VplSettings::portal_share of them; none without a view).
  template <class Tracer, class Shader>
  static LightSet frame_lights(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer, const Shader& shader,
                               const VplSettings& settings) {
    const Portals portals = find_portals(scene, geometry, tracer, shader, settings, settings.portal_share);
    return LightSet(scene, settings.scene_bounds, &portals);
  }

  /// The one VPL of each delta light of `lights` (point, spot, directional), in light order.
  static std::vector<Vpl> exact_vpls(const LightSet& lights) {
    std::vector<Vpl> exact;
    for (std::size_t i = 0; i < lights.size(); ++i) {
      const EmissionSample sample = lights.emitter(i).sample_emission(0.5f, 0.5f, 0.5f, 0.5f);
      if (sample.leaves_vpl && sample.vpl.kind != VplKind::surface) exact.push_back(sample.vpl);
    }
    return exact;
  }

  /// The environment's directional VPLs of the frame scrambled by `scramble`, which every set
  /// shares as it shares the delta lights' (EnvironmentLight::directional_vpls); none without an environment.
  static std::vector<Vpl> environment_vpls(const Scene& scene, const VplSettings& settings, std::uint32_t scramble) {
    if (!scene.environment || !scene.environment->emits()) return {};
    // An arbitrary salt that separates the sky's directions from the walks' numbers.
    constexpr std::uint32_t sky_salt = 0x736b7973u;
    return EnvironmentLight(scene.environment, settings.scene_bounds)
        .directional_vpls(settings.environment_directions, hash(scramble, sky_salt));
  }

  /// Throws std::invalid_argument naming the first setting out of range, the message led by `sampler`.
  static void check(const VplSettings& settings, const std::string& sampler = "QmcVplSampler") {
    if (settings.sets < 1) throw std::invalid_argument(sampler + ": sets must be >= 1, got " + std::to_string(settings.sets));
    if (settings.vpls_per_set < 1)
      throw std::invalid_argument(sampler + ": vpls_per_set must be >= 1, got " + std::to_string(settings.vpls_per_set));
    if (settings.max_bounces < 0)
      throw std::invalid_argument(sampler + ": max_bounces must be >= 0, got " + std::to_string(settings.max_bounces));
  }

  /// Halton dimension `dimension` of point `index`; beyond the 32 Halton dimensions a hash.
  static float sample(const Halton& halton, std::uint32_t scramble, int dimension, std::uint64_t index) {
    constexpr int halton_dimensions = 32;  // the bases sampling.hpp provides
    if (dimension < halton_dimensions) return halton.sample(dimension, index);
    return to_unit_float(hash(hash(scramble, std::uint32_t(index) ^ std::uint32_t(index >> 32)), std::uint32_t(dimension)));
  }

  /// Walk `j` of `n`: picks a light and an emission with u(0..4), follows the particle, appends
  /// its bounce VPLs, and returns the VPL on the light (none for delta lights, lit exactly).
  template <class Tracer, class Shader, class Brdf, class Sample>
  static std::optional<Vpl> start_walk(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer, const Shader& shader,
                        const Brdf& brdf, const VplSettings& settings, const LightSet& lights, int n,
                        const Sample& u, int j, std::vector<Vpl>& bounced, std::vector<VplOrigin>& bounced_origins) {
    const LightSet::Choice choice = lights.choose(u(0));
    const EmissionSample emission = lights.emitter(choice.index).sample_emission(u(1), u(2), u(3), u(4));
    const float scale = 1.0f / (choice.probability * float(n));
    Vpl light_vpl = emission.vpl;
    light_vpl.intensity *= scale;
    walk(scene, geometry, tracer, shader, brdf, settings, lights.bounce_openings(), lights.heavy_flux(choice.index) * scale,
         emission.origin, emission.direction, emission.flux * scale, u, j, bounced, bounced_origins);
    if (!emission.leaves_vpl || light_vpl.kind != VplKind::surface) return std::nullopt;
    return light_vpl;
  }

  /// m: mean VPLs per walk over a pilot of walks scrambled by the seed alone.
  template <class Tracer, class Shader, class Brdf>
  static double pilot(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer, const Shader& shader,
                      const Brdf& brdf, const VplSettings& settings, const LightSet& lights) {
    // 256 walks measure m to a few percent (its relative error is about the walk-length spread
    // over 16) for a few hundred rays, next to the thousands a frame's VPLs cost.
    constexpr int pilot_walks = 256;
    // An arbitrary salt that separates the pilot's scrambling from every frame's.
    constexpr std::uint32_t pilot_salt = 0x70696c74u;
    const std::uint32_t scramble = hash(hash(settings.seed, pilot_salt));
    const Halton halton(scramble);
    std::vector<Vpl> bounced;
    std::vector<VplOrigin> origins;
    int on_lights = 0;
    for (int j = 0; j < pilot_walks; ++j) {
      const auto u = [&](int dimension) { return sample(halton, scramble, dimension, std::uint64_t(j)); };
      if (start_walk(scene, geometry, tracer, shader, brdf, settings, lights, pilot_walks, u, j, bounced, origins)) ++on_lights;
    }
    return double(on_lights + int(bounced.size())) / pilot_walks;
  }

  /// Follows one particle from `origin` along `direction`, appending the VPLs it leaves; if it
  /// reaches its first hit with a flux of at least `heavy` (LightSet::heavy_flux), that
  /// bounce's diffuse continuation is partly aimed back in through the view's `openings`.
  template <class Tracer, class Shader, class Brdf, class Sample>
  static void walk(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer, const Shader& shader,
                   const Brdf& brdf, const VplSettings& settings, const BounceOpenings& openings, float heavy,
                   glm::vec3 origin, glm::vec3 direction,
                   glm::vec3 flux, const Sample& u, int walk_index, std::vector<Vpl>& vpls,
                   std::vector<VplOrigin>& origins) {
    constexpr int first_bounce_dimension = 5;
    // The one ray-offset rule (shading/constants.hpp): a particle leaving a light starts that far
    // along its ray, one leaving a surface that far off it, one passing a cut-out that far beyond.
    const float offset = ray_offset(settings.scene_bounds);
    float start = offset;
    const vmask<1> one(true);
    int layers = 0;
    for (int bounce = 0; bounce < settings.max_bounces;) {
      if (!(light_detail::largest_component(flux) > 0.0f) || !std::isfinite(light_detail::largest_component(flux))) return;
      RayPacket<1> ray;
      ray.set(vec3<1>(origin), vec3<1>(direction), vfloat<1>(start),
              vfloat<1>(std::numeric_limits<float>::infinity()), one);
      HitPacket<1> hit;
      hit.clear();
      tracer.intersect(ray, hit, one);
      if (hit.geomID[0] == invalid_id) return;
      const SurfaceHit<1> surface = make_surface_hit(scene, geometry, ray, hit, one);
      const BrdfParameters<1> parameters = shader.shade(surface, one);
      if (!parameters.opaque[0]) {
        if (++layers > max_cutout_layers) return;
        origin = surface.position[0];
        start = offset;
        continue;
      }
      layers = 0;
      const glm::vec3 position = surface.position[0];
      const glm::vec3 geometric = surface.geometric_normal[0];
      ++bounce;
      const int dimension = first_bounce_dimension + 3 * (bounce - 1);
      // The diffuse continuation: cosine-distributed around the shading normal (a bumped
      // normal's sample that falls under the surface mirrored back above it), or, at a heavy
      // particle's first hit (outside the room: where particles enter it, light was aimed, so
      // they are lighter), partly aimed back in through the view's openings;
      // `bounce_sample.weight` is the cosine lobe's density over the density it was drawn by (1
      // where nothing is aimed).
      glm::vec3 n = parameters.normal[0];
      if (!(glm::dot(n, geometric) > 0.0f)) n = geometric;
      const BounceOpenings::Bounce bounce_sample = openings.sample(position, n, geometric, u(dimension + 1), u(dimension + 2),
                                                                       bounce == 1 && light_detail::largest_component(flux) >= heavy);
      const glm::vec3 diffuse_direction = bounce_sample.direction;
      // What the hit reflects diffusely: its albedo, plus a wide glossy lobe's reflectance
      // towards the diffuse continuation (f x cos / pdf with pdf = cos / pi, an unbiased estimate
      // of the lobe's directional albedo, weighed by the bounce's weight where the direction was
      // aimed). Written as !(>) so that a NaN exponent counts as sharp.
      glm::vec3 albedo = glm::clamp(parameters.albedo[0], glm::vec3(0.0f), glm::vec3(1.0f));
      glm::vec3 reflected = albedo;
      const float cosine = glm::dot(n, diffuse_direction);
      if (!(parameters.shininess[0] > wide_lobe_shininess) && light_detail::largest_component(parameters.glossy[0]) > 0.0f &&
          cosine > 0.0f) {
        albedo = glm::clamp(brdf.evaluate(surface, parameters, vec3<1>(diffuse_direction), one)[0] * (std::numbers::pi_v<float> / cosine),
                            glm::vec3(0.0f), glm::vec3(1.0f));
        reflected = albedo * bounce_sample.weight;
      }
      if (light_detail::largest_component(reflected) > 0.0f) {
        vpls.push_back({.position = position,
                        .normal = geometric,
                        .intensity = flux * reflected * inv_pi,
                        .kind = VplKind::surface});
        origins.push_back({walk_index, bounce});
      }
      if (bounce >= settings.max_bounces) return;

      SecondaryRays<1> reflection, refraction;
      brdf.spawn(surface, parameters, reflection, refraction, one);
      float q_diffuse = light_detail::largest_component(albedo);
      float q_reflect = reflection.active[0] ? light_detail::largest_component(reflection.weight[0]) : 0.0f;
      float q_refract = refraction.active[0] ? light_detail::largest_component(refraction.weight[0]) : 0.0f;
      const float total = q_diffuse + q_reflect + q_refract;
      if (total > 1.0f) {
        q_diffuse /= total;
        q_reflect /= total;
        q_refract /= total;
      }
      const float choice = u(dimension);
      if (choice < q_diffuse) {
        flux *= albedo * (bounce_sample.weight / q_diffuse);
        direction = diffuse_direction;
      } else if (choice < q_diffuse + q_reflect) {
        flux *= reflection.weight[0] / q_reflect;
        direction = reflection.direction[0];
      } else if (choice < q_diffuse + q_reflect + q_refract) {
        flux *= refraction.weight[0] / q_refract;
        direction = refraction.direction[0];
      } else {
        return;
      }
      origin = leave_surface(vec3<1>(position), vec3<1>(geometric), vec3<1>(direction), offset)[0];
      start = 0.0f;
    }
  }

  std::vector<Emitter> user_emitters_;
};

}  // namespace igi
