#pragma once
/// \file
/// The streaming IGI pipeline: one tile, breadth first, as in Benthin, Wald and Slusallek 2003.
/// For each interleaving set s and anti-aliasing sub-sample k:
///   1. primary rays of all pixels of set s in the tile (plus the filter's border, unless the
///      tiles of the frame share their borders: TileEngine::render_frame), in packets of
///      W sub-grid neighbours (Figure 2 of the paper);
///   2. their hits, kept as structure-of-arrays streams. The camera rays of the whole tile are
///      traced once before the sets (trace_camera_rays), in packets of W neighbouring pixels,
///      not of sub-grid neighbours three pixels apart: the same rays, whose hits do not depend
///      on their packet, while neighbours' rays share more of their way through the hierarchy;
///   3. the surface shader turns every hit into BRDF parameters (alpha cut-outs re-traced);
///   4. for each VPL of the set's k-th subset (and the delta lights' exact VPLs, in every
///      sub-sample), for each packet: a coherent shadow packet, one occlusion query (which passes
///      alpha cut-outs where they are transparent: occluded_by_opaque; in a scene with
///      thin-walled glass or alpha blending, shadow_transmittance dims the light by what those
///      let through), and the BRDF shader's masked contribution;
///   4b. with bias compensation (RenderSettings::compensation_rays), short gather rays from the
///       primary hits return the light the 1/d^2 clamp removed (see `compensate`);
///   5. mirror and glass rays spawned by the BRDF shader run steps 2-4 again, level by level;
///   6. the G-buffer receives irradiance, glossy radiance, albedo, normal, depth and the rest
///      (emission, the delta lights' direct light unless RenderSettings::filter_delta_lights,
///      mirror and glass paths).
/// Then the filter reconstructs irradiance, radiance is composed, luminance statistics recorded,
/// and pixels tone mapped with the previous frame's parameters.

#include <algorithm>
#include <array>
#include <bit>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <span>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/backend.hpp"
#include "igi/filters/filter.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/render/frame_state.hpp"
#include "igi/render/interleaving.hpp"
#include "igi/render/pixel_layers.hpp"
#include "igi/shading/brdf_shader.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/cutout_occlusion.hpp"
#include "igi/shading/surface_hit_builder.hpp"
#include "igi/shading/surface_shader.hpp"
#include "igi/simd/sampling.hpp"

namespace igi {

/// The camera rays' closest hits of a region, kept from trace_camera_rays (which traces each ray
/// with its pixel neighbours) until its interleaving set is shaded: one plane per field of a hit
/// the pipeline reads (the geometric normal it does not: make_surface_hit computes it from the
/// triangle), indexed by sub-sample and pixel as Pipeline::camera_hit_index says.
struct CameraHits {
  std::vector<float> distance;                           ///< The rays' tfar after intersect: hit distance, infinite on a miss.
  ///@{
  std::vector<float> u, v;                               ///< HitPacket::u, v.
  ///@}
  ///@{
  std::vector<std::uint32_t> primitive, mesh, instance;  ///< HitPacket::primID, geomID, instID.
  ///@}

  /// Room for `count` hits.
  void resize(std::size_t count) {
    for (std::vector<float>* plane : {&distance, &u, &v}) plane->resize(count);
    for (std::vector<std::uint32_t>* plane : {&primitive, &mesh, &instance}) plane->resize(count);
  }
};

/// Rays a tile traced, by kind.
struct RayCounts {
  std::uint64_t primary = 0;    ///< Camera rays, alpha cut-out continuations included.
  std::uint64_t shadow = 0;     ///< Occlusion rays towards VPLs.
  std::uint64_t secondary = 0;  ///< Mirror and glass rays, and bias compensation's gather rays.
  /// Adds another tile's counts.
  void merge(const RayCounts& o) noexcept {
    primary += o.primary;
    shadow += o.shadow;
    secondary += o.secondary;
  }
  /// All rays.
  std::uint64_t total() const noexcept { return primary + shadow + secondary; }
};

/// Where tiles' time went, stage by stage, in nanoseconds of one thread each (summed over tiles
/// and threads, CPU time). Measured only when FrameState::profile is set, else all zero.
struct StageTimes {
  std::uint64_t primary = 0;  ///< Step 1: camera rays made.
  std::uint64_t closest = 0;  ///< Step 2: closest-hit queries of camera, mirror and glass rays.
  std::uint64_t surface = 0;  ///< Step 3: hit points and the surface shader (alpha cut-outs re-traced inside).
  std::uint64_t connect = 0;  ///< Step 4 less occlusion: VPL geometry terms, shadow rays made, BRDF contributions.
  std::uint64_t shadow = 0;   ///< Step 4: occlusion queries towards the VPLs.
  std::uint64_t compensate = 0;  ///< Step 4b: gather rays made and their light added (their tracing, shading and VPLs count above).
  std::uint64_t spawn = 0;    ///< Step 5: mirror and glass rays made.
  std::uint64_t gbuffer = 0;  ///< Step 6: G-buffer writes.
  std::uint64_t filter = 0;   ///< The irradiance filter.
  std::uint64_t compose = 0;  ///< Radiance composed, luminance recorded, pixels tone mapped.
  /// Adds another tile's times.
  void merge(const StageTimes& o) noexcept {
    for (const auto& [name, field] : fields()) this->*field += o.*field;
  }
  /// All stages.
  std::uint64_t total() const noexcept {
    std::uint64_t sum = 0;
    for (const auto& [name, field] : fields()) sum += this->*field;
    return sum;
  }
  /// Calls `visit(name, nanoseconds)` for each stage in pipeline order, for reports.
  template <class Visit>
  void each(Visit&& visit) const {
    for (const auto& [name, field] : fields()) visit(name, this->*field);
  }

 private:
  /// A stage's name and its field.
  using Field = std::pair<const char*, std::uint64_t StageTimes::*>;
  /// The stages by name, in pipeline order: the one list merge, total and each walk.
  static constexpr std::array<Field, 10> fields() noexcept {
    return {{{"primary", &StageTimes::primary},
             {"closest", &StageTimes::closest},
             {"surface", &StageTimes::surface},
             {"connect", &StageTimes::connect},
             {"shadow", &StageTimes::shadow},
             {"compensate", &StageTimes::compensate},
             {"spawn", &StageTimes::spawn},
             {"gbuffer", &StageTimes::gbuffer},
             {"filter", &StageTimes::filter},
             {"compose", &StageTimes::compose}}};
  }
};

/// Adds the time from its construction to its destruction to a StageTimes field, if given one.
class StageTimer {
 public:
  /// Times into `*into`; a null `into` times nothing (profiling off).
  explicit StageTimer(std::uint64_t* into) noexcept
      : into_(into), start_(into ? std::chrono::steady_clock::now() : std::chrono::steady_clock::time_point{}) {}
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;
  ~StageTimer() {
    if (into_)
      *into_ += std::uint64_t(std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now() - start_).count());
  }

