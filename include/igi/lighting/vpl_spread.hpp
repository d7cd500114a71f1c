#pragma once
/// \file
/// How far each bounce VPL's light is spread for glossy receivers. A VPL stands for the light of
/// the surface around it, about as far as its neighbours are; seen in a sharp glossy lobe as a
/// point it makes a spike, seen as a sphere of that radius (a virtual spherical light, after
/// Hasan, Krivanek, Walter and Bala, "Virtual Spherical Lights for Many-Light Rendering of Glossy
/// Scenes", SIGGRAPH Asia 2009) it makes a highlight as wide as the light it stands for. The
/// radius is the distance to the k-th nearest other VPL of the frame, all interleaving sets
/// together (the filter averages them): it shrinks as VPLs get denser, so the blur, and the bias
/// it brings, vanish as their number grows. Only `VplKind::surface` VPLs (bounce VPLs and samples
/// of area lights) are spread; point, spot and directional lights are true points.

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <unordered_map>
#include <vector>

#include <glm/glm.hpp>

#include "igi/lighting/vpl.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Neighbours whose distance gives a VPL its radius: 4 makes the spheres of neighbouring VPLs
/// overlap (a sphere reaching its 4th neighbour covers about 4 VPLs' share of the surface), so the
/// spread light has no gaps between VPLs, while staying the scale of the VPL spacing.
inline constexpr int vpl_spread_neighbours = 4;

/// Sets `radius` of every surface VPL of `vpls` to the distance to its `neighbours`-th nearest
/// other surface VPL (fewer if the frame has fewer); 0 for other kinds and lone VPLs. VPLs at
/// one position count as one: a VPL shared by the sets has a copy in each, one VPL all the
/// same. A pure function of the VPL positions: a uniform grid of cells about one spacing wide,
/// searched in growing shells until no nearer neighbour can remain.
inline void assign_vpl_radii(VplSets& vpls, int neighbours = vpl_spread_neighbours) {
  std::vector<Vpl*> spread;                         // one VPL per position
  std::vector<std::pair<Vpl*, std::size_t>> copies;  // the others, with their position's index in `spread`
  {
    // Keyed by the coordinates' bits (+0.0f makes -0 and +0 one key): exact positions, and an
    // order even for positions that are not finite.
    std::map<std::array<std::uint32_t, 3>, std::size_t> position_index;
    for (auto& set : vpls.sets)
      for (Vpl& vpl : set) {
        vpl.radius = 0.0f;
        if (vpl.kind != VplKind::surface) continue;
        const std::array<std::uint32_t, 3> key{std::bit_cast<std::uint32_t>(vpl.position.x + 0.0f),
                                               std::bit_cast<std::uint32_t>(vpl.position.y + 0.0f),
                                               std::bit_cast<std::uint32_t>(vpl.position.z + 0.0f)};
        const auto [found, added] = position_index.try_emplace(key, spread.size());
        if (added)
          spread.push_back(&vpl);
        else
          copies.emplace_back(&vpl, found->second);
      }
  }
  const int count = int(spread.size());
  const int k = std::min(neighbours, count - 1);
  if (k < 1) return;
  Bounds bounds;
  for (const Vpl* vpl : spread) bounds.extend(vpl->position);
  const glm::vec3 extent = bounds.extent();
  const float largest = std::max(extent.x, std::max(extent.y, extent.z));
  if (!(largest > 0.0f) || !std::isfinite(largest)) return;  // all at one point (or not finite): nothing to spread over
  // VPLs lie on surfaces, so about k of them share a cell of side largest x sqrt(k / count); at
  // most 2^20 cells per axis keeps the packed key in 64 bits.
  const float cell = std::max(largest * std::sqrt(float(k) / float(count)), largest / float(1 << 20));
  const auto coordinate = [&](float value, float lower) { return std::int64_t(std::floor((value - lower) / cell)); };
  const auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
    return std::uint64_t(x) | (std::uint64_t(y) << 21) | (std::uint64_t(z) << 42);
  };
  const std::int64_t cells_x = coordinate(bounds.upper.x, bounds.lower.x) + 1,
                     cells_y = coordinate(bounds.upper.y, bounds.lower.y) + 1,
                     cells_z = coordinate(bounds.upper.z, bounds.lower.z) + 1;
  std::unordered_map<std::uint64_t, std::vector<int>> grid;
  std::vector<glm::i64vec3> home(spread.size());
  for (int i = 0; i < count; ++i) {
    const glm::vec3 p = spread[std::size_t(i)]->position;
    home[std::size_t(i)] = {coordinate(p.x, bounds.lower.x), coordinate(p.y, bounds.lower.y), coordinate(p.z, bounds.lower.z)};
    grid[key(home[std::size_t(i)].x, home[std::size_t(i)].y, home[std::size_t(i)].z)].push_back(i);
  }
  // Shells searched before a VPL far from the others is measured against all of them instead:
  // about k VPLs per cell find their neighbours within 1 or 2 shells; 8 bounds the cells visited
  // per VPL (17^3) however the VPLs cluster.
  constexpr std::int64_t max_shells = 8;
  std::vector<float> nearest;  // the k smallest squared distances so far, ascending
  const auto consider = [&](int i, int j) {
    if (j == i) return;
    const glm::vec3 d = spread[std::size_t(j)]->position - spread[std::size_t(i)]->position;
    const float distance2 = glm::dot(d, d);
    if (int(nearest.size()) == k && distance2 >= nearest.back()) return;
    nearest.insert(std::upper_bound(nearest.begin(), nearest.end(), distance2), distance2);
    if (int(nearest.size()) > k) nearest.pop_back();
  };
  for (int i = 0; i < count; ++i) {
    const glm::i64vec3 c = home[std::size_t(i)];
    nearest.clear();
    bool complete = false;
    for (std::int64_t shell = 0; shell <= max_shells && !complete; ++shell) {
      for (std::int64_t dz = -shell; dz <= shell; ++dz)
        for (std::int64_t dy = -shell; dy <= shell; ++dy)
          for (std::int64_t dx = -shell; dx <= shell; ++dx) {
            if (std::max(std::abs(dx), std::max(std::abs(dy), std::abs(dz))) != shell) continue;  // inner shells are done
            const std::int64_t x = c.x + dx, y = c.y + dy, z = c.z + dz;
            if (x < 0 || y < 0 || z < 0 || x >= cells_x || y >= cells_y || z >= cells_z) continue;
            const auto found = grid.find(key(x, y, z));
            if (found == grid.end()) continue;
            for (const int j : found->second) consider(i, j);
          }
      // Cells beyond this shell are at least `shell` cells away from any point of the home cell.
      const float reach = float(shell) * cell;
      complete = int(nearest.size()) == k && nearest.back() <= reach * reach;
    }
    if (!complete) {
      nearest.clear();
      for (int j = 0; j < count; ++j) consider(i, j);
    }
    spread[std::size_t(i)]->radius = nearest.empty() ? 0.0f : std::sqrt(nearest.back());
  }
  for (const auto& [vpl, index] : copies) vpl->radius = spread[index]->radius;
}

}  // namespace igi
