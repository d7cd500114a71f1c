#pragma once
/// \file
/// `ImportanceVplSampler`: VPLs where the camera looks. The paper's light walks (QmcVplSampler's
/// walks, randomized Halton, the same exact VPLs of delta lights) propose candidate VPLs; each
/// candidate is kept with a probability that follows its estimated contribution to the frame's
/// view, and a kept VPL is weighted by 1/probability. This is
/// Georgiev and Slusallek's "Simple and Robust Iterative Importance Sampling of Virtual Point
/// Lights" (Eurographics 2010 short paper), made to fit one frame and a fixed budget of VPLs.
///
/// Why this one and not Segovia et al.'s bidirectional instant radiosity (EGSR 2006): BIR makes
/// "reverse" VPLs on camera paths, whose radiance needs a first set of VPLs and a second pass,
/// then resamples both kinds; several strategies and parameters, and the walks' stratification
/// is lost. Acceptance keeps one sampler (the QMC walks), the exact delta lights and each set's
/// unbiasedness, and only adds shadow rays from candidates to a few view points. The measurement
/// that decided it: in the built-in window room (320x240, M = 16) 83% of the walks' candidates
/// add nothing to the view (they light the ground and the walls' outsides), 80% in Sponza_lit,
/// none in the Cornell box; dropping such candidates needs no second pass, only their view
/// contribution, and BIR's reverse VPLs would add nothing where there is nothing to drop. The
/// result (docs/accuracy.md, "VPL samplers"): at equal frame time the window room's relMSE falls 15x at
/// 8 VPLs, 4x at 16 and 1.4x at 32 (both samplers near their floors), Sponza_lit's 1.04-1.3x (its
/// error is mostly the clamp's and the pixel-centre sampling's bias), the Cornell box's VPLs are QMC's.
///
/// The view: `view_samples` camera rays on a jittered grid over the image (jittered by
/// hash(seed, frame)) give view points: the first opaque hit (alpha cut-outs pass), its
/// geometric normal facing the camera and its reflectance (diffuse plus glossy luminance / pi).
/// A candidate's contribution c is the sum over the view points of luminance(intensity) x emission
/// profile x receiver cosine x reflectance / max(d^2, clamp^2) where a shadow ray finds it: the
/// frame's own connect() term (ViewImportance).
///
/// The pilot: walks of one walk's flux each, scrambled by the seed and not the frame (as
/// QmcVplSampler's pilot), until 512 candidates. Its mean c sets the walk count N: with B = M - D
/// (the VPLs a set has besides the D exact ones), N is the smallest count at which Georgiev and
/// Slusallek's rule p = min(1, c B / Phi) would keep 90% of B, at most max_oversampling B
/// candidates per set. Where the rule would keep more than 1 / least_gain of the candidates at
/// QMC's own walk count (light spread evenly over the view, as in the Cornell box, where it kept
/// 70%), acceptance cannot gain enough to pay for its weights and the walks it drops (measured:
/// Cornell's relMSE rose 30-65% at M = 16-32), so the sampler returns QmcVplSampler's VPLs; so it
/// does where the view points see no light at all.
///
/// The frame: all sets' candidates and their c first; Phi is their mean per set. A candidate is
/// kept with p = min(1, c / tau + floor). tau is Phi / B (Georgiev and Slusallek's target: a VPL
/// worth more than a B-th of the view is always kept) unless the sets would then keep fewer than
/// B each on average (a few candidates carrying most of Phi, kept whatever tau is, as the sky
/// panel's VPLs seen through the window); then the smaller tau at which they keep B, found by
/// bisection. The floor, floor_share B / (N m) for m candidates per walk, spends floor_share of
/// the budget (in expectation) on candidates the view points miss (a gap between them, a mirror's
/// reflection): every candidate stays possible, so each set stays an unbiased estimate of the
/// whole light transport, seen or not. Unbiased because each candidate is kept with exactly its
/// p, whatever the others' decisions: E[keep / p] = 1 whatever p > 0 is.
///
/// The decisions are not independent coins (Georgiev and Slusallek's Russian roulette) but
/// systematic sampling: the set's p laid end to end in walk order and a candidate kept where one
/// of the points u, u + 1, u + 2, ... falls in its stretch. Coins keep a binomial count, and
/// with it how much of the view's light a set carries: at B = 16 and 9 sets about 1 / sqrt(144),
/// 8%, of a frame's brightness. Systematic sampling keeps the sum of p rounded up or down, so a
/// set's kept VPLs carry its candidates' light on the view points but for that rounding and the
/// split between seen candidates and the floor's. Measured in the window, blinds and two-window
/// rooms under the sky (320x240, 16 VPLs, seeds 1-8, docs/accuracy.md): the image mean's spread
/// over seeds fell from 3.6 / 9.1 / 6.0% to 2.9 / 3.5 / 5.3%, the worst seed's relMSE from
/// 0.094 / 0.52 / 0.026 to 0.014 / 0.056 / 0.023.
///
/// Heavy VPLs are shared. A kept VPL weighs 1/p, up to ten times what QMC's walks would give it
/// where the floor keeps it; in its set's pixels it then shows ten times a VPL's light, which the
/// discontinuity buffer averages with the other sets' pixels only on smooth surfaces, not on the
/// far trees of an outdoor view (there a frame's error rose 10-20x for one such VPL). A VPL
/// heavier than shared_weight times QMC's weight and brighter than shared_brightness times the
/// frame's mean walk VPL goes to every set, its intensity divided by their count: the sets' mean
/// is unchanged, so is the estimate's expectation, and each pixel carries its share of it (a
/// pixel connects to one more VPL for each shared one: 2-3 a frame in the forest).
///
/// Randomness: walk j of set s is Halton point s N + j scrambled by hash(seed, frame), as in
/// QmcVplSampler; set s's offset u is hash(seed, frame, s). The view points,
/// the pilot, N and tau depend only on the scene, the view, the settings, the frame and the seed,
/// so VPLs are the same on every packet width, thread count and MPI rank, and on every backend up
/// to the float rounding of the hit points (which QmcVplSampler's VPLs show too).

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/blocked_range.h>
#include <oneapi/tbb/parallel_for.h>

