#pragma once
/// \file
/// The glTF loader behind igi/scene/gltf.hpp (see there): included by it when igi is header-only,
/// compiled once by igi/separate_compilation.hpp under IGI_SEPARATE_COMPILATION (igi/config.hpp).

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <stb_image.h>
#include <tbb/parallel_for.h>
#include <tiny_gltf.h>

#include "igi/config.hpp"
#include "igi/scene/error.hpp"
#include "igi/scene/memory.hpp"
#include "igi/scene/scene.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/validate.hpp"

namespace igi {

namespace gltf_detail {

/// glTF extensions the loader understands, so a file may list them as required.
inline const std::set<std::string, std::less<>>& supported_extensions() {
  static const std::set<std::string, std::less<>> names{
      "KHR_lights_punctual",      "KHR_materials_emissive_strength", "KHR_materials_transmission",
      "KHR_materials_ior",        "KHR_mesh_quantization"};
  return names;
}

/// Bytes per component of a glTF component type, 0 if the type is unknown.
inline std::size_t component_size(int component_type) noexcept {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

/// Components per element of a glTF accessor type, 0 if the type is unknown.
inline int component_count(int type) noexcept {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

/// Name of a glTF component type, for messages.
inline std::string component_name(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    default: return "component type " + std::to_string(component_type);
  }
}

/// One component stored as T, as a float; integers map to [0, 1] or [-1, 1] when normalized (glTF 2.0 section 3.11).
template <class T>
float decode_component(const unsigned char* source, bool normalized) noexcept {
  T value;
  std::memcpy(&value, source, sizeof(T));
  if constexpr (std::is_floating_point_v<T>) {
    return value;
  } else {
    if (!normalized) return float(value);
    const float scaled = float(value) / float(std::numeric_limits<T>::max());
    return std::is_signed_v<T> ? std::max(scaled, -1.0f) : scaled;
  }
}

/// Decodes `count` elements of `components` components of type T at `stride` bytes into `target`.
template <class T>
void decode_elements(const unsigned char* source, std::size_t stride, std::size_t count, int components, bool normalized,
                     float* target) noexcept {
  for (std::size_t e = 0; e < count; ++e)
    for (int c = 0; c < components; ++c)
      target[e * std::size_t(components) + std::size_t(c)] =
          decode_component<T>(source + e * stride + std::size_t(c) * sizeof(T), normalized);
}

/// Decodes elements of any component type (see decode_elements).
inline void decode_any(int component_type, const unsigned char* source, std::size_t stride, std::size_t count,
                       int components, bool normalized, float* target) noexcept {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: decode_elements<std::int8_t>(source, stride, count, components, normalized, target); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: decode_elements<std::uint8_t>(source, stride, count, components, normalized, target); break;
    case TINYGLTF_COMPONENT_TYPE_SHORT: decode_elements<std::int16_t>(source, stride, count, components, normalized, target); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: decode_elements<std::uint16_t>(source, stride, count, components, normalized, target); break;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: decode_elements<std::uint32_t>(source, stride, count, components, normalized, target); break;
    default: decode_elements<float>(source, stride, count, components, normalized, target); break;
  }
}

/// Reads one unsigned index of the given component type.
inline std::uint32_t decode_index(int component_type, const unsigned char* source) noexcept {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return source[0];
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      std::uint16_t value;
      std::memcpy(&value, source, sizeof value);
      return value;
    }
    default: {
      std::uint32_t value;
      std::memcpy(&value, source, sizeof value);
      return value;
    }
  }
}

/// tinygltf image callback: keeps the encoded bytes (decoded later, in parallel), checking that an image's bufferView lies inside its buffer.
inline bool keep_encoded_image(tinygltf::Image* image, const int image_index, std::string* error, std::string*, int, int,
                               const unsigned char* bytes, int size, void* model_pointer) {
  const auto* model = static_cast<const tinygltf::Model*>(model_pointer);
  if (image->bufferView >= 0) {
    // tinygltf checked the bufferView and buffer indices, not the view's byte range.
    const tinygltf::BufferView& view = model->bufferViews[std::size_t(image->bufferView)];
    const std::size_t buffer_size = model->buffers[std::size_t(view.buffer)].data.size();
    if (view.byteOffset > buffer_size || view.byteLength > buffer_size - view.byteOffset) {
      if (error != nullptr)
        *error += "image " + std::to_string(image_index) + " uses bufferView " + std::to_string(image->bufferView) +
                  " which runs past the end of its buffer (" + std::to_string(buffer_size) + " bytes)";
      return false;
    }
  }
  if (bytes != nullptr && size > 0) image->image.assign(bytes, bytes + size);
  image->as_is = true;
  return true;
}

/// The state of one load: the parsed file and the scene being built from it.
class Loader {
 public:
  /// Prepares to load `file`, sending warnings to `warnings` (or stderr when null).
  Loader(std::filesystem::path file, std::vector<std::string>* warnings) : file_(std::move(file)), warnings_(warnings) {}

  /// Parses the file and builds the scene.
  Scene load() {
    parse();
    check_required_extensions();
    scene_.name = file_.stem().string();
    decode_images();
    convert_materials();
    convert_nodes();
    with_file([&] { validate_scene(scene_, warnings_, file_.string()); });
    return std::move(scene_);
  }

 private:
  std::filesystem::path file_;
  std::vector<std::string>* warnings_;
  tinygltf::Model model_;
  Scene scene_;
  std::vector<std::optional<Texture>> decoded_;          // per glTF image, when used by a material and decodable
  std::vector<std::string> image_problem_;               // per glTF image, why it has no texels
  std::vector<int> texture_of_image_;                    // glTF image -> Scene::textures, or -1
  std::map<std::pair<int, int>, int> mesh_of_primitive_;  // (glTF mesh, primitive) -> Scene::meshes, or -1 if skipped

