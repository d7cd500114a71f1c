#pragma once
// The IGI pipelines the tests render with most, compiled once in test_renderers_*.cpp (the
// library igi_test_renderers, which every test links) instead of in each of the twenty or so test
// files that render: the glTF materials, the standard BRDF, the paper's QMC VPL walks and the
// discontinuity filter over every Embree width, the reference backend and SaarCOR, and unfiltered
// at width 8; and the path tracer over single Embree rays. Each was compiled in up to 18 test
// files (compensation_test.cpp took 115 CPU-seconds, 18 with these declarations). A test that
// renders another combination compiles it itself.

#include "igi/backends/embree/embree_backend.hpp"
#include "igi/backends/reference/reference_backend.hpp"
#include "igi/backends/saarcor/saarcor_backend.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/lighting/qmc_vpl_sampler.hpp"
#include "igi/render/path_tracer.hpp"
#include "igi/render/renderer.hpp"
#include "igi/shading/brdf_shaders.hpp"
#include "igi/shading/gltf_material_shader.hpp"

/// Declares (`keyword` extern) or defines (`keyword` empty) the tests' pipeline over the backend
/// type and with the filter given after it.
#define IGI_TEST_RENDERER(keyword, filter, ...) \
  keyword template class igi::Renderer<__VA_ARGS__, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler, filter>;

IGI_TEST_RENDERER(extern, igi::DiscontinuityFilter, igi::EmbreeBackend<1>)
IGI_TEST_RENDERER(extern, igi::DiscontinuityFilter, igi::EmbreeBackend<4>)
IGI_TEST_RENDERER(extern, igi::DiscontinuityFilter, igi::EmbreeBackend<8>)
IGI_TEST_RENDERER(extern, igi::DiscontinuityFilter, igi::EmbreeBackend<16>)
IGI_TEST_RENDERER(extern, igi::DiscontinuityFilter, igi::ReferenceBackend<8>)
IGI_TEST_RENDERER(extern, igi::DiscontinuityFilter, igi::SaarcorBackend)
IGI_TEST_RENDERER(extern, igi::NoFilter, igi::EmbreeBackend<8>)

extern template class igi::PathTracer<igi::EmbreeBackend<1>, igi::GltfMaterialShader, igi::StandardBrdf>;