#include "igi/backends/packet.hpp"
#include "igi/io/srgb.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/lighting/vpl_sampler.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/brdf_shader.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"
#include "igi/simd/float_mode.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {

/// One view point of the importance estimate: a camera ray's first opaque hit.
struct ViewPoint {
  glm::vec3 position{0.0f};  ///< World position.
  glm::vec3 normal{0.0f};    ///< Unit geometric normal, facing the camera.
  float reflectance = 0.0f;  ///< Luminance of (diffuse + glossy reflectance) / pi.
};

/// VPLs with their origins and what the acceptance did.
struct ImportanceVplGeneration {
  VplGeneration generation;                     ///< The kept VPLs, their origins, N, and the pilot's candidates per walk.
  std::vector<std::vector<float>> probability;  ///< probability[s][i]: the chance VPL i of set s was kept with (1 for exact VPLs).
  int candidates = 0;                           ///< Candidates proposed over all sets.
  double image_flux = 0.0;                      ///< Phi: one set's mean contribution to the view points.
  double threshold = 0.0;                       ///< tau of the acceptance p = min(1, c / tau + floor).
  int view_points = 0;                          ///< Camera rays that found a surface that reflects.
  double qmc_acceptance = 1.0;                  ///< Share of candidates the rule keeps at QMC's walk count (1: nothing seen).
  int shared = 0;                               ///< Kept VPLs heavy and bright enough to be shared by every set (each counted once).
};

/// What a VPL adds to a frame's view points: the importance estimate of ImportanceVplSampler.
class ViewImportance {
 public:
  /// The estimate over `points`, with the frame's `clamp_distance` and ray offsets of a scene of `bounds`.
  ViewImportance(std::vector<ViewPoint> points, float clamp_distance, const Bounds& bounds)
      : points_(std::move(points)), clamp_distance_(clamp_distance), epsilon_(ray_offset(bounds)) {}

  /// The view points.
  const std::vector<ViewPoint>& points() const noexcept { return points_; }

