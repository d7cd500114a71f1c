#pragma once
// The type lists the property tests run over: every BRDF shader and every filter igi ships.
// Adding one to igi costs one entry in one list here; every property test then covers it (a
// property that a shader or filter lacks by design is excepted, with the reason, in the test).

#include <tuple>

#include "igi/filters/atrous_filter.hpp"
#include "igi/filters/tile_filters.hpp"
#include "igi/shading/brdf_shaders.hpp"

/// Every BRDF shader of igi/shading/brdf_shaders.hpp, as TEMPLATE_TEST_CASE's type arguments
/// (so that each test's name says which shader it ran).
#define IGI_ALL_BRDF_SHADERS igi::LambertBrdf, igi::PhongBrdf, igi::MirrorBrdf, igi::GlassBrdf, igi::StandardBrdf

/// Every filter of igi/filters/, as TEMPLATE_TEST_CASE's type arguments.
#define IGI_ALL_FILTERS igi::DiscontinuityFilter, igi::AtrousFilter, igi::BoxFilter, igi::NoFilter

namespace igi::testing {

/// IGI_ALL_FILTERS as a type list (for loops over the filters inside one test case).
using AllFilters = std::tuple<IGI_ALL_FILTERS>;

}  // namespace igi::testing
