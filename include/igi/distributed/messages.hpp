#pragma once
/// \file
/// What the tile farm sends over the network, as plain bytes: the frame header rank 0 broadcasts
/// (scene changes, tone mapping, frame index) and the finished tiles workers send back (RGB8
/// pixels plus statistics). No MPI here, so the encoding is testable on its own.

#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "igi/render/animation.hpp"
#include "igi/render/pipeline.hpp"
#include "igi/render/tone_mapping.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// A malformed message or a broken tile-farm protocol; the message says what was wrong.
class DistributedError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Appends values to a byte buffer in host byte order (every rank of one job shares an architecture).
class ByteWriter {
 public:
  /// Appends the bytes of a trivially copyable value.
  template <class T>
    requires std::is_trivially_copyable_v<T>
  void put(const T& value) {
    append(&value, sizeof(T));
  }
  /// Appends a length-prefixed string.
  void put_string(const std::string& text) {
    put(std::uint64_t(text.size()));
    append(text.data(), text.size());
  }
  /// Appends a length-prefixed array of trivially copyable values.
  template <class T>
    requires std::is_trivially_copyable_v<T>
  void put_array(const std::vector<T>& values) {
    put(std::uint64_t(values.size()));
    append(values.data(), values.size() * sizeof(T));
  }
  /// Makes room for `size` more bytes without reallocating.
  void reserve(std::size_t size) { buffer_.reserve(buffer_.size() + size); }
  /// The bytes written so far.
  std::vector<std::uint8_t>& bytes() noexcept { return buffer_; }

 private:
  /// Appends raw bytes (resize + memcpy: GCC 12 misreads vector::insert of small ranges as overflow).
  void append(const void* data, std::size_t size) {
    if (size == 0) return;
    const std::size_t at = buffer_.size();
    buffer_.resize(at + size);
    std::memcpy(buffer_.data() + at, data, size);
  }
  std::vector<std::uint8_t> buffer_;
};

/// Reads values back in the order a ByteWriter wrote them; throws DistributedError on truncation.
class ByteReader {
 public:
  /// Reads from `bytes`, which must outlive the reader; `what` names the message in errors.
  ByteReader(const std::vector<std::uint8_t>& bytes, std::string what) : bytes_(&bytes), what_(std::move(what)) {}
  /// Reads one trivially copyable value.
  template <class T>
    requires std::is_trivially_copyable_v<T>
  T get() {
    need(sizeof(T));
    T value;
    std::memcpy(&value, bytes_->data() + offset_, sizeof(T));
    offset_ += sizeof(T);
    return value;
  }
  /// Reads a length-prefixed string.
  std::string get_string() {
    const std::uint64_t size = get<std::uint64_t>();
    need(size);
    std::string text(reinterpret_cast<const char*>(bytes_->data() + offset_), std::size_t(size));
    offset_ += std::size_t(size);
    return text;
  }
  /// Reads a length-prefixed array.
  template <class T>
    requires std::is_trivially_copyable_v<T>
  std::vector<T> get_array() {
    const std::uint64_t count = get<std::uint64_t>();
    if (count > (bytes_->size() - offset_) / sizeof(T))
      throw DistributedError(what_ + ": array of " + std::to_string(count) + " elements runs past the end of the " +
                             std::to_string(bytes_->size()) + "-byte message");
    std::vector<T> values(static_cast<std::size_t>(count));
    // An empty vector's data() may be null, and memcpy from or to null is undefined even for 0 bytes (UBSan).
    if (count > 0) std::memcpy(values.data(), bytes_->data() + offset_, std::size_t(count) * sizeof(T));
    offset_ += std::size_t(count) * sizeof(T);
    return values;
  }
  /// Throws unless every byte was read.
  void finish() const {
    if (offset_ != bytes_->size())
      throw DistributedError(what_ + ": " + std::to_string(bytes_->size() - offset_) + " unexpected trailing bytes");
  }

