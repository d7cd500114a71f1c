#pragma once
/// \file
/// The error the scene layer throws: a bad file or a bad scene, with a message naming the file
/// (or the scene) and the problem.

#include <filesystem>
#include <stdexcept>
#include <string>

namespace igi {

/// A scene that cannot be loaded or used; `what()` names the file or scene and the problem.
class SceneError : public std::runtime_error {
 public:
  /// An error whose message is `message` as given.
  explicit SceneError(const std::string& message) : std::runtime_error(message) {}
  /// An error about `file`: the message reads "<file>: <problem>".
  SceneError(const std::filesystem::path& file, const std::string& problem)
      : std::runtime_error(file.string() + ": " + problem), file_(file) {}
  /// The file the error is about, empty for scenes built in code.
  const std::filesystem::path& file() const noexcept { return file_; }

 private:
  std::filesystem::path file_;
};

}  // namespace igi
