#pragma once
/// \file
/// The image layer: images, PNG / EXR / PFM files and error metrics.

#include "igi/io/image.hpp"
#include "igi/io/metrics.hpp"