 private:
  std::uint64_t* into_;
  std::chrono::steady_clock::time_point start_;
};

/// A finished tile: its interior pixels and statistics.
struct TileResult {
  PixelRect rect;                     ///< Where the pixels go in the image.
  std::vector<glm::vec3> hdr;         ///< Linear radiance, row-major over rect.
  std::vector<glm::u8vec3> rgb8;      ///< Tone-mapped sRGB, row-major over rect.
  LuminanceStatistics luminance;      ///< For the next frame's tone mapping.
  RayCounts rays;                     ///< Work done.
  StageTimes stages;                  ///< Where the time went (with FrameState::profile).
  std::vector<PixelLayers> layers;    ///< The pixels' shading terms, row-major over rect (with FrameState::keep_layers; else empty).
};

/// The streaming pipeline over a Backend, the surface and BRDF shaders and the filter (the VPL
/// sampler has run before, in FrameState::prepare). Stateless between tiles: all per-tile memory
/// lives in a Workspace, one per thread.
template <class B, class Surface, class Brdf, class F>
  requires Backend<B> && SurfaceShader<Surface, B::width> && BrdfShader<Brdf, B::width> && Filter<F>
class Pipeline {
 public:
  /// Packet width.
  static constexpr int W = B::width;

  /// One packet of a ray stream and everything the stages compute for it. Its rays and hits are
  /// a RayHitPacket, so backends that trace both in place (Embree) find them in their layout.
  struct StreamPacket : RayHitPacket<W> {
    vmask<W> active;                ///< Lanes carrying a ray.
    vmask<W> hit;                   ///< Lanes whose ray hit something.
    vec3<W> throughput;             ///< Weight of this path in its pixel (1 for primary rays).
    int pixels = 0;                 ///< Index of the primary PixelPacket whose lanes these are.
    SurfaceHit<W> surface;          ///< Hit points.
    BrdfParameters<W> parameters;   ///< Surface shader output.
    VplReceiver<W> receiver;        ///< The shading frame every VPL shares, resolved after the surface shader.
    VplAccumulator<W> light;        ///< VPL light gathered, filtered on primary hits.
    /// Light of the delta lights' exact VPLs, composed unfiltered beside emission (zero with
    /// RenderSettings::filter_delta_lights, which gathers it into `light`).
    VplAccumulator<W> direct;
    /// Whether the lanes keep their delta lights' shadow answers (FrameState::keeps_shadows, on
    /// sub-sample 0's camera rays' hits): ShadowBits lane by lane, `reused_*` as the previous
    /// frame's histories know them (FrameState::shadow_history), `shadow_*` this frame's.
    bool keeps_shadows = false;
    ///@{
    vuint<W> reused_known, reused_visible, shadow_known, shadow_visible;  ///< One bit per FrameState::delta_lights entry.
    ///@}
  };

  /// Per-thread memory reused across tiles.
  struct Workspace {
    std::vector<PixelPacket<W>> pixels;                ///< Primary packets of the current set.
    RayHitPacket<W> camera;                            ///< trace_camera_rays' packet.
    /// The camera rays' hits of the region being shaded (trace_camera_rays), where
    /// camera_hit_index says.
    CameraHits camera_hits;
    std::vector<std::vector<StreamPacket>> levels;     ///< Stream per bounce depth.
    std::vector<StreamPacket> gather;                  ///< Bias compensation's gather rays, grouped by gather ray.
    TileGBuffer gbuffer;                               ///< Tile + border.
    FilteredTile filtered;                             ///< Filter output.
    StageTimes stages;                                 ///< The current tile's stage times.
    bool profile = false;                              ///< Whether the current tile is timed.
    /// `field` of `stages` when profiling, else null (a StageTimer then times nothing).
    std::uint64_t* timing(std::uint64_t StageTimes::*field) noexcept { return profile ? &(stages.*field) : nullptr; }
  };

  /// A pipeline over a built backend and the policies; all are borrowed, not copied.
  Pipeline(const B& backend, const Surface& surface, const Brdf& brdf, const F& filter) noexcept
      : backend_(&backend), surface_(&surface), brdf_(&brdf), filter_(&filter) {}

  /// Renders `tile` of the frame into `out`: shades it with the filter's border around it, then
  /// filters and composes it. What every tile of the MPI farm does.
  void render_tile(const FrameState& frame, const PixelRect& tile, Workspace& work, TileResult& out) const {
    const PixelRect extended = with_border(tile, border(frame));
    work.gbuffer.resize(extended.width(), extended.height());  // zero: the border outside the image stays "no hit"
    work.gbuffer.border = tile.x0 - extended.x0;
    begin_stages(frame, work);
    out.rays = {};
    shade(frame, inside_image(frame, extended), extended, work, work.gbuffer, out.rays);
    compose(frame, tile, extended, work.gbuffer, work, out);
    out.stages = work.stages;
  }

  /// The first step of a tile of a frame whose tiles share their borders (TileEngine::render_frame):
  /// shades `tile` alone into the interior of `gbuffer`, its G-buffer with `shared_border`
  /// (sized and zeroed here when its size is not that, else only its interior is written); the
  /// rays and stage times go to `rays` and `stages`.
  void shade_tile(const FrameState& frame, const PixelRect& tile, TileGBuffer& gbuffer, Workspace& work, RayCounts& rays,
                  StageTimes& stages) const {
    const PixelRect extended = with_border(tile, shared_border(frame));
    if (gbuffer.width != extended.width() || gbuffer.height != extended.height()) {
      gbuffer.resize(extended.width(), extended.height());
      gbuffer.border = tile.x0 - extended.x0;
    }
    begin_stages(frame, work);
    rays = {};
    // Shaded into the workspace's buffer, which stays in cache from tile to tile, then copied row
    // by row: written in place, the 9 sets' scattered writes to a buffer not touched since the
    // last frame took Cornell's G-buffer stage from 3 to 11 ms of CPU a frame at 640 x 480, copied 6.
    // write_gbuffer sets every entry of the tile's pixels, so a buffer of the right size is not zeroed.
    if (work.gbuffer.width != tile.width() || work.gbuffer.height != tile.height())
      work.gbuffer.resize(tile.width(), tile.height());
    work.gbuffer.border = 0;
    shade(frame, tile, tile, work, work.gbuffer, rays);
    {
      const StageTimer timer(work.timing(&StageTimes::gbuffer));
      gbuffer.copy_from(work.gbuffer, {.x = gbuffer.border, .y = gbuffer.border, .columns = tile.width(), .rows = tile.height()});
    }
    stages = work.stages;
  }

