// RecordingBackend: results are exactly the wrapped backend's, and the log holds every call's
// input rays, mask, query and coherence hint, from any number of threads.

#include <catch2/catch.hpp>

#include <cstring>
#include <oneapi/tbb/parallel_for.h>

#include "cross_check.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/recording_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"

using igi::EmbreeBackend;
using igi::RecordingBackend;

static_assert(igi::Backend<RecordingBackend<EmbreeBackend<1>>> && igi::Backend<RecordingBackend<EmbreeBackend<16>>> &&
              igi::Backend<RecordingBackend<igi::ReferenceBackend<8>>>);

namespace {

/// True if the two packets hold the same bytes in the lanes of `mask` (the inputs a backend reads).
template <int W>
bool same_rays(const igi::RayPacket<W>& a, const igi::RayPacket<W>& b, const igi::vmask<W>& mask) {
  for (int lane = 0; lane < W; ++lane) {
    if (!mask[lane]) continue;
    const float fa[] = {a.org_x[lane], a.org_y[lane], a.org_z[lane], a.dir_x[lane], a.dir_y[lane], a.dir_z[lane], a.tnear[lane], a.tfar[lane]};
    const float fb[] = {b.org_x[lane], b.org_y[lane], b.org_z[lane], b.dir_x[lane], b.dir_y[lane], b.dir_z[lane], b.tnear[lane], b.tfar[lane]};
    if (std::memcmp(fa, fb, sizeof fa) != 0) return false;
  }
  return true;
}

}  // namespace

TEMPLATE_TEST_CASE("recording: results equal the wrapped backend's and every call is logged in order", "[backends]",
                   EmbreeBackend<4>, EmbreeBackend<16>) {
  constexpr int W = TestType::width;
  const igi::Scene scene = igi::testing::instanced_scene();
  const TestType plain(scene);
  const RecordingBackend<TestType> recording(scene);
  const igi::testing::RaySet set = igi::testing::random_rays(scene, 64 * 8, 3);
  std::vector<igi::RayPacket<W>> inputs;
  std::vector<igi::vmask<W>> masks;
  for (std::size_t first = 0; first < set.rays.size(); first += W) {
    igi::RayPacket<W> rays_a, rays_b;
    igi::HitPacket<W> hits_a, hits_b;
    const igi::vmask<W> mask = igi::testing::load_packet(set, first, rays_a, hits_a);
    igi::testing::load_packet(set, first, rays_b, hits_b);
    inputs.push_back(rays_a);
    masks.push_back(mask);
    // Closest hits on even packets, occlusion on odd ones, so both queries are interleaved in the log.
    if ((first / W) % 2 == 0) {
      plain.intersect(rays_a, hits_a, mask);
      recording.intersect(rays_b, hits_b, igi::Coherence::incoherent, mask);
      CHECK(std::memcmp(&hits_a, &hits_b, sizeof hits_a) == 0);
    } else {
      CHECK(plain.occluded(rays_a, mask) == recording.occluded(rays_b, mask));
    }
    CHECK(std::memcmp(&rays_a, &rays_b, sizeof rays_a) == 0);
  }
  // One single ray on the side: it goes to the singles.
  igi::RayPacket<1> single;
  igi::HitPacket<1> single_hit;
  igi::testing::load_packet(set, 0, single, single_hit);
  recording.intersect(single, single_hit, igi::vmask<1>(true));

  const igi::TraceLog<W> log = recording.take();
  REQUIRE(log.packets.size() == inputs.size());
  REQUIRE(log.singles.size() == 1);
  std::uint64_t active = 0;
  for (std::size_t p = 0; p < inputs.size(); ++p) {
    const igi::RecordedPacket<W>& entry = log.packets[p];
    CHECK(entry.query == (p % 2 == 0 ? igi::TraceQuery::closest : igi::TraceQuery::occlusion));
    CHECK(entry.coherence == (p % 2 == 0 ? igi::Coherence::incoherent : igi::Coherence::coherent));
    CHECK(entry.mask() == masks[p]);
    // The log holds the rays as handed in, not as the backend left them (tfar is overwritten by a hit).
    CHECK(same_rays(entry.rays, inputs[p], masks[p]));
    active += std::uint64_t(igi::popcount(masks[p]));
  }
  CHECK(log.rays() == active + 1);
  CHECK(log.rays(igi::TraceQuery::occlusion) + log.rays(igi::TraceQuery::closest) == log.rays());
  // take() emptied the log.
  CHECK(recording.take().packets.empty());
}

TEST_CASE("recording: replaying the log through the wrapped backend reproduces the recorded results", "[backends]") {
  const igi::Scene scene = igi::testing::instanced_scene();
  const RecordingBackend<EmbreeBackend<8>> recording(scene);
  const igi::testing::RaySet set = igi::testing::random_rays(scene, 64 * 4, 9);
  std::vector<igi::HitPacket<8>> first_hits;
  for (std::size_t first = 0; first < set.rays.size(); first += 8) {
    igi::RayPacket<8> rays;
    igi::HitPacket<8> hits;
    const igi::vmask<8> mask = igi::testing::load_packet(set, first, rays, hits);
    hits.clear();
    recording.intersect(rays, hits, mask);
    first_hits.push_back(hits);
  }
  const igi::TraceLog<8> log = recording.take();
  REQUIRE(log.packets.size() == first_hits.size());
  for (std::size_t p = 0; p < log.packets.size(); ++p) {
    igi::RayPacket<8> rays = log.packets[p].rays;
    igi::HitPacket<8> hits;
    hits.clear();
    recording.inner().intersect(rays, hits, log.packets[p].mask());
    CHECK(std::memcmp(&hits, &first_hits[p], sizeof hits) == 0);
  }
}

TEST_CASE("recording: calls from many threads are all logged, each exactly once", "[backends]") {
  const igi::Scene scene = igi::testing::instanced_scene();
  const RecordingBackend<EmbreeBackend<16>> recording(scene);
  constexpr int packets = 2000;  // enough calls that TBB's workers take a share
  tbb::parallel_for(0, packets, [&](int p) {
    igi::RayPacket<16> rays;
    // Packet p is tagged by its origin's x coordinate, so the log can be checked for each one.
    rays.set(igi::vec3<16>(glm::vec3(float(p), 5.0f, 0.0f)), igi::vec3<16>(glm::vec3(0.0f, -1.0f, 0.0f)),
             igi::vfloat<16>(0.0f), igi::vfloat<16>(100.0f), igi::vmask<16>::first(1 + p % 16));
    recording.occluded(rays, igi::vmask<16>::first(1 + p % 16));
  });
  const igi::TraceLog<16> log = recording.take();
  REQUIRE(log.packets.size() == std::size_t(packets));
  std::vector<int> seen(packets, 0);
  for (const auto& entry : log.packets) {
    const int p = int(entry.rays.org_x[0]);
    REQUIRE(p >= 0);
    REQUIRE(p < packets);
    ++seen[std::size_t(p)];
    CHECK(entry.active() == 1 + p % 16);
  }
  CHECK(std::count(seen.begin(), seen.end(), 1) == packets);
}
