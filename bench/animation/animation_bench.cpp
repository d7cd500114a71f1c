// What a skinned mesh adds to a frame: a 50k-triangle skinned tube (a bending arm of 8 bones,
// every vertex weighted to its two nearest bones) in a 262k-triangle scene (the rest static: a
// ground grid, or the shared Sponza when IGI_SCENES_DIR has it), animated, applied to the Embree
// backend (the mesh's BVH refitted), measured per frame without the rendering itself.
//
//   skinned_frame/<grid|sponza>
//                          manual time per frame: what the animation adds to a frame; counters
//                          (ms per frame) split it into sample_ms (channels and node transforms),
//                          deform_ms (skinning the vertices), apply_ms (scene and backend take the
//                          vertices, bounds updated) and commit_ms (the BVH refit and the
//                          instance level)
//
//   animation_bench --benchmark_repetitions=5 --benchmark_report_aggregates_only=true
//
// Threads: all cores (oneTBB's default arena, as igi-render); the target is <= 5 ms total on 2 cores.
//
//   animation_bench --write-gltf skinned.gltf
//                          writes the grid scene (with a camera and a point light) as glTF instead,
//                          for the whole-frame measure: igi-render skinned.gltf --play against
//                          the same file still (both with --temporal 0, frames by themselves).

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/gltf.hpp"
#include "scene/gltf_builder.hpp"
#include "igi/scene/scene_bounds.hpp"

