#pragma once
/// \file
/// The paper's Figure 3 scene, built in code: a Shirley-style room (floor, ceiling, four walls, a
/// few boxes and a wall panel) lit by a ceiling lamp that can move, and `RoomShader`, a surface
/// shader that gives each material its procedural pattern (marble, wood, brick bump) by composing
/// igi's procedural shaders, or, for comparison, the materials' constant diffuse colours.

#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/scene/scene.hpp"
#include "igi/shading/procedural_shaders.hpp"
#include "igi/shading/surface_hit.hpp"

namespace igi_procedural {

/// The room's materials, in Scene::materials order.
enum RoomMaterial : int { plain_wall, blue_wall, wood_floor, brick_wall, marble, wood_box, lamp, material_count };

/// Room size in metres: 4 wide (x), 2.6 high (y), 5 deep (z), the floor's corner at the origin.
inline constexpr glm::vec3 room_size{4.0f, 2.6f, 5.0f};

/// Adds an axis-aligned box from `lower` to `upper` with material `material`, faces wound counter-clockwise seen from outside.
inline void add_box(igi::Scene& scene, const std::string& name, const glm::vec3& lower, const glm::vec3& upper,
                    int material) {
  const glm::vec3 center = 0.5f * (lower + upper), half = 0.5f * (upper - lower);
  igi::Mesh mesh;
  mesh.name = name;
  mesh.material = material;
  for (int axis = 0; axis < 3; ++axis)
    for (float side : {-1.0f, 1.0f}) {
      glm::vec3 normal(0.0f), u(0.0f), v(0.0f);
      normal[axis] = side;
      u[(axis + 1) % 3] = half[(axis + 1) % 3];
      v[(axis + 2) % 3] = half[(axis + 2) % 3];
      // u x v points along +axis: swapping them winds the quad the other way.
      if (side < 0.0f) std::swap(u, v);
      const glm::vec3 face = center + normal * half[axis];
      const unsigned first = unsigned(mesh.positions.size());
      mesh.positions.insert(mesh.positions.end(), {face - u - v, face + u - v, face + u + v, face - u + v});
      mesh.normals.insert(mesh.normals.end(), 4, normal);
      mesh.triangles.push_back({first, first + 1, first + 2});
      mesh.triangles.push_back({first, first + 2, first + 3});
    }
  scene.instances.push_back({.name = name, .mesh = int(scene.meshes.size())});
  scene.meshes.push_back(std::move(mesh));
}

/// Adds a one-sided axis-aligned rectangle facing `-Y` (a ceiling lamp) from `lower` to `upper` in x and z at height `y`.
inline void add_ceiling_panel(igi::Scene& scene, const std::string& name, const glm::vec2& lower, const glm::vec2& upper,
                              float y, int material) {
  igi::Mesh mesh;
  mesh.name = name;
  mesh.material = material;
  // Counter-clockwise seen from below: (x0,z0), (x0,z1), (x1,z1), (x1,z0).
  mesh.positions = {{lower.x, y, lower.y}, {lower.x, y, upper.y}, {upper.x, y, upper.y}, {upper.x, y, lower.y}};
  mesh.normals.assign(4, glm::vec3(0.0f, -1.0f, 0.0f));
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}};
  scene.instances.push_back({.name = name, .mesh = int(scene.meshes.size())});
  scene.meshes.push_back(std::move(mesh));
}

