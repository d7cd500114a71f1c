#pragma once
/// \file
/// Settings of an IGI frame and their validation.

#include <cstdint>
#include <stdexcept>
#include <string>

#include "igi/scene/memory.hpp"

namespace igi {

/// A setting or argument that cannot be used; the message names it.
class SettingsError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Everything besides scene and camera that decides an IGI frame.
struct RenderSettings {
  int width = 640;                ///< Image width in pixels.
  int height = 480;               ///< Image height in pixels.
  int interleave = 3;             ///< S: the S x S interleaving pattern (S^2 VPL sets).
  int vpls_per_pixel = 16;        ///< M: VPLs each pixel connects to (the size of one set).
  int antialiasing = 1;           ///< N: primary rays per pixel; sub-sample k uses the k-th of N VPL subsets.
  /// Tile edge in pixels. 48, not the paper's 40: 48 = 3 x 16, so at the default 3 x 3 interleaving
  /// each set's sub-grid of a tile is 16 x 16 and fills every 4 x 4, 2 x 4 and 2 x 2 packet, where
  /// 40 leaves sub-grids of 13 or 14 and 30% of the lanes of W = 16 empty (Sponza_lit 640 x 480,
  /// 12 VPLs, 2 threads: 125 ms a frame in 40-pixel tiles, 115 ms in 48). The image does not depend on it.
  int tile_size = 48;
  float clamp_distance = -1.0f;   ///< Minimum VPL distance in the 1/d^2 term; < 0 means automatic (see resolve_clamp).
  int max_depth = 6;              ///< Longest chain of mirror/glass bounces.
  /// Longest light random walk of the VPL sampler. Russian roulette ends walks first (a set's
  /// VPL count does not grow with it: fewer walks fill M); the cap cuts rho^33 of the light of
  /// albedo rho, 6e-4 at 0.8 (8 bounces cut 1% of a Cornell corner view's light, measured).
  int max_bounces = 32;
  /// Shadow-ray Russian roulette: a VPL whose unoccluded light is below this fraction of what the
  /// pixel has gathered so far gets its shadow ray with probability light / (fraction x gathered)
  /// and, if visible, that much more weight (unbiased: fewer rays, a little more noise). 0: off.
  float shadow_roulette = 0.0f;
  /// Whether the delta lights' direct light (point, spot and directional lights: one exact VPL
  /// each in every set, see QmcVplSampler) goes through the filter with the VPLs' light, as in
  /// the paper. Off by default: that light is the same in every interleaving set, so filtering it
  /// removes no noise and only spreads sharp shadow edges over the window (and à-trous's wider
  /// footprint) into the dark side, where the error relative to the light there is largest; it is
  /// composed per pixel instead, beside emission. Either way, with anti-aliasing every sub-sample
  /// takes it (where a VPL subset's turn would give it to one sub-sample N-fold).
  bool filter_delta_lights = false;
  /// Whether camera rays read textures at their footprint (a ray cone one pixel wide, over
  /// sqrt(N) with N sub-samples; trilinear in the surface shader's mip chains), so each sample
  /// sees the texture averaged over its share of the pixel, as the reference's pixel-area
  /// integral does. Off: every ray reads full resolution at its point, as the paper did (and
  /// texture detail finer than a pixel aliases).
  bool filter_textures = true;
  /// Directional VPLs that carry the environment's direct light (a sky), drawn in proportion to
  /// its light and shared by every interleaving set, so every pixel sees the same sky: each
  /// pixel pays this many shadow rays besides its M VPLs. 32: Sponza under the neutral sky at
  /// 16 VPLs has relMSE 0.025 against the path tracer (0.037 with 16, 0.017 with 64 at three
  /// times the frame time; docs/sky.md), and open ground gets its irradiance within 6% on every
  /// frame's draw; a sun in the map draws most of them. No effect without an environment.
  int environment_directions = 32;
  /// Share of the particles of directional lights, of the environment and of emitters seen
  /// through openings (a panel outside a window) aimed through the openings by which their light
  /// reaches the view (find_portals: a window, gaps between slats), the rest spread over the
  /// whole scene; the mixture's density weighs each particle,
  /// so the image's expectation does not change, only where the walks go. 0: none aimed, the
  /// paper's walks, whose light in a window-lit room hangs on the few that pass the window (most
  /// frames miss it, a few are 3-6x too bright). 0.7: the lowest median error in every
  /// window-lit room measured, with the unaimed share still large enough that light the
  /// openings found do not aim at stays well sampled (0.9 brought back outlier frames; docs/sky.md).
  float portal_share = 0.7f;
  int compensation_rays = 0;      ///< Bias compensation: gather rays per pixel that return the light the clamp removes (0: off).
  /// Temporal reuse (whole frames of one Renderer): each pixel averages up to this many frames
  /// of its history, reprojected with the camera's motion and dropped where normal or depth
  /// disagree; while the view stays still the clamp shrinks with the history (see TemporalReuse). 0: off.
  int temporal_frames = 0;
  /// With temporal reuse: a first hit that shows the surface the previous frame showed around it
  /// takes that frame's answers for the delta lights' (point, spot, sun) shadow rays instead of
  /// tracing them again, unless the scene changed or the answers disagree (a shadow's edge); each
  /// pixel still traces them every shadow_refresh_frames-th frame (frame_state.hpp). The image is
  /// the traced one up to shadows finer than a pixel. false: every frame traces them all.
  bool reuse_shadows = true;
  /// With temporal reuse: while the camera moves and the scene does not change, a frame keeps
  /// VPLs drawn before it (the frame before's, or a few draws in turn: held_vpl_sets) instead of
  /// drawing new ones, for up to this many frames in a row; a still view draws new VPLs every
  /// frame (its history averages them), and so do the
  /// frames after a change until the moving histories hold only frames of the changed scene. Each frame's
  /// VPLs differ in their few heavy light paths, which a moving camera's short histories cannot
  /// average away: kept ones leave the image mean steady and the flicker at the reference's
  /// (docs/interaction.md). A refresh while moving changes the image mean as much as a new frame
  /// of VPLs does (a step the short histories smooth over a few frames), so it comes rarely:
  /// 240 frames, 10 s at 24 frames a second, only bounds how long VPLs aimed through the openings
  /// of a view left long ago light the new one. A light that changes (moves, turns, dims) draws
  /// its VPLs with the random numbers of those it replaces, so that they move with it instead of
  /// being replaced by other heavy light paths each frame (under a circling sun the image mean
  /// varied by 14% with new numbers, by 4% with the same); those frames count in the same run.
  /// VPLs chosen for the view (a sampler's chooses_for_view: ImportanceVplSampler) are drawn
  /// anew by every moving frame with the run's numbers too, chosen for that frame's view.
  /// 0: every frame draws new VPLs with its own numbers.
  int held_vpl_frames = 240;
  /// With held VPLs (held_vpl_frames): how many draws of VPLs a run of held frames cycles
  /// through, one a frame (the frame before the run's, then new ones drawn by the first frames of
  /// the run; their direct light is the first draw's: share_direct_light). Each pixel's history
  /// averages each draw's frames apart, irradiance and glossy light, and shows the mean of those
  /// averages (TemporalReuse), so a view holds the light paths of all the draws while its light
  /// changes from frame to frame no more than with one draw. 1 (the run keeps the frame before's
  /// VPLs alone) by default: with 4, the window-lit rooms' walks halve their median relMSE, but a
  /// cold start's first frame has one draw (the window room's image mean then varies by 3.1% over
  /// its walk, 2.8% with one) and the blinds flicker more (docs/interaction.md). A sampler that
  /// chooses its VPLs for the view keeps no draws: its moving frames draw anew (held_vpl_frames).
  int held_vpl_sets = 1;
  std::uint32_t seed = 0;         ///< Randomisation of the QMC sequences.
  int threads = 0;                ///< Worker threads; 0 means all cores.
};

/// Largest image edge accepted: 16384 keeps a frame's float buffers under 4 GiB.
inline constexpr int max_image_edge = 16384;
/// Largest VPL set: 4096 VPLs per pixel is far past convergence and bounds per-frame VPL memory.
inline constexpr int max_vpls_per_pixel = 4096;
/// Largest interleaving pattern: beyond 8 x 8 the filter window would blur whole objects.
inline constexpr int max_interleave = 8;
/// Most bias-compensation gather rays per pixel: each takes its own share of the pixel's VPLs, so
/// more than 64 would leave most of them without one at the VPL counts interactive use has.
inline constexpr int max_compensation_rays = 64;
/// Longest temporal history: at 1024 frames the clamp has shrunk to 0.18 of its setting (the
/// fourth root), and a new frame's weight 1/1024 is still far above float rounding of the average.
inline constexpr int max_temporal_frames = 1024;
/// Longest run of frames that keep their VPLs while the camera moves: past 100000 frames (over
/// an hour at 24 frames a second) a run is as good as never refreshed.
inline constexpr int max_held_vpl_frames = 100000;
/// Most held VPL draws: a moving history averages 8 frames (TemporalReuse::moving_frames), so
/// with more draws than that some would hold no frame of the average.
inline constexpr int max_held_vpl_sets = 8;
/// Most environment directions: 1024 shadow rays per pixel for the sky alone is past any use.
inline constexpr int max_environment_directions = 1024;
/// Largest anti-aliasing factor: 64 sub-samples per pixel is past any visible gain.
inline constexpr int max_antialiasing = 64;

/// Bytes a frame keeps per pixel: linear RGB as 3 floats (Frame::hdr) and 8-bit sRGB (Frame::rgb8).
inline constexpr double frame_bytes_per_pixel = 3 * sizeof(float) + 3;

/// Throws SettingsError naming the first setting out of range, or the size if the frame would not fit in memory (see memory_budget).
inline void validate(const RenderSettings& s) {
  auto require = [](bool ok, const std::string& message) {
    if (!ok) throw SettingsError(message);
  };
  require(s.width >= 1 && s.width <= max_image_edge && s.height >= 1 && s.height <= max_image_edge,
          "size " + std::to_string(s.width) + "x" + std::to_string(s.height) + " is outside 1.." +
              std::to_string(max_image_edge) + " per side");
  if (const std::string shortfall = memory_shortfall(double(s.width) * double(s.height), frame_bytes_per_pixel);
      !shortfall.empty())
    throw SettingsError("size " + std::to_string(s.width) + "x" + std::to_string(s.height) + ": the frame " + shortfall);
  require(s.interleave >= 1 && s.interleave <= max_interleave,
          "interleave " + std::to_string(s.interleave) + " is outside 1.." + std::to_string(max_interleave));
  require(s.vpls_per_pixel >= 1 && s.vpls_per_pixel <= max_vpls_per_pixel,
          "vpls " + std::to_string(s.vpls_per_pixel) + " is outside 1.." + std::to_string(max_vpls_per_pixel));
  require(s.antialiasing >= 1 && s.antialiasing <= max_antialiasing,
          "aa " + std::to_string(s.antialiasing) + " is outside 1.." + std::to_string(max_antialiasing));
  require(s.antialiasing <= s.vpls_per_pixel,
          "aa " + std::to_string(s.antialiasing) + " exceeds vpls " + std::to_string(s.vpls_per_pixel) +
              ": each sub-sample needs at least one VPL of its own");
  require(s.environment_directions >= 0 && s.environment_directions <= max_environment_directions,
          "environment directions " + std::to_string(s.environment_directions) + " is outside 0.." +
              std::to_string(max_environment_directions));
  require(s.portal_share >= 0.0f && s.portal_share < 1.0f,
          "portal share " + std::to_string(s.portal_share) + " is outside [0, 1)");
  require(s.shadow_roulette >= 0.0f && s.shadow_roulette <= 1.0f,
          "shadow roulette " + std::to_string(s.shadow_roulette) + " is outside 0..1");
  require(s.compensation_rays >= 0 && s.compensation_rays <= max_compensation_rays,
          "compensation rays " + std::to_string(s.compensation_rays) + " is outside 0.." +
              std::to_string(max_compensation_rays));
  require(s.held_vpl_frames >= 0 && s.held_vpl_frames <= max_held_vpl_frames,
          "held VPL frames " + std::to_string(s.held_vpl_frames) + " is outside 0.." +
              std::to_string(max_held_vpl_frames));
  require(s.held_vpl_sets >= 1 && s.held_vpl_sets <= max_held_vpl_sets,
          "held VPL sets " + std::to_string(s.held_vpl_sets) + " is outside 1.." + std::to_string(max_held_vpl_sets));
  require(s.temporal_frames >= 0 && s.temporal_frames <= max_temporal_frames,
          "temporal frames " + std::to_string(s.temporal_frames) + " is outside 0.." +
              std::to_string(max_temporal_frames));
  require(s.tile_size >= 4 && s.tile_size <= 1024, "tile size " + std::to_string(s.tile_size) + " is outside 4..1024");
  require(!(s.clamp_distance != s.clamp_distance), "clamp distance is NaN");
  require(s.max_depth >= 0 && s.max_depth <= 64, "max depth " + std::to_string(s.max_depth) + " is outside 0..64");
  require(s.max_bounces >= 0 && s.max_bounces <= 64, "max bounces " + std::to_string(s.max_bounces) + " is outside 0..64");
  require(s.threads >= 0 && s.threads <= 1024, "threads " + std::to_string(s.threads) + " is outside 0..1024");
}

/// The clamp distance to use for a scene whose bounding-box diagonal is `scene_diagonal`: the
/// setting itself if >= 0, else 2% of the diagonal. That bounds one VPL's irradiance to
/// intensity/(0.02 d)^2 — bright enough to keep contact lighting in corners, small enough that
/// no single VPL makes a visible spot at 16 VPLs per pixel in the Cornell box.
inline float resolve_clamp(const RenderSettings& s, float scene_diagonal) noexcept {
  return s.clamp_distance >= 0.0f ? s.clamp_distance : 0.02f * scene_diagonal;
}

}  // namespace igi
