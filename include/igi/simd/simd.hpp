#pragma once
/// \file
/// The SIMD layer: packets, vectors and sampling.

#include "igi/simd/lanes.hpp"
#include "igi/simd/vec3.hpp"
#include "igi/simd/sampling.hpp"
