#pragma once
/// \file
/// glTF 2.0 loading (.gltf and .glb) with Debian's tinygltf (a shared library: this header never
/// defines TINYGLTF_IMPLEMENTATION and keeps tinygltf's default configuration, which is how Debian
/// built it). tinygltf parses the JSON and reads buffers and image files; everything the scene
/// takes from the buffers is bounds-checked here, because tinygltf does not check accessors.
/// Images are kept encoded while parsing and decoded once, in parallel, with stb_image.

#include <filesystem>
#include <string>
#include <vector>

#include "igi/config.hpp"
#include "igi/scene/error.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// Loads a glTF 2.0 file (.gltf or .glb); throws SceneError naming the file and the problem, and reports recoverable problems to `warnings` (or stderr).
IGI_INLINE Scene load_gltf(const std::filesystem::path& file, std::vector<std::string>* warnings = nullptr);

}  // namespace igi

#if !defined(IGI_SEPARATE_COMPILATION)
#include "igi/scene/impl/gltf_loader.hpp"
#endif
