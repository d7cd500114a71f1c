// The module's sessions over the reference backend at igi-render's default packet width.
#include "igi/backends/reference/reference_backend.hpp"
#include "sessions.hpp"

namespace igi::python {

std::unique_ptr<RenderSession> make_reference_session(Scene& scene, const programs::IgiRenderOptions& options) {
  return make_session<ReferenceBackend<native_packet_width>>(scene, options);
}

}  // namespace igi::python
