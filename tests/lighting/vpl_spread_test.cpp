// VPL spreading: each surface VPL's radius is the distance to its k-th nearest other surface VPL
// of the frame, whatever the layout (checked against a brute-force search), and only surface
// VPLs are spread.

#include <algorithm>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/lighting/vpl_spread.hpp"
#include "igi/simd/sampling.hpp"

using namespace igi;

namespace {

/// The k-th smallest distance from VPL i to the other surface VPLs, by trying all of them.
float brute_force_radius(const std::vector<Vpl>& all, std::size_t i, int k) {
  std::vector<float> distances;
  for (std::size_t j = 0; j < all.size(); ++j)
    if (j != i && all[j].kind == VplKind::surface) distances.push_back(glm::length(all[j].position - all[i].position));
  if (distances.empty()) return 0.0f;
  std::sort(distances.begin(), distances.end());
  return distances[std::size_t(std::min(k, int(distances.size())) - 1)];
}

}  // namespace

TEST_CASE("VPL spread: radii are the k-th nearest neighbour distances over all sets", "[lighting][spread]") {
  Rng rng(3u);
  // Layouts: spread over a floor and two walls, two tight clusters far apart, one far outlier
  // (which the grid search cannot reach and measures against all), and a handful of VPLs.
  for (const int layout : {0, 1, 2, 3}) {
    const int count = layout == 3 ? 3 : 600;
    VplSets vpls;
    vpls.sets.resize(9);
    for (int i = 0; i < count; ++i) {
      Vpl vpl;
      const float u = rng.next(), v = rng.next();
      if (layout == 0) vpl.position = i % 3 == 0 ? glm::vec3(u, 0, v) : i % 3 == 1 ? glm::vec3(0, u, v) : glm::vec3(u, v, 0);
      if (layout == 1) vpl.position = glm::vec3(u, v, 0) * 0.01f + (i % 2 ? glm::vec3(100, 0, 0) : glm::vec3(0));
      if (layout == 2) vpl.position = i == 0 ? glm::vec3(1e4f, 0, 0) : glm::vec3(u, v, rng.next());
      if (layout == 3) vpl.position = glm::vec3(u, v, 0);
      vpl.kind = i % 7 == 6 ? VplKind::omni : VplKind::surface;  // some point lights among them
      vpl.radius = -1.0f;                                          // every radius must be written
      vpls.sets[std::size_t(i % 9)].push_back(vpl);
    }
    assign_vpl_radii(vpls);
    std::vector<Vpl> all;
    for (const auto& set : vpls.sets) all.insert(all.end(), set.begin(), set.end());
    for (std::size_t i = 0; i < all.size(); ++i) {
      INFO("layout " << layout << ", VPL " << i);
      if (all[i].kind != VplKind::surface) {
        CHECK(all[i].radius == 0.0f);
        continue;
      }
      CHECK(all[i].radius == brute_force_radius(all, i, vpl_spread_neighbours));
    }
  }
}

TEST_CASE("VPL spread: a lone VPL and VPLs at one point stay points", "[lighting][spread]") {
  VplSets one{{{Vpl{.position = {1, 2, 3}, .radius = 5.0f}}}};
  assign_vpl_radii(one);
  CHECK(one.sets[0][0].radius == 0.0f);
  VplSets same{{{Vpl{.position = {1, 2, 3}}, Vpl{.position = {1, 2, 3}}, Vpl{.position = {1, 2, 3}}}}};
  assign_vpl_radii(same);
  for (const Vpl& vpl : same.sets[0]) CHECK(vpl.radius == 0.0f);
}

TEST_CASE("VPL spread: a VPL shared by every set is one VPL, for itself and for its neighbours", "[lighting][spread]") {
  // 300 VPLs over a floor in 9 sets, and every tenth of them copied into all 9 sets (as the
  // importance sampler shares a heavy VPL): each radius is the brute-force one over the VPLs
  // counted once. Counting the copies, a shared VPL's radius would be 0 (its own copies at
  // distance 0) and its neighbours' would shrink.
  Rng rng(5u);
  std::vector<Vpl> distinct;
  VplSets vpls;
  vpls.sets.resize(9);
  for (int i = 0; i < 300; ++i) {
    Vpl vpl;
    vpl.position = glm::vec3(rng.next(), 0.0f, rng.next());
    vpl.radius = -1.0f;
    distinct.push_back(vpl);
    if (i % 10 == 0)
      for (auto& set : vpls.sets) set.push_back(vpl);
    else
      vpls.sets[std::size_t(i % 9)].push_back(vpl);
  }
  assign_vpl_radii(vpls);
  for (std::size_t s = 0; s < vpls.sets.size(); ++s)
    for (const Vpl& vpl : vpls.sets[s]) {
      const auto same = std::find_if(distinct.begin(), distinct.end(), [&](const Vpl& d) { return d.position == vpl.position; });
      REQUIRE(same != distinct.end());
      INFO("set " << s << ", VPL at " << vpl.position.x << ", " << vpl.position.z);
      CHECK(vpl.radius > 0.0f);
      CHECK(vpl.radius == brute_force_radius(distinct, std::size_t(same - distinct.begin()), vpl_spread_neighbours));
    }
}