  /// The second step: `tile` filtered and composed into `out` from `gbuffer`, whose border the
  /// caller has filled with the pixels its neighbours' first steps shaded. These are the pixels
  /// render_tile makes, since a pixel's shading does not depend on the tile that holds it.
  /// `out.rays` are left for the caller (the first step counted them); `out.stages` are this step's.
  void finish_tile(const FrameState& frame, const PixelRect& tile, const TileGBuffer& gbuffer, Workspace& work,
                   TileResult& out) const {
    begin_stages(frame, work);
    compose(frame, tile, with_border(tile, shared_border(frame)), gbuffer, work, out);
    out.stages = work.stages;
  }

  /// For a StagedFilter, the steps between shade_tile and finish_staged_tile: stage `stage` of
  /// the filter over `tile`'s `gbuffer` (border filled from the neighbours) into `stages`, whose
  /// border the caller has filled with the neighbours' previous stage; its time goes to `times.filter`.
  void filter_stage(const FrameState& frame, int stage, const TileGBuffer& gbuffer, typename FilterStages<F>::type& stages,
                    StageTimes& times) const
    requires StagedFilter<F>
  {
    const StageTimer timer(frame.profile ? &times.filter : nullptr);
    filter_->run_stage(stage, gbuffer, frame.settings.interleave, stages);
  }
  /// finish_tile for a StagedFilter whose stages have all run on `stages`: their result composed into `out`.
  void finish_staged_tile(const FrameState& frame, const PixelRect& tile, const TileGBuffer& gbuffer,
                          const typename FilterStages<F>::type& stages, Workspace& work, TileResult& out) const
    requires StagedFilter<F>
  {
    begin_stages(frame, work);
    {
      const StageTimer timer(work.timing(&StageTimes::filter));
      filter_->finish(gbuffer, stages, work.filtered);
    }
    compose_filtered(frame, tile, with_border(tile, shared_border(frame)), gbuffer, work, out);
    out.stages = work.stages;
  }

  /// Pixels the filter reads around a tile.
  int border(const FrameState& frame) const { return filter_->border(frame.settings.interleave); }
  /// Pixels around a tile when the frame's tiles share their borders (shade_tile): a
  /// StagedFilter's staged_border (its stages read less each than all of them together), else `border`.
  int shared_border(const FrameState& frame) const {
    if constexpr (StagedFilter<F>)
      return filter_->staged_border(frame.settings.interleave);
    else
      return border(frame);
  }
  /// The filter.
  const F& filter() const noexcept { return *filter_; }

 private:
  /// `tile` grown by `around` pixels on each side.
  static PixelRect with_border(const PixelRect& tile, int around) noexcept {
    return {tile.x0 - around, tile.y0 - around, tile.x1 + around, tile.y1 + around};
  }

  /// The part of `rect` inside the image: only those pixels are rendered; outside ones stay
  /// "no hit" and the filter skips them.
  static PixelRect inside_image(const FrameState& frame, const PixelRect& rect) noexcept {
    return {std::max(rect.x0, 0), std::max(rect.y0, 0), std::min(rect.x1, frame.settings.width),
            std::min(rect.y1, frame.settings.height)};
  }
  /// Zeroes the workspace's stage times and sets whether they are measured.
  static void begin_stages(const FrameState& frame, Workspace& work) noexcept {
    work.stages = {};
    work.profile = frame.profile;
  }

  /// Steps 1-6 for the pixels of `rendered`, into `gbuffer`, which covers `extended`.
  void shade(const FrameState& frame, const PixelRect& rendered, const PixelRect& extended, Workspace& work,
             TileGBuffer& gbuffer, RayCounts& rays) const {
    const RenderSettings& s = frame.settings;
    const int sets = s.interleave * s.interleave;
    const float subsample_share = 1.0f / float(s.antialiasing);
    trace_camera_rays(frame, rendered, work);
    for (int set = 0; set < sets; ++set) {
      make_set_packets<W>(rendered, s.interleave, set, work.pixels);
      if (work.pixels.empty()) continue;
      for (int k = 0; k < s.antialiasing; ++k) {
        trace_primary(frame, rendered, k, work, rays);
        shade_level(frame, set, k, work, 0, rays);
        compensate(frame, set, k, work, rays);
        for (int depth = 0; depth < s.max_depth && !work.levels[depth].empty(); ++depth) {
          {
            const StageTimer timer(work.timing(&StageTimes::spawn));
            spawn_level(frame, work, depth);
          }
          if (work.levels[depth + 1].empty()) break;
          trace_level(work, work.levels[depth + 1], Coherence::incoherent, rays.secondary);
          shade_level(frame, set, k, work, depth + 1, rays);
        }
        const StageTimer timer(work.timing(&StageTimes::gbuffer));
        write_gbuffer(extended, k, subsample_share, frame.scene->environment.get(), work, gbuffer);
      }
    }
  }

  /// Sub-sample k's camera ray directions through pixels (x, y), zero on lanes off `active`:
  /// trace_camera_rays and trace_primary make them with this one function, so a set's packets
  /// get the very rays whose hits they take.
  static vec3<W> camera_directions(const FrameState& frame, int k, const vint<W>& x, const vint<W>& y,
                                   const vmask<W>& active) {
    float dx = 0.5f, dy = 0.5f;
    subsample_offset(k, frame.settings.antialiasing, dx, dy, frame.pixel_jitter);
    return keep(frame.projection->direction(convert<float>(x) + vfloat<W>(dx), convert<float>(y) + vfloat<W>(dy)),
                active);
  }

  /// Blocks of PacketShape<W> neighbouring pixels covering `region`: columns and rows of them.
  static std::pair<int, int> camera_blocks(const PixelRect& region) noexcept {
    using Shape = PacketShape<W>;
    return {(region.width() + Shape::width - 1) / Shape::width, (region.height() + Shape::height - 1) / Shape::height};
  }

