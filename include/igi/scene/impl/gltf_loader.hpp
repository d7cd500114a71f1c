#pragma once
/// \file
/// The glTF loader behind igi/scene/gltf.hpp (see there): included by it when igi is header-only,
/// compiled once by igi/separate_compilation.hpp under IGI_SEPARATE_COMPILATION (igi/config.hpp).
/// This part parses the file and builds materials, meshes, the node hierarchy, cameras and lights;
/// accessors are read by igi/scene/impl/gltf_accessors.hpp, images decoded by
/// igi/scene/impl/gltf_images.hpp, animations, skins and morph targets by
/// igi/scene/impl/gltf_animations.hpp.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include <glm/glm.hpp>
#include <glm/gtc/constants.hpp>
#include <glm/gtc/matrix_transform.hpp>
#include <glm/gtc/quaternion.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <tiny_gltf.h>

#include "igi/config.hpp"
#include "igi/scene/animation_sampling.hpp"
#include "igi/scene/error.hpp"
#include "igi/scene/gltf.hpp"
#include "igi/scene/impl/gltf_accessors.hpp"
#include "igi/scene/impl/gltf_animations.hpp"
#include "igi/scene/impl/gltf_diagnostics.hpp"
#include "igi/scene/impl/gltf_images.hpp"
#include "igi/scene/scene.hpp"
#include "igi/scene/validate.hpp"

namespace igi {

namespace gltf_detail {

/// glTF extensions the loader understands, so a file may list them as required.
inline const std::set<std::string, std::less<>>& supported_extensions() {
  static const std::set<std::string, std::less<>> names{
      "KHR_lights_punctual",     "KHR_materials_clearcoat", "KHR_materials_emissive_strength",
      "KHR_materials_ior",       "KHR_materials_specular",  "KHR_materials_transmission",
      "KHR_materials_volume",
      "KHR_mesh_quantization",   "KHR_texture_transform"};
  return names;
}

/// The state of one load: the parsed file and the scene being built from it.
class Loader {
 public:
  /// Prepares to load `file`, sending warnings to `warnings` (or stderr when null).
  Loader(std::filesystem::path file, std::vector<std::string>* warnings) : diagnostics_{std::move(file), warnings} {}

  /// Parses the file and builds the scene.
  Scene load() {
    parse();
    check_required_extensions();
    scene_.name = diagnostics_.file.stem().string();
    textures_.decode_images();
    convert_materials();
    convert_nodes();
    convert_motion();
    with_file([&] { validate_scene(scene_, diagnostics_.warnings, diagnostics_.file.string()); });
    return std::move(scene_);
  }

 private:
  Diagnostics diagnostics_;                               // the file and where warnings go
  tinygltf::Model model_;                                 // the parsed file
  AccessorReader accessors_{model_, diagnostics_};          // reads model_'s accessors
  TextureTable textures_{model_, diagnostics_};             // decodes model_'s images
  AnimationReader motion_{model_, accessors_, diagnostics_};  // reads model_'s nodes, animations, skins, morph targets
  std::vector<DeformedPrimitive> deformed_;                  // primitives placed by skinned or morphed nodes
  Scene scene_;
  std::map<std::pair<int, int>, int> mesh_of_primitive_;  // (glTF mesh, primitive) -> Scene::meshes, or -1 if skipped

  [[noreturn]] void fail(const std::string& problem) const { diagnostics_.fail(problem); }
  /// Runs a check of validate.hpp given the file as its location, rethrowing its error as one about the file.
  template <class Check>
  void with_file(Check&& check) const {
    try {
      check();
    } catch (const SceneError& error) {
      const std::string message = error.what();
      const std::string prefix = diagnostics_.file.string() + ": ";
      fail(message.rfind(prefix, 0) == 0 ? message.substr(prefix.size()) : message);
    }
  }
  void warn(const std::string& message) const { diagnostics_.warn(message); }