namespace {

using namespace igi;

/// Rings x segments of the tube: 160 x 158 quads = 50,560 triangles, the 50k of the target.
constexpr int tube_rings = 161;
/// Segments around the tube.
constexpr int tube_segments = 158;
/// Quads per side of the static ground grid: 2 x 326^2 = 212,552 triangles, so the scene has 263k.
constexpr int ground_quads = 326;
/// Bones along the tube: enough that the bend is visibly smooth, as in a character's limb chain.
constexpr int bone_count = 8;

/// A flat grid of `quads` x `quads` cells of side 1 at y = 0, centred at the origin.
Mesh ground_grid(int quads) {
  Mesh mesh;
  mesh.name = "ground";
  for (int z = 0; z <= quads; ++z)
    for (int x = 0; x <= quads; ++x) {
      mesh.positions.emplace_back(float(x) - 0.5f * float(quads), 0.0f, float(z) - 0.5f * float(quads));
      mesh.normals.emplace_back(0.0f, 1.0f, 0.0f);
    }
  const auto vertex = [&](int x, int z) { return unsigned(z * (quads + 1) + x); };
  for (int z = 0; z < quads; ++z)
    for (int x = 0; x < quads; ++x) {
      mesh.triangles.emplace_back(vertex(x, z), vertex(x, z + 1), vertex(x + 1, z));
      mesh.triangles.emplace_back(vertex(x + 1, z), vertex(x, z + 1), vertex(x + 1, z + 1));
    }
  return mesh;
}

/// The scene: `scene` (static), and a vertical tube of height bone_count skinned to a chain of bones
/// (one per unit of height) that one animation "bend" turns about +Z, each bone a little more.
Scene skinned_scene(Scene scene) {
  const int tube_mesh = int(scene.meshes.size());
  const int tube_instance = int(scene.instances.size());
  Mesh tube;
  tube.name = "tube";
  DeformableMesh deformable;
  deformable.influence_sets = 1;
  const float height = float(bone_count);
  for (int ring = 0; ring < tube_rings; ++ring) {
    const float y = height * float(ring) / float(tube_rings - 1);
    // The two bones nearest the ring (bone b spans [b, b + 1)), weighted linearly between their middles.
    const float along = std::clamp(y - 0.5f, 0.0f, height - 1.0f);
    const unsigned lower = unsigned(std::min(int(along), bone_count - 2));
    const float upper_weight = std::clamp(along - float(lower), 0.0f, 1.0f);
    for (int segment = 0; segment < tube_segments; ++segment) {
      const float angle = 6.2831853f * float(segment) / float(tube_segments);
      const glm::vec3 normal(std::cos(angle), 0.0f, std::sin(angle));
      tube.positions.push_back(0.3f * normal + glm::vec3(0.0f, y, 0.0f));
      tube.normals.push_back(normal);
      deformable.joints.emplace_back(lower, lower + 1, 0, 0);
      deformable.weights.emplace_back(1.0f - upper_weight, upper_weight, 0.0f, 0.0f);
    }
  }
  for (int ring = 0; ring + 1 < tube_rings; ++ring)
    for (int segment = 0; segment < tube_segments; ++segment) {
      const unsigned a = unsigned(ring * tube_segments + segment);
      const unsigned b = unsigned(ring * tube_segments + (segment + 1) % tube_segments);
      tube.triangles.emplace_back(a, b + unsigned(tube_segments), b);
      tube.triangles.emplace_back(a, a + unsigned(tube_segments), b + unsigned(tube_segments));
    }
  deformable.rest_positions = tube.positions;
  deformable.rest_normals = tube.normals;
  scene.meshes.push_back(tube);
  scene.instances.push_back({.name = "tube", .mesh = tube_mesh});

  SceneAnimations& data = scene.animations;
  data = SceneAnimations{};  // the static part's own nodes, if any, play no part
  Skin skin;
  skin.name = "arm";
  NodeAnimation bend;
  bend.name = "bend";
  bend.duration = 2.0f;
  for (int b = 0; b < bone_count; ++b) {
    SceneNode bone;
    bone.name = "bone " + std::to_string(b);
    bone.parent = b - 1;
    bone.translation = glm::vec3(0.0f, b == 0 ? 0.0f : 1.0f, 0.0f);
    data.nodes.push_back(bone);
    data.node_order.push_back(b);
    skin.joints.push_back(b);
    skin.inverse_bind_matrices.push_back(glm::mat4(1.0f));
    skin.inverse_bind_matrices.back()[3] = glm::vec4(0.0f, -float(b), 0.0f, 1.0f);
    // Each bone turns up to 10 degrees about +Z over two seconds.
    const glm::quat turn = glm::angleAxis(0.17453f, glm::vec3(0.0f, 0.0f, 1.0f));
    bend.channels.push_back({.node = b,
                             .property = AnimatedProperty::rotation,
                             .interpolation = Interpolation::linear,
                             .times = {0.0f, 2.0f},
                             .values = {0.0f, 0.0f, 0.0f, 1.0f, turn.x, turn.y, turn.z, turn.w},
                             .components = 4});
  }
  SceneNode holder;
  holder.name = "tube";
  data.nodes.push_back(holder);
  data.node_order.push_back(bone_count);
  data.skins.push_back(skin);
  data.animations.push_back(bend);
  deformable.mesh = tube_mesh;
  deformable.instance = tube_instance;
  deformable.node = bone_count;
  deformable.skin = 0;
  data.deformables.push_back(deformable);
  data.instance_nodes.assign(scene.instances.size(), -1);
  data.instance_nodes.back() = bone_count;
  return scene;
}

/// Milliseconds since `start`.
double since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
}

