// EmbreeBackend never reaches an Embree kernel that loops: coherent packets of every width, closest
// hit and occlusion, on the Cornell box and Sponza_lit, traced in a child process under a deadline
// after the stack below the call was filled with ones. Those ones are what makes Embree 3.13.5's
// coherent 16-wide occlusion loop (see detail::embree_coherent_occlusion16_may_loop), so the test
// fails on every AVX-512 CPU if the guard goes, instead of only on CPUs whose code happens to leave
// such garbage; the last test shows that the ones do make the unguarded kernel loop.

#include <catch2/catch.hpp>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <optional>
#include <string>
#include <vector>

#include "child_process.hpp"
#include "igi/backends/embree/embree_backend.hpp"
#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/gltf.hpp"
#include "scenes.hpp"

namespace {

/// Fills 64 KiB of stack below the caller with 1 bits, then returns: the next call's frames start
/// out as that garbage. 64 KiB is several times Embree's deepest traversal frame.
[[gnu::noinline]] void fill_stack_with_ones() {
  unsigned char below[64 * 1024];
  std::memset(below, 0xff, sizeof below);
  asm volatile("" : : "r"(below) : "memory");  // the stores must happen although nothing reads them
}

/// The scene the child traces: "cornell" or "sponza_lit" (from IGI_HANG_SCENE).
igi::Scene child_scene(const std::string& name) {
  if (name == "cornell") return igi::cornell_box();
  return igi::load_gltf(igi::testing::scene_path("sponza/Sponza_lit.gltf"));
}

/// Coherent primary packets of a 64 x 48 view, then coherent shadow packets from their hits to a
/// point above the scene's centre, all through `backend` with the stack full of ones before each
/// call. Returns the number of blocked shadow rays (so the work cannot be skipped).
template <int W>
int trace_coherent_in(const igi::Scene& scene, const igi::EmbreeBackend<W>& backend) {
  const igi::Camera camera = scene.cameras.empty() ? igi::default_camera(scene) : scene.cameras.front();
  constexpr int width = 64, height = 48;
  const igi::PinholeProjection projection(camera, width, height);
  const igi::Bounds bounds = scene.bounds();
  const glm::vec3 light = bounds.center() + glm::vec3(0.0f, 0.4f * bounds.extent().y, 0.0f);
  // Shadow rays stop 1e-4 of the scene's size short of both ends: above hit-point rounding.
  const float offset = 1e-4f * glm::length(bounds.extent());
  int blocked = 0;
  for (int first = 0; first < width * height; first += W) {
    igi::RayPacket<W> rays;
    igi::HitPacket<W> hits;
    hits.clear();
    const igi::vmask<W> all(true);
    igi::vec3<W> direction;
    for (int lane = 0; lane < W; ++lane) {
      const int pixel = first + lane;
      direction.set(lane, projection.direction(float(pixel % width) + 0.5f, float(pixel / width) + 0.5f));
    }
    rays.set(igi::vec3<W>(projection.origin()), direction, igi::vfloat<W>(0.0f),
             igi::vfloat<W>(std::numeric_limits<float>::infinity()), all);
    fill_stack_with_ones();
    backend.intersect(rays, hits, igi::Coherence::coherent, all);
    const igi::vmask<W> found = hits.valid();
    igi::vec3<W> origin, to_light;
    igi::vfloat<W> near(0.0f), far(0.0f);
    for (int lane = 0; lane < W; ++lane) {
      if (!found[lane]) continue;
      const glm::vec3 point = rays.origin()[lane] + rays.tfar[lane] * rays.direction()[lane];
      const glm::vec3 towards = light - point;
      const float distance = std::max(glm::length(towards), offset);
      origin.set(lane, point);
      to_light.set(lane, towards);
      near.set(lane, offset / distance);
      far.set(lane, 1.0f - offset / distance);
    }
    rays.set(origin, to_light, near, far, found);
    fill_stack_with_ones();
    const igi::vmask<W> occluded = backend.occluded(rays, igi::Coherence::coherent, found);
    for (int lane = 0; lane < W; ++lane) blocked += occluded[lane];
  }
  return blocked;
}

/// "Moves" instance 0 to where it is: the backend then traces two levels (the flattened scene and
/// the moved instance under an instance level), as after any change.
template <int W>
void make_two_level(igi::EmbreeBackend<W>& backend, const igi::Scene& scene) {
  backend.set_instance_transform(0, scene.instances[0].transform);
  backend.commit();
}

/// trace_coherent_in on the backend as built (one level) and again after a move (two levels);
/// both give the same blocked count, which is returned.
template <int W>
int trace_coherent(const igi::Scene& scene) {
  igi::EmbreeBackend<W> backend(scene);
  const RTCScene one_level = backend.embree_scene();
  const int blocked = trace_coherent_in(scene, backend);
  make_two_level(backend, scene);
  CHECK(backend.embree_scene() != one_level);
  CHECK(trace_coherent_in(scene, backend) == blocked);
  return blocked;
}

/// Whether Embree 3 dispatches to its AVX-512 kernels on this CPU (it needs all of these).
bool embree_uses_avx512() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
         __builtin_cpu_supports("avx512cd") && __builtin_cpu_supports("avx512bw") &&
         __builtin_cpu_supports("avx512vl");
}

