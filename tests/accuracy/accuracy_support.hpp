#pragma once
// Shared helpers of the accuracy tests: path-traced images of a scene, block averages (a
// low-pass) and noise estimates from independent runs.

#include <cmath>
#include <cstdint>
#include <vector>

#include "../render/render_support.hpp"
#include "igi/io/metrics.hpp"
#include "igi/render/path_tracer.hpp"

namespace igi::testing {

/// A path-traced image of `scene` (first camera, or the default one) through EmbreeBackend<1>.
inline Image path_trace(const Scene& scene, int width, int height, int spp, PathTracerSettings settings = {},
                        PathTracerStatistics* statistics = nullptr) {
  const EmbreeBackend<1> backend(scene);
  const GltfMaterialShader surface(scene);
  const StandardBrdf brdf;
  PathTracer<EmbreeBackend<1>, GltfMaterialShader, StandardBrdf> tracer(scene, backend, surface, brdf, settings);
  const Camera camera = scene.cameras.empty() ? default_camera(scene) : scene.cameras.front();
  Image image = tracer.render(camera, width, height, spp);
  if (statistics) *statistics = tracer.statistics();
  return image;
}

/// Mean of all channels of all pixels.
inline double mean_of(const Image& image) {
  double sum = 0.0;
  for (const glm::vec3& p : image.pixels) sum += double(p.r) + double(p.g) + double(p.b);
  return sum / (3.0 * double(image.pixels.size()));
}

/// Largest channel value over the image.
inline float max_of(const Image& image) {
  float m = 0.0f;
  for (const glm::vec3& p : image.pixels) m = std::max(m, std::max(p.r, std::max(p.g, p.b)));
  return m;
}

/// True if every channel of every pixel is finite.
inline bool finite(const Image& image) {
  for (const glm::vec3& p : image.pixels)
    if (!std::isfinite(p.r) || !std::isfinite(p.g) || !std::isfinite(p.b)) return false;
  return true;
}

/// Means of the channel-averaged pixels over `block` x `block` blocks (a box low-pass), row-major.
inline std::vector<double> block_means(const Image& image, int block) {
  const int bx = image.width / block, by = image.height / block;
  std::vector<double> means(std::size_t(bx) * std::size_t(by), 0.0);
  for (int y = 0; y < by * block; ++y)
    for (int x = 0; x < bx * block; ++x) {
      const glm::vec3 p = image(x, y);
      means[std::size_t(y / block) * std::size_t(bx) + std::size_t(x / block)] += (double(p.r) + double(p.g) + double(p.b)) / 3.0;
    }
  for (double& m : means) m /= double(block) * double(block);
  return means;
}

/// Mean and standard error of the mean of independent estimates.
struct Estimate {
  double mean = 0.0;            ///< Average of the runs.
  double standard_error = 0.0;  ///< Sample standard deviation / sqrt(runs).
};

/// Mean and standard error of `values` (at least two).
inline Estimate estimate(const std::vector<double>& values) {
  Estimate e;
  for (double v : values) e.mean += v;
  e.mean /= double(values.size());
  double squares = 0.0;
  for (double v : values) squares += (v - e.mean) * (v - e.mean);
  e.standard_error = std::sqrt(squares / double(values.size() - 1) / double(values.size()));
  return e;
}

/// Least-squares slope of log(y) against log(x).
inline double log_log_slope(const std::vector<double>& x, const std::vector<double>& y) {
  double mx = 0.0, my = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    mx += std::log(x[i]);
    my += std::log(y[i]);
  }
  mx /= double(x.size());
  my /= double(x.size());
  double sxy = 0.0, sxx = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    sxy += (std::log(x[i]) - mx) * (std::log(y[i]) - my);
    sxx += (std::log(x[i]) - mx) * (std::log(x[i]) - mx);
  }
  return sxy / sxx;
}

}  // namespace igi::testing