/// One frame's animation through the Embree backend, reported as manual time (the parts' sum),
/// each part as a counter (ms per frame). One benchmark times all parts: timing a part alone as
/// manual time would run as many whole frames as a part of a few microseconds needs to fill the
/// minimum time.
void skinned_frame(benchmark::State& state, const char* around) {
  Scene around_scene;
  if (std::string(around) == "sponza") {
    const std::filesystem::path file = std::filesystem::path(IGI_SCENES_DIR) / "sponza" / "Sponza.gltf";
    if (!std::filesystem::exists(file)) {
      state.SkipWithError(("shared scene missing: " + file.string()).c_str());
      return;
    }
    std::vector<std::string> warnings;  // Sponza's known warnings (dropped maps) are no news here
    around_scene = load_gltf(file, &warnings);
  } else {
    around_scene.name = "grid";
    around_scene.meshes.push_back(ground_grid(ground_quads));
    around_scene.instances.push_back({.name = "ground", .mesh = 0});
  }
  Scene scene = skinned_scene(std::move(around_scene));
  EmbreeBackend<8> backend(scene);
  SceneBounds bounds(scene);
  const AnimationPlayer player(scene, 0, true);
  double sums[4] = {0.0, 0.0, 0.0, 0.0};
  std::uint32_t frame = 0;
  // Frame 0 moves the tube out of the flattened static scene once (a rebuild of the static BVH);
  // what each later frame costs is what the benchmark measures.
  const auto step = [&](double* parts) {
    AnimationTimes times;
    const SceneChanges changes = player(double(frame++) / 30.0, Camera{}, -1, &times);
    const auto apply_start = std::chrono::steady_clock::now();
    for (const MeshVertices& vertices : changes.meshes) {
      backend.set_mesh_positions(vertices.mesh, vertices.positions);
      Mesh& mesh = scene.meshes[std::size_t(vertices.mesh)];
      mesh.positions = vertices.positions;
      mesh.normals = vertices.normals;
      bounds.mesh_changed(scene, vertices.mesh);
    }
    const double apply = since(apply_start);
    const auto commit_start = std::chrono::steady_clock::now();
    backend.commit();
    parts[0] = times.sampling_milliseconds;
    parts[1] = times.deforming_milliseconds;
    parts[2] = apply;
    parts[3] = since(commit_start);
  };
  double warm[4];
  step(warm);
  for (auto _ : state) {
    double parts[4];
    step(parts);
    const double total = parts[0] + parts[1] + parts[2] + parts[3];
    for (int i = 0; i < 4; ++i) sums[i] += parts[i];
    state.SetIterationTime(total * 1e-3);
  }
  const double n = double(state.iterations());
  state.counters["sample_ms"] = sums[0] / n;
  state.counters["deform_ms"] = sums[1] / n;
  state.counters["apply_ms"] = sums[2] / n;
  state.counters["commit_ms"] = sums[3] / n;
  state.counters["triangles"] = double(scene.triangle_count());
  state.counters["skinned_triangles"] = double(scene.meshes.back().triangles.size());
}

BENCHMARK_CAPTURE(skinned_frame, grid, "grid")->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(skinned_frame, sponza, "sponza")->UseManualTime()->Unit(benchmark::kMillisecond);

