#pragma once
/// \file
/// Images in one include: the types (igi/io/image_types.hpp), sRGB conversion and quantization
/// (igi/io/srgb.hpp) and PNG / EXR / PFM files (igi/io/image_files.hpp). Code that only
/// converts or tone maps includes the first two and stays free of the codecs.

#include "igi/io/image_files.hpp"
#include "igi/io/image_types.hpp"
#include "igi/io/srgb.hpp"
