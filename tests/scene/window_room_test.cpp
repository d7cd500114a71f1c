// The built-in window rooms: valid geometry, and the blinds cut the sun on the floor into
// stripes that pass the share of light their slats' geometry leaves.

#include <catch2/catch.hpp>

#include <limits>
#include <vector>

#include <glm/glm.hpp>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/scene/validate.hpp"
#include "igi/scene/window_room.hpp"
#include "igi/simd/sampling.hpp"

using namespace igi;

namespace {

/// Whether the sun reaches floor point `point` in the scene traced by `backend`.
bool sunlit(const EmbreeBackend<1>& backend, const glm::vec3& point, const glm::vec3& towards_sun) {
  RayPacket<1> ray;
  ray.set(vec3<1>(point), vec3<1>(towards_sun), vfloat<1>(1e-4f), vfloat<1>(std::numeric_limits<float>::infinity()),
          vmask<1>(true));
  return !backend.occluded(ray, vmask<1>(true))[0];
}

}  // namespace

TEST_CASE("window rooms: valid geometry without warnings", "[scene][window]") {
  for (Scene scene : {window_room(), window_room_with_blinds()}) {
    INFO(scene.name);
    std::vector<std::string> warnings;
    validate_scene(scene, &warnings);
    CHECK(warnings.empty());
    CHECK(scene.lights.size() == 1);
    CHECK(scene.cameras.size() == 1);
  }
  CHECK(window_room_with_blinds().triangle_count() == window_room().triangle_count() + 12 * 12);  // 12 slats, 12 triangles each
}

TEST_CASE("window rooms: the blinds let a third of the sun's patch on the floor through, in stripes", "[scene][window]") {
  const Scene open = window_room(), blinds = window_room_with_blinds();
  const glm::vec3 towards_sun = -open.lights.front().direction;
  const EmbreeBackend<1> open_backend(open), blinds_backend(blinds);
  // Floor points where the sun falls through the open window, on a line across the stripes.
  int in_patch = 0, through = 0, changes = 0;
  bool previous = false;
  for (int i = 0; i < 4000; ++i) {
    const glm::vec3 point(3.6f, 0.0f, 4.0f * (float(i) + 0.5f) / 4000.0f);  // x = 3.6: clear of the table and the sofa
    if (!sunlit(open_backend, point, towards_sun)) continue;
    const bool lit = sunlit(blinds_backend, point, towards_sun);
    if (in_patch > 0 && lit != previous) ++changes;
    previous = lit;
    ++in_patch;
    through += lit;
  }
  REQUIRE(in_patch > 500);
  // Each 10 cm gap between 4 mm slats 9 cm deep: the sun drops 0.55 / 0.8 m per metre it travels
  // in -z, so a slat shades 0.09 x 0.6875 + 0.004 = 0.066 m of every 0.1 m, and 34% passes (the
  // window's top and bottom gaps, 4.8 cm each, pass less: 30-38% over the whole patch).
  const double share = double(through) / double(in_patch);
  CHECK(share > 0.30);
  CHECK(share < 0.38);
  // 13 gaps (11 between the slats, one above and one below them); the wall's 0.2 m reveal shades
  // the top 0.14 m of the opening (0.2 x 0.6875), so at least 10 lit stripes: 19 changes.
  CHECK(changes >= 19);
}
