// make_surface_hit against hand-computed world-space geometry.

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>

#include <catch2/catch.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "scene_builders.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/scene/camera.hpp"
#include "igi/shading/constants.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "igi/shading/surface_hit_builder.hpp"

using namespace igi;

namespace {

// A unit quad in the object-space plane z = 0 (front face +z) with tilted vertex normals, placed
// by a rotation, a non-uniform scale and a translation.
Scene tilted_scene(const glm::mat4& transform) {
  Scene scene;
  testing::add_quad(scene, {0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}, 0.5f, testing::add_material(scene, glm::vec3(0.5f)),
                    transform);
  // Vertex normals leaning towards +x: the shading normal differs from the geometric one.
  for (glm::vec3& n : scene.meshes[0].normals) n = glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f));
  return scene;
}

glm::mat4 test_transform() {
  glm::mat4 t = glm::translate(glm::mat4(1.0f), glm::vec3(1.0f, 2.0f, -3.0f));
  t = glm::rotate(t, 0.7f, glm::normalize(glm::vec3(1.0f, 1.0f, 0.0f)));
  return glm::scale(t, glm::vec3(2.0f, 0.5f, 3.0f));
}

}  // namespace

TEST_CASE("make_surface_hit: world position, normals, uv and ids match the transformed quad", "[shading]") {
  const glm::mat4 transform = test_transform();
  const Scene scene = tilted_scene(transform);
  const ReferenceBackend<4> backend(scene);
  const glm::vec3 world_normal = glm::normalize(glm::transpose(glm::inverse(glm::mat3(transform))) * glm::vec3(0, 0, 1));

  // Four object-space targets on the quad, seen from the front (lanes 0, 1) and the back (2, 3).
  const glm::vec2 targets[4] = {{0.1f, 0.2f}, {-0.3f, 0.25f}, {0.4f, -0.4f}, {-0.2f, -0.1f}};
  RayPacket<4> rays;
  vec3<4> origin, direction;
  glm::vec3 expected[4];
  for (int i = 0; i < 4; ++i) {
    expected[i] = glm::vec3(transform * glm::vec4(targets[i], 0.0f, 1.0f));
    const float side = i < 2 ? 1.0f : -1.0f;
    const glm::vec3 from = expected[i] + side * 4.0f * world_normal + glm::vec3(0.3f, -0.2f, 0.1f);
    origin.set(i, from);
    direction.set(i, (expected[i] - from) * 0.5f);  // deliberately not unit length
  }
  rays.set(origin, direction, vfloat<4>(0.0f), vfloat<4>(1e30f), vmask<4>(true));
  HitPacket<4> hits;
  hits.clear();
  backend.intersect(rays, hits, vmask<4>(true));
  REQUIRE(all(hits.valid()));

  vmask<4> mask(true);
  mask.set(3, false);  // lane 3 hit but is inactive: it must come out zero
  const SurfaceHit<4> hit = make_surface_hit(scene, rays, hits, mask);
  const SurfaceHit<4> cached = make_surface_hit(scene, SceneGeometry(scene), rays, hits, mask);

  const glm::vec3 shading_world =
      glm::normalize(glm::transpose(glm::inverse(glm::mat3(transform))) * glm::normalize(glm::vec3(0.5f, 0, 1)));
  for (int i = 0; i < 3; ++i) {
    INFO("lane " << i);
    const glm::vec3 from = origin[i];
    // Float tolerance: coordinates of size ~5 carry rounding of a few 1e-7 relative.
    CHECK(glm::length(hit.position[i] - expected[i]) < 1e-4f);
    CHECK(hit.distance[i] == Approx(glm::length(expected[i] - from)).epsilon(1e-5));
    const glm::vec3 facing = i < 2 ? world_normal : -world_normal;
    CHECK(glm::length(hit.geometric_normal[i] - facing) < 1e-5f);
    CHECK(hit.front_face[i] == (i < 2));
    CHECK(glm::length(hit.wo[i] - glm::normalize(from - expected[i])) < 1e-5f);
    const glm::vec3 shading = i < 2 ? shading_world : -shading_world;
    CHECK(glm::length(hit.shading_normal[i] - shading) < 1e-5f);
    CHECK(glm::dot(hit.shading_normal[i], hit.geometric_normal[i]) > 0.0f);
    // uv of the quad is (x + 0.5, y + 0.5) in object space, so the position's derivatives along
    // u and v are the transformed x and y axes, on both faces.
    CHECK(hit.u[i] == Approx(targets[i].x + 0.5f).margin(1e-5));
    CHECK(hit.v[i] == Approx(targets[i].y + 0.5f).margin(1e-5));
    CHECK(glm::length(hit.dpdu[i] - glm::mat3(transform) * glm::vec3(1, 0, 0)) < 1e-5f);
    CHECK(glm::length(hit.dpdv[i] - glm::mat3(transform) * glm::vec3(0, 1, 0)) < 1e-5f);
    CHECK(hit.material[i] == 0);
    CHECK(hit.mesh[i] == 0);
    CHECK(hit.instance[i] == 0);
    CHECK((hit.triangle[i] == 0 || hit.triangle[i] == 1));
    // The cached and uncached builders agree exactly.
    CHECK(cached.position[i] == hit.position[i]);
    CHECK(cached.shading_normal[i] == hit.shading_normal[i]);
  }
  CHECK(hit.position[3] == glm::vec3(0.0f));
  CHECK(hit.geometric_normal[3] == glm::vec3(0.0f));
  CHECK(hit.shading_normal[3] == glm::vec3(0.0f));
  CHECK(hit.distance[3] == 0.0f);
  CHECK(hit.u[3] == 0.0f);
  CHECK(hit.dpdu[3] == glm::vec3(0.0f));
  CHECK(hit.dpdv[3] == glm::vec3(0.0f));
  CHECK_FALSE(hit.front_face[3]);
}