  /// Step 2 for the camera rays of every sub-sample of `region`, before its sets are shaded:
  /// traced in packets of W neighbouring pixels (blocks of PacketShape<W>), whose rays stay
  /// closer together through the hierarchy than a set's, which lie S pixels apart (Sponza_lit,
  /// 640 x 480: Embree's closest-hit time per frame falls by 40%). Their hits stay in
  /// work.camera_hits, lane by lane as traced (camera_hit_index), for trace_primary. A ray's hit
  /// does not depend on the packet it is traced in, so the image is the one the sets' own
  /// packets give.
  void trace_camera_rays(const FrameState& frame, const PixelRect& region, Workspace& work) const {
    using Shape = PacketShape<W>;
    const auto [columns, rows] = camera_blocks(region);
    const int subsamples = frame.settings.antialiasing;
    const std::size_t blocks = std::size_t(columns) * std::size_t(rows);
    CameraHits& hits = work.camera_hits;
    hits.resize(blocks * std::size_t(subsamples) * W);
    const glm::vec3 eye = frame.projection->origin();
    // The lanes' pixel offsets inside a block: lane i at (i mod width, i / width).
    const vint<W> lane_x([](int i) { return i % Shape::width; }), lane_y([](int i) { return i / Shape::width; });
    // One packet, made, traced and kept block after block, stays in the first-level cache.
    RayHitPacket<W>& packet = work.camera;
    for (int k = 0; k < subsamples; ++k)
      for (int by = 0; by < rows; ++by)
        for (int bx = 0; bx < columns; ++bx) {
          vmask<W> active;
          {
            const StageTimer timer(work.timing(&StageTimes::primary));
            const vint<W> x = vint<W>(region.x0 + bx * Shape::width) + lane_x;
            const vint<W> y = vint<W>(region.y0 + by * Shape::height) + lane_y;
            active = (x < vint<W>(region.x1)) & (y < vint<W>(region.y1));
            packet.rays.set(vec3<W>(eye), camera_directions(frame, k, x, y, active), vfloat<W>(0.0f),
                            vfloat<W>(std::numeric_limits<float>::infinity()), active);
          }
          const StageTimer timer(work.timing(&StageTimes::closest));
          packet.hits.clear();
          backend_->intersect(packet.rays, packet.hits, Coherence::coherent, active);
          const std::size_t block = (std::size_t(k) * std::size_t(rows) + std::size_t(by)) * std::size_t(columns) + std::size_t(bx);
          const auto keep_plane = [&](const auto* lanes, auto& plane) {
            std::copy(lanes, lanes + W, plane.begin() + std::ptrdiff_t(block * W));
          };
          keep_plane(packet.rays.tfar, hits.distance);
          keep_plane(packet.hits.u, hits.u);
          keep_plane(packet.hits.v, hits.v);
          keep_plane(packet.hits.primID, hits.primitive);
          keep_plane(packet.hits.geomID, hits.mesh);
          keep_plane(packet.hits.instID, hits.instance);
        }
  }

  /// Where trace_camera_rays left sub-sample k's ray through pixel (x, y) of `region`: its
  /// block's lanes, block after block, row by row, sub-sample after sub-sample.
  static vint<W> camera_hit_index(const PixelRect& region, int k, const vint<W>& x, const vint<W>& y) noexcept {
    using Shape = PacketShape<W>;
    const auto [columns, rows] = camera_blocks(region);
    // Shapes are powers of two: shifts and masks, not the lane-by-lane integer divisions.
    constexpr int column_shift = std::countr_zero(unsigned(Shape::width)), row_shift = std::countr_zero(unsigned(Shape::height));
    const vint<W> column = x - vint<W>(region.x0), row = y - vint<W>(region.y0);
    const vint<W> block = vint<W>(k * rows * columns) + (row >> row_shift) * vint<W>(columns) + (column >> column_shift);
    return (block << std::countr_zero(unsigned(W))) + ((row & vint<W>(Shape::height - 1)) << column_shift) +
           (column & vint<W>(Shape::width - 1));
  }

  /// Steps 1-2: primary rays of sub-sample k for every pixel packet of the set, with the hits
  /// trace_camera_rays found for them in `region` (the rays counted here, once).
  void trace_primary(const FrameState& frame, const PixelRect& region, int k, Workspace& work, RayCounts& counts) const {
    ensure_levels(work, frame.settings.max_depth + 1);
    auto& level = work.levels[0];
    const CameraHits& hits = work.camera_hits;
    const StageTimer timer(work.timing(&StageTimes::primary));
    level.resize(work.pixels.size());
    const vec3<W> eye(frame.projection->origin());
    for (std::size_t p = 0; p < work.pixels.size(); ++p) {
      const PixelPacket<W>& pixels = work.pixels[p];
      StreamPacket& packet = level[p];
      packet.pixels = int(p);
      packet.active = vmask<W>::first(pixels.count);
      packet.throughput = vec3<W>(glm::vec3(1.0f));
      // Lanes past the count hold the first lane's pixel (make_set_packets), so every gathered
      // index addresses an element; their ray and hit are then made what RayPacket::set and
      // HitPacket::clear() make inactive lanes.
      const vint<W> x = vint<W>::load(pixels.x), y = vint<W>::load(pixels.y);
      const vmask<W>& active = packet.active;
      const vint<W> at = camera_hit_index(region, k, x, y);
      packet.rays.set(eye, camera_directions(frame, k, x, y, active), vfloat<W>(0.0f),
                      gather_every(hits.distance.data(), at), active);
      packet.hits.clear();
      const vfloat<W> zero(0.0f);
      const vuint<W> no_id(invalid_id);
      select(active, gather_every(hits.u.data(), at), zero).store(packet.hits.u);
      select(active, gather_every(hits.v.data(), at), zero).store(packet.hits.v);
      select(active, gather_every(hits.primitive.data(), at), no_id).store(packet.hits.primID);
      select(active, gather_every(hits.mesh.data(), at), no_id).store(packet.hits.geomID);
      select(active, gather_every(hits.instance.data(), at), no_id).store(packet.hits.instID);
      counts.primary += std::uint64_t(popcount(active));
    }
  }

  /// Step 2 for a whole stream: camera rays are `coherent`, mirror and glass rays not (a curved
  /// or bumpy surface scatters them; Embree traces such packets faster flagged incoherent).
  void trace_level(Workspace& work, std::vector<StreamPacket>& level, Coherence coherence, std::uint64_t& count) const {
    const StageTimer timer(work.timing(&StageTimes::closest));
    for (StreamPacket& packet : level) {
      packet.hits.clear();
      if (none(packet.active)) continue;  // a gather packet whose lanes all missed or face away
      backend_->intersect(packet.rays, packet.hits, coherence, packet.active);
      count += std::uint64_t(popcount(packet.active));
    }
  }

