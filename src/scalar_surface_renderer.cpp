// igi::compiled: the one instantiation of igi::Renderer behind igi::ScalarSurfaceRenderer.
#include "igi/render/scalar_surface_renderer.hpp"

#include <utility>

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/shading/brdf_shaders.hpp"

namespace igi {

/// The policies and the renderer borrowing them, declared in that order so that they outlive it.
struct ScalarSurfaceRenderer::Engine {
  ScalarShaderAdapter<SurfaceFunction> surface;
  StandardBrdf brdf;
  QmcVplSampler sampler;
  DiscontinuityFilter filter;
  Renderer<EmbreeBackend<native_packet_width>, ScalarShaderAdapter<SurfaceFunction>, StandardBrdf, QmcVplSampler,
           DiscontinuityFilter>
      renderer;

  Engine(Scene& scene, const RenderSettings& settings, SurfaceFunction function, QmcVplSampler vpl_sampler)
      : surface(std::move(function)),
        sampler(std::move(vpl_sampler)),
        renderer(scene, settings, surface, brdf, sampler, filter) {}
};

ScalarSurfaceRenderer::ScalarSurfaceRenderer(Scene& scene, const RenderSettings& settings, SurfaceFunction surface,
                                             QmcVplSampler sampler)
    : engine_(std::make_unique<Engine>(scene, settings, std::move(surface), std::move(sampler))) {}

ScalarSurfaceRenderer::~ScalarSurfaceRenderer() = default;

Frame ScalarSurfaceRenderer::render(const Camera& camera, std::uint32_t index) {
  return engine_->renderer.render(camera, index);
}

int ScalarSurfaceRenderer::packet_width() noexcept { return native_packet_width; }

}  // namespace igi
