#pragma once
/// \file
/// glTF images for the loader (igi/scene/impl/gltf_loader.hpp): tinygltf keeps them encoded while
/// parsing (`keep_encoded_image`); the ones materials use are decoded once, in parallel, with
/// stb_image, and become scene textures as materials ask for them.

#include <array>
#include <cstddef>
#include <limits>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <stb_image.h>
#include <tbb/parallel_for.h>
#include <tiny_gltf.h>

#include "igi/scene/impl/gltf_diagnostics.hpp"
#include "igi/scene/memory.hpp"
#include "igi/scene/scene.hpp"

namespace igi::gltf_detail {

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

/// A texture reference inside a material extension (KHR_materials_specular's and _clearcoat's textures): glTF's
/// textureInfo as a JSON value rather than tinygltf's parsed struct.
struct ExtensionTexture {
  int index = -1;                   ///< glTF texture index, -1 when absent or not an integer.
  int uv_set = 0;                   ///< texCoord.
  tinygltf::ExtensionMap extensions;  ///< The textureInfo's own extensions (KHR_texture_transform).
};

/// Texture info `field` of material extension `extension` in `extensions`.
inline ExtensionTexture extension_texture(const tinygltf::ExtensionMap& extensions, const char* extension, const char* field) {
  ExtensionTexture texture;
  const auto found = extensions.find(extension);
  if (found == extensions.end() || !found->second.IsObject() || !found->second.Has(field)) return texture;
  const tinygltf::Value& info = found->second.Get(field);
  if (!info.IsObject() || !info.Has("index") || !info.Get("index").IsInt()) return texture;
  texture.index = info.Get("index").GetNumberAsInt();
  if (info.Has("texCoord") && info.Get("texCoord").IsInt()) texture.uv_set = info.Get("texCoord").GetNumberAsInt();
  if (info.Has("extensions") && info.Get("extensions").IsObject()) {
    const tinygltf::Value& nested = info.Get("extensions");
    for (const std::string& key : nested.Keys()) texture.extensions.emplace(key, nested.Get(key));
  }
  return texture;
}

/// The glTF texture indices of every slot of `material` igi reads (-1 where a slot is empty).
inline std::array<int, 8> material_texture_indices(const tinygltf::Material& material) {
  return {material.pbrMetallicRoughness.baseColorTexture.index, material.emissiveTexture.index,
          material.pbrMetallicRoughness.metallicRoughnessTexture.index, material.normalTexture.index,
          extension_texture(material.extensions, "KHR_materials_specular", "specularTexture").index,
          extension_texture(material.extensions, "KHR_materials_specular", "specularColorTexture").index,
          extension_texture(material.extensions, "KHR_materials_clearcoat", "clearcoatTexture").index,
          extension_texture(material.extensions, "KHR_materials_clearcoat", "clearcoatRoughnessTexture").index};
}

/// The decoded images of one parsed glTF model and the scene textures made from them.
class TextureTable {
 public:
  /// Decodes from `model`, reporting through `diagnostics`; both must outlive the table.
  TextureTable(const tinygltf::Model& model, const Diagnostics& diagnostics) : model_(model), diagnostics_(diagnostics) {}

  /// Decodes every used image once, in parallel; failures are remembered for the warnings of the materials using them.
  void decode_images() {
    decoded_.assign(model_.images.size(), std::nullopt);
    image_problem_.assign(model_.images.size(), std::string());
    for (std::vector<int>& textures : texture_of_image_) textures.assign(model_.images.size(), -1);
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
      texture.srgb = true;  // as base colour and emissive textures are stored; scene_texture sets it per use
      stbi_image_free(texels);
      decoded_[i] = std::move(texture);
    });
  }

  /// Index in `textures` (the scene's) of the texture for a material's texture slot, added on first
  /// use, or -1 with a warning if the image is unusable. `srgb`: whether the slot stores sRGB
  /// (base colour, emissive) or linear values (metallic-roughness, normals); an image both kinds of slot
  /// use becomes two scene textures, one per encoding.
  int scene_texture(int texture_index, const std::string& user, std::string_view slot, bool srgb, std::vector<Texture>& textures) {
    const int image = image_of_texture(texture_index, user);
    if (image < 0) return -1;
    const std::size_t i = std::size_t(image);
    if (!decoded_[i]) {
      warn(user + ": " + image_problem_[i] + "; the material drops the texture" +
           (slot == "normal" ? std::string(" and keeps its normals") : "; its " + std::string(slot) + " factor stays"));
      return -1;
    }
    int& texture = texture_of_image_[srgb ? 1 : 0][i];
    if (texture < 0) {
      texture = int(textures.size());
      textures.push_back(*decoded_[i]);
      textures.back().srgb = srgb;
    }
    return texture;
  }

 private:
  const tinygltf::Model& model_;                 ///< The parsed file.
  const Diagnostics& diagnostics_;               ///< Where failures and warnings go.
  std::vector<std::optional<Texture>> decoded_;  ///< Per glTF image, when used by a material and decodable.
  std::vector<std::string> image_problem_;       ///< Per glTF image, why it has no texels.
  std::array<std::vector<int>, 2> texture_of_image_;  ///< Per encoding (0 linear, 1 sRGB): glTF image -> scene texture, or -1.

  [[noreturn]] void fail(const std::string& problem) const { diagnostics_.fail(problem); }
  void warn(const std::string& message) const { diagnostics_.warn(message); }

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

  /// The glTF images the materials' texture slots use.
  std::vector<int> used_images() const {
    std::vector<char> used(model_.images.size(), 0);
    for (const tinygltf::Material& material : model_.materials) {
      for (const int texture : material_texture_indices(material))
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
};

}  // namespace igi::gltf_detail
