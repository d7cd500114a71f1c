#pragma once
/// \file
/// `RecordingBackend<B>`: any Backend, with a log of every packet traced through it. Each call
/// is forwarded unchanged to the wrapped backend (results are exactly B's) after its input rays,
/// lane mask, query kind and coherence hint are copied into the calling thread's log. The log
/// holds the exact ray workload of a frame, to replay without the pipeline around it (the
/// "physical limit" benchmark) or to inspect. Recording costs a copy and an allocation now and
/// then per call: time frames with the plain backend, record them with this one.

#include <bit>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <oneapi/tbb/enumerable_thread_specific.h>

#include "igi/backends/backend.hpp"
#include "igi/backends/coherence.hpp"
#include "igi/backends/packet.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Which query a recorded packet went to.
enum class TraceQuery : std::uint8_t {
  closest,   ///< intersect(): nearest hit.
  occlusion  ///< occluded(): any hit within [tnear, tfar].
};

/// One recorded call: the rays as they were handed in (before the backend wrote tfar), the lanes
/// of its mask as bits (bit i = lane i), the query and the coherence hint (coherent when the
/// caller gave none, which is what the backends assume then).
template <int W>
struct RecordedPacket {
  RayPacket<W> rays;                           ///< Input rays.
  std::uint64_t lanes = 0;                     ///< Mask bits; W <= 64 fits.
  TraceQuery query = TraceQuery::closest;      ///< intersect or occluded.
  Coherence coherence = Coherence::coherent;   ///< The hint passed on.

  /// The recorded mask as a vmask.
  vmask<W> mask() const noexcept {
    vmask<W> m;
    for (int lane = 0; lane < W; ++lane) m.set(lane, (lanes >> lane) & 1u);
    return m;
  }
  /// Rays in the mask.
  int active() const noexcept { return std::popcount(lanes); }
};

/// Everything recorded: W-wide calls and single-ray calls, each in the order of the thread that
/// made them, the threads' logs one after another.
template <int W>
struct TraceLog {
  std::vector<RecordedPacket<W>> packets;  ///< Calls on W-wide packets.
  std::vector<RecordedPacket<1>> singles;  ///< Calls on single rays (W > 1 only; at W = 1 all are packets).

  /// Active rays of the log, optionally only those of one query.
  std::uint64_t rays(std::optional<TraceQuery> query = std::nullopt) const noexcept {
    std::uint64_t n = 0;
    for (const auto& p : packets)
      if (!query || p.query == *query) n += std::uint64_t(p.active());
    for (const auto& p : singles)
      if (!query || p.query == *query) n += std::uint64_t(p.active());
    return n;
  }
};

/// Backend B with a log of every packet it traces (see the file comment). Safe to trace from
/// many threads at once; take() and clear() must not run while tracing.
template <class B>
  requires Backend<B>
class RecordingBackend {
 public:
  /// Lanes per packet: B's.
  static constexpr int width = B::width;
  /// Name for tables and messages.
  static constexpr const char* name() noexcept { return "recording"; }

  /// Builds the wrapped backend from `scene` and any further arguments B's constructor takes.
  template <class... Args>
  explicit RecordingBackend(const Scene& scene, Args&&... args) : inner_(scene, std::forward<Args>(args)...) {}

  /// B::intersect, recorded.
  template <int N>
    requires(N == width || N == 1)
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, const vmask<N>& mask) const {
    record(rays, mask, TraceQuery::closest, Coherence::coherent);
    inner_.intersect(rays, hits, mask);
  }
  /// B::intersect with a coherence hint, recorded (only where B takes the hint).
  template <int N>
    requires(N == width || N == 1) &&
            requires(const B& b, RayPacket<N>& r, HitPacket<N>& h, const vmask<N>& m) { b.intersect(r, h, Coherence::coherent, m); }
  void intersect(RayPacket<N>& rays, HitPacket<N>& hits, Coherence coherence, const vmask<N>& mask) const {
    record(rays, mask, TraceQuery::closest, coherence);
    inner_.intersect(rays, hits, coherence, mask);
  }
  /// B::occluded, recorded.
  template <int N>
    requires(N == width || N == 1)
  vmask<N> occluded(RayPacket<N>& rays, const vmask<N>& mask) const {
    record(rays, mask, TraceQuery::occlusion, Coherence::coherent);
    return inner_.occluded(rays, mask);
  }
  /// B::occluded with a coherence hint, recorded (only where B takes the hint).
  template <int N>
    requires(N == width || N == 1) &&
            requires(const B& b, RayPacket<N>& r, const vmask<N>& m) { b.occluded(r, Coherence::coherent, m); }
  vmask<N> occluded(RayPacket<N>& rays, Coherence coherence, const vmask<N>& mask) const {
    record(rays, mask, TraceQuery::occlusion, coherence);
    return inner_.occluded(rays, coherence, mask);
  }

  /// Forwarded to B.
  void set_instance_transform(int index, const glm::mat4& transform) { inner_.set_instance_transform(index, transform); }
  /// Forwarded to B.
  void set_mesh_positions(int index, std::span<const glm::vec3> positions) { inner_.set_mesh_positions(index, positions); }
  /// Forwarded to B.
  void commit() { inner_.commit(); }
  /// B::set_cutout_test, where B has one (the occlusion queries' filtering is B's, not recorded).
  void set_cutout_test(CutoutTest test)
    requires CutoutTestingBackend<B>
  {
    inner_.set_cutout_test(std::move(test));
  }
  /// B::cutout_test_set, where B has one.
  bool cutout_test_set() const noexcept
    requires CutoutTestingBackend<B>
  {
    return inner_.cutout_test_set();
  }

  /// The wrapped backend.
  const B& inner() const noexcept { return inner_; }

  /// Everything recorded since construction or the last take()/clear(), which it empties.
  TraceLog<width> take() const {
    TraceLog<width> log;
    for (ThreadLog& thread : logs_) {
      log.packets.insert(log.packets.end(), thread.packets.begin(), thread.packets.end());
      log.singles.insert(log.singles.end(), thread.singles.begin(), thread.singles.end());
    }
    clear();
    return log;
  }
  /// Forgets what was recorded (keeps the threads' buffers for reuse).
  void clear() const {
    for (ThreadLog& thread : logs_) {
      thread.packets.clear();
      thread.singles.clear();
    }
  }

 private:
  static_assert(width <= 64, "RecordedPacket keeps the mask in 64 bits");

  /// One thread's calls in order.
  struct ThreadLog {
    std::vector<RecordedPacket<width>> packets;  ///< W-wide calls.
    std::vector<RecordedPacket<1>> singles;      ///< Single-ray calls (at W = 1 they go to packets).
  };

  template <int N>
  void record(const RayPacket<N>& rays, const vmask<N>& mask, TraceQuery query, Coherence coherence) const {
    RecordedPacket<N> entry{rays, 0, query, coherence};
    for (int lane = 0; lane < N; ++lane)
      if (mask[lane]) entry.lanes |= std::uint64_t(1) << lane;
    ThreadLog& log = logs_.local();
    if constexpr (N == width)
      log.packets.push_back(entry);
    else
      log.singles.push_back(entry);
  }

  B inner_;
  /// Mutable: recording is not part of the backend's tracing state, and tracing calls are const.
  mutable tbb::enumerable_thread_specific<ThreadLog> logs_;
};

}  // namespace igi