/// The grid scene as glTF at `file` (.gltf + .bin): its meshes, skin and animation as built
/// above, a terracotta ground and a green tube, a camera 12 units in front of the tube and a
/// point light above it.
void write_gltf(const std::filesystem::path& file) {
  Scene grid;
  grid.meshes.push_back(ground_grid(ground_quads));
  grid.instances.push_back({.name = "ground", .mesh = 0});
  const Scene scene = skinned_scene(std::move(grid));
  const DeformableMesh& tube = scene.animations.deformables.front();
  testing::GltfBuilder gltf;
  std::vector<int> roots;
  for (std::size_t m = 0; m < scene.meshes.size(); ++m) {
    const Mesh& mesh = scene.meshes[m];
    std::vector<std::uint32_t> indices;
    for (const glm::uvec3& t : mesh.triangles) indices.insert(indices.end(), {t.x, t.y, t.z});
    nlohmann::json attributes = {{"POSITION", gltf.add_positions(mesh.positions)}, {"NORMAL", gltf.add_positions(mesh.normals)}};
    nlohmann::json node = {{"name", mesh.name}};
    if (int(m) == tube.mesh) {
      std::vector<std::uint8_t> joints;
      std::vector<float> weights;
      for (std::size_t v = 0; v < tube.joints.size(); ++v)
        for (int c = 0; c < 4; ++c) {
          joints.push_back(std::uint8_t(tube.joints[v][c]));
          weights.push_back(tube.weights[v][c]);
        }
      attributes["JOINTS_0"] = gltf.add_data(joints, testing::u8, "VEC4", 4);
      attributes["WEIGHTS_0"] = gltf.add_data(weights, testing::f32, "VEC4", 4);
      node["skin"] = 0;
    }
    node["mesh"] = gltf.add_mesh(mesh.name, nlohmann::json::array({{{"attributes", attributes},
                                                                    {"indices", gltf.add_indices(indices)},
                                                                    {"material", int(m) == tube.mesh ? 1 : 0}}}));
    roots.push_back(gltf.add_node(node));
  }
  const SceneAnimations& data = scene.animations;
  const Skin& skin = data.skins.front();
  // Bones in SceneAnimations order, each the next one's parent: glTF node i + bone_first is bone i.
  const int bone_first = int(gltf.doc["nodes"].size());
  std::vector<float> inverse_bind;
  for (std::size_t b = 0; b < skin.joints.size(); ++b) {
    const SceneNode& bone = data.nodes[std::size_t(skin.joints[b])];
    nlohmann::json node = {{"name", bone.name}, {"translation", {bone.translation.x, bone.translation.y, bone.translation.z}}};
    if (b + 1 < skin.joints.size()) node["children"] = {bone_first + int(b) + 1};
    gltf.add_node(node);
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r) inverse_bind.push_back(skin.inverse_bind_matrices[b][c][r]);
  }
  roots.push_back(bone_first);
  std::vector<int> joints(skin.joints.size());
  for (std::size_t b = 0; b < joints.size(); ++b) joints[b] = bone_first + int(b);
  gltf.doc["skins"] = {{{"name", skin.name}, {"joints", joints},
                        {"inverseBindMatrices", gltf.add_data(inverse_bind, testing::f32, "MAT4", 16)}}};
  nlohmann::json animation = {{"name", data.animations.front().name}};
  for (const AnimationChannel& channel : data.animations.front().channels) {
    animation["samplers"].push_back({{"input", gltf.add_data(channel.times, testing::f32, "SCALAR", 1)},
                                     {"output", gltf.add_data(channel.values, testing::f32, "VEC4", 4)},
                                     {"interpolation", "LINEAR"}});
    animation["channels"].push_back({{"sampler", int(animation["samplers"].size()) - 1},
                                     {"target", {{"node", bone_first + channel.node}, {"path", "rotation"}}}});
  }
  gltf.doc["animations"] = {animation};
  gltf.doc["materials"] = {
      {{"name", "ground"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.8, 0.4, 0.3, 1.0}}, {"metallicFactor", 0.0}}}},
      {{"name", "tube"}, {"pbrMetallicRoughness", {{"baseColorFactor", {0.3, 0.7, 0.3, 1.0}}, {"metallicFactor", 0.0}}}}};
  gltf.doc["extensionsUsed"] = {"KHR_lights_punctual"};
  gltf.doc["extensions"]["KHR_lights_punctual"]["lights"] = {{{"type", "point"}, {"intensity", 200.0}}};
  roots.push_back(gltf.add_node({{"name", "lamp"}, {"translation", {2, 9, 4}}, {"extensions", {{"KHR_lights_punctual", {{"light", 0}}}}}}));
  gltf.doc["cameras"] = {{{"type", "perspective"}, {"perspective", {{"yfov", 0.9}, {"znear", 0.01}}}}};
  roots.push_back(gltf.add_node({{"name", "eye"}, {"camera", 0}, {"translation", {0, 4, 12}}}));
  gltf.set_roots(roots);
  const std::filesystem::path written = gltf.write_gltf(file.parent_path().empty() ? "." : file.parent_path(), file.stem().string());
  std::printf("wrote %s (%zu triangles, %zu skinned)\n", written.string().c_str(), scene.triangle_count(),
              scene.meshes[std::size_t(tube.mesh)].triangles.size());
}

}  // namespace

int main(int argc, char** argv) {
  if (argc == 3 && std::string(argv[1]) == "--write-gltf") {
    write_gltf(argv[2]);
    return 0;
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
