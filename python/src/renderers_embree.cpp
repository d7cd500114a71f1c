// The module's sessions over the Embree backend at igi-render's default packet width.
#include "igi/backends/embree/embree_backend.hpp"
#include "sessions.hpp"

namespace igi::python {

std::unique_ptr<RenderSession> make_embree_session(Scene& scene, const programs::IgiRenderOptions& options) {
  return make_session<EmbreeBackend<native_packet_width>>(scene, options);
}

}  // namespace igi::python