  /// Steps 3-4 for the stream at `depth`: surface shading (with alpha cut-outs), then each VPL
  /// of sub-sample k's subset of set `set` against every packet.
  void shade_level(const FrameState& frame, int set, int k, Workspace& work, int depth, RayCounts& counts) const {
    auto& level = work.levels[depth];
    {
      const StageTimer timer(work.timing(&StageTimes::surface));
      const float cone_spread = depth == 0 ? camera_cone_spread(frame) : 0.0f;
      for (StreamPacket& packet : level) {
        shade_surface(frame, packet, depth == 0 ? Coherence::coherent : Coherence::incoherent,
                      depth == 0 ? counts.primary : counts.secondary, cone_spread);
        packet.light = {};
        packet.direct = {};
      }
    }
    {
      const StageTimer timer(work.timing(&StageTimes::shadow));
      for (StreamPacket& packet : level) recall_shadows(frame, depth == 0 && k == 0, work, packet);
    }
    const int subsets = frame.settings.antialiasing;
    // Each subset alone estimates the full light, so a sub-sample's subset is weighted by N.
    gather_vpls(frame, set, std::size_t(k), std::size_t(subsets), float(subsets),
                frame.settings.filter_delta_lights ? DeltaLights::filtered : DeltaLights::composed, level, work, counts);
  }

  /// Sets up `packet`'s shadow answers: kept if `first_hits` (sub-sample 0's camera rays) and the
  /// frame keeps them, with the previous frame's answers at each hit where the frame has them
  /// (TemporalReuse::previous_shadows), except on the pixels whose turn it is to trace every ray
  /// again (shadow_refresh_frames).
  void recall_shadows(const FrameState& frame, bool first_hits, const Workspace& work, StreamPacket& packet) const {
    const vuint<W> none_known(0u);
    packet.keeps_shadows = first_hits && frame.keeps_shadows;
    packet.reused_known = packet.reused_visible = packet.shadow_known = packet.shadow_visible = none_known;
    if (!packet.keeps_shadows || frame.shadow_history == nullptr) return;
    const vuint<W> pixel = pixel_indices(work.pixels[std::size_t(packet.pixels)], frame.settings.width);
    alignas(64) std::uint32_t known[W] = {}, visible[W] = {};
    for (int i = 0; i < W; ++i) {
      if (!packet.hit[i] || (pixel[i] + frame.index) % shadow_refresh_frames == 0) continue;
      const ShadowBits before = frame.shadow_history->previous_shadows(packet.surface.position[i], packet.parameters.normal[i],
                                                                       packet.surface.distance[i]);
      const ShadowBits now = renumber(before, frame.previous_shadow_bit, frame.delta_lights.size());
      known[i] = now.known;
      visible[i] = now.visible;
    }
    packet.reused_known = vuint<W>::load(known);
    packet.reused_visible = vuint<W>::load(visible);
  }

  /// What gather_vpls does with the exact VPLs of delta lights (point, spot, directional).
  enum class DeltaLights {
    in_turn,   ///< As any VPL: in the subset whose turn it is (bias compensation's gather rays).
    filtered,  ///< Every sub-sample's, at weight 1, into `light`.
    composed,  ///< Every sub-sample's, at weight 1, into `direct`.
  };

  /// Step 4 for `packets`: VPLs first, first + stride, ... of set `set`, each weighted by
  /// `weight`, against every packet, into each packet's `light`, and the delta lights' VPLs as
  /// `delta` says. The loop is timed whole as `connect`, its occlusion queries also alone as
  /// `shadow`, which is then taken out of `connect`.
  void gather_vpls(const FrameState& frame, int set, std::size_t first, std::size_t stride, float weight,
                   DeltaLights delta, std::span<StreamPacket> packets, Workspace& work, RayCounts& counts) const {
    const std::uint64_t shadow_before = work.stages.shadow;
    std::uint64_t vpl_loop = 0;
    {
      const StageTimer loop_timer(work.profile ? &vpl_loop : nullptr);
      const std::vector<Vpl>& vpls = frame.vpls.sets[std::size_t(set)];
      const float roulette = frame.settings.shadow_roulette;
      // Out of turn, a delta light's one VPL lights every sub-sample at weight 1, so a pixel's
      // sub-samples average its exact light over the pixel's area (in a subset it would light
      // one sub-sample N-fold); the other VPLs take turns.
      for (std::size_t j = 0; j < vpls.size(); ++j) {
        const Vpl& vpl = vpls[j];
        const bool exact = delta != DeltaLights::in_turn && vpl.kind != VplKind::surface;
        const bool turn = j >= first && (j - first) % stride == 0;
        if (!exact && !turn) continue;
        // A delta light's bit in the packets' shadow answers (-1: none kept for it).
        const int bit = exact ? frame.delta_light_bit(vpl) : -1;
        const vuint<W> flag(bit >= 0 ? 1u << bit : 0u);
        const glm::vec3 intensity = vpl.intensity * (exact ? 1.0f : weight);
        VplAccumulator<W> StreamPacket::*const into =
            exact && delta == DeltaLights::composed ? &StreamPacket::direct : &StreamPacket::light;
        for (StreamPacket& packet : packets) {
          if (none(packet.hit)) continue;
          const VplGeometry<W> geometry =
              connect(vpl, packet.surface.position, packet.surface.geometric_normal, frame.clamp_distance, packet.hit);
          if (none(geometry.reaches)) continue;
          RayPacket<W> shadow;
          const vec3<W> origin = packet.surface.position + packet.surface.geometric_normal * vfloat<W>(frame.ray_epsilon);
          // The shadow ray stops short of the VPL by the offset so it does not hit the VPL's own surface.
          const vfloat<W> length = max(geometry.distance - vfloat<W>(2.0f * frame.ray_epsilon), vfloat<W>(0.0f));
          shadow.set(origin, geometry.wi, vfloat<W>(0.0f), length, geometry.reaches);
          if (roulette > 0.0f) {
            play_roulette(frame, std::uint32_t(j), packet, geometry, intensity, shadow, packet.*into, work, counts);
            continue;
          }
          if (frame.see_through.any()) {
            VplAccumulator<W> light;
            add_vpl(packet, geometry, intensity, light, geometry.reaches);
            add_through(frame, light, vfloat<W>(1.0f), shadow, geometry.reaches, packet.*into, work, counts);
            continue;
          }
          // Lanes whose answer the previous frame gives (none unless the packet keeps answers).
          const bool keeps = bit >= 0 && packet.keeps_shadows;
          vmask<W> answered, answered_visible;
          if (keeps) {
            const vuint<W> no_bit(0u);
            answered = geometry.reaches & ((packet.reused_known & flag) != no_bit);
            answered_visible = answered & ((packet.reused_visible & flag) != no_bit);
          }
          const vmask<W> traced = geometry.reaches & !answered;
          vmask<W> occluded;
          if (any(traced)) {
            const StageTimer timer(work.timing(&StageTimes::shadow));
            occluded = occluded_by_opaque(frame, shadow, traced);
          }
          counts.shadow += std::uint64_t(popcount(traced));
          const vmask<W> visible = (traced & !occluded) | answered_visible;
          if (keeps) {
            packet.shadow_known = packet.shadow_known | keep(flag, geometry.reaches);
            packet.shadow_visible = packet.shadow_visible | keep(flag, visible);
          }
          add_vpl(packet, geometry, intensity, packet.*into, visible);
        }
      }
    }
    if (work.profile) work.stages.connect += vpl_loop - (work.stages.shadow - shadow_before);
  }

