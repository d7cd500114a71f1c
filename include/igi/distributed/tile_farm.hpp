#pragma once
/// \file
/// The paper's tile farm (Benthin, Wald, Slusallek 2003, section 3.4) on MPI. Rank 0 is the
/// master and display: it broadcasts each frame's header (scene changes, tone mapping, frame
/// index), hands out tiles on demand (a worker asks again when it has finished; no static
/// partition), places the RGB8 pixels that come back, combines the tiles' luminance statistics and
/// uses them for the next frame's tone mapping (one frame of latency). Workers build their own
/// VPLs from the frame index, and render, filter and tone map their tiles themselves. With one
/// rank, rank 0 renders every tile itself.

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include <mpi.h>

#include "igi/distributed/messages.hpp"
#include "igi/distributed/mpi.hpp"
#include "igi/distributed/tile_renderer.hpp"
#include "igi/render/renderer.hpp"

namespace igi {

/// Message tags of the tile farm.
enum FarmTag : int {
  farm_tag_request = 101,     ///< Worker to master: int32 number of tiles wanted.
  farm_tag_assignment = 102,  ///< Master to worker: int32 tile indices; none means "frame done for you".
  farm_tag_tile = 103,        ///< Worker to master: an encoded TileMessage.
};

/// How the farm runs.
struct FarmOptions {
  int slow_rank = -1;          ///< Test hook: this rank is slowed artificially (-1: none).
  double slow_factor = 1.0;    ///< The slowed rank sleeps (factor - 1) x each tile's render time after it.
  bool hdr_output = false;     ///< Workers send linear radiance every frame (for HDR image output).
  int tiles_per_request = 0;   ///< Tiles a worker asks for at once; 0 means its thread count.
  bool prefetch = false;       ///< Workers ask for the next tiles when they start a batch, not when they finish it.
};

/// What one frame cost, as rank 0 saw it.
struct ClusterFrameReport {
  std::uint32_t index = 0;              ///< Frame index.
  double milliseconds = 0.0;            ///< From the header broadcast to the last pixel placed (and re-mapped).
  std::uint64_t bytes_to_master = 0;    ///< Every byte rank 0 received: tile messages and tile requests.
  std::uint64_t pixel_bytes = 0;        ///< Of those, RGB8 (and HDR when asked for) pixel payload.
  std::uint64_t header_bytes = 0;       ///< Bytes of the broadcast frame header (per receiving rank).
  std::uint64_t tile_messages = 0;      ///< Tile messages received.
  bool hdr_sent = false;                ///< Whether workers sent HDR pixels this frame.
  std::vector<int> tiles_per_rank;      ///< Tiles each rank rendered (rank 0 only when alone).
  double tile_milliseconds = 0.0;       ///< Sum of the tiles' render times on their ranks (work done).
  RayCounts rays;                       ///< Rays traced.
  LuminanceStatistics luminance;        ///< Combined statistics (in tile order).
  /// Frames per second at rank 0.
  double fps() const noexcept { return milliseconds > 0.0 ? 1000.0 / milliseconds : 0.0; }
};

/// The tile farm over a communicator. Every rank constructs one with a TileRenderer over the same
/// scene and settings; rank 0 calls render_frame for each frame and shutdown at the end, the
/// others call serve, which returns after shutdown.
template <class B, class Surface, class Brdf, class Sampler, class F>
class TileFarm {
 public:
  /// The per-rank renderer type.
  using RendererType = TileRenderer<B, Surface, Brdf, Sampler, F>;

