#pragma once
// A small glTF writer for tests: builds the JSON with nlohmann::json and one binary buffer, then
// writes .gltf + .bin or a .glb into a scratch folder, so every test makes exactly the file it needs
// (well-formed or deliberately broken).

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <nlohmann/json.hpp>

namespace igi::testing {

/// A fresh empty folder under the system temp dir, unique per test name and process; all of them go when the process ends.
inline std::filesystem::path scratch_dir(const std::string& test_name) {
  /// Removes this process's scratch root at exit.
  struct Root {
    std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("igi-scene-test-" + std::to_string(::getpid()));
    ~Root() {
      std::error_code ignored;
      std::filesystem::remove_all(path, ignored);
    }
  };
  static const Root root;
  const std::filesystem::path dir = root.path / test_name;
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

/// Writes `bytes` to `file`.
inline void write_bytes(const std::filesystem::path& file, const std::string& bytes) {
  std::ofstream out(file, std::ios::binary);
  out.write(bytes.data(), std::streamsize(bytes.size()));
}

/// The whole content of `file`.
inline std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// glTF component type codes.
enum Component : int { i8 = 5120, u8 = 5121, i16 = 5122, u16 = 5123, u32 = 5125, f32 = 5126 };

/// Builds a glTF document and its single binary buffer.
struct GltfBuilder {
  nlohmann::json doc = {{"asset", {{"version", "2.0"}}}};  ///< The JSON being built.
  std::vector<unsigned char> bin;                            ///< Buffer 0.

  /// Appends raw bytes (4-byte aligned) as a new bufferView; returns its index.
  int add_view(const void* data, std::size_t size, std::size_t stride = 0) {
    while (bin.size() % 4 != 0) bin.push_back(0);
    const std::size_t offset = bin.size();
    bin.resize(offset + size);
    if (size > 0) std::memcpy(bin.data() + offset, data, size);
    nlohmann::json view = {{"buffer", 0}, {"byteOffset", offset}, {"byteLength", size}};
    if (stride != 0) view["byteStride"] = stride;
    doc["bufferViews"].push_back(view);
    return int(doc["bufferViews"].size()) - 1;
  }

  /// Adds an accessor over bufferView `view`; returns its index.
  int add_accessor(int view, int component, const char* type, std::size_t count, bool normalized = false,
                   std::size_t byte_offset = 0) {
    nlohmann::json accessor = {{"bufferView", view}, {"componentType", component}, {"type", type}, {"count", count}};
    if (normalized) accessor["normalized"] = true;
    if (byte_offset != 0) accessor["byteOffset"] = byte_offset;
    doc["accessors"].push_back(accessor);
    return int(doc["accessors"].size()) - 1;
  }

  /// Adds tightly packed values of type T as a view plus accessor; returns the accessor.
  template <class T>
  int add_data(const std::vector<T>& values, int component, const char* type, int components, bool normalized = false) {
    const int view = add_view(values.data(), values.size() * sizeof(T));
    return add_accessor(view, component, type, values.size() / std::size_t(components), normalized);
  }

  /// Float vec3 positions.
  int add_positions(const std::vector<glm::vec3>& positions) {
    std::vector<float> flat;
    for (const glm::vec3& p : positions) flat.insert(flat.end(), {p.x, p.y, p.z});
    return add_data(flat, f32, "VEC3", 3);
  }

  /// Unsigned 32-bit indices.
  int add_indices(const std::vector<std::uint32_t>& indices) { return add_data(indices, u32, "SCALAR", 1); }

  /// Adds a mesh with the given primitives; returns its index.
  int add_mesh(const std::string& name, const nlohmann::json& primitives) {
    doc["meshes"].push_back({{"name", name}, {"primitives", primitives}});
    return int(doc["meshes"].size()) - 1;
  }

  /// Adds a node; returns its index.
  int add_node(const nlohmann::json& node) {
    doc["nodes"].push_back(node);
    return int(doc["nodes"].size()) - 1;
  }

  /// Makes scene 0 with the given root nodes the default scene.
  void set_roots(const std::vector<int>& roots) {
    doc["scenes"] = nlohmann::json::array({{{"nodes", roots}}});
    doc["scene"] = 0;
  }

  /// Writes `<dir>/<name>.gltf` with the buffer in `<dir>/<name>.bin`; returns the .gltf path.
  std::filesystem::path write_gltf(const std::filesystem::path& dir, const std::string& name) {
    nlohmann::json out = doc;
    if (!bin.empty()) {
      out["buffers"] = nlohmann::json::array({{{"uri", name + ".bin"}, {"byteLength", bin.size()}}});
      write_bytes(dir / (name + ".bin"), std::string(bin.begin(), bin.end()));
    }
    const std::filesystem::path file = dir / (name + ".gltf");
    write_bytes(file, out.dump(1));
    return file;
  }

  /// The document as a binary glTF (.glb) with the buffer in its BIN chunk.
  std::string glb_bytes() const {
    nlohmann::json out = doc;
    std::string json;
    std::string binary(bin.begin(), bin.end());
    while (binary.size() % 4 != 0) binary.push_back('\0');
    if (!bin.empty()) out["buffers"] = nlohmann::json::array({{{"byteLength", bin.size()}}});
    json = out.dump();
    while (json.size() % 4 != 0) json.push_back(' ');
    std::string glb;
    const auto put = [&glb](std::uint32_t value) { glb.append(reinterpret_cast<const char*>(&value), 4); };
    glb += "glTF";
    put(2);
    put(std::uint32_t(12 + 8 + json.size() + (binary.empty() ? 0 : 8 + binary.size())));
    put(std::uint32_t(json.size()));
    put(0x4E4F534Au);  // "JSON"
    glb += json;
    if (!binary.empty()) {
      put(std::uint32_t(binary.size()));
      put(0x004E4942u);  // "BIN\0"
      glb += binary;
    }
    return glb;
  }

  /// Writes `<dir>/<name>.glb`; returns its path.
  std::filesystem::path write_glb(const std::filesystem::path& dir, const std::string& name) const {
    const std::filesystem::path file = dir / (name + ".glb");
    write_bytes(file, glb_bytes());
    return file;
  }

  /// A unit quad in the XY plane (two triangles, normal +Z) as mesh `name` with a node; returns the node.
  int add_quad_node(const std::string& name, const nlohmann::json& extra_node_fields = nlohmann::json::object()) {
    const int position = add_positions({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}});
    const int indices = add_indices({0, 1, 2, 0, 2, 3});
    const int mesh = add_mesh(name, nlohmann::json::array({{{"attributes", {{"POSITION", position}}}, {"indices", indices}}}));
    nlohmann::json node = {{"name", name}, {"mesh", mesh}};
    node.update(extra_node_fields);
    return add_node(node);
  }
};

}  // namespace igi::testing