  /// Lanes of `mask` an opaque surface blocks on the way along `shadow` (igi::occluded_by_opaque:
  /// alpha cut-outs pass light where they are transparent). Shadow rays all end at one VPL:
  /// coherent, even from a mirror's scattered hit points.
  vmask<W> occluded_by_opaque(const FrameState& frame, RayPacket<W>& shadow, const vmask<W>& mask) const {
    return igi::occluded_by_opaque(*backend_, *surface_, *frame.scene, frame.geometry, frame.cutouts, frame.ray_epsilon, shadow,
                                   Coherence::coherent, mask);
  }

  /// Step 4 in a scene with see-through surfaces (thin-walled glass, alpha blending): `light`,
  /// one VPL's unoccluded light on the lanes of `traced`, times `weight`, times what gets through
  /// to the VPL along `shadow` (igi::shadow_transmittance, per colour), into `into`.
  void add_through(const FrameState& frame, const VplAccumulator<W>& light, const vfloat<W>& weight, RayPacket<W>& shadow,
                   const vmask<W>& traced, VplAccumulator<W>& into, Workspace& work, RayCounts& counts) const {
    vec3<W> passed;
    {
      const StageTimer timer(work.timing(&StageTimes::shadow));
      passed = shadow_transmittance(*backend_, *surface_, *frame.scene, frame.geometry, frame.cutouts, frame.see_through,
                                    frame.ray_epsilon, shadow, Coherence::coherent, traced);
    }
    counts.shadow += std::uint64_t(popcount(traced));
    passed = passed * weight;
    into.irradiance += keep(light.irradiance * passed, traced);
    into.glossy += keep(light.glossy * passed, traced);
  }

  /// Step 4 for one VPL and packet with shadow-ray Russian roulette: the VPL's unoccluded light is
  /// computed first; on lanes where it is below `shadow_roulette` x what the pixel gathered so far
  /// (its `light` and `direct`, both as the sum of irradiance and pi x glossy radiance over the
  /// channels) the shadow ray is traced with probability p = light / (shadow_roulette x gathered)
  /// and the light, if visible, weighted 1/p and added to `into`. The random number is hashed
  /// from the pixel, the VPL's index in its set, the frame index and the seed, so every packet
  /// width, tile, thread and process makes the same choice.
  void play_roulette(const FrameState& frame, std::uint32_t vpl_index, StreamPacket& packet, const VplGeometry<W>& geometry,
                     const glm::vec3& intensity, RayPacket<W>& shadow, VplAccumulator<W>& into, Workspace& work,
                     RayCounts& counts) const {
    VplAccumulator<W> light;
    add_vpl(packet, geometry, intensity, light, geometry.reaches);
    const auto size = [](const VplAccumulator<W>& a) {
      const vec3<W> sum = a.irradiance + a.glossy * vfloat<W>(std::numbers::pi_v<float>);
      return sum.x + sum.y + sum.z;
    };
    const vfloat<W> threshold = (size(packet.light) + size(packet.direct)) * vfloat<W>(frame.settings.shadow_roulette);
    const vfloat<W> gain = size(light);
    const vmask<W> faint = geometry.reaches & (gain < threshold);
    vmask<W> traced = geometry.reaches;
    vfloat<W> boost(1.0f);
    if (any(faint)) {
      const vuint<W> pixel = pixel_indices(work.pixels[std::size_t(packet.pixels)], frame.settings.width);
      const std::uint32_t key = hash(hash(frame.index, frame.settings.seed), vpl_index);
      const vfloat<W> u = to_unit_float(hash(hash(pixel) ^ vuint<W>(key)));
      // On faint lanes gain < threshold, so the probability is below 1 (and above 0 where light arrives).
      const vfloat<W> probability = select(faint, gain / select(faint, threshold, vfloat<W>(1.0f)), vfloat<W>(1.0f));
      traced = geometry.reaches & ((!faint) | (u < probability));
      boost = select(faint, vfloat<W>(1.0f) / max(probability, vfloat<W>(std::numeric_limits<float>::min())), boost);
    }
    if (none(traced)) return;
    if (frame.see_through.any()) {
      add_through(frame, light, boost, shadow, traced, into, work, counts);
      return;
    }
    vmask<W> occluded;
    {
      const StageTimer timer(work.timing(&StageTimes::shadow));
      occluded = occluded_by_opaque(frame, shadow, traced);
    }
    counts.shadow += std::uint64_t(popcount(traced));
    const vmask<W> visible = traced & !occluded;
    into.irradiance += keep(light.irradiance * boost, visible);
    into.glossy += keep(light.glossy * boost, visible);
  }