  /// Joins the farm; collective. Throws DistributedError if the ranks disagree on image, tiles or scene.
  TileFarm(MPI_Comm comm, RendererType& renderer, const FarmOptions& options)
      : comm_(comm), renderer_(&renderer), options_(options) {
    check_mpi(MPI_Comm_rank(comm, &rank_), "MPI_Comm_rank");
    check_mpi(MPI_Comm_size(comm, &size_), "MPI_Comm_size");
    if (options.slow_factor < 1.0 || !std::isfinite(options.slow_factor))
      throw SettingsError("slow factor " + std::to_string(options.slow_factor) + " must be finite and >= 1");
    if (options.tiles_per_request < 0) throw SettingsError("tiles per request must be >= 0");
    const RenderSettings& s = renderer.settings();
    const Scene& scene = renderer.scene();
    // Every rank must cut the same tiles of the same scene, or pixels would land in the wrong place.
    const std::int64_t fingerprint[6] = {s.width, s.height, s.tile_size, std::int64_t(scene.instances.size()),
                                         std::int64_t(scene.lights.size()), std::int64_t(scene.triangle_count())};
    std::int64_t low[6], high[6];
    check_mpi(MPI_Allreduce(fingerprint, low, 6, MPI_INT64_T, MPI_MIN, comm), "MPI_Allreduce");
    check_mpi(MPI_Allreduce(fingerprint, high, 6, MPI_INT64_T, MPI_MAX, comm), "MPI_Allreduce");
    for (int i = 0; i < 6; ++i)
      if (low[i] != high[i])
        throw DistributedError("ranks disagree on image size, tile size or scene (instances, lights, triangles)");
  }

  /// This rank.
  int rank() const noexcept { return rank_; }
  /// Ranks in the farm.
  int size() const noexcept { return size_; }
  /// The report of the last frame rank 0 rendered.
  const ClusterFrameReport& report() const noexcept { return report_; }

  /// Rank 0: renders frame `index` with `changes` on the workers (alone if there are none).
  /// The first frame, having no previous statistics, is re-mapped with its own, as Renderer does.
  Frame render_frame(const SceneChanges& changes, std::uint32_t index) {
    if (rank_ != 0) throw DistributedError("render_frame is for rank 0; other ranks call serve()");
    changes.check(renderer_->scene());
    const auto start = std::chrono::steady_clock::now();
    const RenderSettings& s = renderer_->settings();
    const std::vector<PixelRect>& tiles = renderer_->tiles();
    FrameHeader header;
    header.index = index;
    header.has_tone_mapping = tone_mapping_.has_value();
    header.tone_mapping = tone_mapping_.value_or(ToneMapping{});
    header.send_hdr = !header.has_tone_mapping || options_.hdr_output;
    header.changes = changes;

    report_ = ClusterFrameReport{};
    report_.index = index;
    report_.hdr_sent = header.send_hdr;
    report_.tiles_per_rank.assign(std::size_t(size_), 0);
    Frame frame = Frame::blank(s.width, s.height, index);
    tile_luminance_.assign(tiles.size(), LuminanceStatistics{});
    tile_rays_.assign(tiles.size(), RayCounts{});

    if (size_ == 1) {
      render_alone(header, frame);
    } else {
      std::vector<std::uint8_t> bytes = encode(header);
      report_.header_bytes = bytes.size();
      broadcast_bytes(bytes, 0, comm_);
      collect(header, frame);
    }

    // Combined in tile order, so the statistics do not depend on which rank finished first.
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      report_.luminance.merge(tile_luminance_[t]);
      report_.rays.merge(tile_rays_[t]);
    }
    const ToneMapping next = ToneMapping::from(report_.luminance);
    if (!tone_mapping_) frame.tone_map(next);
    tone_mapping_ = next;
    frame.statistics.rays = report_.rays;
    frame.statistics.tiles = int(tiles.size());
    frame.statistics.luminance = report_.luminance;
    report_.milliseconds = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
    frame.statistics.milliseconds = report_.milliseconds;
    return frame;
  }

  /// Rank 0: tells the workers there are no more frames.
  void shutdown() {
    if (rank_ != 0 || size_ == 1 || shut_down_) return;
    FrameHeader header;
    header.quit = true;
    std::vector<std::uint8_t> bytes = encode(header);
    broadcast_bytes(bytes, 0, comm_);
    shut_down_ = true;
  }

  /// Forgets the tone-mapping history (the next frame is re-mapped with its own statistics).
  void reset_tone_mapping() noexcept { tone_mapping_.reset(); }

