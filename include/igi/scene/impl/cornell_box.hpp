#pragma once
/// \file
/// The Cornell box's numbers behind igi/scene/cornell.hpp (see there for their source): included by
/// it when igi is header-only, compiled once by igi/separate_compilation.hpp under
/// IGI_SEPARATE_COMPILATION (igi/config.hpp).

#include <vector>

#include <glm/glm.hpp>

#include "igi/config.hpp"
#include "igi/scene/cornell.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

namespace cornell_detail {

/// One planar quad of the box: corners a, b, c, d (triangles a-b-c and a-c-d) and its normal.
struct Quad {
  glm::vec3 corners[4];              ///< Counter-clockwise seen from the front.
  glm::vec3 normal;                  ///< Unit normal of the file (slightly tilted on the red wall).
};

/// One object of the box: its name, material index and quads.
struct Part {
  const char* name;         ///< Node and mesh name in the glTF.
  int material;             ///< 0 white, 1 red, 2 green, 3 light.
  std::vector<Quad> quads;  ///< Its faces.
};

/// The eight objects of the glTF, in file order (nodes 0-7 place them with identity transforms).
inline std::vector<Part> parts() {
  return {
      {"floor", 0, {
          {{{0.5528f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.5592f}, {0.5496f, 0.0f, 0.5592f}}, {0.0f, 1.0f, 0.0f}},
      }},
      {"ceiling", 0, {
          {{{0.556f, 0.5488f, 0.0f}, {0.556f, 0.5488f, 0.5592f}, {0.0f, 0.5488f, 0.5592f}, {0.0f, 0.5488f, 0.0f}}, {0.0f, -1.0f, 0.0f}},
      }},
      {"back", 0, {
          {{{0.5496f, 0.0f, 0.5592f}, {0.0f, 0.0f, 0.5592f}, {0.0f, 0.5488f, 0.5592f}, {0.556f, 0.5488f, 0.5592f}}, {0.0f, 0.0f, -1.0f}},
      }},
      {"greenwall", 2, {
          {{{0.0f, 0.0f, 0.5592f}, {0.0f, 0.0f, 0.0f}, {0.0f, 0.5488f, 0.0f}, {0.0f, 0.5488f, 0.5592f}}, {1.0f, 0.0f, 0.0f}},
      }},
      {"redwall", 1, {
          {{{0.5528f, 0.0f, 0.0f}, {0.5496f, 0.0f, 0.5592f}, {0.556f, 0.5488f, 0.5592f}, {0.556f, 0.5488f, 0.0f}}, {-0.99991566f, 0.011660824f, -0.005721978f}},
      }},
      {"smallbox", 0, {
          {{{0.13f, 0.165f, 0.065f}, {0.082f, 0.165f, 0.225f}, {0.24f, 0.165f, 0.272f}, {0.29f, 0.165f, 0.114f}}, {0.0f, 1.0f, 0.0f}},
          {{{0.29f, 0.0f, 0.114f}, {0.29f, 0.165f, 0.114f}, {0.24f, 0.165f, 0.272f}, {0.24f, 0.0f, 0.272f}}, {0.9534001f, 0.0f, 0.30170888f}},
          {{{0.13f, 0.0f, 0.065f}, {0.13f, 0.165f, 0.065f}, {0.29f, 0.165f, 0.114f}, {0.29f, 0.0f, 0.114f}}, {0.2928258f, 0.0f, -0.9561658f}},
          {{{0.082f, 0.0f, 0.225f}, {0.082f, 0.165f, 0.225f}, {0.13f, 0.165f, 0.065f}, {0.13f, 0.0f, 0.065f}}, {-0.95782626f, 0.0f, -0.28734788f}},
          {{{0.24f, 0.0f, 0.272f}, {0.24f, 0.165f, 0.272f}, {0.082f, 0.165f, 0.225f}, {0.082f, 0.0f, 0.225f}}, {-0.2851209f, 0.0f, 0.95849156f}},
          {{{0.29f, 0.0f, 0.114f}, {0.24f, 0.0f, 0.272f}, {0.082f, 0.0f, 0.225f}, {0.13f, 0.0f, 0.065f}}, {0.0f, -1.0f, 0.0f}},
      }},
      {"largebox", 0, {
          {{{0.423f, 0.33f, 0.247f}, {0.265f, 0.33f, 0.296f}, {0.314f, 0.33f, 0.456f}, {0.472f, 0.33f, 0.406f}}, {0.0f, 1.0f, 0.0f}},
          {{{0.423f, 0.0f, 0.247f}, {0.423f, 0.33f, 0.247f}, {0.472f, 0.33f, 0.406f}, {0.472f, 0.0f, 0.406f}}, {0.95564896f, 0.0f, -0.29450816f}},
          {{{0.472f, 0.0f, 0.406f}, {0.472f, 0.33f, 0.406f}, {0.314f, 0.33f, 0.456f}, {0.314f, 0.0f, 0.456f}}, {0.30170888f, 0.0f, 0.9534001f}},
          {{{0.314f, 0.0f, 0.456f}, {0.314f, 0.33f, 0.456f}, {0.265f, 0.33f, 0.296f}, {0.265f, 0.0f, 0.296f}}, {-0.9561658f, 0.0f, 0.2928258f}},
          {{{0.265f, 0.0f, 0.296f}, {0.265f, 0.33f, 0.296f}, {0.423f, 0.33f, 0.247f}, {0.423f, 0.0f, 0.247f}}, {-0.29620907f, 0.0f, -0.9551231f}},
          {{{0.472f, 0.0f, 0.406f}, {0.314f, 0.0f, 0.456f}, {0.265f, 0.0f, 0.296f}, {0.423f, 0.0f, 0.247f}}, {0.0f, -1.0f, 0.0f}},
      }},
      {"luminaire", 3, {
          {{{0.343f, 0.5483f, 0.227f}, {0.343f, 0.5483f, 0.332f}, {0.213f, 0.5483f, 0.332f}, {0.213f, 0.5483f, 0.227f}}, {0.0f, -1.0f, 0.0f}},
      }},
  };
}

}  // namespace cornell_detail

