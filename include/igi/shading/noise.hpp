#pragma once
/// \file
/// 3D gradient (Perlin-style) noise on packets, for procedural surface shaders. The lattice
/// gradients come from an integer hash of the cell corner and a seed instead of a stored
/// permutation table, so the noise vectorises and any seed gives a different, repeatable field.
/// `fbm` and `turbulence` sum octaves of it.

#include <cstdint>

#include <glm/glm.hpp>

#include "igi/simd/simd.hpp"

namespace igi {

namespace noise_detail {

/// Avalanching 32-bit mix (xor-shift / multiply rounds with odd constants): every input bit
/// flips about half of the output bits, which is all the gradient choice needs.
template <int W>
vuint<W> mix_bits(vuint<W> h) noexcept {
  h = h ^ (h >> 16);
  h = h * vuint<W>(0x7feb352du);
  h = h ^ (h >> 15);
  h = h * vuint<W>(0x846ca68bu);
  h = h ^ (h >> 16);
  return h;
}

/// Hash of an integer lattice point and a seed. The three multipliers are large odd constants
/// with unrelated bit patterns, so neighbouring cells hash far apart.
template <int W>
vuint<W> lattice_hash(const vint<W>& x, const vint<W>& y, const vint<W>& z, std::uint32_t seed) noexcept {
  const vuint<W> h = bit_cast<std::uint32_t>(x) * vuint<W>(0x9e3779b1u) ^ bit_cast<std::uint32_t>(y) * vuint<W>(0x85ebca77u) ^
                     bit_cast<std::uint32_t>(z) * vuint<W>(0xc2b2ae3du) ^ vuint<W>(seed * 0x27d4eb2fu);
  return mix_bits(h);
}

/// Gradient of a lattice corner dotted with the offset (dx, dy, dz) from that corner. The
/// gradient's components are three 10-bit fields of the hash mapped to [-1, 1].
template <int W>
vfloat<W> corner_gradient(const vuint<W>& h, const vfloat<W>& dx, const vfloat<W>& dy, const vfloat<W>& dz) noexcept {
  const vuint<W> ten_bits(0x3ffu);
  // 1023 / 2 maps the 10-bit field 0..1023 onto -1..1.
  const vfloat<W> scale(2.0f / 1023.0f), one(1.0f);
  const vfloat<W> gx = convert<float>(bit_cast<std::int32_t>(h & ten_bits)) * scale - one;
  const vfloat<W> gy = convert<float>(bit_cast<std::int32_t>((h >> 10) & ten_bits)) * scale - one;
  const vfloat<W> gz = convert<float>(bit_cast<std::int32_t>((h >> 20) & ten_bits)) * scale - one;
  return gx * dx + gy * dy + gz * dz;
}

/// Perlin's quintic fade 6t^5 - 15t^4 + 10t^3: C2 across cell faces, so bump-mapped normals
/// (derivatives of the noise) stay continuous.
template <int W>
vfloat<W> fade(const vfloat<W>& t) noexcept {
  return t * t * t * (t * (t * vfloat<W>(6.0f) - vfloat<W>(15.0f)) + vfloat<W>(10.0f));
}

}  // namespace noise_detail

/// Gradient noise at W points, roughly in [-1, 1], zero at lattice points, period-free.
template <int W>
vfloat<W> perlin_noise(const vec3<W>& p, std::uint32_t seed = 0) noexcept {
  // Far from the origin floats lose their fraction; 2^22 keeps 1/2 unit of resolution and the
  // int conversion in range. Points beyond are folded back (the pattern repeats there).
  const vfloat<W> limit(4194304.0f);
  const auto fold = [&](const vfloat<W>& x) {
    const vfloat<W> safe = select(isfinite(x), x, vfloat<W>(0.0f));
    return safe - floor(safe / limit) * limit;
  };
  const vfloat<W> x = fold(p.x), y = fold(p.y), z = fold(p.z);
  const vfloat<W> fx = floor(x), fy = floor(y), fz = floor(z);
  const vint<W> ix = convert<std::int32_t>(fx), iy = convert<std::int32_t>(fy), iz = convert<std::int32_t>(fz);
  const vfloat<W> dx = x - fx, dy = y - fy, dz = z - fz;
  const vfloat<W> one(1.0f);
  const vint<W> i1(1);

  vfloat<W> corner[8];
  for (int c = 0; c < 8; ++c) {
    const bool ox = c & 1, oy = c & 2, oz = c & 4;
    const vuint<W> h = noise_detail::lattice_hash(ox ? ix + i1 : ix, oy ? iy + i1 : iy, oz ? iz + i1 : iz, seed);
    corner[c] = noise_detail::corner_gradient(h, ox ? dx - one : dx, oy ? dy - one : dy, oz ? dz - one : dz);
  }
  const vfloat<W> sx = noise_detail::fade(dx), sy = noise_detail::fade(dy), sz = noise_detail::fade(dz);
  const auto lerp = [](const vfloat<W>& a, const vfloat<W>& b, const vfloat<W>& t) { return a + (b - a) * t; };
  const vfloat<W> x00 = lerp(corner[0], corner[1], sx), x10 = lerp(corner[2], corner[3], sx);
  const vfloat<W> x01 = lerp(corner[4], corner[5], sx), x11 = lerp(corner[6], corner[7], sx);
  return lerp(lerp(x00, x10, sy), lerp(x01, x11, sy), sz);
}

/// Fractal sum of `octaves` noise octaves, each at double frequency and half amplitude.
template <int W>
vfloat<W> fbm(const vec3<W>& p, int octaves, std::uint32_t seed = 0) noexcept {
  vfloat<W> sum(0.0f);
  float amplitude = 1.0f, frequency = 1.0f;
  for (int octave = 0; octave < octaves; ++octave) {
    sum += vfloat<W>(amplitude) * perlin_noise(p * vfloat<W>(frequency), seed + std::uint32_t(octave));
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return sum;
}

/// Perlin's turbulence: like `fbm` but summing absolute values (creases for marble veins).
template <int W>
vfloat<W> turbulence(const vec3<W>& p, int octaves, std::uint32_t seed = 0) noexcept {
  vfloat<W> sum(0.0f);
  float amplitude = 1.0f, frequency = 1.0f;
  for (int octave = 0; octave < octaves; ++octave) {
    sum += vfloat<W>(amplitude) * abs(perlin_noise(p * vfloat<W>(frequency), seed + std::uint32_t(octave)));
    amplitude *= 0.5f;
    frequency *= 2.0f;
  }
  return sum;
}

/// Scalar gradient noise (the W = 1 packet), for user code and tests.
inline float perlin_noise(const glm::vec3& p, std::uint32_t seed = 0) noexcept {
  return perlin_noise(vec3<1>(p), seed)[0];
}

}  // namespace igi