  /// Step 4b, bias compensation (Kollig and Keller, "Illumination in the presence of weak
  /// singularities", 2004) for the primary hits of sub-sample k. The clamp replaces 1/d^2 by
  /// 1/max(d^2, c^2); the light it removes is that of the surfaces y closer than c, weighted by
  /// 1 - d^2/c^2. R gather rays per pixel, cosine-distributed around the shading normal and
  /// traced no further than c, find those surfaces; each hit y is lit by its own share of the
  /// pixel's VPLs (gather ray g takes every R-th VPL of the sub-sample's subset, weighted by R,
  /// so the R rays together cost at most one pass over the set) plus its emission, and
  /// pi x L(y) x (1 - d^2/c^2) / R is added to the pixel's irradiance, which is then filtered
  /// with the rest. The estimate is unbiased for the diffuse part up to L(y)'s own clamp (a
  /// second-order term); glossy lobes' light near their VPLs is not returned. Gather directions
  /// are hashed from the pixel, the frame index, the seed, k and g: the same on every tile,
  /// thread, process and packet width.
  void compensate(const FrameState& frame, int set, int k, Workspace& work, RayCounts& counts) const {
    const int rays = frame.settings.compensation_rays;
    const float reach = frame.clamp_distance;
    auto& level = work.levels[0];
    auto& gather = work.gather;
    gather.clear();
    if (rays <= 0 || !(reach > 0.0f)) return;
    {
      // Only the making and the adding count as `compensate`; tracing, shading and VPLs go to their own stages.
      const StageTimer timer(work.timing(&StageTimes::compensate));
      const std::uint32_t frame_key = hash(hash(frame.index, frame.settings.seed), std::uint32_t(k));
      for (int g = 0; g < rays; ++g)
        for (std::size_t p = 0; p < level.size(); ++p) {
          const StreamPacket& packet = level[p];
          StreamPacket& child = gather.emplace_back();
          child.pixels = packet.pixels;
          child.active = packet.hit & packet.parameters.opaque;
          if (none(child.active)) continue;
          const vec3<W>& normal = packet.receiver.normal;
          const vuint<W> pixel = pixel_indices(work.pixels[std::size_t(packet.pixels)], frame.settings.width);
          vec3<W> direction;
          for (int i = 0; i < W; ++i) {
            if (!child.active[i]) continue;
            Rng rng(hash(hash(frame_key, pixel[i]), std::uint32_t(g)));
            const float u1 = rng.next(), u2 = rng.next();
            direction.set(i, sample_cosine_hemisphere(normal[i], u1, u2));
          }
          // A direction below the geometric surface would start inside the object: that lane gathers nothing.
          child.active &= dot(direction, packet.surface.geometric_normal) > vfloat<W>(0.0f);
          child.rays.set(leave_surface(packet.surface.position, packet.surface.geometric_normal, direction, frame.ray_epsilon),
                         direction, vfloat<W>(0.0f), vfloat<W>(reach), child.active);
        }
    }
    trace_level(work, gather, Coherence::incoherent, counts.secondary);
    {
      const StageTimer timer(work.timing(&StageTimes::surface));
      for (StreamPacket& packet : gather) {
        shade_surface(frame, packet, Coherence::incoherent, counts.secondary);
        packet.light = {};
      }
    }
    const std::size_t subsets = std::size_t(frame.settings.antialiasing);
    const std::span<StreamPacket> all(gather);
    for (int g = 0; g < rays; ++g)
      gather_vpls(frame, set, std::size_t(k) + std::size_t(g) * subsets, subsets * std::size_t(rays),
                  float(subsets) * float(rays), DeltaLights::in_turn, all.subspan(std::size_t(g) * level.size(), level.size()),
                  work, counts);
    {
      const StageTimer timer(work.timing(&StageTimes::compensate));
      const float inverse_reach2 = 1.0f / (reach * reach);
      for (int g = 0; g < rays; ++g)
        for (std::size_t p = 0; p < level.size(); ++p) {
          const StreamPacket& ray = gather[std::size_t(g) * level.size() + p];
          if (none(ray.hit)) continue;
          const vfloat<W> distance = ray.surface.distance;
          const vfloat<W> share = max(vfloat<W>(1.0f) - distance * distance * vfloat<W>(inverse_reach2), vfloat<W>(0.0f)) *
                                  vfloat<W>(std::numbers::pi_v<float> / float(rays));
          const vec3<W> radiance = ray.parameters.emission + ray.parameters.albedo * ray.light.irradiance * vfloat<W>(inv_pi) +
                                   ray.light.glossy;
          level[p].light.irradiance += keep(radiance * share, ray.hit);
        }
    }
  }

  /// How much a camera ray's cone widens per unit of distance: one pixel, shared by the N
  /// sub-samples (each covers 1/N of its area: a side of 1/sqrt(N)), times the frame's
  /// texture_cone_scale; 0 without texture filtering.
  static float camera_cone_spread(const FrameState& frame) noexcept {
    if (!frame.settings.filter_textures) return 0.0f;
    return frame.texture_cone_scale * frame.projection->pixel_spread() / std::sqrt(float(frame.settings.antialiasing));
  }

  /// Step 3 for one packet: hit points (with ray cones that widen by `cone_spread` per unit of
  /// distance, for the textures' footprint; 0: none), BRDF parameters, and rays continued
  /// through alpha cut-outs (traced with the `coherence` of the packet's level).
  void shade_surface(const FrameState& frame, StreamPacket& packet, Coherence coherence, std::uint64_t& count,
                     float cone_spread = 0.0f) const {
    packet.hit = packet.active & packet.hits.valid();
    packet.surface = make_surface_hit(*frame.scene, frame.geometry, packet.rays, packet.hits, packet.hit, cone_spread);
    packet.parameters = surface_->shade(packet.surface, packet.hit);
    for (int layer = 0; layer < max_cutout_layers; ++layer) {
      const vmask<W> pass = packet.hit & !packet.parameters.opaque;
      if (none(pass)) break;
      // Continue the passing lanes from just behind the cut-out surface.
      const vfloat<W> t = packet.rays.far();
      select(pass, t + vfloat<W>(frame.ray_epsilon), packet.rays.near()).store(packet.rays.tnear);
      select(pass, vfloat<W>(std::numeric_limits<float>::infinity()), t).store(packet.rays.tfar);
      for (int i = 0; i < W; ++i)
        if (pass[i]) packet.hits.geomID[i] = packet.hits.instID[i] = packet.hits.primID[i] = invalid_id;
      backend_->intersect(packet.rays, packet.hits, coherence, pass);
      count += std::uint64_t(popcount(pass));
      const vmask<W> again = pass & packet.hits.valid();
      packet.hit = (packet.hit & !pass) | again;
      const SurfaceHit<W> surface = make_surface_hit(*frame.scene, frame.geometry, packet.rays, packet.hits, again, cone_spread);
      const BrdfParameters<W> parameters = surface_->shade(surface, again);
      packet.surface.assign(surface, again);
      packet.parameters.assign(parameters, again);
      if (layer + 1 == max_cutout_layers) packet.hit &= packet.parameters.opaque;  // give up: treat as opaque miss
    }
    packet.receiver = make_vpl_receiver(packet.surface, packet.parameters);
  }

  /// The BRDF shader's contribution of one VPL to `packet`'s lanes of `mask`, through the
  /// packet's resolved receiver where the shader takes one.
  void add_vpl(const StreamPacket& packet, const VplGeometry<W>& geometry, const glm::vec3& intensity,
               VplAccumulator<W>& accumulator, const vmask<W>& mask) const noexcept {
    if constexpr (ReceiverBrdfShader<Brdf, W>)
      brdf_->add_vpl(packet.receiver, packet.parameters, geometry, intensity, accumulator, mask);
    else
      brdf_->add_vpl(packet.surface, packet.parameters, geometry, intensity, accumulator, mask);
  }