TEST_CASE("make_surface_hit: a ray cone's texture footprint is its width over the surface in uv units", "[shading][texture]") {
  // The quad of the test above: object uv = (x + 0.5, y + 0.5), so after the scale (2, 0.5, 3)
  // one unit of uv spans 2 x 0.5 world units of area: sqrt(1 / 1) = 1 uv unit per world unit.
  // A quad of its own scaled by 4 has 1/4; one without uvs 0.
  const glm::mat4 transform = test_transform();
  for (const float extra_scale : {1.0f, 4.0f}) {
    const Scene scene = tilted_scene(transform * glm::scale(glm::mat4(1.0f), glm::vec3(extra_scale)));
    const glm::mat4 placed = transform * glm::scale(glm::mat4(1.0f), glm::vec3(extra_scale));
    const glm::vec3 world_normal = glm::normalize(glm::transpose(glm::inverse(glm::mat3(placed))) * glm::vec3(0, 0, 1));
    const ReferenceBackend<4> backend(scene);
    // Lanes: head-on-ish, slanted, from behind, and within a degree of grazing (the 1/64 bound).
    const glm::vec2 targets[4] = {{0.1f, 0.2f}, {-0.3f, 0.25f}, {0.4f, -0.4f}, {-0.2f, -0.1f}};
    const glm::vec3 tangent = glm::normalize(glm::vec3(placed * glm::vec4(1, 0, 0, 0)));
    const glm::vec3 offsets[4] = {4.0f * world_normal, 2.0f * world_normal + 3.0f * tangent, -3.0f * world_normal,
                                  0.01f * world_normal - 2.0f * tangent};
    RayPacket<4> rays;
    vec3<4> origin, direction;
    glm::vec3 expected[4];
    for (int i = 0; i < 4; ++i) {
      expected[i] = glm::vec3(placed * glm::vec4(targets[i], 0.0f, 1.0f));
      origin.set(i, expected[i] + offsets[i]);
      direction.set(i, -offsets[i] * 0.25f);  // not unit length: distances are in world units all the same
    }
    rays.set(origin, direction, vfloat<4>(0.0f), vfloat<4>(1e30f), vmask<4>(true));
    HitPacket<4> hits;
    hits.clear();
    backend.intersect(rays, hits, vmask<4>(true));
    REQUIRE(all(hits.valid()));
    const float spread = 0.003f;
    const SurfaceHit<4> hit = make_surface_hit(scene, SceneGeometry(scene), rays, hits, vmask<4>(true), spread);
    for (int i = 0; i < 4; ++i) {
      INFO("scale " << extra_scale << ", lane " << i);
      const float distance = glm::length(offsets[i]);
      const float cosine = std::max(std::abs(glm::dot(world_normal, glm::normalize(offsets[i]))), 1.0f / 64.0f);
      const float density = 1.0f / extra_scale;
      CHECK(hit.texture_footprint[i] == Approx(density * spread * distance / std::sqrt(cosine)).epsilon(1e-4));
    }
    CHECK(hit.texture_footprint[3] == Approx(8.0f * spread * glm::length(offsets[3]) / extra_scale).epsilon(1e-4));
    // Without a cone, and on a packet of one lane, the footprint is what it should be too.
    const SurfaceHit<4> no_cone = make_surface_hit(scene, SceneGeometry(scene), rays, hits, vmask<4>(true));
    for (int i = 0; i < 4; ++i) CHECK(no_cone.texture_footprint[i] == 0.0f);
    RayPacket<1> ray;
    ray.set(vec3<1>(origin[1]), vec3<1>(direction[1]), vfloat<1>(0.0f), vfloat<1>(1e30f), vmask<1>(true));
    HitPacket<1> one;
    one.clear();
    backend.intersect(ray, one, vmask<1>(true));
    const SurfaceHit<1> single = make_surface_hit(scene, SceneGeometry(scene), ray, one, vmask<1>(true), spread);
    CHECK(single.texture_footprint[0] == Approx(hit.texture_footprint[1]).epsilon(1e-6));
  }
  // No texture coordinates: nothing to filter.
  Scene bare = tilted_scene(glm::mat4(1.0f));
  bare.meshes[0].uvs.clear();
  const ReferenceBackend<4> backend(bare);
  RayPacket<4> rays;
  rays.set(vec3<4>(glm::vec3(0, 0, 1)), vec3<4>(glm::vec3(0, 0, -1)), vfloat<4>(0.0f), vfloat<4>(10.0f), vmask<4>(true));
  HitPacket<4> hits;
  hits.clear();
  backend.intersect(rays, hits, vmask<4>(true));
  REQUIRE(all(hits.valid()));
  CHECK(make_surface_hit(bare, SceneGeometry(bare), rays, hits, vmask<4>(true), 0.01f).texture_footprint[0] == 0.0f);
}

