#pragma once
/// \file
/// The definitions of igi's IGI_INLINE functions for a program built with IGI_SEPARATE_COMPILATION
/// (see igi/config.hpp): include this header in exactly one .cpp of the program.

#if !defined(IGI_SEPARATE_COMPILATION)
#error "igi/separate_compilation.hpp: define IGI_SEPARATE_COMPILATION in every translation unit (see igi/config.hpp)"
#endif

#include "igi/io/impl/image_codecs.hpp"
#include "igi/scene/impl/cornell_box.hpp"
#include "igi/scene/impl/gltf_loader.hpp"