  /// c: what `vpl` adds to the view points, summed: luminance(intensity) x connect()'s falloff x
  /// receiver cosine x reflectance where a shadow ray finds the VPL. (A mean over the camera rays
  /// would differ by their count, a scale common to every candidate that cancels in c / Phi.)
  template <class Tracer>
  double contribution(const Vpl& vpl, const Tracer& tracer) const {
    const float power = luminance(vpl.intensity);
    if (!(power > 0.0f)) return 0.0;
    const vmask<1> one(true);
    double sum = 0.0;
    for (const ViewPoint& point : points_) {
      const VplGeometry<1> g = connect(vpl, vec3<1>(point.position), vec3<1>(point.normal), clamp_distance_, one);
      if (!g.reaches[0]) continue;
      const float unoccluded = power * g.falloff[0] * glm::dot(point.normal, g.wi[0]) * point.reflectance;
      if (!(unoccluded > 0.0f)) continue;
      RayPacket<1> shadow;
      // As the pipeline's shadow rays: off the surface, stopping twice the offset short of the VPL.
      const float length = std::max(g.distance[0] - 2.0f * epsilon_, 0.0f);
      shadow.set(vec3<1>(point.position + point.normal * epsilon_), vec3<1>(g.wi[0]), vfloat<1>(0.0f), vfloat<1>(length), one);
      if (tracer.occluded(shadow, one)[0]) continue;
      sum += double(unoccluded);
    }
    return sum;
  }

  /// contribution() of `count` VPLs, `vpl(i)` the i-th, on oneTBB's threads (the calling
  /// thread's task arena: its thread count), each with denormals flushed as the frame's tiles.
  /// Every value is computed alone, so the result does not depend on the threads.
  template <class Tracer, class VplOf>
  std::vector<double> contributions(std::size_t count, const VplOf& vpl, const Tracer& tracer) const {
    std::vector<double> values(count);
    // 8 candidates (512 shadow rays at 64 view points) a task: enough work per task to hide its
    // scheduling, and a few hundred tasks for the threads to balance.
    constexpr std::size_t grain = 8;
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, count, grain), [&](const tbb::blocked_range<std::size_t>& range) {
      const FlushDenormals flush;
      for (std::size_t i = range.begin(); i != range.end(); ++i) values[i] = contribution(vpl(i), tracer);
    });
    return values;
  }

 private:
  std::vector<ViewPoint> points_;
  float clamp_distance_;
  float epsilon_;
};

/// View-importance VPL sampler: QMC light walks, candidates kept in proportion to their
/// contribution to the frame's view (Georgiev and Slusallek 2010).
class ImportanceVplSampler {
 public:
  /// What the acceptance is made of.
  struct Settings {
    /// Camera rays of the estimate (a jittered grid over the image). 64 rays find the few large
    /// surfaces a room or a courtyard shows well enough to tell seen light from unseen, at 64
    /// shadow rays a candidate (a few ms a frame at 16 VPLs per pixel, against 30-400 ms of frame).
    int view_samples = 64;
    /// Share of the kept VPLs spent, in expectation, on candidates the view points do not see: a
    /// tenth keeps nine in ten VPLs where the view points see light, and the weight of an unseen
    /// one at most 10x its share of the candidates.
    float floor_share = 0.1f;
    /// Most candidates per set, in multiples of the VPLs it keeps: 16, as QmcVplSampler's bound
    /// of 16 M walks, bounds the candidates' shadow rays at 16 B x view_samples a set.
    int max_oversampling = 16;
    /// Acceptance runs only where it can raise the share of VPLs that light the view this much
    /// (1 / the share of candidates the rule keeps at QMC's walk count): below 2 the weights and
    /// the dropped walks cost more than the gain where it was measured (the Cornell box, 1.4).
    float least_gain = 2.0f;
    /// A kept VPL weighing more than this many times what QMC's walk count would give it (the
    /// floor's unseen candidates weigh 10) and brighter than shared_brightness goes to every set,
    /// its intensity divided by their count, so that no pixel shows it 9 times over where the
    /// filter cannot average the sets. Measured on the camera walks (docs/interaction.md): the
    /// forest's worst frame from relMSE 0.55 to 0.11 at 3; 1.5 shares alike, 10 none (the floor's
    /// VPLs weigh 10 at most). Infinity shares none.
    float shared_weight = 3.0f;
    /// ... and shining more than this many times the frame's mean walk VPL: 3 leaves the floor's
    /// ordinary VPLs in their sets (sharing all heavy ones, 11 a frame in the forest, cost 40-50% more
    /// shadow rays for the same images) and shares the 2-3 a frame that make the bad frames.
    float shared_brightness = 3.0f;
  };