  [[noreturn]] void fail(const std::string& problem) const { throw SceneError(file_, problem); }
  /// Runs a check of validate.hpp given `file_` as its location, rethrowing its error as one about the file.
  template <class Check>
  void with_file(Check&& check) const {
    try {
      check();
    } catch (const SceneError& error) {
      const std::string message = error.what();
      const std::string prefix = file_.string() + ": ";
      fail(message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message);
    }
  }
  void warn(const std::string& message) const { detail::report_warning(warnings_, file_.string() + ": " + message); }

  /// Reads the file and lets tinygltf parse it (JSON, buffers, image files).
  void parse() {
    std::error_code code;
    if (!std::filesystem::exists(file_, code)) fail("file not found");
    if (std::filesystem::is_directory(file_, code)) fail("is a directory, not a glTF file");
    std::ifstream in(file_, std::ios::binary);
    if (!in) fail("cannot open file for reading");
    const std::vector<unsigned char> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    if (in.bad()) fail("read error");
    if (bytes.empty()) fail("file is empty");
    if (bytes.size() >= std::numeric_limits<unsigned int>::max()) fail("file is larger than 4 GiB, more than glTF allows");

    const bool binary = bytes.size() >= 4 && std::memcmp(bytes.data(), "glTF", 4) == 0;
    if (!binary) {
      const auto first = std::find_if(bytes.begin(), bytes.end(), [](unsigned char c) {
        return c != ' ' && c != '\t' && c != '\r' && c != '\n';
      });
      // A UTF-8 byte-order mark may precede the JSON of a .gltf.
      const bool bom = bytes.size() >= 3 && bytes[0] == 0xEF && bytes[1] == 0xBB && bytes[2] == 0xBF;
      if (!bom && (first == bytes.end() || *first != '{'))
        fail("not a glTF file: neither a JSON object (.gltf) nor a binary glTF with the 'glTF' magic (.glb)");
    }

    tinygltf::TinyGLTF parser;
    parser.SetImageLoader(&keep_encoded_image, &model_);
    std::string error;
    std::string warning;
    const std::string base_dir = file_.parent_path().string();
    const bool ok = binary ? parser.LoadBinaryFromMemory(&model_, &error, &warning, bytes.data(),
                                                         static_cast<unsigned int>(bytes.size()), base_dir)
                           : parser.LoadASCIIFromString(&model_, &error, &warning,
                                                        reinterpret_cast<const char*>(bytes.data()),
                                                        static_cast<unsigned int>(bytes.size()), base_dir);
    for (const std::string& line : split_lines(warning)) warn("tinygltf: " + line);
    if (!ok) {
      std::string message;
      for (const std::string& line : split_lines(error)) message += (message.empty() ? "" : "; ") + line;
      fail((binary ? "invalid binary glTF: " : "invalid glTF: ") + (message.empty() ? "unknown parse error" : message));
    }
    if (model_.asset.version.empty()) fail("not a glTF file: asset.version is missing");
    if (model_.asset.version.rfind("2.", 0) != 0)
      fail("glTF version " + model_.asset.version + " is not supported (igi reads glTF 2.x)");
  }

  /// Lines of a tinygltf message, without empty ones.
  static std::vector<std::string> split_lines(const std::string& text) {
    std::vector<std::string> lines;
    std::size_t start = 0;
    while (start < text.size()) {
      std::size_t end = text.find('\n', start);
      if (end == std::string::npos) end = text.size();
      if (end > start) lines.push_back(text.substr(start, end - start));
      start = end + 1;
    }
    return lines;
  }

  /// A required extension igi does not implement makes the file unusable; an optional one is ignored with a warning.
  void check_required_extensions() const {
    for (const std::string& name : model_.extensionsRequired)
      if (!supported_extensions().contains(name))
        fail("requires the glTF extension '" + name + "', which igi does not support");
    for (const std::string& name : model_.extensionsUsed)
      if (!supported_extensions().contains(name)) warn("uses the glTF extension '" + name + "', which igi ignores");
  }

  // ---- accessors ----------------------------------------------------------------------------

  /// "accessor N (what)" for messages.
  static std::string accessor_label(int index, std::string_view what) {
    return "accessor " + std::to_string(index) + " (" + std::string(what) + ")";
  }

  /// Start of `length` bytes at `offset` in bufferView `view_index`, checked against view and buffer.
  const unsigned char* view_bytes(int view_index, std::size_t offset, std::size_t length, const std::string& label) const {
    if (view_index < 0 || std::size_t(view_index) >= model_.bufferViews.size())
      fail(label + ": bufferView " + std::to_string(view_index) + " does not exist");
    const tinygltf::BufferView& view = model_.bufferViews[std::size_t(view_index)];
    if (view.buffer < 0 || std::size_t(view.buffer) >= model_.buffers.size())
      fail(label + ": bufferView " + std::to_string(view_index) + " uses buffer " + std::to_string(view.buffer) +
           ", which does not exist");
    const std::vector<unsigned char>& buffer = model_.buffers[std::size_t(view.buffer)].data;
    if (view.byteOffset > buffer.size() || view.byteLength > buffer.size() - view.byteOffset)
      fail(label + ": bufferView " + std::to_string(view_index) + " (offset " + std::to_string(view.byteOffset) +
           ", length " + std::to_string(view.byteLength) + ") runs past the end of buffer " +
           std::to_string(view.buffer) + " (" + std::to_string(buffer.size()) + " bytes)");
    if (offset > view.byteLength || length > view.byteLength - offset)
      fail(label + ": reads bytes " + std::to_string(offset) + " .. " + std::to_string(offset + length) +
           " past the end of bufferView " + std::to_string(view_index) + " (" + std::to_string(view.byteLength) +
           " bytes)");
    return buffer.data() + view.byteOffset + offset;
  }