  /// Step 5: the BRDF shader's reflection and refraction rays of level `depth` become level depth+1.
  void spawn_level(const FrameState& frame, Workspace& work, int depth) const {
    auto& next = work.levels[std::size_t(depth) + 1];
    next.clear();
    for (StreamPacket& packet : work.levels[std::size_t(depth)]) {
      if (none(packet.hit)) continue;
      SecondaryRays<W> reflection, refraction;
      if (none(brdf_->spawn(packet.surface, packet.parameters, reflection, refraction, packet.hit))) continue;
      for (const SecondaryRays<W>* rays : {&reflection, &refraction}) {
        if (none(rays->active)) continue;
        StreamPacket& child = next.emplace_back();
        child.pixels = packet.pixels;
        child.active = rays->active;
        child.throughput = keep(packet.throughput * rays->weight, rays->active);
        child.rays.set(leave_surface(packet.surface.position, packet.surface.geometric_normal, rays->direction, frame.ray_epsilon),
                       rays->direction, vfloat<W>(0.0f),
                       vfloat<W>(std::numeric_limits<float>::infinity()), rays->active);
      }
    }
  }

  /// Step 6: sub-sample k's results into `g`, which covers `extended` (first-hit normal and depth
  /// from sub-sample 0). Sub-sample 0's camera rays set their pixels' every entry (0 + x is x, so
  /// the buffer needs no zeroing first), later ones and deeper levels add. Rays that left the
  /// scene bring the `environment`'s radiance (none if null).
  static void write_gbuffer(const PixelRect& extended, int k, float share, const Environment* environment, const Workspace& work,
                            TileGBuffer& g) {
    for (std::size_t level = 0; level < work.levels.size(); ++level) {
      for (const StreamPacket& packet : work.levels[level]) {
        const PixelPacket<W>& pixels = work.pixels[std::size_t(packet.pixels)];
        // Radiance not filtered: emission and the delta lights' direct light, plus for deeper
        // levels everything they gathered.
        vec3<W> rest = packet.parameters.emission + packet.parameters.albedo * packet.direct.irradiance * vfloat<W>(inv_pi) +
                       packet.direct.glossy;
        if (level > 0)
          rest += packet.parameters.albedo * packet.light.irradiance * vfloat<W>(inv_pi) +
                  packet.light.glossy;
        rest = keep(packet.throughput * rest, packet.hit);
        if (const vmask<W> missed = packet.active & !packet.hit; environment && any(missed)) {
          const vec3<W> direction = packet.rays.direction();
          for (int i = 0; i < W; ++i)
            if (missed[i]) rest.set(i, packet.throughput[i] * environment->radiance(glm::normalize(direction[i])));
        }
        for (int i = 0; i < pixels.count; ++i) {
          if (!packet.active[i]) continue;
          const std::size_t at = g.index(pixels.x[i] - extended.x0, pixels.y[i] - extended.y0);
          if (level > 0) {
            g.radiance[at] += rest[i] * share;
            continue;
          }
          if (k == 0) {
            const bool hit = packet.hit[i];
            g.radiance[at] = rest[i] * share;
            g.irradiance[at] = packet.light.irradiance[i] * share;
            g.glossy[at] = packet.light.glossy[i] * share;
            g.albedo[at] = packet.parameters.albedo[i] * share;
            g.hit[at] = hit ? 1.0f : 0.0f;
            g.normal[at] = hit ? packet.parameters.normal[i] : glm::vec3(0.0f);
            g.depth[at] = hit ? packet.surface.distance[i] : 0.0f;
            g.shadows[at] = hit ? ShadowBits{packet.shadow_known[i], packet.shadow_visible[i]} : ShadowBits{};
            continue;
          }
          g.radiance[at] += rest[i] * share;
          g.irradiance[at] += packet.light.irradiance[i] * share;
          g.glossy[at] += packet.light.glossy[i] * share;
          g.albedo[at] += packet.parameters.albedo[i] * share;
        }
      }
    }
  }

  /// After all sets: filter, compose, record statistics, tone map.
  void compose(const FrameState& frame, const PixelRect& tile, const PixelRect& extended, const TileGBuffer& g,
               Workspace& work, TileResult& out) const {
    {
      const StageTimer timer(work.timing(&StageTimes::filter));
      filter_->apply(g, frame.settings.interleave, work.filtered);
    }
    compose_filtered(frame, tile, extended, g, work, out);
  }
  /// compose after the filter: `work.filtered` and the G-buffer's unfiltered layers into `out`.
  void compose_filtered(const FrameState& frame, const PixelRect& tile, const PixelRect& extended, const TileGBuffer& g,
                        Workspace& work, TileResult& out) const {
    const StageTimer timer(work.timing(&StageTimes::compose));
    const FilteredTile& filtered = work.filtered;
    out.rect = tile;
    const std::size_t n = std::size_t(tile.width()) * std::size_t(tile.height());
    out.hdr.resize(n);
    out.rgb8.resize(n);
    out.layers.resize(frame.keep_layers ? n : 0);
    LuminanceAccumulator luminance;
    const int border = tile.x0 - extended.x0;
    for (int y = 0; y < tile.height(); ++y)
      for (int x = 0; x < tile.width(); ++x) {
        const std::size_t at = g.index(x + border, y + border);
        const std::size_t inner = std::size_t(y) * std::size_t(tile.width()) + std::size_t(x);
        const PixelLayers layers{.irradiance = filtered.irradiance[inner],
                                 .glossy = filtered.glossy[inner],
                                 .albedo = g.albedo[at],
                                 .rest = g.radiance[at],
                                 .normal = g.normal[at],
                                 .depth = g.depth[at],
                                 .hit = g.hit[at] != 0.0f,
                                 .shadows = g.shadows[at]};
        const glm::vec3 radiance = layers.radiance();
        if (frame.keep_layers) out.layers[inner] = layers;
        out.hdr[inner] = radiance;
        luminance.add(radiance);
        out.rgb8[inner] = quantize_srgb(frame.tone_mapping.apply(radiance));
      }
    out.luminance = luminance.statistics();
  }

  /// Row-major image index y x width + x of each lane's pixel, 0 on lanes past the packet's count:
  /// what the roulette's and the gather rays' random numbers are hashed from.
  static vuint<W> pixel_indices(const PixelPacket<W>& pixels, int width) noexcept {
    return vuint<W>([&](int i) {
      return i < pixels.count ? std::uint32_t(pixels.y[i]) * std::uint32_t(width) + std::uint32_t(pixels.x[i]) : 0u;
    });
  }

  /// Makes sure the stream vector has a level per depth.
  static void ensure_levels(Workspace& work, int levels) {
    if (int(work.levels.size()) < levels) work.levels.resize(std::size_t(levels));
    for (auto& level : work.levels) level.clear();
  }

  const B* backend_;
  const Surface* surface_;
  const Brdf* brdf_;
  const F* filter_;
};

}  // namespace igi