  /// Policy name.
  static constexpr const char* name() noexcept { return "importance"; }
  /// Its VPLs are chosen for the frame's view (igi::chooses_for_view).
  static constexpr bool chooses_for_view() noexcept { return true; }

  /// The sampler with the default settings.
  ImportanceVplSampler() = default;
  /// The sampler with `settings`; throws std::invalid_argument naming a setting out of range.
  explicit ImportanceVplSampler(const Settings& settings) : settings_(settings) {
    if (settings.view_samples < 1 || settings.view_samples > max_view_samples)
      throw std::invalid_argument("ImportanceVplSampler: view_samples must be in 1.." + std::to_string(max_view_samples) +
                                  ", got " + std::to_string(settings.view_samples));
    if (!(settings.floor_share > 0.0f && settings.floor_share < 1.0f))
      throw std::invalid_argument("ImportanceVplSampler: floor_share must be in (0, 1), got " +
                                  std::to_string(settings.floor_share));
    if (!(settings.least_gain >= 1.0f) || !std::isfinite(settings.least_gain))
      throw std::invalid_argument("ImportanceVplSampler: least_gain must be finite and >= 1, got " +
                                  std::to_string(settings.least_gain));
    if (!(settings.shared_weight >= 1.0f))
      throw std::invalid_argument("ImportanceVplSampler: shared_weight must be >= 1 (infinity: none shared), got " +
                                  std::to_string(settings.shared_weight));
    if (!(settings.shared_brightness >= 0.0f))
      throw std::invalid_argument("ImportanceVplSampler: shared_brightness must be >= 0 (infinity: none shared), got " +
                                  std::to_string(settings.shared_brightness));
    if (settings.max_oversampling < 1 || settings.max_oversampling > max_oversampling_limit)
      throw std::invalid_argument("ImportanceVplSampler: max_oversampling must be in 1.." +
                                  std::to_string(max_oversampling_limit) + ", got " +
                                  std::to_string(settings.max_oversampling));
  }

  /// The settings.
  const Settings& settings() const noexcept { return settings_; }

  /// The frame's VPL sets, as QmcVplSampler::generate, kept by their contribution to `settings.view`.
  template <class Tracer, class Shader, class Brdf>
    requires SurfaceShader<Shader, 1> && BrdfShader<Brdf, 1>
  VplSets generate(const Scene& scene, const Tracer& tracer, const Shader& shader, const Brdf& brdf,
                   const VplSettings& settings) const {
    return generate_with_statistics(scene, tracer, shader, brdf, settings).generation.vpls;
  }