/// Runs this program's hidden test `name` as a child with `environment`; waits at most `seconds`.
std::optional<igi::testing::ChildExit> run_child(const std::string& name, const std::vector<std::string>& environment,
                                                 int seconds) {
  igi::testing::ChildProcess child(igi::testing::this_program(), {name}, environment);
  return child.wait_for(std::chrono::seconds(seconds));
}

/// A child that traces a scene returns in well under a second on an idle machine (Sponza_lit's
/// loading and three Embree builds included); 120 s leaves room for the sanitizer build on a
/// loaded machine while still failing long before ctest's own timeout.
constexpr int trace_deadline_seconds = 120;

}  // namespace

TEST_CASE("child: embree coherent packets of every width after a stack full of ones", "[.child]") {
  const char* scene_name = std::getenv("IGI_HANG_SCENE");
  REQUIRE(scene_name != nullptr);
  const igi::Scene scene = child_scene(scene_name);
  const int blocked4 = trace_coherent<4>(scene), blocked8 = trace_coherent<8>(scene),
            blocked16 = trace_coherent<16>(scene);
  // The same rays at every width: the same shadow rays blocked.
  CHECK(blocked4 == blocked8);
  CHECK(blocked8 == blocked16);
}

TEST_CASE("child: embree Embree's own coherent 16-wide occlusion after a stack full of ones", "[.child]") {
  const igi::Scene scene = igi::cornell_box();
  igi::EmbreeBackend<16> backend(scene);
  // Two levels, the layout in which the loop was first seen (an instance level over the flattened
  // triangles): there it loops on every AVX-512 CPU.
  make_two_level(backend, scene);
  // 16 parallel rays from the middle of the box upwards: one octant, as coherent as rays get.
  alignas(64) RTCRay16 rays;
  alignas(64) int valid[16];
  const igi::Bounds bounds = scene.bounds();
  const glm::vec3 centre = bounds.center();
  for (int lane = 0; lane < 16; ++lane) {
    valid[lane] = -1;
    rays.org_x[lane] = centre.x + 0.01f * float(lane) * bounds.extent().x;
    rays.org_y[lane] = centre.y;
    rays.org_z[lane] = centre.z;
    rays.dir_x[lane] = 0.0f;
    rays.dir_y[lane] = 1.0f;
    rays.dir_z[lane] = 0.0f;
    rays.tnear[lane] = 0.0f;
    rays.tfar[lane] = 0.25f * bounds.extent().y;
    rays.time[lane] = 0.0f;
    rays.mask[lane] = igi::invalid_id;
    rays.id[lane] = unsigned(lane);
    rays.flags[lane] = 0;
  }
  RTCIntersectContext context;
  rtcInitIntersectContext(&context);
  context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
  fill_stack_with_ones();
  rtcOccluded16(valid, backend.embree_scene(), &context, &rays);
  // Returning at all is what the parent test looks for; whether the rays were blocked is not.
}

TEST_CASE("embree: coherent packets of every width return on the Cornell box, whatever the stack holds",
          "[backends]") {
  const std::optional<igi::testing::ChildExit> exit =
      run_child("child: embree coherent packets of every width after a stack full of ones", {"IGI_HANG_SCENE=cornell"},
                trace_deadline_seconds);
  INFO("a child tracing coherent 4-, 8- and 16-wide packets did not return within "
       << trace_deadline_seconds << " s: EmbreeBackend reached an Embree kernel that loops");
  REQUIRE(exit.has_value());
  INFO("the child ended with " << exit->describe());
  CHECK((exit->exited && exit->code == 0));
}

TEST_CASE("embree: coherent packets of every width return on Sponza_lit, whatever the stack holds (shared scene Sponza_lit.gltf)", "[backends]") {
  IGI_REQUIRE_SCENE(igi::testing::scene_path("sponza/Sponza_lit.gltf"));
  const std::optional<igi::testing::ChildExit> exit =
      run_child("child: embree coherent packets of every width after a stack full of ones",
                {"IGI_HANG_SCENE=sponza_lit"}, trace_deadline_seconds);
  INFO("a child tracing coherent 4-, 8- and 16-wide packets did not return within "
       << trace_deadline_seconds << " s: EmbreeBackend reached an Embree kernel that loops");
  REQUIRE(exit.has_value());
  INFO("the child ended with " << exit->describe());
  CHECK((exit->exited && exit->code == 0));
}

TEST_CASE("embree: a stack full of ones makes the unguarded coherent 16-wide occlusion loop, as the guard assumes",
          "[backends]") {
  if (!igi::detail::embree_coherent_occlusion16_may_loop) {
    IGI_SKIP("this Embree's coherent 16-wide occlusion is not known to loop");
  }
  if (!embree_uses_avx512()) {
    IGI_SKIP("no AVX-512 here, so Embree runs no AVX-512 kernel (its 16-wide packets take another path)");
  }
  // The loop never ends; 10 s is 10x what the child needs to build and trace the Cornell box.
  constexpr int seconds = 10;
  const std::optional<igi::testing::ChildExit> exit =
      run_child("child: embree Embree's own coherent 16-wide occlusion after a stack full of ones", {}, seconds);
  INFO("Embree's coherent rtcOccluded16 returned with a stack full of ones (child ended with "
       << (exit ? exit->describe() : std::string("-"))
       << "): the hang tests above no longer prove the guard; check whether this Embree build still has "
          "the loop of detail::embree_coherent_occlusion16_may_loop");
  CHECK_FALSE(exit.has_value());
}
