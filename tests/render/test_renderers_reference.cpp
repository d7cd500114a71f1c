// The tests' pipeline over the reference backend (test_renderers.hpp).
#include "render/test_renderers.hpp"

IGI_TEST_RENDERER(, igi::DiscontinuityFilter, igi::ReferenceBackend<8>)
