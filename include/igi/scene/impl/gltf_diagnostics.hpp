#pragma once
/// \file
/// Where one glTF load reports its problems: shared by the loader's parts
/// (igi/scene/impl/gltf_loader.hpp, gltf_accessors.hpp, gltf_images.hpp).

#include <filesystem>
#include <string>
#include <vector>

#include "igi/scene/error.hpp"
#include "igi/scene/validate.hpp"

namespace igi::gltf_detail {

/// The file a load reads, named in every message, and where its warnings go.
struct Diagnostics {
  std::filesystem::path file;                    ///< The glTF file.
  std::vector<std::string>* warnings = nullptr;  ///< Receives warnings; null sends them to stderr.

  /// Throws SceneError naming the file and `problem`.
  [[noreturn]] void fail(const std::string& problem) const { throw SceneError(file, problem); }
  /// Reports a recoverable problem, prefixed with the file.
  void warn(const std::string& message) const { detail::report_warning(warnings, file.string() + ": " + message); }
};

}  // namespace igi::gltf_detail
