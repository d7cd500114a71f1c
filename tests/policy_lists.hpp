#pragma once
// The type lists the property tests run over: every BRDF shader and every filter igi ships.
// Adding one to igi costs one line here; every property test then covers it (a property that a
// shader or filter lacks by design is excepted, with the reason, in the test itself).

#include <tuple>

#include "igi/filters/tile_filters.hpp"
#include "igi/shading/brdf_shaders.hpp"

namespace igi::testing {

/// Every BRDF shader of igi/shading/brdf_shaders.hpp.
using AllBrdfShaders = std::tuple<LambertBrdf, PhongBrdf, MirrorBrdf, GlassBrdf, StandardBrdf>;

/// Every filter of igi/filters/.
using AllFilters = std::tuple<DiscontinuityFilter, BoxFilter, NoFilter>;

}  // namespace igi::testing