  /// Byte length of `count` elements of `element_size` bytes placed `stride` apart, failing on overflow.
  std::size_t span_bytes(std::size_t count, std::size_t stride, std::size_t element_size, const std::string& label) const {
    if (count == 0) return 0;
    if (count - 1 > (std::numeric_limits<std::size_t>::max() - element_size) / stride)
      fail(label + ": count " + std::to_string(count) + " is impossibly large");
    return (count - 1) * stride + element_size;
  }

  /// The accessor `index`, checked to exist and to hold `components` components of an allowed type.
  const tinygltf::Accessor& checked_accessor(int index, int components, std::initializer_list<int> allowed, std::string_view what) const {
    if (index < 0 || std::size_t(index) >= model_.accessors.size())
      fail(accessor_label(index, what) + " does not exist (the file has " + std::to_string(model_.accessors.size()) +
           " accessors)");
    const tinygltf::Accessor& accessor = model_.accessors[std::size_t(index)];
    if (component_count(accessor.type) != components)
      fail(accessor_label(index, what) + " has " + std::to_string(component_count(accessor.type)) +
           " components per element, needs " + std::to_string(components));
    if (std::find(allowed.begin(), allowed.end(), accessor.componentType) == allowed.end())
      fail(accessor_label(index, what) + ": " + component_name(accessor.componentType) + " is not allowed here");
    if (accessor.count == 0) fail(accessor_label(index, what) + " has count 0 (glTF requires at least 1)");
    return accessor;
  }

  /// Distance between elements of `accessor` in its bufferView, checked to hold one element.
  std::size_t stride_of(const tinygltf::Accessor& accessor, std::size_t element_size, const std::string& label) const {
    if (accessor.bufferView < 0 || std::size_t(accessor.bufferView) >= model_.bufferViews.size())
      fail(label + ": bufferView " + std::to_string(accessor.bufferView) + " does not exist");
    const std::size_t stride = model_.bufferViews[std::size_t(accessor.bufferView)].byteStride;
    if (stride == 0) return element_size;  // glTF: no byteStride means tightly packed
    if (stride < element_size)
      fail(label + ": byteStride " + std::to_string(stride) + " is smaller than its element size " +
           std::to_string(element_size));
    return stride;
  }

  /// A sparse accessor's substitutions: the element indices and where their replacement values start.
  struct SparseEntries {
    std::vector<std::uint32_t> targets;  ///< Elements replaced, each < the accessor's count.
    const unsigned char* values;         ///< Tightly packed replacement elements.
  };

