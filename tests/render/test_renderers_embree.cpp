// The tests' pipelines over Embree at packet widths 8 and 16 (test_renderers.hpp).
#include "render/test_renderers.hpp"

IGI_TEST_RENDERER(, igi::DiscontinuityFilter, igi::EmbreeBackend<8>)
IGI_TEST_RENDERER(, igi::DiscontinuityFilter, igi::EmbreeBackend<16>)
IGI_TEST_RENDERER(, igi::NoFilter, igi::EmbreeBackend<8>)