  /// Reads the file and lets tinygltf parse it (JSON, buffers, image files).
  void parse() {
    std::error_code code;
    if (!std::filesystem::exists(diagnostics_.file, code)) fail("file not found");
    if (std::filesystem::is_directory(diagnostics_.file, code)) fail("is a directory, not a glTF file");
    std::ifstream in(diagnostics_.file, std::ios::binary);
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
    const std::string base_dir = diagnostics_.file.parent_path().string();
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

  // ---- materials --------------------------------------------------------------------------

  /// `field` of material extension `extension`, or `fallback` when absent.
  static double extension_number(const tinygltf::ExtensionMap& extensions, const char* extension, const char* field,
                                 double fallback) {
    const auto found = extensions.find(extension);
    if (found == extensions.end() || !found->second.IsObject() || !found->second.Has(field)) return fallback;
    const tinygltf::Value& value = found->second.Get(field);
    return value.IsNumber() ? value.GetNumberAsDouble() : fallback;
  }

  /// Colour `field` of material extension `extension`, or `fallback` when absent; a value that is
  /// not three numbers is named in a warning to `user` and left at `fallback`.
  glm::vec3 extension_color(const tinygltf::ExtensionMap& extensions, const char* extension, const char* field,
                            glm::vec3 fallback, const std::string& user) const {
    const auto found = extensions.find(extension);
    if (found == extensions.end() || !found->second.IsObject() || !found->second.Has(field)) return fallback;
    const tinygltf::Value& value = found->second.Get(field);
    if (!value.IsArray() || value.ArrayLen() != 3 || !value.Get(0).IsNumber() || !value.Get(1).IsNumber() ||
        !value.Get(2).IsNumber()) {
      warn(user + ": " + extension + " " + field + " is not three numbers; left at its default");
      return fallback;
    }
    return {float(value.Get(0).GetNumberAsDouble()), float(value.Get(1).GetNumberAsDouble()),
            float(value.Get(2).GetNumberAsDouble())};
  }

  /// The KHR_texture_transform of the texture in `slot` of `user`, whose texture info carries
  /// `extensions` (identity without one), and the uv set it reads: `uv_set`, or the extension's
  /// texCoord. Fields that are not numbers are named in a warning and left at their defaults.
  UvTransform texture_transform(const tinygltf::ExtensionMap& extensions, const std::string& user, const std::string& slot,
                                int& uv_set) const {
    const auto found = extensions.find("KHR_texture_transform");
    if (found == extensions.end() || !found->second.IsObject()) return {};
    const tinygltf::Value& transform = found->second;
    const auto pair = [&](const char* field, glm::vec2 fallback) {
      if (!transform.Has(field)) return fallback;
      const tinygltf::Value& value = transform.Get(field);
      if (!value.IsArray() || value.ArrayLen() != 2 || !value.Get(0).IsNumber() || !value.Get(1).IsNumber()) {
        warn(user + ": the " + slot + " texture's KHR_texture_transform " + field + " is not two numbers; left at its default");
        return fallback;
      }
      return glm::vec2(float(value.Get(0).GetNumberAsDouble()), float(value.Get(1).GetNumberAsDouble()));
    };
    const glm::vec2 offset = pair("offset", glm::vec2(0.0f)), scale = pair("scale", glm::vec2(1.0f));
    float rotation = 0.0f;
    if (transform.Has("rotation")) {
      if (transform.Get("rotation").IsNumber())
        rotation = float(transform.Get("rotation").GetNumberAsDouble());
      else
        warn(user + ": the " + slot + " texture's KHR_texture_transform rotation is not a number; left at 0");
    }
    if (transform.Has("texCoord") && transform.Get("texCoord").IsInt()) uv_set = transform.Get("texCoord").GetNumberAsInt();
    return UvTransform::from(offset, rotation, scale);
  }

  /// Warns when the texture in `slot` of `user` reads another uv set than TEXCOORD_0, the one shading reads.
  void warn_uv_set(int texture, int uv_set, const std::string& user, const std::string& slot) const {
    if (texture >= 0 && uv_set != 0)
      warn(user + ": " + slot + " texture uses TEXCOORD_" + std::to_string(uv_set) + "; igi samples " + slot +
           " textures with set 0");
  }

  /// KHR_materials_specular's factors and textures into `material` (glTF's defaults without it).
  void convert_specular(const tinygltf::ExtensionMap& extensions, const std::string& user, Material& material) {
    const char* extension = "KHR_materials_specular";
    material.specular = float(extension_number(extensions, extension, "specularFactor", 1.0));
    material.specular_color = extension_color(extensions, extension, "specularColorFactor", glm::vec3(1.0f), user);
    ExtensionTexture specular = extension_texture(extensions, extension, "specularTexture");
    material.specular_texture = textures_.scene_texture(specular.index, user, "specular", false, scene_.textures);
    material.specular_transform = texture_transform(specular.extensions, user, "specular", specular.uv_set);
    warn_uv_set(material.specular_texture, specular.uv_set, user, "specular");
    ExtensionTexture color = extension_texture(extensions, extension, "specularColorTexture");
    material.specular_color_texture = textures_.scene_texture(color.index, user, "specular colour", true, scene_.textures);
    material.specular_color_transform = texture_transform(color.extensions, user, "specular colour", color.uv_set);
    warn_uv_set(material.specular_color_texture, color.uv_set, user, "specular colour");
  }

  /// KHR_materials_volume's factors into `material` (thin-walled without it). A thickness
  /// texture is not read (the factor alone says whether the mesh is a solid); a negative
  /// thickness and a non-positive attenuation distance, which the extension forbids, are named
  /// in a warning and left at their defaults.
  void convert_volume(const tinygltf::ExtensionMap& extensions, const std::string& user, Material& material) const {
    const char* extension = "KHR_materials_volume";
    material.thickness = float(extension_number(extensions, extension, "thicknessFactor", 0.0));
    if (material.thickness < 0.0f) {
      warn(user + ": KHR_materials_volume thicknessFactor " + std::to_string(material.thickness) + " is negative; taken as 0");
      material.thickness = 0.0f;
    }
    const double infinite = double(std::numeric_limits<float>::infinity());
    material.attenuation_distance = float(extension_number(extensions, extension, "attenuationDistance", infinite));
    if (!(material.attenuation_distance > 0.0f)) {
      warn(user + ": KHR_materials_volume attenuationDistance is not positive; taken as infinite");
      material.attenuation_distance = std::numeric_limits<float>::infinity();
    }
    material.attenuation_color = extension_color(extensions, extension, "attenuationColor", glm::vec3(1.0f), user);
    if (extension_texture(extensions, extension, "thicknessTexture").index >= 0)
      warn(user + ": KHR_materials_volume thicknessTexture is ignored; thicknessFactor alone says whether it is a solid");
  }

  /// KHR_materials_clearcoat's factors and textures into `material` (no coat without it). The
  /// coat's own normal map is not read: the coat takes the base's normal (a warning says so).
  void convert_clearcoat(const tinygltf::ExtensionMap& extensions, const std::string& user, Material& material) {
    const char* extension = "KHR_materials_clearcoat";
    material.clearcoat = float(extension_number(extensions, extension, "clearcoatFactor", 0.0));
    material.clearcoat_roughness = float(extension_number(extensions, extension, "clearcoatRoughnessFactor", 0.0));
    ExtensionTexture coat = extension_texture(extensions, extension, "clearcoatTexture");
    material.clearcoat_texture = textures_.scene_texture(coat.index, user, "clearcoat", false, scene_.textures);
    material.clearcoat_transform = texture_transform(coat.extensions, user, "clearcoat", coat.uv_set);
    warn_uv_set(material.clearcoat_texture, coat.uv_set, user, "clearcoat");
    ExtensionTexture roughness = extension_texture(extensions, extension, "clearcoatRoughnessTexture");
    material.clearcoat_roughness_texture =
        textures_.scene_texture(roughness.index, user, "clearcoat roughness", false, scene_.textures);
    material.clearcoat_roughness_transform = texture_transform(roughness.extensions, user, "clearcoat roughness", roughness.uv_set);
    warn_uv_set(material.clearcoat_roughness_texture, roughness.uv_set, user, "clearcoat roughness");
    if (extension_texture(extensions, extension, "clearcoatNormalTexture").index >= 0)
      warn(user + ": KHR_materials_clearcoat clearcoatNormalTexture is ignored; the coat takes the base's normal");
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
      material.base_color_texture =
          textures_.scene_texture(source.pbrMetallicRoughness.baseColorTexture.index, user, "base colour", true, scene_.textures);
      const tinygltf::TextureInfo& base_texture = source.pbrMetallicRoughness.baseColorTexture;
      material.base_color_uv_set = base_texture.texCoord;
      material.base_color_transform = texture_transform(base_texture.extensions, user, "base colour", material.base_color_uv_set);
      warn_uv_set(material.base_color_texture, material.base_color_uv_set, user, "base colour");
      if (material.base_color_uv_set < 0 || material.base_color_uv_set > 1) material.base_color_uv_set = 0;
      material.metallic = float(source.pbrMetallicRoughness.metallicFactor);
      material.roughness = float(source.pbrMetallicRoughness.roughnessFactor);
      const tinygltf::TextureInfo& metallic_roughness = source.pbrMetallicRoughness.metallicRoughnessTexture;
      material.metallic_roughness_texture =
          textures_.scene_texture(metallic_roughness.index, user, "metallic and roughness", false, scene_.textures);
      int uv_set = metallic_roughness.texCoord;
      material.metallic_roughness_transform = texture_transform(metallic_roughness.extensions, user, "metallic-roughness", uv_set);
      warn_uv_set(material.metallic_roughness_texture, uv_set, user, "metallic-roughness");
      material.normal_texture = textures_.scene_texture(source.normalTexture.index, user, "normal", false, scene_.textures);
      material.normal_scale = float(source.normalTexture.scale);
      uv_set = source.normalTexture.texCoord;
      material.normal_transform = texture_transform(source.normalTexture.extensions, user, "normal", uv_set);
      warn_uv_set(material.normal_texture, uv_set, user, "normal");
      if (source.emissiveFactor.size() == 3) {
        const float strength = float(extension_number(source.extensions, "KHR_materials_emissive_strength", "emissiveStrength", 1.0));
        material.emission = strength * glm::vec3(float(source.emissiveFactor[0]), float(source.emissiveFactor[1]),
                                                 float(source.emissiveFactor[2]));
      }
      material.emissive_texture = textures_.scene_texture(source.emissiveTexture.index, user, "emissive", true, scene_.textures);
      uv_set = source.emissiveTexture.texCoord;
      material.emissive_transform = texture_transform(source.emissiveTexture.extensions, user, "emissive", uv_set);
      warn_uv_set(material.emissive_texture, uv_set, user, "emissive");
      material.transmission = float(extension_number(source.extensions, "KHR_materials_transmission", "transmissionFactor", 0.0));
      material.ior = float(extension_number(source.extensions, "KHR_materials_ior", "ior", 1.5));  // glTF's default IOR
      convert_volume(source.extensions, user, material);
      convert_specular(source.extensions, user, material);
      convert_clearcoat(source.extensions, user, material);
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
    const std::vector<float> positions = accessors_.read_floats(position->second, 3, any_attribute, mesh.name + " POSITION");
    const std::size_t vertex_count = positions.size() / 3;
    mesh.positions.resize(vertex_count);
    std::memcpy(mesh.positions.data(), positions.data(), positions.size() * sizeof(float));

    const auto read_uvs = [&](const char* attribute, std::vector<glm::vec2>& uvs) {
      const auto found = primitive.attributes.find(attribute);
      if (found == primitive.attributes.end()) return;
      const std::vector<float> values = read_vertex_attribute(found->second, 2, any_attribute, attribute, label, mesh);
      uvs.resize(vertex_count);
      std::memcpy(uvs.data(), values.data(), values.size() * sizeof(float));
    };
    read_uvs("TEXCOORD_0", mesh.uvs);
    read_uvs("TEXCOORD_1", mesh.uvs1);

    std::vector<std::uint32_t> indices;
    if (primitive.indices >= 0) {
      indices = accessors_.read_indices(primitive.indices, mesh.name + " indices");
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

    with_file([&] { validate_mesh(mesh, diagnostics_.warnings, diagnostics_.file.string()); });
    read_normals(primitive, label, mesh);
    read_tangents(primitive, label, mesh);
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
    const std::vector<float> values = read_vertex_attribute(
        found->second, 3, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT}, "NORMAL",
        label, mesh);
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

  /// The floats of per-vertex `attribute` of `mesh` (accessor `accessor`, `components` per element,
  /// of the component types `allowed`); an element count other than the mesh's positions' is an
  /// error naming `label`.
  std::vector<float> read_vertex_attribute(int accessor, int components, std::initializer_list<int> allowed,
                                           const std::string& attribute, const std::string& label, const Mesh& mesh) const {
    std::vector<float> values = accessors_.read_floats(accessor, components, allowed, mesh.name + " " + attribute);
    const std::size_t elements = values.size() / std::size_t(components);
    if (elements != mesh.positions.size())
      fail(label + ": " + attribute + " has " + std::to_string(elements) + " elements for " +
           std::to_string(mesh.positions.size()) + " positions");
    return values;
  }

  /// TANGENT (float, or normalized byte or short under KHR_mesh_quantization): xyz normalized, w
  /// reduced to its sign. Zero or non-finite tangents are left all zero (those vertices' normal
  /// maps take the uv frame) and counted in a warning.
  void read_tangents(const tinygltf::Primitive& primitive, const std::string& label, Mesh& mesh) const {
    const auto found = primitive.attributes.find("TANGENT");
    if (found == primitive.attributes.end()) return;
    const std::size_t vertex_count = mesh.positions.size();
    const std::vector<float> values = read_vertex_attribute(
        found->second, 4, {TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_COMPONENT_TYPE_BYTE, TINYGLTF_COMPONENT_TYPE_SHORT}, "TANGENT",
        label, mesh);
    mesh.tangents.assign(vertex_count, glm::vec4(0.0f));
    std::size_t unusable = 0;
    for (std::size_t v = 0; v < vertex_count; ++v) {
      const glm::vec3 tangent(values[4 * v], values[4 * v + 1], values[4 * v + 2]);
      const float length = glm::length(tangent), sign = values[4 * v + 3];
      if (std::isfinite(length) && length > 0.0f && std::isfinite(sign))
        mesh.tangents[v] = glm::vec4(tangent / length, sign < 0.0f ? -1.0f : 1.0f);
      else
        ++unusable;
    }
    if (unusable > 0)
      warn(label + ": " + std::to_string(unusable) + " zero or non-finite tangents; normal maps use the uv frame there");
  }

  /// `n` normalized, or +Y for a zero vector (a vertex of no triangle with area: never shaded, but must be unit).
  static glm::vec3 unit_or_up(const glm::vec3& n) noexcept {
    const float length = glm::length(n);
    return length > 0.0f && std::isfinite(length) ? n / length : glm::vec3(0.0f, 1.0f, 0.0f);
  }

  // ---- motion -------------------------------------------------------------------------------

  /// Reads the rest transforms, skins, animations and deformed meshes into scene_.animations, and
  /// poses the deformed meshes at rest (skinned ones in world space, their instances at identity).
  void convert_motion() {
    SceneAnimations& data = scene_.animations;
    motion_.read_nodes(data);
    motion_.read_skins(data);
    motion_.read_animations(data);
    for (const DeformedPrimitive& primitive : deformed_)
      data.deformables.push_back(motion_.read_deformable(primitive, scene_.meshes[std::size_t(primitive.mesh)], data));
    with_file([&] {
      check_animations(scene_);
      AnimationPlayer::rest(scene_).apply_to(scene_);
    });
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
      int node;          // the node placing it
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
      int parent_node = -1;
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
      scene_.animations.node_order.push_back(step.node);
      scene_.animations.nodes.resize(model_.nodes.size());
      scene_.animations.nodes[std::size_t(step.node)].parent = step.parent_node;

      if (node.mesh >= 0) {
        if (std::size_t(node.mesh) >= model_.meshes.size())
          fail(label + " uses mesh " + std::to_string(node.mesh) + ", which does not exist (the file has " +
               std::to_string(model_.meshes.size()) + " meshes)");
        const std::size_t primitives = model_.meshes[std::size_t(node.mesh)].primitives.size();
        // A skinned or morphed primitive gets a mesh of its own, as its vertices follow this node alone.
        const bool deformed = node.skin >= 0 || motion_.has_targets(node.mesh);
        for (std::size_t p = 0; p < primitives; ++p)
          if (const int mesh = deformed ? build_mesh(node.mesh, int(p)) : mesh_for(node.mesh, int(p)); mesh >= 0) {
            if (deformed) deformed_.push_back({step.node, node.mesh, int(p), mesh, int(scene_.instances.size())});
            scene_.instances.push_back({.name = name, .mesh = mesh, .transform = glm::mat4(world)});
            scene_.animations.instance_nodes.push_back(step.node);
          }
      }
      if (node.camera >= 0) {
        if (std::size_t(node.camera) >= model_.cameras.size())
          fail(label + " uses camera " + std::to_string(node.camera) + ", which does not exist");
        if (std::optional<Camera> camera = convert_camera(node.camera, name, world)) {
          camera_keys.push_back({node.camera, visit, cameras.size(), step.node});
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
          light_keys.push_back({light, visit, lights.size(), step.node});
          lights.push_back(std::move(*converted));
        }
      }

      stack.push_back({step.node, glm::dmat4(1.0), true});
      for (auto child = node.children.rbegin(); child != node.children.rend(); ++child)
        stack.push_back({*child, world, false, step.node});
    }

    // Cameras and lights in the order of the file's arrays (then of the nodes using them).
    const auto by_source = [](const Found& left, const Found& right) {
      return left.source != right.source ? left.source < right.source : left.order < right.order;
    };
    std::sort(camera_keys.begin(), camera_keys.end(), by_source);
    for (const Found& key : camera_keys) {
      scene_.cameras.push_back(std::move(cameras[key.slot]));
      scene_.animations.camera_nodes.push_back(key.node);
    }
    std::sort(light_keys.begin(), light_keys.end(), by_source);
    for (const Found& key : light_keys) {
      scene_.lights.push_back(std::move(lights[key.slot]));
      scene_.animations.light_nodes.push_back(key.node);
    }
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