 private:
  void need(std::uint64_t size) const {
    if (size > bytes_->size() - offset_)
      throw DistributedError(what_ + ": truncated (needs " + std::to_string(size) + " bytes at offset " +
                             std::to_string(offset_) + " of " + std::to_string(bytes_->size()) + ")");
  }
  const std::vector<std::uint8_t>* bytes_;
  std::string what_;
  std::size_t offset_ = 0;
};

/// What rank 0 broadcasts at the start of a frame (or to say there are no more frames).
struct FrameHeader {
  bool quit = false;                ///< True: no more frames, workers leave.
  std::uint32_t index = 0;          ///< Frame index (decides the VPLs).
  bool has_tone_mapping = false;    ///< False on the first frame: no statistics exist yet.
  ToneMapping tone_mapping;         ///< From the previous frame's combined statistics.
  bool send_hdr = false;            ///< Workers also send linear radiance (first frame, HDR output).
  SceneChanges changes;             ///< Camera, lights and instances for this frame.
};

/// A finished tile as a worker reports it.
struct TileMessage {
  std::int32_t tile = 0;              ///< Index into the frame's tile list.
  std::uint32_t frame = 0;            ///< Frame it belongs to.
  RayCounts rays;                     ///< Rays traced for it.
  LuminanceStatistics luminance;      ///< Its statistics for the next frame's tone mapping.
  double milliseconds = 0.0;          ///< Time the worker spent rendering it.
  std::vector<glm::u8vec3> rgb8;      ///< Tone-mapped pixels, row-major over the tile.
  std::vector<glm::vec3> hdr;         ///< Linear radiance, only when the header asked for it.
};

namespace message_detail {

/// Writes a camera.
inline void put(ByteWriter& out, const Camera& camera) {
  out.put_string(camera.name);
  out.put(camera.camera_to_world);
  out.put(camera.yfov);
  out.put(camera.aspect);
  out.put(camera.znear);
}
/// Reads a camera.
inline Camera get_camera(ByteReader& in) {
  Camera camera;
  camera.name = in.get_string();
  camera.camera_to_world = in.get<glm::mat4>();
  camera.yfov = in.get<float>();
  camera.aspect = in.get<float>();
  camera.znear = in.get<float>();
  return camera;
}
/// Writes a punctual light.
inline void put(ByteWriter& out, const PunctualLight& light) {
  out.put_string(light.name);
  out.put(std::int32_t(light.kind));
  out.put(light.color);
  out.put(light.intensity);
  out.put(light.position);
  out.put(light.direction);
  out.put(light.range);
  out.put(light.inner_cone);
  out.put(light.outer_cone);
}
/// Reads a punctual light.
inline PunctualLight get_light(ByteReader& in) {
  PunctualLight light;
  light.name = in.get_string();
  const auto kind = in.get<std::int32_t>();
  if (kind < 0 || kind > std::int32_t(PunctualKind::directional))
    throw DistributedError("frame header: punctual light kind " + std::to_string(kind) + " is unknown");
  light.kind = PunctualKind(kind);
  light.color = in.get<glm::vec3>();
  light.intensity = in.get<float>();
  light.position = in.get<glm::vec3>();
  light.direction = in.get<glm::vec3>();
  light.range = in.get<float>();
  light.inner_cone = in.get<float>();
  light.outer_cone = in.get<float>();
  return light;
}

}  // namespace message_detail

/// Encodes a frame header.
inline std::vector<std::uint8_t> encode(const FrameHeader& header) {
  ByteWriter out;
  out.put(std::uint8_t(header.quit));
  out.put(header.index);
  out.put(std::uint8_t(header.has_tone_mapping));
  out.put(header.tone_mapping.scale);
  out.put(header.tone_mapping.white);
  out.put(std::uint8_t(header.send_hdr));
  message_detail::put(out, header.changes.camera);
  out.put(std::uint64_t(header.changes.lights.size()));
  for (const auto& [index, light] : header.changes.lights) {
    out.put(std::int32_t(index));
    message_detail::put(out, light);
  }
  out.put(std::uint64_t(header.changes.instances.size()));
  for (const auto& [index, transform] : header.changes.instances) {
    out.put(std::int32_t(index));
    out.put(transform);
  }
  out.put(std::uint64_t(header.changes.meshes.size()));
  for (const MeshVertices& vertices : header.changes.meshes) {
    out.put(std::int32_t(vertices.mesh));
    out.put_array(vertices.positions);
    out.put_array(vertices.normals);
    out.put_array(vertices.tangents);
  }
  return std::move(out.bytes());
}

