// Writes the images the igi-compare command-line tests compare, into the folder given as the
// only argument: two 16 x 16 PFMs whose RMSE is exactly known, a smaller one, and a corrupt PNG.
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "igi/io/image_files.hpp"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: compare_fixtures FOLDER\n");
    return 2;
  }
  const std::filesystem::path folder = argv[1];
  std::filesystem::create_directories(folder);
  // Reference 0.5 everywhere, test 0.75 everywhere: RMSE 0.25 (both exact in binary floats).
  igi::write_image(folder / "reference.pfm", igi::Image(16, 16, glm::vec3(0.5f)));
  igi::write_image(folder / "test.pfm", igi::Image(16, 16, glm::vec3(0.75f)));
  igi::write_image(folder / "small.pfm", igi::Image(12, 16, glm::vec3(0.5f)));
  std::ofstream(folder / "corrupt.png", std::ios::binary) << "this is not a PNG file";
  return 0;
}
