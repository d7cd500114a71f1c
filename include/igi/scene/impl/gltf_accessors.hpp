#pragma once
/// \file
/// glTF accessors for the loader (igi/scene/impl/gltf_loader.hpp): component types, decoding of
/// normalized and integer components, and reading an accessor's elements (with its sparse
/// substitutions) with every byte range checked against its bufferView and buffer, because
/// tinygltf does not check accessors.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <initializer_list>
#include <limits>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <tiny_gltf.h>

#include "igi/scene/impl/gltf_diagnostics.hpp"
#include "igi/scene/memory.hpp"

namespace igi::gltf_detail {

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

/// Reads the accessors of one parsed glTF model; a malformed accessor fails the load.
class AccessorReader {
 public:
  /// Reads from `model`, reporting through `diagnostics`; both must outlive the reader.
  AccessorReader(const tinygltf::Model& model, const Diagnostics& diagnostics) : model_(model), diagnostics_(diagnostics) {}

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
 private:
  const tinygltf::Model& model_;    ///< The parsed file.
  const Diagnostics& diagnostics_;  ///< Where failures go.

  [[noreturn]] void fail(const std::string& problem) const { diagnostics_.fail(problem); }

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
};

}  // namespace igi::gltf_detail