  /// Reads and checks the sparse part of `accessor`.
  SparseEntries sparse_entries(const tinygltf::Accessor& accessor, const std::string& label, std::size_t element_size) const {
    const std::string sparse_label = label + " sparse";
    if (accessor.sparse.count <= 0 || std::size_t(accessor.sparse.count) > accessor.count)
      fail(sparse_label + ": count " + std::to_string(accessor.sparse.count) + " must be in 1 .. " + std::to_string(accessor.count));
    const std::size_t count = std::size_t(accessor.sparse.count);
    const int index_type = accessor.sparse.indices.componentType;
    if (index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        index_type != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
      fail(sparse_label + " indices: " + component_name(index_type) + " is not an index type");
    if (accessor.sparse.indices.byteOffset < 0 || accessor.sparse.values.byteOffset < 0) fail(sparse_label + ": negative byteOffset");
    const std::size_t index_size = component_size(index_type);
    const unsigned char* indices = view_bytes(accessor.sparse.indices.bufferView, std::size_t(accessor.sparse.indices.byteOffset),
                                              span_bytes(count, index_size, index_size, sparse_label), sparse_label + " indices");
    SparseEntries entries;
    entries.values = view_bytes(accessor.sparse.values.bufferView, std::size_t(accessor.sparse.values.byteOffset),
                                span_bytes(count, element_size, element_size, sparse_label), sparse_label + " values");
    entries.targets.resize(count);
    for (std::size_t s = 0; s < count; ++s) {
      entries.targets[s] = decode_index(index_type, indices + s * index_size);
      if (entries.targets[s] >= accessor.count)
        fail(sparse_label + ": index " + std::to_string(entries.targets[s]) + " is out of range (count " +
             std::to_string(accessor.count) + ")");
    }
    return entries;
  }

  /// Fails before allocating if `count` elements of `components` 4-byte values do not fit in memory.
  /// With a bufferView the elements lie in a buffer already in memory, whose size bounds them; an
  /// accessor without one (zeros, then sparse) may claim any count, e.g. 2^40 triangles.
  void require_memory(const std::string& label, std::size_t count, int components) const {
    if (const std::string shortfall = memory_shortfall(double(count), 4.0 * double(components)); !shortfall.empty())
      fail(label + ": count " + std::to_string(count) + " " + shortfall);
  }

  /// Accessor `index` decoded to floats (count x components), sparse substitutions applied.
  std::vector<float> read_floats(int index, int components, std::initializer_list<int> allowed, std::string_view what) const {
    const tinygltf::Accessor& accessor = checked_accessor(index, components, allowed, what);
    const std::string label = accessor_label(index, what);
    const std::size_t element_size = component_size(accessor.componentType) * std::size_t(components);
    if (accessor.count > std::numeric_limits<std::size_t>::max() / element_size / sizeof(float))
      fail(label + ": count " + std::to_string(accessor.count) + " is impossibly large");
    require_memory(label, accessor.count, components);
    std::vector<float> values;
    if (accessor.bufferView >= 0) {
      const std::size_t stride = stride_of(accessor, element_size, label);
      const unsigned char* source = view_bytes(accessor.bufferView, accessor.byteOffset, span_bytes(accessor.count, stride, element_size, label), label);
      values.resize(accessor.count * std::size_t(components));
      decode_any(accessor.componentType, source, stride, accessor.count, components, accessor.normalized, values.data());
    } else {
      values.assign(accessor.count * std::size_t(components), 0.0f);  // glTF: no bufferView means zeros (before sparse)
    }
    if (accessor.sparse.isSparse) apply_sparse(accessor, label, components, values);
    return values;
  }

  /// Replaces the elements a sparse accessor lists.
  void apply_sparse(const tinygltf::Accessor& accessor, const std::string& label, int components, std::vector<float>& values) const {
    const std::size_t element_size = component_size(accessor.componentType) * std::size_t(components);
    const SparseEntries entries = sparse_entries(accessor, label, element_size);
    std::vector<float> decoded(entries.targets.size() * std::size_t(components));
    decode_any(accessor.componentType, entries.values, element_size, entries.targets.size(), components, accessor.normalized, decoded.data());
    for (std::size_t s = 0; s < entries.targets.size(); ++s)
      std::copy_n(decoded.begin() + std::ptrdiff_t(s * std::size_t(components)), components,
                  values.begin() + std::ptrdiff_t(std::size_t(entries.targets[s]) * std::size_t(components)));
  }

  /// Vertex indices of accessor `index` (UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT scalars).
  std::vector<std::uint32_t> read_indices(int index, std::string_view what) const {
    const tinygltf::Accessor& accessor = checked_accessor(index, 1,
                                           {TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT,
                                            TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT},
                                           what);
    const std::string label = accessor_label(index, what);
    const std::size_t size = component_size(accessor.componentType);
    if (accessor.count > std::numeric_limits<std::size_t>::max() / sizeof(std::uint32_t))
      fail(label + ": count " + std::to_string(accessor.count) + " is impossibly large");
    require_memory(label, accessor.count, 1);
    std::vector<std::uint32_t> result(accessor.count, 0u);  // glTF: no bufferView means zeros (before sparse)
    if (accessor.bufferView >= 0) {
      const std::size_t stride = stride_of(accessor, size, label);
      const unsigned char* source = view_bytes(accessor.bufferView, accessor.byteOffset, span_bytes(accessor.count, stride, size, label), label);
      for (std::size_t i = 0; i < accessor.count; ++i) result[i] = decode_index(accessor.componentType, source + i * stride);
    }
    if (accessor.sparse.isSparse) {
      const SparseEntries entries = sparse_entries(accessor, label, size);
      for (std::size_t s = 0; s < entries.targets.size(); ++s)
        result[entries.targets[s]] = decode_index(accessor.componentType, entries.values + s * size);
    }
    return result;
  }

  // ---- images and materials -----------------------------------------------------------------

  /// The glTF image of texture `texture_index`, or -1 (with a warning) if the texture has no usable source.
  int image_of_texture(int texture_index, const std::string& user) const {
    if (texture_index < 0) return -1;
    if (std::size_t(texture_index) >= model_.textures.size())
      fail(user + " uses texture " + std::to_string(texture_index) + ", which does not exist (the file has " +
           std::to_string(model_.textures.size()) + " textures)");
    const int source = model_.textures[std::size_t(texture_index)].source;
    if (source < 0) {
      warn(user + ": texture " + std::to_string(texture_index) +
           " has no PNG/JPEG source igi can decode; the material keeps its factor and drops the texture");
      return -1;
    }
    if (std::size_t(source) >= model_.images.size())
      fail("texture " + std::to_string(texture_index) + " uses image " + std::to_string(source) + ", which does not exist");
    return source;
  }

  /// The glTF images base colour or emissive textures use.
  std::vector<int> used_images() const {
    std::vector<char> used(model_.images.size(), 0);
    for (const tinygltf::Material& material : model_.materials) {
      for (const int texture : {material.pbrMetallicRoughness.baseColorTexture.index, material.emissiveTexture.index})
        if (texture >= 0 && std::size_t(texture) < model_.textures.size()) {
          const int source = model_.textures[std::size_t(texture)].source;
          if (source >= 0 && std::size_t(source) < model_.images.size()) used[std::size_t(source)] = 1;
        }
    }
    std::vector<int> images;
    for (std::size_t i = 0; i < used.size(); ++i)
      if (used[i]) images.push_back(int(i));
    return images;
  }

  /// Decodes every used image once, in parallel; failures are remembered for the warnings of the materials using them.
  void decode_images() {
    decoded_.assign(model_.images.size(), std::nullopt);
    image_problem_.assign(model_.images.size(), std::string());
    texture_of_image_.assign(model_.images.size(), -1);
    const std::vector<int> images = used_images();
    tbb::parallel_for(std::size_t(0), images.size(), [&](std::size_t k) {
      const std::size_t i = std::size_t(images[k]);
      const tinygltf::Image& image = model_.images[i];
      const std::string name = !image.uri.empty() ? image.uri : !image.name.empty() ? image.name : "image " + std::to_string(i);
      if (image.image.empty()) {
        image_problem_[i] = "image '" + name + "' could not be read (missing file or empty data)";
        return;
      }
      if (image.image.size() > std::size_t(std::numeric_limits<int>::max())) {
        image_problem_[i] = "image '" + name + "' is too large to decode";
        return;
      }
      int width = 0;
      int height = 0;
      int channels = 0;
      constexpr int rgba = 4;  // stb expands grey, grey-alpha and RGB to RGBA8
      // The header gives the size before anything is decoded; stb's buffer and the texture's copy
      // exist together, hence two images' worth.
      if (stbi_info_from_memory(image.image.data(), int(image.image.size()), &width, &height, &channels) == 1) {
        if (const std::string shortfall = memory_shortfall(2.0 * double(width) * double(height), rgba); !shortfall.empty()) {
          image_problem_[i] = "image '" + name + "' (" + std::to_string(width) + "x" + std::to_string(height) + ") " + shortfall;
          return;
        }
      }
      stbi_uc* texels = stbi_load_from_memory(image.image.data(), int(image.image.size()), &width, &height, &channels, rgba);
      if (texels == nullptr) {
        image_problem_[i] = "image '" + name + "' could not be decoded (" +
                            (stbi_failure_reason() != nullptr ? stbi_failure_reason() : "unknown format") + ")";
        return;
      }
      Texture texture;
      texture.name = name;
      texture.width = width;
      texture.height = height;
      texture.texels.assign(texels, texels + std::size_t(width) * std::size_t(height) * rgba);
      texture.srgb = true;  // only base colour and emissive textures are loaded; glTF stores both in sRGB
      stbi_image_free(texels);
      decoded_[i] = std::move(texture);
    });
  }

  /// Scene texture for a material's texture slot, or -1 with a warning if the image is unusable.
  int scene_texture(int texture_index, const std::string& user, std::string_view slot) {
    const int image = image_of_texture(texture_index, user);
    if (image < 0) return -1;
    const std::size_t i = std::size_t(image);
    if (!decoded_[i]) {
      warn(user + ": " + image_problem_[i] + "; the material keeps its " + std::string(slot) +
           " factor and drops the texture");
      return -1;
    }
    if (texture_of_image_[i] < 0) {
      texture_of_image_[i] = int(scene_.textures.size());
      scene_.textures.push_back(*decoded_[i]);
    }
    return texture_of_image_[i];
  }

  /// `field` of material extension `extension`, or `fallback` when absent.
  static double extension_number(const tinygltf::ExtensionMap& extensions, const char* extension, const char* field,
                                 double fallback) {
    const auto found = extensions.find(extension);
    if (found == extensions.end() || !found->second.IsObject() || !found->second.Has(field)) return fallback;
    const tinygltf::Value& value = found->second.Get(field);
    return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
  }

  /// Converts every glTF material (indices are kept, so primitives keep theirs).
  void convert_materials() {
    for (std::size_t m = 0; m < model_.materials.size(); ++m) {
      const tinygltf::Material& source = model_.materials[m];
      const std::string user = "material " + std::to_string(m) + " '" + source.name + "'";
      Material material;
      material.name = source.name.empty() ? "material " + std::to_string(m) : source.name;
      const std::vector<double>& base = source.pbrMetallicRoughness.baseColorFactor;
      if (base.size() == 4) material.base_color = glm::vec4(float(base[0]), float(base[1]), float(base[2]), float(base[3]));
      material.base_color_texture = scene_texture(source.pbrMetallicRoughness.baseColorTexture.index, user, "base colour");
      material.base_color_uv_set = source.pbrMetallicRoughness.baseColorTexture.texCoord;
      if (material.base_color_uv_set < 0 || material.base_color_uv_set > 1) {
        warn(user + ": base colour texture uses TEXCOORD_" + std::to_string(material.base_color_uv_set) +
             "; igi reads sets 0 and 1 and uses set 0");
        material.base_color_uv_set = 0;
      }
      material.metallic = float(source.pbrMetallicRoughness.metallicFactor);
      material.roughness = float(source.pbrMetallicRoughness.roughnessFactor);
      if (source.emissiveFactor.size() == 3) {
        const float strength = float(extension_number(source.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0));
        material.emission = strength * glm::vec3(float(source.emissiveFactor[0]), float(source.emissiveFactor[1]),
                                                 float(source.emissiveFactor[2]));
      }
      material.emissive_texture = scene_texture(source.emissiveTexture.index, user, "emissive");
      if (source.emissiveTexture.index >= 0 && source.emissiveTexture.texCoord != 0)
        warn(user + ": emissive texture uses TEXCOORD_" + std::to_string(source.emissiveTexture.texCoord) +
             "; igi samples emissive textures with set 0");
      material.transmission = float(extension_number(source.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0));
      material.ior = float(extension_number(source.extensions, "KHR_materials_ior", "ior", 1.5));  // glTF's default IOR
      if (source.alphaMode == "MASK") {
        material.alpha_mode = AlphaMode::mask;
      } else if (source.alphaMode == "BLEND") {
        material.alpha_mode = AlphaMode::blend;
      } else if (source.alphaMode != "OPAQUE" && !source.alphaMode.empty()) {
        warn(user + ": unknown alphaMode '" + source.alphaMode + "', treated as OPAQUE");
      }
      material.alpha_cutoff = float(source.alphaCutoff);
      material.double_sided = source.doubleSided;
      scene_.materials.push_back(std::move(material));
    }
  }

  // ---- meshes -------------------------------------------------------------------------------

  /// The scene mesh of primitive `p` of glTF mesh `m`, built on first use; -1 if the primitive is skipped.
  int mesh_for(int m, int p) {
    const auto key = std::make_pair(m, p);
    if (const auto found = mesh_of_primitive_.find(key); found != mesh_of_primitive_.end()) return found->second;
    const int built = build_mesh(m, p);
    mesh_of_primitive_.emplace(key, built);
    return built;
  }

  /// Converts one glTF primitive to a Mesh and returns its index, or -1 (with a warning) if it has no triangles to give.
  int build_mesh(int m, int p) {
    const tinygltf::Mesh& source_mesh = model_.meshes[std::size_t(m)];
    const tinygltf::Primitive& primitive = source_mesh.primitives[std::size_t(p)];
    Mesh mesh;
    mesh.name = source_mesh.name.empty() ? "mesh " + std::to_string(m) : source_mesh.name;
    if (source_mesh.primitives.size() > 1) mesh.name += "#" + std::to_string(p);
    const std::string label = "mesh '" + mesh.name + "'";
    if (primitive.mode != TINYGLTF_MODE_TRIANGLES && primitive.mode != TINYGLTF_MODE_TRIANGLE_STRIP &&
        primitive.mode != TINYGLTF_MODE_TRIANGLE_FAN) {
      warn(label + ": primitive mode " + std::to_string(primitive.mode) + " (points or lines) is skipped");
      return -1;
    }
    const auto position = primitive.attributes.find("POSITION");
    if (position == primitive.attributes.end()) {
      warn(label + ": primitive has no POSITION attribute and is skipped");
      return -1;
    }
    // KHR_mesh_quantization allows integer positions, normals and uvs besides glTF's floats.
    const std::initializer_list<int> any_attribute{TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE,
                                                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT,
                                                       TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT};
    const std::vector<float> positions = read_floats(position->second, 3, any_attribute, mesh.name + " POSITION");
    const std::size_t vertex_count = positions.size() / 3;
    mesh.positions.resize(vertex_count);
    std::memcpy(mesh.positions.data(), positions.data(), positions.size() * sizeof(float));

    const auto read_uvs = [&](const char* attribute, std::vector<glm::vec2>& uvs) {
      const auto found = primitive.attributes.find(attribute);
      if (found == primitive.attributes.end()) return;
      const std::vector<float> values = read_floats(found->second, 2, any_attribute, mesh.name + " " + attribute);
      if (values.size() / 2 != vertex_count)
        fail(label + ": " + attribute + " has " + std::to_string(values.size() / 2) + " elements for " +
             std::to_string(vertex_count) + " positions");
      uvs.resize(vertex_count);
      std::memcpy(uvs.data(), values.data(), values.size() * sizeof(float));
    };
    read_uvs("TEXCOORD_0", mesh.uvs);
    read_uvs("TEXCOORD_1", mesh.uvs1);

    std::vector<std::uint32_t> indices;
    if (primitive.indices >= 0) {
      indices = read_indices(primitive.indices, mesh.name + " indices");
      for (std::size_t i = 0; i < indices.size(); ++i)
        if (indices[i] >= vertex_count)
          fail(label + ": index " + std::to_string(indices[i]) + " at position " + std::to_string(i) +
               " is out of range (the primitive has " + std::to_string(vertex_count) + " vertices)");
    } else {
      indices.resize(vertex_count);
      for (std::size_t i = 0; i < vertex_count; ++i) indices[i] = std::uint32_t(i);
    }
    assemble_triangles(primitive.mode, indices, label, mesh.triangles);

    if (primitive.material < -1 || primitive.material >= int(model_.materials.size()))
      fail(label + ": material " + std::to_string(primitive.material) + " does not exist (the file has " +
           std::to_string(model_.materials.size()) + " materials)");
    mesh.material = primitive.material;

    with_file([&] { validate_mesh(mesh, warnings_, file_.string()); });
    read_normals(primitive, label, mesh);
    scene_.meshes.push_back(std::move(mesh));
    return int(scene_.meshes.size()) - 1;
  }

  /// Triangles from an index list in glTF's triangle modes (glTF 2.0 section 3.7.2.1).
  void assemble_triangles(int mode, const std::vector<std::uint32_t>& indices, const std::string& label,
                          std::vector<glm::uvec3>& triangles) const {
    const std::size_t n = indices.size();
    if (mode == TINYGLTF_MODE_TRIANGLES) {
      if (n % 3 != 0) warn(label + ": " + std::to_string(n) + " indices is not a multiple of 3; the last " +
                           std::to_string(n % 3) + " are ignored");
      triangles.reserve(n / 3);
      for (std::size_t i = 0; i + 2 < n; i += 3) triangles.emplace_back(indices[i], indices[i + 1], indices[i + 2]);
    } else if (mode == TINYGLTF_MODE_TRIANGLE_STRIP) {
      for (std::size_t i = 0; i + 2 < n; ++i)
        triangles.emplace_back(indices[i], indices[i + 1 + i % 2], indices[i + 2 - i % 2]);  // odd triangles swap to keep the winding
    } else {
      for (std::size_t i = 0; i + 2 < n; ++i) triangles.emplace_back(indices[i + 1], indices[i + 2], indices[0]);
    }
  }

  /// NORMAL (normalized) or, where absent or unusable, area-weighted normals of the triangles.
  void read_normals(const tinygltf::Primitive& primitive, const std::string& label, Mesh& mesh) const {
    const std::size_t vertex_count = mesh.positions.size();
    std::vector<glm::vec3> computed;
    const auto compute = [&] {
      computed.assign(vertex_count, glm::vec3(0.0f));
      for (const glm::uvec3& t : mesh.triangles) {
        // The cross product's length is twice the triangle's area: summing it weights by area.
        const glm::vec3 weighted = glm::cross(mesh.positions[t.y] - mesh.positions[t.x], mesh.positions[t.z] - mesh.positions[t.x]);
        computed[t.x] += weighted;
        computed[t.y] += weighted;
        computed[t.z] += weighted;
      }
      for (glm::vec3& n : computed) n = unit_or_up(n);
    };
    const auto found = primitive.attributes.find("NORMAL");
    if (found == primitive.attributes.end()) {
      compute();
      mesh.normals = std::move(computed);
      return;
    }
    const std::vector<float> values =
        read_floats(found->second, 3,
                    {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT},
                    mesh.name + " NORMAL");
    if (values.size() / 3 != vertex_count)
      fail(label + ": NORMAL has " + std::to_string(values.size() / 3) + " elements for " + std::to_string(vertex_count) +
           " positions");
    mesh.normals.resize(vertex_count);
    std::size_t repaired = 0;
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const glm::vec3 n(values[3 * v], values[3 * v + 1], values[3 * v + 2]);
      const float length = glm::length(n);
      if (std::isfinite(length) && length > 0.0f) {
        mesh.normals[v] = n / length;
      } else {
        if (computed.empty()) compute();
        mesh.normals[v] = computed[v];
        ++repaired;
      }
    }
    if (repaired > 0)
      warn(label + ": " + std::to_string(repaired) + " zero or non-finite normals replaced by area-weighted ones");
  }

