// igi-compare REF TEST: error metrics of an image against a reference (RMSE, relMSE, SSIM).
// Exit codes: 0 compared, 1 the images cannot be compared (unreadable, different sizes, not
// finite), 2 usage error. Errors are one line on stderr.
#include <cstdio>
#include <exception>
#include <iostream>
#include <optional>
#include <string>

#include "common/command_line.hpp"
#include "common/stats_json.hpp"

#include "igi/io/image_files.hpp"
#include "igi/io/metrics.hpp"

int main(int argc, char** argv) {
  igi::programs::CommandLine command_line{"igi-compare", "RMSE, relMSE and SSIM of TEST against the reference REF (PNG, EXR or PFM)"};
  std::string reference_path, test_path;
  bool json = false, ignore_brightest = false;
  command_line.add("REF", reference_path, "Reference image").required();
  command_line.add("TEST", test_path, "Image to measure").required();
  command_line.flag("--json", json, "Print one JSON object instead of text");
  command_line.flag("--ignore-brightest", ignore_brightest, "relMSE without the brightest 0.1% of reference pixels");
  if (const std::optional<int> exit_code = command_line.parse(argc, argv)) return *exit_code;
  try {
    const igi::Image reference = igi::read_image(reference_path);
    const igi::Image test = igi::read_image(test_path);
    if (reference.width != test.width || reference.height != test.height)
      throw std::invalid_argument("images differ in size: " + reference_path + " is " + std::to_string(reference.width) +
                                  "x" + std::to_string(reference.height) + ", " + test_path + " is " +
                                  std::to_string(test.width) + "x" + std::to_string(test.height));
    igi::RelMseOptions options;
    options.ignore_brightest = ignore_brightest;
    const double rmse = igi::rmse(test, reference);
    const double relmse = igi::relmse(test, reference, options);
    // SSIM's 11 x 11 window needs images at least that large; smaller ones get the 8 x 8 box
    // window when they fit it, and no SSIM otherwise.
    const bool gaussian_fits = test.width >= 11 && test.height >= 11;
    const bool box_fits = test.width >= 8 && test.height >= 8;
    const double ssim = gaussian_fits ? igi::ssim(test, reference)
                        : box_fits    ? igi::ssim(test, reference, igi::SsimWindow::box8)
                                      : std::nan("");
    if (json) {
      igi::programs::StatsJson out;
      out.set("reference", reference_path)
          .set("test", test_path)
          .set("width", test.width)
          .set("height", test.height)
          .set("rmse", rmse)
          .set("relmse", relmse)
          .set("relmse_epsilon", options.epsilon)
          .set("relmse_ignore_brightest", ignore_brightest);
      if (box_fits)
        out.set("ssim", ssim);
      else
        out.set("ssim", nullptr);
      out.print();
    } else {
      std::printf("RMSE   %.6g\nrelMSE %.6g\nSSIM   ", rmse, relmse);
      if (box_fits) std::printf("%.6g\n", ssim);
      else std::printf("n/a (images smaller than 8x8)\n");
    }
    return 0;
  } catch (const std::exception& error) {
    std::string message = error.what();
    for (char& c : message)
      if (c == '\n' || c == '\r') c = ' ';  // one line, whatever the library said
    std::cerr << "igi-compare: " << message << "\n";
    return 1;
  }
}