TEST_CASE("texture footprints: one camera ray per pixel reads a textured floor as its pixel's average",
          "[shading][texture]") {
  // A 40 m floor with bands 8 texels wide (dark and light) under a checkerboard of single
  // texels (64 x 64, repeated 16 times: 4 cm checks), seen from 1.5 m high at 64 x 48 pixels:
  // near pixels cover about a texel, far ones ten or more, where a lookup at the pixel's centre
  // reads either check at random; the bands show when a filter blurs more than the pixel.
  // Truth: the mean albedo of 8 x 8 rays spread over each pixel, read at their points.
  Scene scene;
  Texture board;
  board.name = "board";
  board.width = board.height = 64;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x)
      for (int channel = 0; channel < 4; ++channel)
        board.texels.push_back(std::uint8_t(channel == 3 ? 255 : ((x / 8) % 2 ? 200 : 60) + ((x + y) % 2 ? 25 : -25)));
  scene.textures.push_back(board);
  const int material = testing::add_material(scene, glm::vec3(1.0f));
  scene.materials[std::size_t(material)].base_color_texture = 0;
  testing::add_quad(scene, {0, 0, -20}, {1, 0, 0}, {0, 0, 1}, {0, 1, 0}, 20.0f, material);
  for (glm::vec2& uv : scene.meshes[0].uvs) uv *= 16.0f;
  const GltfMaterialShader shader(scene);
  const SceneGeometry geometry(scene);
  const ReferenceBackend<8> backend(scene);
  const PinholeProjection projection(testing::look_at({0.0f, 1.5f, 0.0f}, {0.0f, 0.0f, -10.0f}, 0.8f), 64, 48);

  // The albedo of one ray per lane through pixel coordinates (px, py), with a cone of `spread`.
  const auto albedo = [&](const vfloat<8>& px, const vfloat<8>& py, float spread, vmask<8>& hit) {
    RayPacket<8> rays;
    rays.set(vec3<8>(projection.origin()), projection.direction(px, py), vfloat<8>(0.0f),
             vfloat<8>(std::numeric_limits<float>::infinity()), vmask<8>(true));
    HitPacket<8> hits;
    hits.clear();
    backend.intersect(rays, hits, vmask<8>(true));
    hit = hits.valid();
    return shader.shade(make_surface_hit(scene, geometry, rays, hits, hit, spread), hit).albedo.x;
  };
  double filtered_error = 0.0, point_error = 0.0;
  int pixels = 0;
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; x += 8) {
      vfloat<8> truth(0.0f);
      vmask<8> covered(true);
      for (int sy = 0; sy < 8; ++sy)
        for (int sx = 0; sx < 8; ++sx) {
          vmask<8> hit;
          truth += albedo(vfloat<8>([&](int i) { return float(x + i) + (sx + 0.5f) / 8.0f; }),
                          vfloat<8>(float(y) + (sy + 0.5f) / 8.0f), 0.0f, hit) / vfloat<8>(64.0f);
          covered &= hit;
        }
      const vfloat<8> px([&](int i) { return float(x + i) + 0.5f; }), py(float(y) + 0.5f);
      vmask<8> hit;
      const vfloat<8> filtered = albedo(px, py, projection.pixel_spread(), hit);
      const vfloat<8> point = albedo(px, py, 0.0f, hit);
      for (int i = 0; i < 8; ++i) {
        if (!covered[i]) continue;  // the horizon's pixels, partly sky
        filtered_error += double(filtered[i] - truth[i]) * double(filtered[i] - truth[i]);
        point_error += double(point[i] - truth[i]) * double(point[i] - truth[i]);
        ++pixels;
      }
    }
  REQUIRE(pixels > 1000);
  filtered_error = std::sqrt(filtered_error / pixels);
  point_error = std::sqrt(point_error / pixels);
  INFO("RMSE against the pixels' averages: filtered " << filtered_error << ", point " << point_error);
  // Measured 0.041 against 0.128. A cone half or twice as wide gives 0.097 or 0.110 (under- and
  // over-filtered): 0.4 x the point lookups' error fails both.
  CHECK(filtered_error < 0.4 * point_error);
}