  /// The frame's VPL sets with their origins and acceptance. Throws std::invalid_argument on bad
  /// settings or when `settings.view` is null (FrameState::prepare sets it).
  template <class Tracer, class Shader, class Brdf>
    requires SurfaceShader<Shader, 1> && BrdfShader<Brdf, 1>
  ImportanceVplGeneration generate_with_statistics(const Scene& scene, const Tracer& tracer, const Shader& shader,
                                                   const Brdf& brdf, const VplSettings& frame_settings) const {
    QmcVplSampler::check(frame_settings, "ImportanceVplSampler");
    if (!frame_settings.view)
      throw std::invalid_argument(
          "ImportanceVplSampler: VplSettings::view is null; this sampler needs the frame's camera and image size "
          "(FrameState::prepare fills them in)");
    if (!(frame_settings.view->clamp_distance >= 0.0f) || !std::isfinite(frame_settings.view->clamp_distance))
      throw std::invalid_argument("ImportanceVplSampler: the view's clamp distance must be finite and >= 0, got " +
                                  std::to_string(frame_settings.view->clamp_distance));
    VplSettings settings = frame_settings;
    if (settings.scene_bounds.empty()) settings.scene_bounds = scene.bounds();
    const SceneGeometry geometry(scene);
    const LightSet lights = QmcVplSampler::frame_lights(scene, geometry, tracer, shader, settings);
    ImportanceVplGeneration out;
    VplGeneration& generation = out.generation;
    const auto sets = std::size_t(settings.sets);
    generation.vpls.sets.resize(sets);
    generation.origins.resize(sets);
    out.probability.resize(sets);
    if (lights.empty()) return out;

    std::vector<Vpl> exact = QmcVplSampler::exact_vpls(lights);
    const std::size_t delta_lights = exact.size();
    {
      const std::vector<Vpl> sky = QmcVplSampler::environment_vpls(scene, settings, hash(settings.seed, settings.frame));
      exact.insert(exact.end(), sky.begin(), sky.end());
    }
    const ViewImportance view(view_points(scene, geometry, tracer, shader, settings), settings.view->clamp_distance,
                              settings.scene_bounds);
    out.view_points = int(view.points().size());

    const Pilot pilot = run_pilot(scene, geometry, tracer, shader, brdf, settings, lights, view);
    generation.vpls_per_walk = pilot.vpls_per_walk;
    const bool importance_known = pilot.image_flux > 0.0 && std::isfinite(pilot.image_flux);
    // The share of candidates Georgiev and Slusallek's rule would keep at QmcVplSampler's walk
    // count: mean(min(1, c / mean c)); 1 / that bounds how much more of the view's light the
    // kept VPLs can carry than QMC's.
    if (importance_known) {
      const double mean = pilot.image_flux / pilot.vpls_per_walk;
      double kept = 0.0;
      for (const double c : pilot.contributions) kept += std::min(1.0, c / mean);
      out.qmc_acceptance = kept / double(pilot.contributions.size());
    }
    if (!importance_known || out.qmc_acceptance * double(settings_.least_gain) >= 1.0) {
      // Nothing seen, or light spread so evenly over the view that acceptance cannot gain
      // least_gain: its weights and the walks it drops would cost more than it brings, so these
      // are QmcVplSampler's VPLs, every candidate kept.
      const int exact_count = int(exact.size());
      ImportanceVplGeneration qmc;
      qmc.generation = QmcVplSampler{}.generate_with_origins(scene, tracer, shader, brdf, settings);
      qmc.view_points = out.view_points;
      qmc.qmc_acceptance = out.qmc_acceptance;
      for (const auto& set : qmc.generation.vpls.sets) {
        qmc.probability.emplace_back(set.size(), 1.0f);
        qmc.candidates += int(set.size()) - exact_count;
      }
      return qmc;
    }
    const double budget = std::max(1.0, double(settings.vpls_per_set) - double(delta_lights));
    const double per_walk = std::max(pilot.vpls_per_walk, 1.0 / double(pilot.walks));
    long walks = 1;
    {
      // Expected kept candidates of a set of n walks under Georgiev and Slusallek's target Phi / B
      // without the floor, from the pilot's (whose c is for one walk: c / n in a set of n).
      const auto expected_kept = [&](long n) {
        double kept = 0.0;
        for (const double c : pilot.contributions) kept += std::min(1.0, c / double(n) * budget / pilot.image_flux);
        return double(n) * kept / double(pilot.walks);
      };
      // The count capped at p = 1 only approaches B as n grows: it reaches 90% of B with a few
      // times QMC's walks where contributions are even (every candidate a fair share), never where
      // a few carry most of the light (then max_oversampling sets n, and the frame's tau the count).
      constexpr double coverage = 0.9;
      long lower = 1, upper = std::max(1L, std::lround(double(settings_.max_oversampling) * budget / per_walk));
      if (expected_kept(upper) < coverage * budget) lower = upper;  // the cap binds: spend all it allows
      while (lower < upper) {  // the smallest n that reaches the coverage (expected_kept grows with n)
        const long middle = lower + (upper - lower) / 2;
        if (expected_kept(middle) >= coverage * budget)
          upper = middle;
        else
          lower = middle + 1;
      }
      walks = lower;
    }
    generation.walks_per_set = int(walks);
    const int n = generation.walks_per_set;
    // The floor spends floor_share of the budget, in expectation, on candidates of any contribution.
    const double floor = std::min(1.0, double(settings_.floor_share) * budget / (double(n) * per_walk));

    // All sets' candidates first: the target comes from all of them.
    struct Candidate {
      Vpl vpl;
      VplOrigin origin;
      double contribution;
      bool on_light;
    };
    std::vector<std::vector<Candidate>> candidates(sets);
    std::vector<double> set_flux(sets, 0.0);
    const std::uint32_t scramble = hash(settings.seed, settings.frame);
    const Halton halton(scramble);
    // The sets' walks are independent (walk j of set s is Halton point s N + j): a task a set.
    tbb::parallel_for(std::size_t(0), sets, [&](std::size_t s) {
      const FlushDenormals flush;
      for (int j = 0; j < n; ++j) {
        const std::uint64_t index = std::uint64_t(s) * std::uint64_t(n) + std::uint64_t(j);
        const auto u = [&](int dimension) { return QmcVplSampler::sample(halton, scramble, dimension, index); };
        std::vector<Vpl> walk_vpls;
        std::vector<VplOrigin> walk_origins;
        const std::optional<Vpl> on_light = QmcVplSampler::start_walk(scene, geometry, tracer, shader, brdf, settings,
                                                                      lights, n, u, j, walk_vpls, walk_origins);
        if (on_light) candidates[s].push_back({*on_light, {j, 0}, 0.0, true});
        for (std::size_t k = 0; k < walk_vpls.size(); ++k) candidates[s].push_back({walk_vpls[k], walk_origins[k], 0.0, false});
      }
    });
    // Then every candidate's contribution (most of the sampler's time: a shadow ray per view point).
    std::vector<Candidate*> all;
    for (auto& set : candidates)
      for (Candidate& candidate : set) all.push_back(&candidate);
    const std::vector<double> contributions =
        view.contributions(all.size(), [&](std::size_t i) -> const Vpl& { return all[i]->vpl; }, tracer);
    for (std::size_t i = 0; i < all.size(); ++i) all[i]->contribution = contributions[i];
    for (std::size_t s = 0; s < sets; ++s) {
      for (const Candidate& candidate : candidates[s]) set_flux[s] += candidate.contribution;
      out.candidates += int(candidates[s].size());
    }

    double image_flux = 0.0;
    for (const double flux : set_flux) image_flux += flux / double(sets);
    out.image_flux = image_flux;
    // The threshold tau of p = min(1, c / tau + floor): Georgiev and Slusallek's Phi / B where
    // contributions are even; where a few candidates carry most of Phi (they are kept whatever
    // tau is) the smaller tau at which the sets keep B each on average, found by bisection.
    double threshold = 1.0;
    if (image_flux > 0.0) {
      const auto expected_kept = [&](double tau) {
        double kept = 0.0;
        for (const auto& set : candidates)
          for (const Candidate& candidate : set) kept += std::min(1.0, candidate.contribution / tau + floor);
        return kept / double(sets);
      };
      threshold = image_flux / budget;
      if (expected_kept(threshold) < budget) {
        // Halve tau until enough are kept (or every seen candidate is, at 2^-40 of Phi / B), then bisect.
        constexpr int halvings = 40;
        double upper = threshold, lower = threshold;
        for (int i = 0; i < halvings && expected_kept(lower) < budget; ++i) lower *= 0.5;
        constexpr int bisections = 30;  // 2^-30 of the bracket: far finer than the count's noise
        for (int i = 0; i < bisections; ++i) {
          const double middle = 0.5 * (lower + upper);
          (expected_kept(middle) < budget ? upper : lower) = middle;
        }
        threshold = lower;
      }
    }
    out.threshold = threshold;
    // An arbitrary salt that separates the acceptance decisions from the walks' own numbers.
    constexpr std::uint32_t accept_salt = 0x6b656570u;
    const std::uint32_t accept_seed = hash(hash(scramble, accept_salt));
    for (std::size_t s = 0; s < sets; ++s) {
      std::vector<Vpl>& set = generation.vpls.sets[s];
      std::vector<VplOrigin>& origins = generation.origins[s];
      std::vector<float>& kept_with = out.probability[s];
      for (const Vpl& vpl : exact) {
        set.push_back(vpl);
        origins.push_back({-1, 0});
        kept_with.push_back(1.0f);
      }
      // Which candidates are kept: systematic sampling, one uniform offset u per set and the
      // points u, u + 1, u + 2, ... along the candidates' p laid end to end in walk order; a
      // candidate is kept where a point falls in its stretch, so with probability p (p <= 1).
      const std::vector<Candidate>& proposed = candidates[s];
      std::vector<double> p(proposed.size(), 1.0);
      std::vector<bool> kept(proposed.size(), true);
      if (image_flux > 0.0) {
        const double offset = double(to_unit_float(hash(accept_seed, std::uint32_t(s))));
        double before = 0.0;
        for (std::size_t i = 0; i < proposed.size(); ++i) {
          p[i] = std::min(1.0, proposed[i].contribution / threshold + floor);
          const double after = before + p[i];
          kept[i] = p[i] >= 1.0 || std::floor(after - offset) > std::floor(before - offset);
          before = after;
        }
      }
      // VPLs on lights first, then the bounced ones, as QmcVplSampler orders them.
      for (const bool on_lights : {true, false})
        for (std::size_t i = 0; i < proposed.size(); ++i) {
          if (!kept[i] || proposed[i].on_light != on_lights) continue;
          Vpl vpl = proposed[i].vpl;
          vpl.intensity *= float(1.0 / p[i]);
          set.push_back(vpl);
          origins.push_back(proposed[i].origin);
          kept_with.push_back(float(p[i]));
        }
    }
    share_heavy(out, budget / (per_walk * double(n)));
    return out;
  }

