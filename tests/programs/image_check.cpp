// igi-image-check: is an image a plausible rendering? Exits 0 if its display values (sRGB
// encoded, 0..1) have a mean inside [--min-mean, --max-mean], a standard deviation of at least
// --min-stddev (not constant) and a mean colourfulness (largest minus smallest channel) of at
// least --min-chroma (not grey); else prints which test failed and exits 1. The program tests
// in tests/programs run it on the images the example programs write.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <optional>
#include <string>

#include "common/command_line.hpp"

#include "igi/io/image.hpp"

int main(int argc, char** argv) {
  std::string path;
  // Defaults: a black frame has mean 0 and a blown-out one 1, so [0.05, 0.95] rejects both yet
  // admits any sensibly exposed rendering; 0.03 is about 8 grey levels of spread, far below any
  // lit scene with shadows and far above a constant image's 0; 0.02 (5 levels of colourfulness
  // on average) rejects grey images but not a white room with one coloured wall.
  double min_mean = 0.05, max_mean = 0.95, min_stddev = 0.03, min_chroma = 0.02;
  int width = 0, height = 0;
  igi::programs::CommandLine command_line{"igi-image-check", "checks that an image is a plausible rendering"};
  command_line.add("image", path, "image file (.png, .exr, .pfm)").required();
  command_line.add("--min-mean", min_mean, "lowest mean display value").show_default();
  command_line.add("--max-mean", max_mean, "highest mean display value").show_default();
  command_line.add("--min-stddev", min_stddev, "lowest standard deviation of display values").show_default();
  command_line.add("--min-chroma", min_chroma, "lowest mean of (largest - smallest channel)").show_default();
  command_line.add("--width", width, "expected width (0: any)");
  command_line.add("--height", height, "expected height (0: any)");
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  try {
    const igi::Image image = igi::read_image(path);
    if ((width > 0 && image.width != width) || (height > 0 && image.height != height)) {
      std::printf("%s: FAIL size %dx%d, expected %dx%d\n", path.c_str(), image.width, image.height, width, height);
      return 1;
    }
    double sum = 0.0, sum2 = 0.0, chroma = 0.0;
    for (const glm::vec3& linear : image.pixels) {
      const glm::dvec3 display(igi::srgb_encode(linear.r), igi::srgb_encode(linear.g), igi::srgb_encode(linear.b));
      for (int c = 0; c < 3; ++c) {
        sum += display[c];
        sum2 += display[c] * display[c];
      }
      chroma += std::max({display.r, display.g, display.b}) - std::min({display.r, display.g, display.b});
    }
    const double n = 3.0 * double(image.pixels.size());
    const double mean = sum / n;
    const double stddev = std::sqrt(std::max(0.0, sum2 / n - mean * mean));
    chroma /= double(image.pixels.size());
    std::printf("%s: %dx%d, mean %.4f, stddev %.4f, chroma %.4f\n", path.c_str(), image.width, image.height, mean, stddev, chroma);
    bool ok = true;
    if (!(mean >= min_mean && mean <= max_mean)) ok = (std::printf("FAIL: mean outside [%g, %g]\n", min_mean, max_mean), false);
    if (!(stddev >= min_stddev)) ok = (std::printf("FAIL: stddev below %g (constant image)\n", min_stddev), false);
    if (!(chroma >= min_chroma)) ok = (std::printf("FAIL: chroma below %g (no colour)\n", min_chroma), false);
    return ok ? 0 : 1;
  } catch (const std::exception& e) {
    std::printf("FAIL: %s\n", e.what());
    return 1;
  }
}
