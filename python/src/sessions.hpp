#pragma once
// The two RenderSession implementations as templates over the backend type: each backend's
// translation unit instantiates them for its type only (renderers.hpp says why).

#include <chrono>
#include <memory>
#include <optional>
#include <vector>

#include <oneapi/tbb/info.h>

#include "common/importance_sampler.hpp"
#include "igi/render/filter_choice.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/renderer.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"
#include "renderers.hpp"

namespace igi::python {

/// The worker threads the options ask for, as igi-render reports them (0: all cores).
inline int reported_threads(const programs::IgiRenderOptions& options) {
  return options.settings.threads > 0 ? options.settings.threads : tbb::info::default_concurrency();
}

/// Copies the G-buffer images (albedo, normal, depth) of `layers` into `frame`.
inline void copy_layers(std::span<const PixelLayers> layers, RenderedFrame& frame) {
  frame.albedo.reserve(layers.size());
  frame.normal.reserve(layers.size());
  frame.depth.reserve(layers.size());
  for (const PixelLayers& pixel : layers) {
    frame.albedo.push_back(pixel.albedo);
    frame.normal.push_back(pixel.normal);
    frame.depth.push_back(pixel.depth);
  }
}

/// igi-render's IGI pipeline over backend B: the same policies, settings and statistics.
template <class B>
class IgiSession final : public RenderSession {
 public:
  /// Builds the renderer (and its backend) for `scene`.
  IgiSession(Scene& scene, const programs::IgiRenderOptions& options)
      : options_(options),
        scene_(&scene),
        surface_(scene),
        sampler_(options.vpl_sampler),
        filter_(options.filter),
        renderer_(scene, options.settings, surface_, brdf_, sampler_, filter_) {
    renderer_.set_profiling(options.profile);
    renderer_.set_keep_layers(true);  // the G-buffer images of every frame
  }

  RenderedFrame render(const Camera& camera, std::uint32_t index) override {
    Frame frame = renderer_.render(camera, index);
    RenderedFrame out{.width = frame.width, .height = frame.height, .hdr = std::move(frame.hdr), .rgb8 = std::move(frame.rgb8)};
    copy_layers(renderer_.layers(), out);
    out.statistics = programs::run_statistics(*scene_, options_, B::name(), B::width, options_.animate)
                         .update(programs::frame_time_statistics(options_, frame.statistics.milliseconds,
                                                                 frame.statistics.rays, reported_threads(options_)))
                         .update(programs::igi_frame_statistics(options_, filter_.chosen(), sampler_.chosen(),
                                                                 std::span<const FrameStatistics>(&frame.statistics, 1)))
                         .dump();
    return out;
  }

  void apply(const SceneChanges& changes) override { static_cast<void>(renderer_.apply(changes)); }

 private:
  programs::IgiRenderOptions options_;
  const Scene* scene_;
  GltfMaterialShader surface_;
  StandardBrdf brdf_;
  programs::ProgramVplSampler sampler_;
  FilterChoice filter_;
  Renderer<B, GltfMaterialShader, StandardBrdf, programs::ProgramVplSampler, FilterChoice> renderer_;
};

/// igi-render's reference path tracer over backend B: --frames passes of --spp samples per pixel,
/// accumulated into one image, tone mapped with its own statistics. Scene changes rebuild the
/// backend before the next image.
template <class B>
class PathSession final : public RenderSession {
 public:
  /// Builds the backend for `scene`.
  PathSession(Scene& scene, const programs::IgiRenderOptions& options)
      : options_(options), scene_(&scene), surface_(scene) {
    settings_.seed = options.settings.seed;
    settings_.threads = options.settings.threads;
    build();
  }

  RenderedFrame render(const Camera& camera, std::uint32_t /*index: the image is the passes' own*/) override {
    if (!tracer_) build();
    tracer_->reset(camera, options_.settings.width, options_.settings.height);
    std::vector<double> milliseconds;
    for (int pass = 0; pass < options_.frames; ++pass) {
      const auto start = std::chrono::steady_clock::now();
      tracer_->add_samples(options_.spp);
      milliseconds.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
    }
    RenderedFrame out{.width = options_.settings.width, .height = options_.settings.height, .hdr = tracer_->image()};
    out.rgb8 = programs::tone_map_converged(out.hdr);
    copy_layers(tracer_->first_hits(), out);
    RayCounts per_pass = tracer_->statistics().rays;
    const auto passes = std::uint64_t(options_.frames);
    per_pass = {per_pass.primary / passes, per_pass.shadow / passes, per_pass.secondary / passes};
    out.statistics = programs::run_statistics(*scene_, options_, B::name(), B::width, options_.animate)
                         .update(programs::frame_time_statistics(options_, programs::median(milliseconds), per_pass,
                                                                 reported_threads(options_)))
                         .set("spp", options_.spp)
                         .set("spp_total", tracer_->samples())
                         .dump();
    return out;
  }

  void apply(const SceneChanges& changes) override {
    changes.apply_to(*scene_);
    tracer_.reset();  // the tracer borrows the backend: it goes first
    backend_.reset();
  }

 private:
  /// Builds the backend and the tracer for the scene as it is now.
  void build() {
    backend_.emplace(*scene_);
    tracer_.emplace(*scene_, *backend_, surface_, brdf_, settings_);
  }

  programs::IgiRenderOptions options_;
  Scene* scene_;
  GltfMaterialShader surface_;
  StandardBrdf brdf_;
  PathTracerSettings settings_;
  std::optional<B> backend_;
  std::optional<PathTracer<B, GltfMaterialShader, StandardBrdf>> tracer_;
};

/// The session of the integrator `options` name over backend B.
template <class B>
std::unique_ptr<RenderSession> make_session(Scene& scene, const programs::IgiRenderOptions& options) {
  if (options.integrator == "path") return std::make_unique<PathSession<B>>(scene, options);
  return std::make_unique<IgiSession<B>>(scene, options);
}

}  // namespace igi::python