  /// The view points of `settings.view` (which must be set): the first opaque, reflecting hits of
  /// `view_samples` camera rays on the grid jittered by hash(seed, frame).
  template <class Tracer, class Shader>
    requires SurfaceShader<Shader, 1>
  std::vector<ViewPoint> view_points(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer,
                                     const Shader& shader, const VplSettings& settings) const {
    const PinholeProjection& projection = settings.view->projection;
    // An arbitrary salt that separates the view jitter from the walks and the acceptance.
    constexpr std::uint32_t jitter_salt = 0x6a697474u;
    const float offset = ray_offset(settings.scene_bounds);
    std::vector<ViewPoint> points;
    for_each_view_ray(projection, settings_.view_samples, hash(hash(settings.seed, settings.frame), jitter_salt),
                      [&](std::uint32_t, const glm::vec3& direction) {
                        const std::optional<OpaqueHit> hit =
                            first_opaque_hit(scene, geometry, tracer, shader, projection.origin(), direction, 0.0f, offset);
                        if (!hit) return;
                        const glm::vec3 reflectance =
                            glm::clamp(hit->parameters.albedo[0] + hit->parameters.glossy[0], glm::vec3(0.0f), glm::vec3(1.0f));
                        const float reflected = luminance(reflectance) * inv_pi;
                        if (reflected > 0.0f && std::isfinite(reflected))
                          points.push_back({.position = hit->surface.position[0],
                                            .normal = hit->surface.geometric_normal[0],
                                            .reflectance = reflected});
                      });
    return points;
  }