/// The room, its materials, lamp and camera.
inline igi::Scene procedural_room() {
  // The materials' base colours are each pattern's mean colour: what the constant diffuse
  // comparison shows and what the VPL random walks bounce with.
  igi::Scene scene;
  scene.name = "procedural room";
  const auto diffuse = [](const char* name, glm::vec3 albedo) {
    return igi::Material{.name = name, .base_color = glm::vec4(albedo, 1.0f), .metallic = 0.0f, .roughness = 1.0f, .specular = 0.0f};
  };
  scene.materials = {
      diffuse("plain wall", {0.75f, 0.74f, 0.70f}),
      diffuse("blue wall", {0.40f, 0.50f, 0.70f}),
      diffuse("wood floor", {0.62f, 0.42f, 0.22f}),
      diffuse("brick wall", {0.62f, 0.30f, 0.22f}),
      diffuse("marble", {0.70f, 0.68f, 0.66f}),
      diffuse("wood box", {0.62f, 0.42f, 0.22f}),
      diffuse("lamp", {0.78f, 0.78f, 0.78f}),
  };
  // The lamp's radiance: 15 W/(m^2 sr) over its 0.64 m^2 gives the floor about 1.5 W/m^2, a
  // living-room level once tone mapped (the mapping removes the absolute scale anyway).
  scene.materials[lamp].emission = glm::vec3(15.0f, 14.0f, 12.0f);

  // Each wall is a thin slab of its own, so each can have its own material.
  const float t = 0.02f;  // wall thickness: thin, but solid for the VPL walks
  const glm::vec3 s = room_size;
  add_box(scene, "floor", {0, -t, 0}, {s.x, 0, s.z}, wood_floor);
  add_box(scene, "ceiling", {0, s.y, 0}, {s.x, s.y + t, s.z}, plain_wall);
  add_box(scene, "back wall", {0, 0, -t}, {s.x, s.y, 0}, brick_wall);
  add_box(scene, "front wall", {0, 0, s.z}, {s.x, s.y, s.z + t}, plain_wall);
  add_box(scene, "left wall", {-t, 0, 0}, {0, s.y, s.z}, blue_wall);
  add_box(scene, "right wall", {s.x, 0, 0}, {s.x + t, s.y, s.z}, plain_wall);
  // Furniture: a marble block and a marble pillar, a wooden chest, a marble panel on the right wall.
  add_box(scene, "marble block", {0.5f, 0.0f, 1.0f}, {1.3f, 0.8f, 1.8f}, marble);
  add_box(scene, "marble pillar", {2.9f, 0.0f, 0.6f}, {3.4f, 1.9f, 1.1f}, marble);
  add_box(scene, "wood chest", {1.7f, 0.0f, 2.2f}, {2.9f, 0.6f, 2.9f}, wood_box);
  add_box(scene, "marble panel", {s.x - 0.05f, 0.8f, 2.0f}, {s.x, 2.0f, 3.6f}, marble);
  // The lamp hangs 5 cm below the ceiling, 0.8 m square, centred over the room.
  add_ceiling_panel(scene, "lamp", {0.5f * s.x - 0.4f, 0.5f * s.z - 0.4f}, {0.5f * s.x + 0.4f, 0.5f * s.z + 0.4f},
                    s.y - 0.05f, lamp);

  igi::Camera camera;
  camera.name = "room camera";
  // Near the front wall at eye height, looking at the back wall's centre.
  camera.camera_to_world = glm::inverse(glm::lookAt(glm::vec3(0.5f * s.x, 1.4f, s.z - 0.1f),
                                                    glm::vec3(0.5f * s.x, 1.0f, 0.0f), glm::vec3(0.0f, 1.0f, 0.0f)));
  camera.yfov = glm::radians(60.0f);  // wide enough to see both side walls from the front wall
  camera.znear = 0.01f;
  scene.cameras.push_back(camera);
  return scene;
}

/// Index of the instance named "lamp"; throws std::invalid_argument if there is none.
inline int lamp_instance(const igi::Scene& scene) {
  for (std::size_t i = 0; i < scene.instances.size(); ++i)
    if (scene.instances[i].name == "lamp") return int(i);
  throw std::invalid_argument("scene '" + scene.name + "' has no instance named 'lamp'");
}

/// The transform that moves the lamp from where procedural_room() put it to where it is at frame `frame`.
inline glm::mat4 lamp_transform(std::uint32_t frame) {
  // A horizontal circle around the ceiling's centre, one turn every 60 frames (2 s at 30 fps);
  // 0.9 m keeps the 0.8 m lamp at least 0.7 m from every wall.
  constexpr int period = 60;
  constexpr float radius = 0.9f;
  const float angle = glm::two_pi<float>() * float(frame % period) / float(period);
  return glm::translate(glm::mat4(1.0f), radius * glm::vec3(std::cos(angle), 0.0f, std::sin(angle)));
}

