#pragma once
/// \file
/// The built-in Cornell box: the scene of ../shared/scenes/cornell/cornell_box.gltf, with no file.
/// Source of the numbers: that glTF and its .bin, which hold the Cornell measured geometry (metres)
/// as packaged in Mitsuba 3's `cbox` scene (mitsuba-renderer/mitsuba-data, scenes/cbox) and the
/// albedos and light radiance of Mitsuba 3's cbox materials. Positions and normals below are the
/// file's float32 values (in igi/scene/impl/cornell_box.hpp), written in the shortest decimal form that
/// reads back to the same float.

#include "igi/config.hpp"
#include "igi/scene/scene.hpp"

namespace igi {

/// The Cornell box scene (36 triangles, 4 materials, emissive ceiling light, the Cornell camera), built in code.
IGI_INLINE Scene cornell_box();

}  // namespace igi

#if !defined(IGI_SEPARATE_COMPILATION)
#include "igi/scene/impl/cornell_box.hpp"
#endif