  /// Workers: renders tiles of every frame rank 0 announces until it shuts the farm down.
  void serve() {
    if (rank_ == 0) throw DistributedError("serve is for worker ranks; rank 0 calls render_frame()");
    const int threads = renderer_->settings().threads > 0 ? renderer_->settings().threads
                                                          : tbb::this_task_arena::max_concurrency();
    const std::int32_t wanted = options_.tiles_per_request > 0 ? options_.tiles_per_request : std::max(1, threads);
    std::vector<TileResult> results;
    for (;;) {
      std::vector<std::uint8_t> bytes;
      broadcast_bytes(bytes, 0, comm_);
      const FrameHeader header = decode_frame_header(bytes);
      if (header.quit) return;
      renderer_->apply(header.changes);
      renderer_->begin_frame(header.index, header.has_tone_mapping ? header.tone_mapping : ToneMapping{});
      std::vector<double> milliseconds;
      // Plain demand: ask, render, send, ask again. With prefetch one request is always ahead: the
      // next assignment travels while this batch renders, hiding the round trip, and a worker
      // never holds more than two batches.
      check_mpi(MPI_Send(&wanted, 1, MPI_INT32_T, 0, farm_tag_request, comm_), "MPI_Send of a tile request");
      for (;;) {
        const std::vector<int> assigned = receive_assignment();
        if (assigned.empty()) break;  // no tiles left in this frame, and no request outstanding
        if (options_.prefetch)
          check_mpi(MPI_Send(&wanted, 1, MPI_INT32_T, 0, farm_tag_request, comm_), "MPI_Send of a tile request");
        milliseconds.assign(assigned.size(), 0.0);
        const bool slow = rank_ == options_.slow_rank && options_.slow_factor > 1.0;
        renderer_->render_all(assigned, results, [&](std::size_t i, TileResult&, double ms) {
          milliseconds[i] = ms;
          if (slow) std::this_thread::sleep_for(std::chrono::duration<double, std::milli>((options_.slow_factor - 1.0) * ms));
        });
        for (std::size_t i = 0; i < assigned.size(); ++i) {
          TileMessage message;
          message.tile = assigned[i];
          message.frame = header.index;
          message.rays = results[i].rays;
          message.luminance = results[i].luminance;
          message.milliseconds = milliseconds[i];
          message.rgb8 = results[i].rgb8;
          if (header.send_hdr) message.hdr = results[i].hdr;
          const std::vector<std::uint8_t> out = encode(message);
          check_mpi(MPI_Send(out.data(), int(out.size()), MPI_BYTE, 0, farm_tag_tile, comm_), "MPI_Send of a tile");
        }
        if (!options_.prefetch)
          check_mpi(MPI_Send(&wanted, 1, MPI_INT32_T, 0, farm_tag_request, comm_), "MPI_Send of a tile request");
      }
    }
  }

 private:
  /// Workers: waits for the master's answer to a tile request.
  std::vector<int> receive_assignment() {
    const MPI_Status status = probe_polling(0, farm_tag_assignment, comm_);
    const std::vector<std::uint8_t> reply = receive_bytes(status, comm_);
    if (reply.size() % sizeof(std::int32_t) != 0)
      throw DistributedError("tile assignment of " + std::to_string(reply.size()) + " bytes is not whole int32s");
    std::vector<int> assigned(reply.size() / sizeof(std::int32_t));
    for (std::size_t i = 0; i < assigned.size(); ++i) {
      std::int32_t tile;
      std::memcpy(&tile, reply.data() + i * sizeof(std::int32_t), sizeof(tile));
      assigned[i] = tile;
    }
    return assigned;
  }

  /// Rank 0 without workers: all tiles on its own threads.
  void render_alone(const FrameHeader& header, Frame& frame) {
    renderer_->apply(header.changes);
    renderer_->begin_frame(header.index, header.tone_mapping);
    const std::size_t count = renderer_->tiles().size();
    std::vector<int> all(count);
    for (std::size_t t = 0; t < count; ++t) all[t] = int(t);
    std::vector<TileResult> results;
    std::vector<double> milliseconds(count, 0.0);
    renderer_->render_all(all, results, [&](std::size_t i, TileResult& result, double ms) {
      place_tile(result, frame);  // tiles are disjoint: no lock needed
      tile_luminance_[i] = result.luminance;
      tile_rays_[i] = result.rays;
      milliseconds[i] = ms;
      result = TileResult{};  // the frame holds the pixels now
    });
    report_.tiles_per_rank[0] = int(count);
    for (double ms : milliseconds) report_.tile_milliseconds += ms;
  }