IGI_INLINE Scene cornell_box() {
  Scene scene;
  scene.name = "cornell";
  // Mitsuba 3 cbox albedos (linear RGB) and the light's radiance: emissiveFactor x emissiveStrength.
  // The box's paints were measured as diffuse reflectances, so no specular layer (specular 0;
  // cornell_box.gltf, which cannot say so without KHR_materials_specular, has glTF's 4%).
  scene.materials = {
      Material{.name = "white", .base_color = {0.885809f, 0.698859f, 0.666422f, 1.0f}, .metallic = 0.0f, .roughness = 1.0f,
               .specular = 0.0f},
      Material{.name = "red", .base_color = {0.570068f, 0.0430135f, 0.0443706f, 1.0f}, .metallic = 0.0f, .roughness = 1.0f,
               .specular = 0.0f},
      Material{.name = "green", .base_color = {0.105421f, 0.37798f, 0.076425f, 1.0f}, .metallic = 0.0f, .roughness = 1.0f,
               .specular = 0.0f},
      Material{.name = "light",
               .base_color = {0.78f, 0.78f, 0.78f, 1.0f},
               .metallic = 0.0f,
               .roughness = 1.0f,
               .emission = 18.387f * glm::vec3(1.0f, 0.7607168107902321f, 0.36730135421765375f),
               .specular = 0.0f},
  };
  for (const cornell_detail::Part& part : cornell_detail::parts()) {
    Mesh mesh;
    mesh.name = part.name;
    mesh.material = part.material;
    for (const cornell_detail::Quad& quad : part.quads) {
      const unsigned first = unsigned(mesh.positions.size());
      for (const glm::vec3& corner : quad.corners) {
        mesh.positions.push_back(corner);
        mesh.normals.push_back(quad.normal);
      }
      mesh.triangles.emplace_back(first, first + 1, first + 2);
      mesh.triangles.emplace_back(first, first + 2, first + 3);
    }
    scene.instances.push_back({.name = part.name, .mesh = int(scene.meshes.size()), .transform = glm::mat4(1.0f)});
    scene.meshes.push_back(std::move(mesh));
  }
  // The camera node: translation (0.278, 0.273, -0.8), rotation 180 degrees about +Y (quaternion
  // (0, 1, 0, 0)), so it looks along +Z into the open side of the box.
  Camera camera;
  camera.name = "cornell_camera";
  camera.camera_to_world = glm::mat4(glm::vec4(-1.0f, 0.0f, 0.0f, 0.0f), glm::vec4(0.0f, 1.0f, 0.0f, 0.0f),
                                     glm::vec4(0.0f, 0.0f, -1.0f, 0.0f), glm::vec4(0.278f, 0.273f, -0.8f, 1.0f));
  camera.yfov = 0.6860487863861751f;  // 39.3077 degrees
  camera.aspect = 1.0f;
  camera.znear = 0.01f;
  scene.cameras.push_back(camera);
  return scene;
}

}  // namespace igi
