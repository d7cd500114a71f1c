#pragma once
/// \file
/// A renderer of fixed policies whose code comes compiled in the library igi::compiled, for a
/// program that shades with a scalar function: it includes this header and compiles in a few
/// seconds, where instantiating igi::Renderer with its own types costs some 15 CPU-seconds of
/// optimization in every translation unit that does it. Embree traces the rays at the packet
/// width of the ISA igi::compiled was built for; the surface function runs through
/// ScalarShaderAdapter, StandardBrdf shades, the QmcVplSampler's own light sources and emitters
/// make the VPLs, DiscontinuityFilter filters. A program linking igi::compiled defines
/// IGI_SEPARATE_COMPILATION (the target does so): the library also holds the glTF loader and the
/// image codecs of igi/config.hpp.

#include <cstdint>
#include <functional>
#include <memory>

#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/renderer.hpp"
#include "igi/render/settings.hpp"
#include "igi/scene/scene.hpp"
#include "igi/shading/scalar_shader_adapter.hpp"

namespace igi {

/// Renders whole frames like igi::Renderer with an Embree backend, a scalar surface function,
/// StandardBrdf, a QmcVplSampler and DiscontinuityFilter, compiled once in igi::compiled. The
/// scene is borrowed and must outlive the renderer; the surface function and the sampler are
/// kept.
class ScalarSurfaceRenderer {
 public:
  /// The surface shader: hit point to BRDF parameters, called once per shaded lane.
  using SurfaceFunction = std::function<ScalarBrdfParameters(const SurfacePoint&)>;

  /// Builds the backend for `scene`; throws as igi::Renderer's constructor does.
  ScalarSurfaceRenderer(Scene& scene, const RenderSettings& settings, SurfaceFunction surface, QmcVplSampler sampler);
  /// Releases the backend.
  ~ScalarSurfaceRenderer();
  /// Not copyable: the backend and the frame history are one renderer's.
  ScalarSurfaceRenderer(const ScalarSurfaceRenderer&) = delete;
  /// Not copyable.
  ScalarSurfaceRenderer& operator=(const ScalarSurfaceRenderer&) = delete;

  /// Renders frame `index` as seen by `camera` (see igi::Renderer::render).
  Frame render(const Camera& camera, std::uint32_t index);
  /// Packet width of the compiled backend: igi::native_packet_width of igi::compiled's ISA.
  static int packet_width() noexcept;

 private:
  struct Engine;
  std::unique_ptr<Engine> engine_;
};

}  // namespace igi