 private:
  /// Most view samples: 4096 camera rays is past any use for the estimate and bounds its cost.
  static constexpr int max_view_samples = 4096;
  /// Most oversampling: 256 candidates per kept VPL (an acceptance rate of 0.4%) bounds the walks.
  static constexpr int max_oversampling_limit = 256;

  /// Moves the kept VPLs that weigh more than shared_weight times `qmc_weight` (1 / QMC's walks a
  /// set) and shine more than shared_brightness times the frame's mean walk VPL out of their set
  /// and into every set, each with its intensity divided by the sets' count.
  void share_heavy(ImportanceVplGeneration& out, double qmc_weight) const {
    VplGeneration& generation = out.generation;
    const std::size_t sets = generation.vpls.sets.size();
    double sum = 0.0;
    std::size_t count = 0;
    for (std::size_t s = 0; s < sets; ++s)
      for (std::size_t i = 0; i < generation.vpls.sets[s].size(); ++i)
        if (generation.origins[s][i].walk >= 0) {
          sum += double(luminance(generation.vpls.sets[s][i].intensity));
          ++count;
        }
    if (count == 0) return;
    const double brightest = double(settings_.shared_brightness) * sum / double(count);
    // Kept with p below this, a VPL weighs more than shared_weight times QMC's weight.
    const double heavy_below = qmc_weight / double(settings_.shared_weight);
    struct Shared {
      Vpl vpl;
      VplOrigin origin;
      float probability;
    };
    std::vector<Shared> shared;
    for (std::size_t s = 0; s < sets; ++s) {
      std::vector<Vpl>& set = generation.vpls.sets[s];
      std::vector<VplOrigin>& origins = generation.origins[s];
      std::vector<float>& kept_with = out.probability[s];
      std::size_t kept = 0;
      for (std::size_t i = 0; i < set.size(); ++i) {
        if (origins[i].walk >= 0 && double(kept_with[i]) < heavy_below && double(luminance(set[i].intensity)) > brightest) {
          Vpl vpl = set[i];
          vpl.intensity /= float(sets);
          shared.push_back({vpl, origins[i], kept_with[i]});
          continue;
        }
        set[kept] = set[i];
        origins[kept] = origins[i];
        kept_with[kept] = kept_with[i];
        ++kept;
      }
      set.resize(kept);
      origins.resize(kept);
      kept_with.resize(kept);
    }
    // Every set holds them, each set a share of their weight: the sets' mean is the same, and a
    // pixel no longer depends on which set drew one of them.
    for (std::size_t s = 0; s < sets; ++s)
      for (const Shared& one : shared) {
        generation.vpls.sets[s].push_back(one.vpl);
        generation.origins[s].push_back(one.origin);
        out.probability[s].push_back(one.probability);
      }
    out.shared = int(shared.size());
  }

