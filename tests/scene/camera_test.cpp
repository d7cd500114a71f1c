// Cameras: the fitted default camera, lookup by name, and the pinhole projection (scalar and per
// packet at every width), checked against an independent projection of points to pixels.

#include <cmath>
#include <limits>
#include <stdexcept>

#include <catch2/catch.hpp>
#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>

#include "igi/scene/camera.hpp"
#include "igi/scene/cornell.hpp"

namespace {

/// Continuous pixel coordinates of world point `p` seen by `camera` on a width x height image,
/// computed from the camera's definition (independently of PinholeProjection): square pixels, the
/// vertical field of view over the height, the camera's own aspect ignored.
glm::vec2 project(const igi::Camera& camera, int width, int height, const glm::vec3& p) {
  const glm::vec3 local(glm::inverse(camera.camera_to_world) * glm::vec4(p, 1.0f));
  const float aspect = float(width) / float(height);
  const float t = std::tan(0.5f * camera.yfov);
  const float x = local.x / -local.z / (aspect * t);  // -1 at the left edge, +1 at the right
  const float y = local.y / -local.z / t;             // +1 at the top edge
  return {0.5f * (x + 1.0f) * float(width), 0.5f * (1.0f - y) * float(height)};
}

/// A scene with one box mesh spanning `lower` .. `upper`.
igi::Scene box_scene(const glm::vec3& lower, const glm::vec3& upper) {
  igi::Scene scene;
  scene.name = "box";
  igi::Mesh mesh;
  mesh.name = "box";
  for (int corner = 0; corner < 8; ++corner)
    mesh.positions.push_back({corner & 1 ? upper.x : lower.x, corner & 2 ? upper.y : lower.y, corner & 4 ? upper.z : lower.z});
  mesh.triangles = {{0, 1, 2}};
  scene.meshes.push_back(mesh);
  scene.instances.push_back({.name = "box", .mesh = 0});
  return scene;
}

/// A camera turned and moved away from the axes, so no component is trivially zero.
igi::Camera tilted_camera(float aspect) {
  igi::Camera camera;
  camera.name = "tilted";
  camera.camera_to_world = glm::rotate(glm::translate(glm::mat4(1.0f), glm::vec3(1, 2, 3)), 0.7f, glm::normalize(glm::vec3(1, 2, -1)));
  camera.yfov = 0.9f;
  camera.aspect = aspect;
  return camera;
}

/// Pixel accuracy of a project-after-unproject round trip: float rounding on a 1000-pixel image.
constexpr float pixel_tolerance = 1e-3f;

}  // namespace

TEST_CASE("default_camera sees the whole scene from +Z, looking along -Z", "[scene][camera]") {
  const igi::Scene scene = box_scene({-3, 1, -2}, {5, 4, 0});
  const igi::Camera camera = igi::default_camera(scene);
  CHECK(camera.aspect == 0.0f);
  CHECK(glm::vec3(camera.camera_to_world[2]) == glm::vec3(0, 0, 1));  // looks down -Z
  CHECK(camera.position().x == Approx(1.0f));
  CHECK(camera.position().y == Approx(2.5f));
  for (const auto& [width, height] : {std::pair{400, 400}, std::pair{1920, 1080}}) {
    for (const glm::vec3& corner : scene.meshes[0].positions) {
      const glm::vec2 pixel = project(camera, width, height, corner);
      CHECK(pixel.x >= 0.0f);
      CHECK(pixel.x <= float(width));
      CHECK(pixel.y >= 0.0f);
      CHECK(pixel.y <= float(height));
    }
    // Fitted, not lost in the distance: the box spans over a third of the image height.
    const float top = project(camera, width, height, {1, 4, 0}).y;
    const float bottom = project(camera, width, height, {1, 1, 0}).y;
    CHECK(bottom - top > float(height) / 3.0f);
  }
  CHECK(camera.znear > 0.0f);
  CHECK(camera.znear < glm::length(camera.position() - scene.bounds().center()) - 0.5f * glm::length(scene.bounds().extent()));
}

TEST_CASE("default_camera of an empty scene is an error naming the scene", "[scene][camera]") {
  igi::Scene empty;
  empty.name = "nothing";
  CHECK_THROWS_AS(igi::default_camera(empty), igi::SceneError);
  CHECK_THROWS_WITH(igi::default_camera(empty), Catch::Contains("nothing"));
}

TEST_CASE("find_camera by name", "[scene][camera]") {
  igi::Scene scene = igi::cornell_box();
  scene.cameras.push_back({.name = "second"});
  REQUIRE(igi::find_camera(scene, "second") != nullptr);
  CHECK(igi::find_camera(scene, "second") == &scene.cameras[1]);
  CHECK(igi::find_camera(scene, "cornell_camera") == &scene.cameras[0]);
  CHECK(igi::find_camera(scene, "missing") == nullptr);
}