  /// `n` normalized, or +Y for a zero vector (a vertex of no triangle with area: never shaded, but must be unit).
  static glm::vec3 unit_or_up(const glm::vec3& n) noexcept {
    const float length = glm::length(n);
    return length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
  }

  // ---- nodes --------------------------------------------------------------------------------

  /// The node's transform relative to its parent: `matrix`, or translation x rotation x scale.
  glm::dmat4 local_transform(const tinygltf::Node& node, const std::string& label) const {
    if (!node.matrix.empty()) {
      if (node.matrix.size() != 16) fail(label + ": matrix has " + std::to_string(node.matrix.size()) + " values, needs 16");
      return glm::make_mat4(node.matrix.data());  // glTF matrices are column-major, like GLM's
    }
    glm::dmat4 transform(1.0);
    if (!node.translation.empty()) {
      if (node.translation.size() != 3) fail(label + ": translation needs 3 values");
      transform = glm::translate(transform, glm::dvec3(node.translation[0], node.translation[1], node.translation[2]));
    }
    if (!node.rotation.empty()) {
      if (node.rotation.size() != 4) fail(label + ": rotation needs 4 values");
      glm::dquat rotation(node.rotation[3], node.rotation[0], node.rotation[1], node.rotation[2]);  // glTF order x, y, z, w
      const double length = glm::length(rotation);
      if (!(length > 0.0) || !std::isfinite(length)) fail(label + ": rotation is not a unit quaternion");
      transform *= glm::mat4_cast(rotation / length);
    }
    if (!node.scale.empty()) {
      if (node.scale.size() != 3) fail(label + ": scale needs 3 values");
      transform = glm::scale(transform, glm::dvec3(node.scale[0], node.scale[1], node.scale[2]));
    }
    return transform;
  }