TEST_CASE("make_surface_hit: missed lanes are zero and bad ids throw", "[shading]") {
  const Scene scene = tilted_scene(glm::mat4(1.0f));
  RayPacket<4> rays;
  rays.set(vec3<4>(glm::vec3(0, 0, 1)), vec3<4>(glm::vec3(0, 0, -1)), vfloat<4>(0.0f), vfloat<4>(10.0f), vmask<4>(true));
  HitPacket<4> hits;
  hits.clear();
  const SurfaceHit<4> none_hit = make_surface_hit(scene, rays, hits, vmask<4>(true));
  for (int i = 0; i < 4; ++i) CHECK(none_hit.wo[i] == glm::vec3(0.0f));

  hits.geomID[0] = 0;
  hits.instID[0] = 0;
  hits.primID[0] = 7;  // the quad has 2 triangles
  CHECK_THROWS_AS(make_surface_hit(scene, rays, hits, vmask<4>(true)), std::out_of_range);
  hits.primID[0] = 0;
  hits.instID[0] = 5;
  CHECK_THROWS_WITH(make_surface_hit(scene, rays, hits, vmask<4>(true)), Catch::Contains("instance id 5"));
}

TEST_CASE("make_surface_hit: a degenerate triangle gives finite normals facing the ray", "[shading]") {
  Scene scene = tilted_scene(glm::mat4(1.0f));
  scene.meshes[0].positions[2] = scene.meshes[0].positions[1];  // triangle 0 collapses to a segment
  scene.meshes[0].normals.clear();                             // and no vertex normals
  RayPacket<1> ray;
  ray.set(vec3<1>(glm::vec3(0, 0, 1)), vec3<1>(glm::vec3(0, 0, -1)), vfloat<1>(0.0f), vfloat<1>(1.0f), vmask<1>(true));
  HitPacket<1> hit;
  hit.clear();
  hit.geomID[0] = hit.instID[0] = hit.primID[0] = 0;
  hit.u[0] = 0.3f;
  hit.v[0] = 0.3f;
  const SurfaceHit<1> s = make_surface_hit(scene, ray, hit, vmask<1>(true));
  CHECK(glm::length(s.geometric_normal[0] - glm::vec3(0, 0, 1)) < 1e-6f);
  CHECK(glm::length(s.shading_normal[0] - glm::vec3(0, 0, 1)) < 1e-6f);
}

