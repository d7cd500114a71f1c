#pragma once
/// \file
/// The built-in window room: a furnished room that daylight reaches only through one window, the
/// case where VPLs from the lights mostly land outside, where the camera does not look. A 5 x 4 m
/// room, 2.8 m high, with 0.2 m thick walls, floor and ceiling (boxes, so light cannot leak
/// through an edge); a 2 x 1.2 m window opening in the wall at +z; outside, a ground plane, the sun
/// (a directional light shining in through the window onto the floor) and a bright overcast-sky
/// panel (an emissive quad) facing the window; inside, a table, a tall cabinet and a low sofa.
/// The camera stands in the corner opposite the window and looks across the room at the window
/// wall, the sun patch on the floor and the furniture. Units are metres, y is up.

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/scene/scene.hpp"

namespace igi {

namespace window_room_detail {

/// An empty mesh called `name`.
inline Mesh named_mesh(const std::string& name) {
  Mesh mesh;
  mesh.name = name;
  return mesh;
}

/// Appends an axis-aligned box from `lower` to `upper` to `mesh`, faces outward, flat normals.
inline void add_box(Mesh& mesh, const glm::vec3& lower, const glm::vec3& upper) {
  const glm::vec3 l = lower, u = upper;
  // Each face: its outward normal and four corners counter-clockwise seen from outside.
  const struct {
    glm::vec3 normal;
    glm::vec3 corners[4];
  } faces[6] = {
      {{1, 0, 0}, {{u.x, l.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z}, {u.x, l.y, u.z}}},
      {{-1, 0, 0}, {{l.x, l.y, l.z}, {l.x, l.y, u.z}, {l.x, u.y, u.z}, {l.x, u.y, l.z}}},
      {{0, 1, 0}, {{l.x, u.y, l.z}, {l.x, u.y, u.z}, {u.x, u.y, u.z}, {u.x, u.y, l.z}}},
      {{0, -1, 0}, {{l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, l.y, u.z}, {l.x, l.y, u.z}}},
      {{0, 0, 1}, {{l.x, l.y, u.z}, {u.x, l.y, u.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z}}},
      {{0, 0, -1}, {{l.x, l.y, l.z}, {l.x, u.y, l.z}, {u.x, u.y, l.z}, {u.x, l.y, l.z}}},
  };
  for (const auto& face : faces) {
    const auto first = unsigned(mesh.positions.size());
    for (const glm::vec3& corner : face.corners) {
      mesh.positions.push_back(corner);
      mesh.normals.push_back(face.normal);
    }
    mesh.triangles.push_back({first, first + 1, first + 2});
    mesh.triangles.push_back({first, first + 2, first + 3});
  }
}

/// Appends a material of linear `albedo` (and `emission`, radiance) to `scene`; returns its index.
inline int add_material(Scene& scene, const std::string& name, const glm::vec3& albedo,
                        const glm::vec3& emission = glm::vec3(0.0f)) {
  Material material;
  material.name = name;
  material.base_color = glm::vec4(albedo, 1.0f);
  material.metallic = 0.0f;
  material.roughness = 1.0f;
  material.specular = 0.0f;  // matte paint: exactly Lambertian, as the room's reference comparisons assume
  material.emission = emission;
  scene.materials.push_back(material);
  return int(scene.materials.size()) - 1;
}

/// Appends `mesh` with `material` as one instance at the identity.
inline void add_object(Scene& scene, Mesh mesh, int material) {
  mesh.material = material;
  Instance instance;
  instance.name = mesh.name;
  instance.mesh = int(scene.meshes.size());
  scene.meshes.push_back(std::move(mesh));
  scene.instances.push_back(instance);
}

}  // namespace window_room_detail

/// The window room scene (boxes and one quad, 8 materials, the sun, a sky panel, one camera), built in code.
inline Scene window_room();

/// The window room with venetian blinds in the window: 12 level white slats, 9 cm deep, 10 cm
/// apart, so the sun (33 degrees high) falls through 42% of each gap in sharp stripes on the
/// floor, and the sky's light comes in only between them. The case of thin shadow edges the
/// interleaving filter must not turn into staircases, and of light that reaches the room
/// through many narrow gaps.
inline Scene window_room_with_blinds() {
  using namespace window_room_detail;
  Scene scene = window_room();
  scene.name = "blinds";
  const int slat_material = add_material(scene, "blind slat", {0.80f, 0.80f, 0.78f});  // white painted aluminium
  // The opening (window_room): x 1.5 .. 3.5, y 0.9 .. 2.1, the wall's inner face at z = 4.
  constexpr int slats = 12;
  constexpr float spacing = 0.1f, first_centre = 0.95f;
  Mesh blinds = named_mesh("blinds");
  for (int i = 0; i < slats; ++i) {
    const float y = first_centre + spacing * float(i);
    add_box(blinds, {1.51f, y - 0.002f, 3.9f}, {3.49f, y + 0.002f, 3.99f});  // 4 mm thick, 1 cm inside the opening
  }
  add_object(scene, std::move(blinds), slat_material);
  return scene;
}

/// `room` (window_room() or window_room_with_blinds()) under the sky instead of its sky panel:
/// the panel removed, the neutral sky (neutral_sky()) around it, the sun kept. The rooms as users
/// light them, where the sky's light reaches the room only through the window.
inline Scene with_sky(Scene room) {
  for (std::size_t i = 0; i < room.instances.size(); ++i)
    if (room.instances[i].name == "sky panel") room.instances.erase(room.instances.begin() + std::ptrdiff_t(i--));
  room.environment = std::make_shared<const Environment>(neutral_sky());
  room.name += " under the sky";
  return room;
}

/// The window room under the sky (with_sky) with a second window, 1.4 x 1.2 m in the left wall
/// (x = 0, z 0.8 .. 2.2), so daylight comes from two sides: the sun falls through both (its
/// light travels towards +x as well as -z), and the sky shows in both. Aiming particles at one
/// opening would light half the room: this room checks that openings are found, not assumed.
inline Scene two_window_room() {
  using namespace window_room_detail;
  Scene scene = with_sky(window_room());
  scene.name = "two windows";
  // The left wall (x -0.2 .. 0) rebuilt around the new opening: below, above, behind and before it.
  constexpr float depth = 4.0f, height = 2.8f, t = 0.2f;
  constexpr float bottom = 0.9f, top = 2.1f, back = 0.8f, front = 2.2f;
  Mesh& walls = scene.meshes[std::size_t(scene.instances.front().mesh)];
  // The wall is the first box of the shell (window_room's order): its 24 vertices and 12 triangles go.
  walls.positions.erase(walls.positions.begin(), walls.positions.begin() + 24);
  walls.normals.erase(walls.normals.begin(), walls.normals.begin() + 24);
  walls.triangles.erase(walls.triangles.begin(), walls.triangles.begin() + 12);
  for (glm::uvec3& triangle : walls.triangles) triangle -= glm::uvec3(24);
  add_box(walls, {-t, 0.0f, -t}, {0.0f, bottom, depth + t});
  add_box(walls, {-t, top, -t}, {0.0f, height, depth + t});
  add_box(walls, {-t, bottom, -t}, {0.0f, top, back});
  add_box(walls, {-t, bottom, front}, {0.0f, top, depth + t});
  return scene;
}

inline Scene window_room() {
  using namespace window_room_detail;
  Scene scene;
  scene.name = "window";
  // Albedos of ordinary interior finishes (painted plaster, oak floor, fabric, a grey lawn-and-paving mix).
  const int wall = add_material(scene, "plaster", {0.75f, 0.72f, 0.66f});
  const int floor = add_material(scene, "oak", {0.45f, 0.30f, 0.18f});
  const int ceiling = add_material(scene, "ceiling", {0.80f, 0.80f, 0.78f});
  const int wood = add_material(scene, "walnut", {0.30f, 0.18f, 0.10f});
  const int fabric = add_material(scene, "blue fabric", {0.15f, 0.25f, 0.55f});
  const int cabinet = add_material(scene, "white cabinet", {0.70f, 0.70f, 0.70f});
  const int ground = add_material(scene, "ground", {0.25f, 0.30f, 0.20f});
  // The sky panel's radiance: a bright overcast sky is about 5-10x the sunlit floor's radiance
  // in these units (sun irradiance 3 on an albedo of 0.45 reflects 0.43); 2.5 keeps it the
  // second light, the sun the first.
  const int sky = add_material(scene, "sky panel", glm::vec3(0.0f), {2.2f, 2.4f, 2.5f});

  constexpr float width = 5.0f, depth = 4.0f, height = 2.8f, thickness = 0.2f;
  constexpr float window_left = 1.5f, window_right = 3.5f, window_bottom = 0.9f, window_top = 2.1f;
  const float t = thickness;

  Mesh shell = named_mesh("walls");
  add_box(shell, {-t, 0.0f, -t}, {0.0f, height, depth + t});                       // left wall (x = 0)
  add_box(shell, {width, 0.0f, -t}, {width + t, height, depth + t});               // right wall (x = 5)
  add_box(shell, {0.0f, 0.0f, -t}, {width, height, 0.0f});                         // back wall (z = 0)
  add_box(shell, {0.0f, 0.0f, depth}, {width, window_bottom, depth + t});          // window wall: below,
  add_box(shell, {0.0f, window_top, depth}, {width, height, depth + t});           // above,
  add_box(shell, {0.0f, window_bottom, depth}, {window_left, window_top, depth + t});   // left
  add_box(shell, {window_right, window_bottom, depth}, {width, window_top, depth + t}); // and right of the opening
  add_object(scene, std::move(shell), wall);
  Mesh floor_slab = named_mesh("floor");
  add_box(floor_slab, {-t, -t, -t}, {width + t, 0.0f, depth + t});
  add_object(scene, std::move(floor_slab), floor);
  Mesh ceiling_slab = named_mesh("ceiling");
  add_box(ceiling_slab, {-t, height, -t}, {width + t, height + t, depth + t});
  add_object(scene, std::move(ceiling_slab), ceiling);

  Mesh table = named_mesh("table");
  add_box(table, {1.6f, 0.70f, 1.6f}, {3.0f, 0.75f, 2.5f});  // top
  for (const float x : {1.65f, 2.9f})
    for (const float z : {1.65f, 2.4f}) add_box(table, {x, 0.0f, z}, {x + 0.05f, 0.70f, z + 0.05f});
  add_object(scene, std::move(table), wood);
  Mesh tall_cabinet = named_mesh("cabinet");
  add_box(tall_cabinet, {0.0f, 0.0f, 2.6f}, {0.5f, 1.9f, 3.7f});
  add_object(scene, std::move(tall_cabinet), cabinet);
  Mesh sofa = named_mesh("sofa");
  add_box(sofa, {4.1f, 0.0f, 1.0f}, {5.0f, 0.45f, 3.0f});   // seat
  add_box(sofa, {4.75f, 0.45f, 1.0f}, {5.0f, 0.9f, 3.0f});  // back
  add_object(scene, std::move(sofa), fabric);

  // Outside: ground 5 cm under the floor's top, so inside the room the floor slab covers it.
  constexpr float reach = 20.0f;  // far enough that the sun's disc over the scene mostly lands on ground
  Mesh lawn = named_mesh("ground");
  add_box(lawn, {-reach, -0.1f, -reach}, {width + reach, -0.05f, depth + reach});
  add_object(scene, std::move(lawn), ground);
  // The sky panel: 4 x 2.5 m, 6 m outside the window, facing it (normal -z).
  Mesh panel = named_mesh("sky panel");
  const float z = depth + 6.0f;
  for (const glm::vec3& corner : {glm::vec3(0.5f, 0.5f, z), glm::vec3(0.5f, 3.0f, z), glm::vec3(4.5f, 3.0f, z),
                                  glm::vec3(4.5f, 0.5f, z)}) {
    panel.positions.push_back(corner);
    panel.normals.push_back({0.0f, 0.0f, -1.0f});
  }
  panel.triangles = {{0, 1, 2}, {0, 2, 3}};
  add_object(scene, std::move(panel), sky);

  PunctualLight sun;
  sun.name = "sun";
  sun.kind = PunctualKind::directional;
  sun.color = {1.0f, 0.95f, 0.85f};
  sun.intensity = 3.0f;  // irradiance; the sky panel's radiance is set against it
  sun.direction = glm::normalize(glm::vec3(0.25f, -0.55f, -0.8f));  // in through the window, down onto the floor
  scene.lights.push_back(sun);

  Camera camera;
  camera.name = "corner";
  const glm::vec3 eye(4.6f, 1.6f, 0.3f), target(1.8f, 0.9f, 3.6f);
  camera.camera_to_world = glm::inverse(glm::lookAt(eye, target, glm::vec3(0.0f, 1.0f, 0.0f)));
  camera.yfov = glm::radians(60.0f);  // a wide interior view
  scene.cameras.push_back(camera);
  return scene;
}

}  // namespace igi