  /// Walks the default scene's node trees, emitting instances, cameras and lights.
  void convert_nodes() {
    std::vector<int> roots;
    if (!model_.scenes.empty()) {
      const int chosen = model_.defaultScene >= 0 ? model_.defaultScene : 0;
      if (std::size_t(chosen) >= model_.scenes.size()) fail("default scene " + std::to_string(chosen) + " does not exist");
      roots = model_.scenes[std::size_t(chosen)].nodes;
    } else {
      // No scenes: every node that is nobody's child is a root.
      std::vector<char> is_child(model_.nodes.size(), 0);
      for (const tinygltf::Node& node : model_.nodes)
        for (const int child : node.children)
          if (child >= 0 && std::size_t(child) < model_.nodes.size()) is_child[std::size_t(child)] = 1;
      for (std::size_t n = 0; n < model_.nodes.size(); ++n)
        if (!is_child[n]) roots.push_back(int(n));
    }

    struct Found {
      int source;        // glTF camera or light index
      int order;         // visit order, to keep duplicates stable
      std::size_t slot;  // index in the unsorted list
    };
    std::vector<Camera> cameras;
    std::vector<Found> camera_keys;
    std::vector<PunctualLight> lights;
    std::vector<Found> light_keys;

    // Depth-first with an explicit stack (deep hierarchies cannot overflow the call stack). A node
    // met again while still on the current path is a cycle; met again otherwise, it has several
    // parents, which glTF forbids and which could multiply instances exponentially.
    struct Step {
      int node;
      glm::dmat4 parent;
      bool leave;
    };
    std::vector<char> on_path(model_.nodes.size(), 0);
    std::vector<char> visited(model_.nodes.size(), 0);
    std::vector<Step> stack;
    for (auto r = roots.rbegin(); r != roots.rend(); ++r) stack.push_back({*r, glm::dmat4(1.0), false});
    int visit = 0;
    while (!stack.empty()) {
      const Step step = stack.back();
      stack.pop_back();
      if (step.leave) {
        on_path[std::size_t(step.node)] = 0;
        continue;
      }
      if (step.node < 0 || std::size_t(step.node) >= model_.nodes.size())
        fail("node " + std::to_string(step.node) + " does not exist (the file has " + std::to_string(model_.nodes.size()) +
             " nodes)");
      if (on_path[std::size_t(step.node)]) fail("the node hierarchy has a cycle through node " + std::to_string(step.node));
      if (visited[std::size_t(step.node)])
        fail("node " + std::to_string(step.node) +
             " is reached twice (several parents, or listed twice); glTF node hierarchies must be trees");
      on_path[std::size_t(step.node)] = 1;
      visited[std::size_t(step.node)] = 1;
      const tinygltf::Node& node = model_.nodes[std::size_t(step.node)];
      const std::string name = node.name.empty() ? "node " + std::to_string(step.node) : node.name;
      const std::string label = "node " + std::to_string(step.node) + " '" + node.name + "'";
      const glm::dmat4 world = step.parent * local_transform(node, label);
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r)
          if (!std::isfinite(world[c][r])) fail(label + " has a non-finite transform");
      ++visit;

      if (node.mesh >= 0) {
        if (std::size_t(node.mesh) >= model_.meshes.size())
          fail(label + " uses mesh " + std::to_string(node.mesh) + ", which does not exist (the file has " +
               std::to_string(model_.meshes.size()) + " meshes)");
        const std::size_t primitives = model_.meshes[std::size_t(node.mesh)].primitives.size();
        for (std::size_t p = 0; p < primitives; ++p)
          if (const int mesh = mesh_for(node.mesh, int(p)); mesh >= 0)
            scene_.instances.push_back({.name = name, .mesh = mesh, .transform = glm::mat4(world)});
      }
      if (node.camera >= 0) {
        if (std::size_t(node.camera) >= model_.cameras.size())
          fail(label + " uses camera " + std::to_string(node.camera) + ", which does not exist");
        if (std::optional<Camera> camera = convert_camera(node.camera, name, world)) {
          camera_keys.push_back({node.camera, visit, cameras.size()});
          cameras.push_back(std::move(*camera));
        }
      }
      if (const auto extension = node.extensions.find("KHR_lights_punctual"); extension != node.extensions.end()) {
        const tinygltf::Value& value = extension->second;
        if (!value.IsObject() || !value.Has("light") || !value.Get("light").IsNumber())
          fail(label + ": KHR_lights_punctual needs a light index");
        const int light = value.Get("light").GetNumberAsInt();
        if (light < 0 || std::size_t(light) >= model_.lights.size())
          fail(label + " uses light " + std::to_string(light) + ", which does not exist (the file has " +
               std::to_string(model_.lights.size()) + " lights)");
        if (std::optional<PunctualLight> converted = convert_light(light, name, world)) {
          light_keys.push_back({light, visit, lights.size()});
          lights.push_back(std::move(*converted));
        }
      }

      stack.push_back({step.node, glm::dmat4(1.0), true});
      for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
        stack.push_back({*child, world, false});
    }

