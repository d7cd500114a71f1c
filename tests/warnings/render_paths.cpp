// A program that includes every public header of igi and instantiates its main render paths at
// packet widths 4, 8 and 16 (and SaarCOR's 64), so that compiling it at -O2 inlines igi's SIMD
// code the way a renderer's own build does. The warnings tests compile it with -Wall -Wextra
// -Werror at several instruction sets; it is compiled, never run.
#include "every_public_header.hpp"

// Explicit instantiation definitions compile every member of a class, as a program calling all of
// them would: the glTF path with Embree at packet width IGI_WARNINGS_WIDTH (4, 8 or 16; each with
// its own VPL sampler and filter, so each is compiled once), or SaarCOR's 8 x 8 packets (64). One
// path per compile, so that ctest -j spreads them: each costs 35-90 CPU-seconds at -O2.
#if IGI_WARNINGS_WIDTH == 4
template class igi::Renderer<igi::EmbreeBackend<4>, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                             igi::DiscontinuityFilter>;
#elif IGI_WARNINGS_WIDTH == 8
template class igi::Renderer<igi::EmbreeBackend<8>, igi::GltfMaterialShader, igi::StandardBrdf,
                             igi::ImportanceVplSampler, igi::AtrousFilter>;
// The path tracer that reuses the à-trous filter, with it.
template class igi::DenoisedPathTracer<igi::EmbreeBackend<8>, igi::GltfMaterialShader, igi::StandardBrdf>;
#elif IGI_WARNINGS_WIDTH == 16
template class igi::Renderer<igi::EmbreeBackend<16>, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                             igi::BoxFilter>;
#elif IGI_WARNINGS_WIDTH == 64
template class igi::Renderer<igi::SaarcorBackend, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                             igi::DiscontinuityFilter>;
#else
#error "define IGI_WARNINGS_WIDTH as 4, 8, 16 or 64"
#endif
