// The tests' pipelines over Embree at packet widths 1 and 4 and over SaarCOR, and the path
// tracer (test_renderers.hpp).
#include "render/test_renderers.hpp"

IGI_TEST_RENDERER(, igi::DiscontinuityFilter, igi::EmbreeBackend<1>)
IGI_TEST_RENDERER(, igi::DiscontinuityFilter, igi::EmbreeBackend<4>)
IGI_TEST_RENDERER(, igi::DiscontinuityFilter, igi::SaarcorBackend)
template class igi::PathTracer<igi::EmbreeBackend<1>, igi::GltfMaterialShader, igi::StandardBrdf>;