    // Cameras and lights in the order of the file's arrays (then of the nodes using them).
    const auto by_source = [](const Found& left, const Found& right) {
      return left.source != right.source ? left.source < right.source : left.order < right.order;
    };
    std::sort(camera_keys.begin(), camera_keys.end(), by_source);
    for (const Found& key : camera_keys) scene_.cameras.push_back(std::move(cameras[key.slot]));
    std::sort(light_keys.begin(), light_keys.end(), by_source);
    for (const Found& key : light_keys) scene_.lights.push_back(std::move(lights[key.slot]));
  }

  /// glTF camera `index` placed by `world`; orthographic cameras are skipped with a warning.
  std::optional<Camera> convert_camera(int index, const std::string& node_name, const glm::dmat4& world) const {
    const tinygltf::Camera& source = model_.cameras[std::size_t(index)];
    const std::string label = "camera " + std::to_string(index) + " '" + source.name + "'";
    if (source.type != "perspective") {
      warn(label + ": type '" + source.type + "' is not supported (igi renders perspective cameras); skipped");
      return std::nullopt;
    }
    const tinygltf::PerspectiveCamera& perspective = source.perspective;
    if (!(perspective.yfov > 0.0 && perspective.yfov < glm::pi<double>()))
      fail(label + ": yfov " + std::to_string(perspective.yfov) + " must be in (0, pi)");
    if (!(perspective.aspectRatio >= 0.0) || !std::isfinite(perspective.aspectRatio))
      fail(label + ": aspectRatio must be positive");
    if (!(perspective.znear > 0.0) || !std::isfinite(perspective.znear)) fail(label + ": znear must be positive");
    Camera camera;
    camera.name = source.name.empty() ? node_name : source.name;
    // A camera's transform should be rigid; scale would stretch the view, so the axes are made unit.
    glm::dmat4 rigid = world;
    for (int axis = 0; axis < 3; ++axis) {
      const double length = glm::length(glm::dvec3(rigid[axis]));
      if (!(length > 0.0)) fail(label + ": its node transform collapses an axis");
      rigid[axis] /= length;
    }
    camera.camera_to_world = glm::mat4(rigid);
    camera.yfov = float(perspective.yfov);
    camera.aspect = float(perspective.aspectRatio);
    camera.znear = float(perspective.znear);
    return camera;
  }

  /// KHR_lights_punctual light `index` placed by `world` (it shines along the node's -Z).
  std::optional<PunctualLight> convert_light(int index, const std::string& node_name, const glm::dmat4& world) const {
    const tinygltf::Light& source = model_.lights[std::size_t(index)];
    const std::string label = "light " + std::to_string(index) + " '" + source.name + "'";
    PunctualLight light;
    if (source.type == "point") {
      light.kind = PunctualKind::point;
    } else if (source.type == "spot") {
      light.kind = PunctualKind::spot;
    } else if (source.type == "directional") {
      light.kind = PunctualKind::directional;
    } else {
      warn(label + ": unknown type '" + source.type + "'; skipped");
      return std::nullopt;
    }
    light.name = source.name.empty() ? node_name : source.name;
    if (!source.color.empty()) {
      if (source.color.size() != 3) fail(label + ": color needs 3 values");
      light.color = glm::vec3(float(source.color[0]), float(source.color[1]), float(source.color[2]));
    }
    light.intensity = float(source.intensity);
    if (!(light.intensity >= 0.0f) || !std::isfinite(light.intensity)) fail(label + ": intensity must be finite and >= 0");
    light.range = float(source.range);
    light.inner_cone = float(source.spot.innerConeAngle);
    light.outer_cone = float(source.spot.outerConeAngle);
    if (light.kind == PunctualKind::spot &&
        !(light.inner_cone >= 0.0f && light.inner_cone < light.outer_cone && light.outer_cone <= glm::half_pi<float>()))
      fail(label + ": spot cone angles need 0 <= innerConeAngle < outerConeAngle <= pi/2");
    light.position = glm::vec3(world * glm::dvec4(0.0, 0.0, 0.0, 1.0));
    const glm::dvec3 direction = glm::dmat3(world) * glm::dvec3(0.0, 0.0, -1.0);
    if (!(glm::length(direction) > 0.0)) fail(label + ": its node transform collapses the light's direction");
    light.direction = glm::vec3(glm::normalize(direction));
    return light;
  }
};

}  // namespace gltf_detail

IGI_INLINE Scene load_gltf(const std::filesystem::path& file, std::vector<std::string>* warnings) {
  return gltf_detail::Loader(file, warnings).load();
}

}  // namespace igi
