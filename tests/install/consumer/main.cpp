// Uses a few igi headers the way another renderer would; exits 0 only if they work.
#include <cstdio>

#include <igi/simd/simd.hpp>
#include <igi/scene/scene.hpp>

int main() {
  igi::vec3<8> a(glm::vec3(1.0f, 2.0f, 2.0f));
  const igi::vfloat<8> len = igi::length(a);
  igi::Scene scene;
  scene.meshes.push_back({.name = "triangle", .positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, .triangles = {{0, 1, 2}}});
  scene.instances.push_back({.name = "one", .mesh = 0});
  const bool ok = len[7] == 3.0f && scene.triangle_count() == 1;
  std::printf("igi consumer: %s\n", ok ? "ok" : "wrong");
  return ok ? 0 : 1;
}
