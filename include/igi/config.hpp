#pragma once
/// \file
/// How igi compiles its few large non-template functions (the glTF loader, the built-in Cornell
/// box, the image codecs). By default igi is header-only: they are `inline`, and every translation
/// unit that calls one compiles it (the loader alone is some 20 CPU-seconds at -O3). A program of
/// many translation units can compile them once instead: define IGI_SEPARATE_COMPILATION in all of
/// its translation units and include igi/separate_compilation.hpp in exactly one .cpp; only that
/// one then includes tinygltf, stb and tinyexr. igi's own tests, benchmarks and examples
/// build this way (the CMake target igi_separate); the install tests build a consumer
/// header-only. The SIMD and template code stays in the headers either way.

#if defined(IGI_SEPARATE_COMPILATION)
/// Marks igi's out-of-line functions: empty here, so they have external linkage and
/// igi/separate_compilation.hpp defines them in one translation unit.
#define IGI_INLINE
#else
/// Marks igi's out-of-line functions: `inline` when header-only, so every translation unit that
/// calls one may compile its own copy without breaking the one-definition rule.
#define IGI_INLINE inline
#endif
