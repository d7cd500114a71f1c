#pragma once
// What the Python module's Renderer runs: igi-render's two integrators (the IGI pipeline and the
// reference path tracer) over one backend type, behind one interface, so that each backend type is
// compiled in a translation unit of its own (renderers_embree.cpp, renderers_reference.cpp) and
// the two compile side by side. The frames, settings and statistics are igi-render's, made by
// the same code (examples/common/).

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "common/igi_render_options.hpp"
#include "igi/scene/scene.hpp"
#include "igi/scene/scene_changes.hpp"

namespace igi::python {

/// One rendered frame as the module hands it to Python: igi-render's images, the G-buffer and
/// the statistics igi-render --stats json prints.
struct RenderedFrame {
  int width = 0;                 ///< Pixels per row.
  int height = 0;                ///< Rows.
  Image hdr{};                     ///< Linear radiance, rows from the top.
  Rgb8Image rgb8{};                ///< Tone-mapped sRGB.
  std::vector<glm::vec3> albedo{}; ///< Diffuse albedo of the first hit, row-major (empty where not rendered).
  std::vector<glm::vec3> normal{}; ///< Unit shading normal of the first hit, zero on a miss.
  std::vector<float> depth{};      ///< Distance along the primary ray to the first hit, 0 on a miss.
  std::string statistics{};        ///< igi-render's --stats json object, as JSON text.
};

/// A scene being rendered with igi-render's options by one integrator over one backend type. The
/// scene is borrowed and must outlive the session; change it only through the session.
class RenderSession {
 public:
  virtual ~RenderSession() = default;
  /// Renders frame `index` as seen by `camera`.
  virtual RenderedFrame render(const Camera& camera, std::uint32_t index) = 0;
  /// Applies `changes` (instances moved, meshes deformed, lights replaced; their camera is not
  /// used) before the next frame; throws SceneError for an index the scene does not have.
  virtual void apply(const SceneChanges& changes) = 0;
};

/// A session over the Embree backend at igi-render's default packet width, with the integrator
/// `options` name; throws what the renderer's constructor throws for unusable settings.
std::unique_ptr<RenderSession> make_embree_session(Scene& scene, const programs::IgiRenderOptions& options);
/// The same over the reference backend (the cross-check) at the same packet width.
std::unique_ptr<RenderSession> make_reference_session(Scene& scene, const programs::IgiRenderOptions& options);

}  // namespace igi::python
