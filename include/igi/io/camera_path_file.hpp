#pragma once
/// \file
/// Writing a camera path: a glTF 2.0 file holding one perspective camera and one animation that
/// moves it, which igi::CameraPath plays over any scene (igi-render --camera-path) and which
/// glTF viewers and Blender open as an ordinary animated camera.

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <span>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/quaternion.hpp>

#include "igi/scene/error.hpp"

namespace igi {

/// Where a camera path's camera is at one time.
struct CameraKey {
  float seconds = 0.0f;            ///< Time of the key.
  glm::mat4 camera_to_world{1.0f};  ///< The camera's rigid transform (looking down its -Z, +Y up).
};

namespace camera_path_detail {

/// RFC 4648 base64 of `bytes` (the encoding of a glTF data URI).
inline std::string base64(const std::vector<unsigned char>& bytes) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string text;
  text.reserve((bytes.size() + 2) / 3 * 4);
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t group = std::uint32_t(bytes[i]) << 16 | (i + 1 < bytes.size() ? std::uint32_t(bytes[i + 1]) << 8 : 0u) |
                                (i + 2 < bytes.size() ? std::uint32_t(bytes[i + 2]) : 0u);
    text += digits[(group >> 18) & 63];
    text += digits[(group >> 12) & 63];
    text += i + 1 < bytes.size() ? digits[(group >> 6) & 63] : '=';
    text += i + 2 < bytes.size() ? digits[group & 63] : '=';
  }
  return text;
}

/// Appends `values` to `buffer` as little-endian floats (x86 and every glTF reader's order).
inline void append(std::vector<unsigned char>& buffer, const std::vector<float>& values) {
  const std::size_t offset = buffer.size();
  buffer.resize(offset + values.size() * sizeof(float));
  std::memcpy(buffer.data() + offset, values.data(), values.size() * sizeof(float));
}

}  // namespace camera_path_detail

/// Writes `file` (.gltf, its buffer embedded as a data URI): a camera of vertical field of view
/// `yfov` (radians) moved through `keys` by animation `name`, translation and rotation
/// interpolated linearly (rotations by the shortest arc). Throws SceneError naming the problem
/// if the keys are empty, not in strictly increasing time, not finite, or the file cannot be written.
inline void write_camera_path(const std::filesystem::path& file, std::span<const CameraKey> keys, float yfov,
                              const std::string& name = "walkthrough") {
  const std::string where = "camera path '" + file.string() + "'";
  if (keys.empty()) throw SceneError(where + ": no keys to write");
  for (const char c : name)
    if (c == '"' || c == '\\' || static_cast<unsigned char>(c) < 0x20)
      throw SceneError(where + ": the animation name may not hold quotes, backslashes or control characters");
  if (!(yfov > 0.0f && yfov < 3.14159f)) throw SceneError(where + ": field of view " + std::to_string(yfov) + " is not in (0, pi)");
  std::vector<float> times, translations, rotations;
  glm::quat previous(1.0f, 0.0f, 0.0f, 0.0f);
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const CameraKey& key = keys[k];
    if (!std::isfinite(key.seconds) || (k > 0 && !(key.seconds > keys[k - 1].seconds)))
      throw SceneError(where + ": key " + std::to_string(k) + " at " + std::to_string(key.seconds) +
                       " s is not after the one before it");
    for (int c = 0; c < 4; ++c)
      for (int r = 0; r < 4; ++r)
        if (!std::isfinite(key.camera_to_world[c][r])) throw SceneError(where + ": key " + std::to_string(k) + " has a non-finite transform");
    glm::quat rotation = glm::normalize(glm::quat_cast(glm::mat3(key.camera_to_world)));
    if (k > 0 && glm::dot(rotation, previous) < 0.0f) rotation = -rotation;  // neighbours on one hemisphere: no sign flips in the file
    previous = rotation;
    const glm::vec3 position(key.camera_to_world[3]);
    times.push_back(key.seconds);
    translations.insert(translations.end(), {position.x, position.y, position.z});
    rotations.insert(rotations.end(), {rotation.x, rotation.y, rotation.z, rotation.w});  // glTF's order: x, y, z, w
  }
  std::vector<unsigned char> buffer;
  camera_path_detail::append(buffer, times);
  camera_path_detail::append(buffer, translations);
  camera_path_detail::append(buffer, rotations);
  const std::size_t count = keys.size();
  const std::size_t time_bytes = 4 * count, translation_bytes = 12 * count, rotation_bytes = 16 * count;

  std::ostringstream json;
  json.precision(9);  // float's round-trip digits: the file reads back the same keys
  json << "{\n \"asset\": {\"version\": \"2.0\", \"generator\": \"igi\"},\n"
       << " \"scene\": 0,\n \"scenes\": [{\"nodes\": [0]}],\n"
       << " \"nodes\": [{\"name\": \"" << name << " camera\", \"camera\": 0, \"translation\": [" << translations[0] << ", "
       << translations[1] << ", " << translations[2] << "], \"rotation\": [" << rotations[0] << ", " << rotations[1] << ", "
       << rotations[2] << ", " << rotations[3] << "]}],\n"
       << " \"cameras\": [{\"type\": \"perspective\", \"perspective\": {\"yfov\": " << yfov << ", \"znear\": 0.01}}],\n"
       << " \"buffers\": [{\"byteLength\": " << buffer.size() << ", \"uri\": \"data:application/octet-stream;base64,"
       << camera_path_detail::base64(buffer) << "\"}],\n"
       << " \"bufferViews\": [{\"buffer\": 0, \"byteOffset\": 0, \"byteLength\": " << time_bytes << "}, "
       << "{\"buffer\": 0, \"byteOffset\": " << time_bytes << ", \"byteLength\": " << translation_bytes << "}, "
       << "{\"buffer\": 0, \"byteOffset\": " << time_bytes + translation_bytes << ", \"byteLength\": " << rotation_bytes << "}],\n"
       << " \"accessors\": [{\"bufferView\": 0, \"componentType\": 5126, \"count\": " << count
       << ", \"type\": \"SCALAR\", \"min\": [" << times.front() << "], \"max\": [" << times.back() << "]}, "
       << "{\"bufferView\": 1, \"componentType\": 5126, \"count\": " << count << ", \"type\": \"VEC3\"}, "
       << "{\"bufferView\": 2, \"componentType\": 5126, \"count\": " << count << ", \"type\": \"VEC4\"}],\n"
       << " \"animations\": [{\"name\": \"" << name << "\", \"samplers\": [{\"input\": 0, \"output\": 1, \"interpolation\": \"LINEAR\"}, "
       << "{\"input\": 0, \"output\": 2, \"interpolation\": \"LINEAR\"}], \"channels\": ["
       << "{\"sampler\": 0, \"target\": {\"node\": 0, \"path\": \"translation\"}}, "
       << "{\"sampler\": 1, \"target\": {\"node\": 0, \"path\": \"rotation\"}}]}]\n}\n";
  std::ofstream out(file, std::ios::binary);
  out << json.str();
  if (!out.flush()) throw SceneError(where + ": cannot write the file");
}

}  // namespace igi