/// The room's surface shader: per material, marble, wood or brick bump (or all constant diffuse).
class RoomShader {
 public:
  /// Procedural patterns, or every material's constant base colour.
  enum class Mode { procedural, constant };

  /// Shader for the materials of `scene` (procedural_room()); throws if it has another material count.
  RoomShader(const igi::Scene& scene, Mode mode) : mode_(mode) {
    if (scene.materials.size() != std::size_t(material_count))
      throw std::invalid_argument("RoomShader: scene '" + scene.name + "' has " + std::to_string(scene.materials.size()) +
                                  " materials, the procedural room has " + std::to_string(int(material_count)));
    for (const igi::Material& material : scene.materials) {
      constants_.emplace_back(glm::vec3(material.base_color));
      emission_.push_back(material.emission);
    }
  }
  /// Policy name.
  static constexpr const char* name() noexcept { return "procedural-room"; }
  /// The mode it was built with.
  Mode mode() const noexcept { return mode_; }

  /// BRDF parameters of the lanes of `mask` (zeros elsewhere), each lane shaded by its material's shader.
  template <int W>
  igi::BrdfParameters<W> shade(const igi::SurfaceHit<W>& hit, const igi::vmask<W>& mask) const noexcept {
    // Each material's shader runs once, on the lanes of that material. Every shader leaves zeros
    // outside its lanes, so the sum of their results is the per-lane choice.
    igi::BrdfParameters<W> out;
    for (int material = 0; material < material_count; ++material) {
      const igi::vmask<W> lanes = mask & (hit.material == igi::vint<W>(material));
      if (igi::none(lanes)) continue;
      add(out, shade_material(material, hit, lanes));
      out.emission += igi::keep(igi::vec3<W>(emission_[std::size_t(material)]), lanes);
    }
    return out;
  }

 private:
  template <int W>
  igi::BrdfParameters<W> shade_material(int material, const igi::SurfaceHit<W>& hit, const igi::vmask<W>& lanes) const noexcept {
    if (mode_ == Mode::procedural) {
      switch (material) {
        case wood_floor: return floor_wood_.shade(hit, lanes);
        case wood_box: return box_wood_.shade(hit, lanes);
        case brick_wall: return brick_.shade(hit, lanes);
        case marble: return marble_.shade(hit, lanes);
        default: break;
      }
    }
    return constants_[std::size_t(material)].shade(hit, lanes);
  }

  /// `to` += `from`, field by field (masks or'ed).
  template <int W>
  static void add(igi::BrdfParameters<W>& to, const igi::BrdfParameters<W>& from) noexcept {
    to.albedo += from.albedo;
    to.glossy += from.glossy;
    to.shininess += from.shininess;
    to.mirror += from.mirror;
    to.transmission += from.transmission;
    to.ior += from.ior;
    to.normal += from.normal;
    to.emission += from.emission;
    to.opaque |= from.opaque;
  }

  Mode mode_;
  std::vector<igi::ConstantDiffuseShader> constants_;
  std::vector<glm::vec3> emission_;
  // Floor boards: rings around an axis along x half a metre under the floor, 4 cm apart.
  igi::WoodShader floor_wood_{igi::WoodSettings{.center = {0.0f, -0.5f, 2.5f}, .axis = {1.0f, 0.0f, 0.0f}, .scale = 0.04f}};
  // The chest: a darker wood, rings around a vertical axis through its corner, 3 cm apart.
  igi::WoodShader box_wood_{igi::WoodSettings{.light = {0.55f, 0.34f, 0.16f}, .dark = {0.30f, 0.16f, 0.06f},
                                              .center = {1.7f, 0.0f, 2.2f}, .scale = 0.03f, .seed = 7}};
  // Bricks of 40 x 16 cm with 2 cm joints: large enough to read at 640 x 480 across a 4 m wall.
  igi::BrickBumpShader brick_{igi::BrickBumpSettings{.brick_width = 0.4f, .brick_height = 0.16f, .mortar_width = 0.02f}};
  // Marble bands 30 cm wide.
  igi::MarbleShader marble_{igi::MarbleSettings{.scale = 0.3f}};
};

}  // namespace igi_procedural