TEST_CASE("PinholeProjection: centre, edges and corners match the field of view, y grows downwards", "[scene][camera]") {
  const igi::Camera camera = igi::cornell_box().cameras[0];
  // The camera says aspect 1; the image is 2:1, and pixels stay square: the vertical field of
  // view spans the height, the horizontal one is twice as wide in tangent.
  REQUIRE(camera.aspect == 1.0f);
  const igi::PinholeProjection projection(camera, 200, 100);
  CHECK(projection.origin() == camera.position());
  const glm::vec3 forward(0, 0, 1);  // the Cornell camera looks along +Z
  CHECK(glm::length(projection.direction(100, 50) - forward) < 1e-6f);  // unit vectors: float rounding
  const float half = 0.5f * camera.yfov;
  // Top edge: up by half the vertical fov; bottom edge: down by as much.
  // Angles from acos of float dot products of unit vectors: 1e-5 relative covers their rounding.
  constexpr double angle_tolerance = 1e-5;
  const glm::vec3 top = projection.direction(100, 0);
  CHECK(std::acos(glm::dot(top, forward)) == Approx(half).epsilon(angle_tolerance));
  CHECK(top.y > 0.0f);
  CHECK(projection.direction(100, 100).y == Approx(-top.y));
  // Left edge: the camera's left is world +X after the 180 degree turn; the image's aspect 2
  // doubles the tangent of the half angle.
  const glm::vec3 left = projection.direction(0, 50);
  CHECK(left.x > 0.0f);
  CHECK(std::acos(glm::dot(left, forward)) == Approx(std::atan(2.0f * std::tan(half))).epsilon(angle_tolerance));
  // Square pixels: one pixel to the side turns the ray as much as one pixel down, at the centre.
  const glm::vec3 right_one = projection.direction(101, 50), down_one = projection.direction(100, 51);
  const glm::vec3 centre = projection.direction(100, 50);
  CHECK(std::acos(glm::dot(right_one, centre)) == Approx(std::acos(glm::dot(down_one, centre))).epsilon(1e-3));
  for (const glm::vec3& d : {top, left, projection.direction(13.5f, 77.25f)})
    CHECK(glm::length(d) == Approx(1.0f).epsilon(1e-6));  // a normalized float vector: a few ulps
}

TEST_CASE("PinholeProjection: any camera aspect gives the image's, and directions project back to their pixels", "[scene][camera]") {
  for (const float aspect : {0.0f, 2.5f}) {
    const igi::Camera camera = tilted_camera(aspect);
    const int width = 1000, height = 600;
    const igi::PinholeProjection projection(camera, width, height);
    for (const glm::vec2 pixel : {glm::vec2(0, 0), glm::vec2(1000, 600), glm::vec2(0.5f, 599.5f), glm::vec2(731.25f, 12.75f)}) {
      const glm::vec3 point = projection.origin() + 7.0f * projection.direction(pixel.x, pixel.y);
      const glm::vec2 back = project(camera, width, height, point);
      CHECK(back.x == Approx(pixel.x).margin(pixel_tolerance));
      CHECK(back.y == Approx(pixel.y).margin(pixel_tolerance));
    }
  }
}

TEMPLATE_TEST_CASE_SIG("PinholeProjection: packet directions equal the scalar ones in every lane", "[scene][camera]",
                       ((int W), W), 1, 4, 8, 16, 64) {
  const igi::PinholeProjection projection(tilted_camera(0.0f), 640, 480);
  const igi::vfloat<W> px([](int i) { return 3.5f + 9.75f * float(i); });
  const igi::vfloat<W> py([](int i) { return 470.5f - 7.25f * float(i); });
  const igi::vec3<W> directions = projection.direction(px, py);
  for (int i = 0; i < W; ++i) {
    const glm::vec3 scalar = projection.direction(px[i], py[i]);
    // Same formula; only fused multiply-adds may round differently: a few ulps of a unit vector.
    CHECK(glm::length(directions[i] - scalar) < 1e-6f);
  }
}

TEST_CASE("PinholeProjection: bad sizes and cameras are errors", "[scene][camera]") {
  const igi::Camera good = tilted_camera(0.0f);
  CHECK_THROWS_AS(igi::PinholeProjection(good, 0, 10), std::invalid_argument);
  CHECK_THROWS_WITH(igi::PinholeProjection(good, 10, -1), Catch::Contains("10x-1"));
  igi::Camera bad = good;
  bad.yfov = glm::pi<float>();
  CHECK_THROWS_WITH(igi::PinholeProjection(bad, 10, 10), Catch::Contains("tilted") && Catch::Contains("yfov"));
  bad = good;
  bad.aspect = -1.0f;
  CHECK_THROWS_AS(igi::PinholeProjection(bad, 10, 10), std::invalid_argument);
  bad = good;
  bad.camera_to_world[0][0] = std::numeric_limits<float>::quiet_NaN();
  CHECK_THROWS_WITH(igi::PinholeProjection(bad, 10, 10), Catch::Contains("non-finite"));
}
