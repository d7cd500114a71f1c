#pragma once
/// \file
/// Warnings for images that are surely not what the user wanted: black ones, and ones whose light
/// is far below what the scene's emitters give (lights outside the room the camera is in,
/// turned away, or shut in). A render that goes on silently with such an image wastes the
/// user's time guessing; a named cause does not.

#include <cmath>
#include <cstddef>
#include <numbers>
#include <string>

#include <glm/glm.hpp>

#include "igi/io/image_types.hpp"
#include "igi/lighting/lights.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// The fraction of the scene's light scale (light_check_scale) under which an image's mean
/// radiance is named in a warning: a room lit through a window is rarely darker than a tenth or a
/// hundredth of the sunlit ground outside, so a thousandth is light that did not arrive.
inline constexpr double dark_image_fraction = 1e-3;

/// The radiance a white diffuse surface would have on average if the emitters' power `lights`
/// spread over all the scene's surfaces once: power / (pi x area). For an open ground under the
/// sun it is the ground's own radiance; in a closed room, the first bounce's.
inline double light_check_scale(const Scene& scene) {
  double area = 0.0;
  for (const Instance& instance : scene.instances) {
    if (instance.mesh < 0 || std::size_t(instance.mesh) >= scene.meshes.size()) continue;
    const Mesh& mesh = scene.meshes[std::size_t(instance.mesh)];
    for (const glm::uvec3& t : mesh.triangles) {
      if (t.x >= mesh.positions.size() || t.y >= mesh.positions.size() || t.z >= mesh.positions.size()) continue;
      const auto world = [&](unsigned i) { return glm::dvec3(instance.transform * glm::vec4(mesh.positions[i], 1.0f)); };
      const double twice = glm::length(glm::cross(world(t.y) - world(t.x), world(t.z) - world(t.x)));
      if (std::isfinite(twice)) area += 0.5 * twice;
    }
  }
  if (!(area > 0.0)) return 0.0;
  const glm::vec3 power = LightSet(scene).total_power();
  return double(power.x + power.y + power.z) / 3.0 / (std::numbers::pi * area);
}

/// A one-line warning for `image` rendered from `scene`, or an empty string: for an image whose
/// every pixel is black (naming whether the scene has any light at all), and for one whose mean
/// radiance is below dark_image_fraction of light_check_scale.
inline std::string light_warning(const Scene& scene, const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += (double(p.x) + double(p.y) + double(p.z)) / 3.0;
  const double mean = image.pixels.empty() ? 0.0 : sum / double(image.pixels.size());
  if (!scene.has_lights())
    return "scene '" + scene.name + "' has no lights (no punctual light, emissive material or environment): the image is black";
  if (!(mean > 0.0))
    return "the image is black: no light of scene '" + scene.name +
           "' reaches what the camera sees (lights outside the room, turned away or blocked?)";
  const double scale = light_check_scale(scene);
  if (scale > 0.0 && mean < dark_image_fraction * scale)
    return "the image's mean radiance " + std::to_string(mean) + " is below a thousandth of the " + std::to_string(scale) +
           " that the lights of scene '" + scene.name +
           "' give its surfaces on average: they may be outside the room the camera is in, turned away or blocked";
  return {};
}

}  // namespace igi