  /// Rank 0 with workers: answers tile requests and places finished tiles until the frame is done.
  void collect(const FrameHeader& header, Frame& frame) {
    const std::vector<PixelRect>& tiles = renderer_->tiles();
    std::vector<char> received(tiles.size(), 0);
    std::size_t next = 0, done = 0;
    int finished_workers = 0;
    while (done < tiles.size() || finished_workers < size_ - 1) {
      const MPI_Status status = probe_polling(MPI_ANY_SOURCE, MPI_ANY_TAG, comm_);
      const std::vector<std::uint8_t> bytes = receive_bytes(status, comm_);
      report_.bytes_to_master += bytes.size();
      const int source = status.MPI_SOURCE;
      if (status.MPI_TAG == farm_tag_request) {
        if (bytes.size() != sizeof(std::int32_t))
          throw DistributedError("tile request from rank " + std::to_string(source) + " has " +
                                 std::to_string(bytes.size()) + " bytes, not 4");
        std::int32_t wanted;
        std::memcpy(&wanted, bytes.data(), sizeof(wanted));
        if (wanted < 1)
          throw DistributedError("rank " + std::to_string(source) + " asked for " + std::to_string(wanted) + " tiles");
        const std::size_t give = std::min(std::size_t(wanted), tiles.size() - next);
        std::vector<std::int32_t> assigned(give);
        for (std::size_t i = 0; i < give; ++i) assigned[i] = std::int32_t(next++);
        check_mpi(MPI_Send(assigned.data(), int(give), MPI_INT32_T, source, farm_tag_assignment, comm_),
                  "MPI_Send of a tile assignment");
        if (give == 0) ++finished_workers;
      } else if (status.MPI_TAG == farm_tag_tile) {
        const TileMessage message = decode_tile_message(bytes);
        check_tile(message, header, source, received);
        const PixelRect& rect = tiles[std::size_t(message.tile)];
        std::size_t from = 0;
        for (int y = rect.y0; y < rect.y1; ++y)
          for (int x = rect.x0; x < rect.x1; ++x, ++from) {
            store_pixel(frame.rgb8, x, y, message.rgb8[from]);
            if (header.send_hdr) frame.hdr(x, y) = message.hdr[from];
          }
        received[std::size_t(message.tile)] = 1;
        ++done;
        tile_luminance_[std::size_t(message.tile)] = message.luminance;
        tile_rays_[std::size_t(message.tile)] = message.rays;
        report_.pixel_bytes += message.rgb8.size() * sizeof(glm::u8vec3) + message.hdr.size() * sizeof(glm::vec3);
        report_.tile_milliseconds += message.milliseconds;
        ++report_.tile_messages;
        ++report_.tiles_per_rank[std::size_t(source)];
      } else {
        throw DistributedError("unexpected message tag " + std::to_string(status.MPI_TAG) + " from rank " +
                               std::to_string(source));
      }
    }
  }

  /// Throws DistributedError unless `message` is a tile of this frame not yet received, of the right size.
  void check_tile(const TileMessage& message, const FrameHeader& header, int source,
                  const std::vector<char>& received) const {
    const std::vector<PixelRect>& tiles = renderer_->tiles();
    const std::string from = " from rank " + std::to_string(source);
    if (message.frame != header.index)
      throw DistributedError("tile of frame " + std::to_string(message.frame) + from + " during frame " +
                             std::to_string(header.index));
    if (message.tile < 0 || std::size_t(message.tile) >= tiles.size())
      throw DistributedError("tile index " + std::to_string(message.tile) + from + " is out of range");
    if (received[std::size_t(message.tile)])
      throw DistributedError("tile " + std::to_string(message.tile) + from + " arrived twice");
    const PixelRect& rect = tiles[std::size_t(message.tile)];
    const std::size_t pixels = std::size_t(rect.width()) * std::size_t(rect.height());
    if (message.rgb8.size() != pixels || message.hdr.size() != (header.send_hdr ? pixels : 0))
      throw DistributedError("tile " + std::to_string(message.tile) + from + " has " +
                             std::to_string(message.rgb8.size()) + " RGB8 and " + std::to_string(message.hdr.size()) +
                             " HDR pixels; expected " + std::to_string(pixels));
  }

  MPI_Comm comm_;
  RendererType* renderer_;
  FarmOptions options_;
  int rank_ = 0;
  int size_ = 1;
  bool shut_down_ = false;
  std::optional<ToneMapping> tone_mapping_;
  ClusterFrameReport report_;
  std::vector<LuminanceStatistics> tile_luminance_;
  std::vector<RayCounts> tile_rays_;
};

}  // namespace igi