TEST_CASE("ray offsets: one rule scales with the scene and puts rays on the side they leave to", "[shading][ray-offset]") {
  const Bounds unit{glm::vec3(0.0f), glm::vec3(1.0f)};
  const Bounds large{glm::vec3(0.0f), glm::vec3(1000.0f)};
  // The offset is linear in the scene's size (diagonal plus distance from the origin).
  CHECK(ray_offset(large) == Approx(1000.0f * ray_offset(unit)).epsilon(1e-5));
  CHECK(ray_offset(Bounds{}) > 0.0f);  // an empty scene still gets a usable offset

  const vec3<4> position(glm::vec3(0.5f, 0.5f, 0.0f));
  const vec3<4> normal(glm::vec3(0.0f, 0.0f, 1.0f));
  vec3<4> direction;
  direction.set(0, glm::vec3(0.0f, 0.0f, 1.0f));     // straight out
  direction.set(1, glm::vec3(0.0f, 0.0f, -1.0f));    // straight in (refraction)
  direction.set(2, glm::vec3(0.6f, 0.0f, 0.8f));     // oblique out
  direction.set(3, glm::vec3(0.0f, 0.99f, -0.14f));  // grazing in
  const vec3<4> start = leave_surface(position, normal, direction, 0.25f);
  CHECK(start[0].z == 0.25f);
  CHECK(start[1].z == -0.25f);
  CHECK(start[2].z == 0.25f);
  CHECK(start[3].z == -0.25f);
  CHECK(start[2].x == 0.5f);  // moved along the normal only
}

TEST_CASE("ray offsets: rays leaving a surface far from the origin never hit it again", "[shading][ray-offset]") {
  // A wall 10 km from the origin, tilted so its hit points round in every coordinate: float
  // spacing there is about 1 mm, so a fixed small offset would let rays re-hit their own surface.
  Scene scene;
  const glm::vec3 center(10000.0f, 2000.0f, -7000.0f);
  const glm::vec3 u = glm::normalize(glm::vec3(1.0f, 0.3f, 0.2f));
  const glm::vec3 normal = glm::normalize(glm::cross(u, glm::vec3(0.1f, 1.0f, 0.4f)));
  const glm::vec3 v = glm::cross(normal, u);
  testing::add_quad(scene, center, u, v, normal, 50.0f, testing::add_material(scene, glm::vec3(0.5f)));
  const ReferenceBackend<8> backend(scene);
  const float offset = ray_offset(scene.bounds());
  int rays = 0;
  for (int i = 0; i < 64; ++i) {
    // Hit the wall from the front at scattered points, then leave it in scattered directions on
    // both sides: reflection-like rays (front) and refraction-like rays (back).
    const float a = float(i % 8) / 8.0f - 0.45f, b = float(i / 8) / 8.0f - 0.45f;
    const glm::vec3 target = center + 40.0f * (a * u + b * v);
    RayPacket<8> primary;
    primary.set(vec3<8>(target + 100.0f * normal + 7.0f * u), vec3<8>(glm::normalize(-100.0f * normal - 7.0f * u)),
                vfloat<8>(0.0f), vfloat<8>(1e30f), vmask<8>::first(1));
    HitPacket<8> hit;
    hit.clear();
    backend.intersect(primary, hit, vmask<8>::first(1));
    REQUIRE(hit.geomID[0] != invalid_id);
    const glm::vec3 point = primary.origin()[0] + primary.tfar[0] * primary.direction()[0];
    vec3<8> direction;
    for (int lane = 0; lane < 8; ++lane) {
      const float side = lane < 4 ? 1.0f : -1.0f;
      const float tilt = 0.05f + 0.3f * float(lane % 4);  // from nearly grazing to steep
      direction.set(lane, glm::normalize(side * tilt * normal + u * std::cos(float(i + lane)) + v * std::sin(float(i + lane))));
    }
    RayPacket<8> leaving;
    leaving.set(leave_surface(vec3<8>(point), vec3<8>(normal), direction, offset), direction, vfloat<8>(0.0f),
                vfloat<8>(1e30f), vmask<8>(true));
    HitPacket<8> again;
    again.clear();
    backend.intersect(leaving, again, vmask<8>(true));
    for (int lane = 0; lane < 8; ++lane, ++rays) CHECK(again.geomID[lane] == invalid_id);
  }
  CHECK(rays == 512);
}