  /// What the pilot found: its candidates' contributions (one walk's flux each) and Phi.
  struct Pilot {
    std::vector<double> contributions;  ///< c of every pilot candidate.
    int walks = 0;                      ///< Walks traced.
    double image_flux = 0.0;            ///< Phi: mean over walks of the sum of their candidates' c.
    double vpls_per_walk = 0.0;         ///< m: candidates per walk.
  };

  /// Walks of one walk's flux each, scrambled by the seed alone, until 512 candidates or 8192
  /// walks: a sample of candidates, not of walks, so Phi is as good where walks mostly escape.
  template <class Tracer, class Shader, class Brdf>
  static Pilot run_pilot(const Scene& scene, const SceneGeometry& geometry, const Tracer& tracer, const Shader& shader,
                         const Brdf& brdf, const VplSettings& settings, const LightSet& lights, const ViewImportance& view) {
    // 512 candidates estimate Phi to a few percent where contributions are even, for 512 x
    // view_samples shadow rays at most; 8192 walks bound the pilot where walks rarely leave one.
    constexpr int pilot_candidates = 512, pilot_walks = 8192;
    // An arbitrary salt that separates this pilot's scrambling from QmcVplSampler's and every frame's.
    constexpr std::uint32_t pilot_salt = 0x76696577u;
    const std::uint32_t scramble = hash(hash(settings.seed, pilot_salt));
    const Halton halton(scramble);
    std::vector<Vpl> candidates;
    std::vector<VplOrigin> origins;
    Pilot pilot;
    while (int(candidates.size()) < pilot_candidates && pilot.walks < pilot_walks) {
      const int j = pilot.walks++;
      const auto u = [&](int dimension) { return QmcVplSampler::sample(halton, scramble, dimension, std::uint64_t(j)); };
      if (const std::optional<Vpl> on_light =
              QmcVplSampler::start_walk(scene, geometry, tracer, shader, brdf, settings, lights, 1, u, j, candidates, origins))
        candidates.push_back(*on_light);
    }
    pilot.contributions =
        view.contributions(candidates.size(), [&](std::size_t i) -> const Vpl& { return candidates[i]; }, tracer);
    for (const double contribution : pilot.contributions) pilot.image_flux += contribution / double(pilot.walks);
    pilot.vpls_per_walk = double(candidates.size()) / double(pilot.walks);
    return pilot;
  }

  Settings settings_{};
};

}  // namespace igi
