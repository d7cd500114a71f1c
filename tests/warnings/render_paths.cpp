// A program that includes every public header of igi and instantiates its main render paths at
// packet widths 4, 8 and 16 (and SaarCOR's 64), so that compiling it at -O2 inlines igi's SIMD
// code the way a renderer's own build does. The warnings tests compile it with -Wall -Wextra
// -Werror at several instruction sets; it is compiled, never run.
#include "every_public_header.hpp"

// Explicit instantiation definitions compile every member of a class, as a program calling all of
// them would: the glTF path with Embree at packet widths 4, 8 and 16 (each with its own VPL sampler
// and filter, so each is compiled once) and SaarCOR's 8 x 8 packets. All in one compile per
// instruction set: they share their headers and much of their code, so together they take about
// four fifths of what four compiles of one path each took (214 against 267 CPU-seconds at -O2,
// -march=haswell, AMD EPYC).
template class igi::Renderer<igi::EmbreeBackend<4>, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                             igi::DiscontinuityFilter>;
template class igi::Renderer<igi::EmbreeBackend<8>, igi::GltfMaterialShader, igi::StandardBrdf,
                             igi::ImportanceVplSampler, igi::AtrousFilter>;
// The path tracer that reuses the à-trous filter, with it.
template class igi::DenoisedPathTracer<igi::EmbreeBackend<8>, igi::GltfMaterialShader, igi::StandardBrdf>;
template class igi::Renderer<igi::EmbreeBackend<16>, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                             igi::BoxFilter>;
template class igi::Renderer<igi::SaarcorBackend, igi::GltfMaterialShader, igi::StandardBrdf, igi::QmcVplSampler,
                             igi::DiscontinuityFilter>;