TEST_CASE("make_surface_hit: a mesh's TANGENTs turn the normal maps' frame, mirrored instances included",
          "[shading][normal-map]") {
  // The quad's tangents run along object +y (a quarter turn from its u axis, +x), w = +-1; under
  // a plain and a mirroring transform the frame must follow the tangents: dpdu along the world
  // tangent, -dpdv along the bitangent w cross(n, t), on the same side as the transformed object
  // bitangent (a mirror turns the cross product, which the handedness undoes), each as long as
  // the uv derivative it replaces. A vertex without a usable tangent (w = 0) keeps the uv frame.
  for (const float mirror : {1.0f, -1.0f})
    for (const float sign : {1.0f, -1.0f}) {
      INFO("mirror " << mirror << ", w " << sign);
      const glm::mat4 transform = glm::scale(test_transform(), glm::vec3(mirror, 1.0f, 1.0f));
      Scene scene = tilted_scene(transform);
      Mesh& mesh = scene.meshes[0];
      mesh.tangents.assign(mesh.positions.size(), glm::vec4(0.0f, 1.0f, 0.0f, sign));
      const ReferenceBackend<4> backend(scene);
      const glm::vec3 world_normal = glm::normalize(glm::transpose(glm::inverse(glm::mat3(transform))) * glm::vec3(0, 0, 1));
      RayPacket<4> rays;
      vec3<4> origin, direction;
      for (int i = 0; i < 4; ++i) {
        const glm::vec3 target(transform * glm::vec4(0.1f * float(i) - 0.2f, 0.15f - 0.1f * float(i), 0.0f, 1.0f));
        origin.set(i, target + 3.0f * world_normal);
        direction.set(i, -world_normal);
      }
      rays.set(origin, direction, vfloat<4>(0.0f), vfloat<4>(1e30f), vmask<4>(true));
      HitPacket<4> hits;
      hits.clear();
      backend.intersect(rays, hits, vmask<4>(true));
      REQUIRE(all(hits.valid()));
      const SurfaceHit<4> hit = make_surface_hit(scene, rays, hits, vmask<4>(true));

      const glm::mat3 linear(transform);
      const glm::vec3 vertex_normal =
          glm::normalize(glm::transpose(glm::inverse(linear)) * glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f)));
      const glm::vec3 tangent = glm::normalize(linear * glm::vec3(0, 1, 0));
      const glm::vec3 bitangent = glm::cross(vertex_normal, tangent) * sign * mirror;
      const glm::vec3 object_bitangent = glm::cross(glm::normalize(glm::vec3(0.5f, 0.0f, 1.0f)), glm::vec3(0, 1, 0)) * sign;
      const float u_length = glm::length(linear * glm::vec3(1, 0, 0)), v_length = glm::length(linear * glm::vec3(0, 1, 0));
      for (int i = 0; i < 4; ++i) {
        INFO("lane " << i);
        // 1e-5: float rounding of the transforms and normalisations (lengths up to 3).
        CHECK(glm::length(hit.dpdu[i] - tangent * u_length) < 1e-5f);
        CHECK(glm::length(hit.dpdv[i] + bitangent * v_length) < 1e-5f);
        CHECK(glm::dot(-hit.dpdv[i], linear * object_bitangent) > 0.0f);
      }
      // Vertices without usable tangents (w = 0, as the loader leaves them): the uv derivatives stay.
      for (glm::vec4& t : mesh.tangents) t.w = 0.0f;
      const SurfaceHit<4> plain = make_surface_hit(scene, rays, hits, vmask<4>(true));
      for (int i = 0; i < 4; ++i) {
        CHECK(glm::length(plain.dpdu[i] - linear * glm::vec3(1, 0, 0)) < 1e-5f);
        CHECK(glm::length(plain.dpdv[i] - linear * glm::vec3(0, 1, 0)) < 1e-5f);
      }
    }
}