/// Decodes a frame header; throws DistributedError if the bytes are not one.
inline FrameHeader decode_frame_header(const std::vector<std::uint8_t>& bytes) {
  ByteReader in(bytes, "frame header");
  FrameHeader header;
  header.quit = in.get<std::uint8_t>() != 0;
  header.index = in.get<std::uint32_t>();
  header.has_tone_mapping = in.get<std::uint8_t>() != 0;
  header.tone_mapping.scale = in.get<float>();
  header.tone_mapping.white = in.get<float>();
  header.send_hdr = in.get<std::uint8_t>() != 0;
  header.changes.camera = message_detail::get_camera(in);
  const auto lights = in.get<std::uint64_t>();
  // Each light takes at least its index and fixed fields: a count beyond the bytes left is corrupt.
  if (lights > bytes.size()) throw DistributedError("frame header: " + std::to_string(lights) + " lights cannot fit");
  for (std::uint64_t i = 0; i < lights; ++i) {
    const int index = in.get<std::int32_t>();
    header.changes.lights.emplace_back(index, message_detail::get_light(in));
  }
  const auto instances = in.get<std::uint64_t>();
  if (instances > bytes.size())
    throw DistributedError("frame header: " + std::to_string(instances) + " instances cannot fit");
  for (std::uint64_t i = 0; i < instances; ++i) {
    const int index = in.get<std::int32_t>();
    header.changes.instances.emplace_back(index, in.get<glm::mat4>());
  }
  const auto meshes = in.get<std::uint64_t>();
  if (meshes > bytes.size()) throw DistributedError("frame header: " + std::to_string(meshes) + " meshes cannot fit");
  for (std::uint64_t i = 0; i < meshes; ++i) {
    MeshVertices vertices;
    vertices.mesh = in.get<std::int32_t>();
    vertices.positions = in.get_array<glm::vec3>();
    vertices.normals = in.get_array<glm::vec3>();
    vertices.tangents = in.get_array<glm::vec4>();
    header.changes.meshes.push_back(std::move(vertices));
  }
  in.finish();
  return header;
}

/// Encodes a finished tile.
inline std::vector<std::uint8_t> encode(const TileMessage& tile) {
  ByteWriter out;
  // 76 fixed bytes (see the fields below) plus the pixels: one allocation per tile.
  out.reserve(76 + tile.rgb8.size() * sizeof(glm::u8vec3) + tile.hdr.size() * sizeof(glm::vec3));
  out.put(tile.tile);
  out.put(tile.frame);
  out.put(tile.rays.primary);
  out.put(tile.rays.shadow);
  out.put(tile.rays.secondary);
  out.put(tile.luminance.log_sum);
  out.put(tile.luminance.count);
  out.put(tile.luminance.max_luminance);
  out.put(tile.milliseconds);
  out.put_array(tile.rgb8);
  out.put_array(tile.hdr);
  return std::move(out.bytes());
}

/// Decodes a finished tile; throws DistributedError if the bytes are not one.
inline TileMessage decode_tile_message(const std::vector<std::uint8_t>& bytes) {
  ByteReader in(bytes, "tile message");
  TileMessage tile;
  tile.tile = in.get<std::int32_t>();
  tile.frame = in.get<std::uint32_t>();
  tile.rays.primary = in.get<std::uint64_t>();
  tile.rays.shadow = in.get<std::uint64_t>();
  tile.rays.secondary = in.get<std::uint64_t>();
  tile.luminance.log_sum = in.get<double>();
  tile.luminance.count = in.get<std::uint64_t>();
  tile.luminance.max_luminance = in.get<float>();
  tile.milliseconds = in.get<double>();
  tile.rgb8 = in.get_array<glm::u8vec3>();
  tile.hdr = in.get_array<glm::vec3>();
  in.finish();
  return tile;
}

}  // namespace igi
