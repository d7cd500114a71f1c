#pragma once
/// \file
/// `vec3<W>`: three `vfloat<W>` in structure-of-arrays order, with the vector algebra shading
/// needs. Scalar vectors are GLM's (`glm::vec3`); this is their packet counterpart.

#include <glm/vec3.hpp>

#include "igi/simd/lanes.hpp"

namespace igi {

/// W three-component vectors, one per lane, stored as x, y and z packets.
template <int W>
struct vec3 {
  ///@{
  vfloat<W> x, y, z;  ///< Components.
  ///@}

  /// All lanes (0, 0, 0).
  constexpr vec3() noexcept = default;
  /// From three packets.
  [[gnu::always_inline]] constexpr vec3(const vfloat<W>& x_, const vfloat<W>& y_, const vfloat<W>& z_) noexcept : x(x_), y(y_), z(z_) {}
  /// Every lane `v`.
  [[gnu::always_inline]] vec3(const glm::vec3& v) noexcept : x(v.x), y(v.y), z(v.z) {}  // NOLINT: broadcast

  /// Lane `i` as a GLM vector.
  [[gnu::always_inline]] glm::vec3 operator[](int i) const noexcept { return {x[i], y[i], z[i]}; }
  /// Sets lane `i`.
  [[gnu::always_inline]] void set(int i, const glm::vec3& v) noexcept {
    x.set(i, v.x);
    y.set(i, v.y);
    z.set(i, v.z);
  }
  /// Sets the lanes of `mask` to `value`.
  [[gnu::always_inline]] void assign(const vec3& value, const vmask<W>& mask) noexcept {
    x.assign(value.x, mask);
    y.assign(value.y, mask);
    z.assign(value.z, mask);
  }

  [[gnu::always_inline]] friend vec3 operator+(const vec3& a, const vec3& b) noexcept { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  [[gnu::always_inline]] friend vec3 operator-(const vec3& a, const vec3& b) noexcept { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  [[gnu::always_inline]] friend vec3 operator*(const vec3& a, const vec3& b) noexcept { return {a.x * b.x, a.y * b.y, a.z * b.z}; }
  [[gnu::always_inline]] friend vec3 operator/(const vec3& a, const vec3& b) noexcept { return {a.x / b.x, a.y / b.y, a.z / b.z}; }
  [[gnu::always_inline]] friend vec3 operator*(const vec3& a, const vfloat<W>& s) noexcept { return {a.x * s, a.y * s, a.z * s}; }
  [[gnu::always_inline]] friend vec3 operator*(const vfloat<W>& s, const vec3& a) noexcept { return a * s; }
  [[gnu::always_inline]] friend vec3 operator/(const vec3& a, const vfloat<W>& s) noexcept { return a * (vfloat<W>(1.0f) / s); }
  [[gnu::always_inline]] friend vec3 operator-(const vec3& a) noexcept { return {-a.x, -a.y, -a.z}; }
  /// Component-wise compound assignment (by a vector, or every component by a scalar packet).
  ///@{
  [[gnu::always_inline]] vec3& operator+=(const vec3& b) noexcept { return *this = *this + b; }
  [[gnu::always_inline]] vec3& operator-=(const vec3& b) noexcept { return *this = *this - b; }
  [[gnu::always_inline]] vec3& operator*=(const vec3& b) noexcept { return *this = *this * b; }
  [[gnu::always_inline]] vec3& operator*=(const vfloat<W>& s) noexcept { return *this = *this * s; }
  ///@}
};

/// Lane-wise dot product.
template <int W>
[[gnu::always_inline]] inline vfloat<W> dot(const vec3<W>& a, const vec3<W>& b) noexcept {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
/// Lane-wise cross product.
template <int W>
[[gnu::always_inline]] inline vec3<W> cross(const vec3<W>& a, const vec3<W>& b) noexcept {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
/// Lane-wise squared length.
template <int W>
[[gnu::always_inline]] inline vfloat<W> length_squared(const vec3<W>& a) noexcept {
  return dot(a, a);
}
/// Lane-wise length.
template <int W>
[[gnu::always_inline]] inline vfloat<W> length(const vec3<W>& a) noexcept {
  return sqrt(dot(a, a));
}
/// Lane-wise unit vector; a zero vector stays zero instead of becoming NaN.
template <int W>
[[gnu::always_inline]] inline vec3<W> normalize(const vec3<W>& a) noexcept {
  const vfloat<W> len2 = dot(a, a);
  const vmask<W> nonzero = len2 > vfloat<W>(0.0f);
  const vfloat<W> inverse = keep(vfloat<W>(1.0f) / sqrt(select(nonzero, len2, vfloat<W>(1.0f))), nonzero);
  return a * inverse;
}
/// Component-wise minimum.
template <int W>
[[gnu::always_inline]] inline vec3<W> min(const vec3<W>& a, const vec3<W>& b) noexcept {
  return {min(a.x, b.x), min(a.y, b.y), min(a.z, b.z)};
}
/// Component-wise maximum.
template <int W>
[[gnu::always_inline]] inline vec3<W> max(const vec3<W>& a, const vec3<W>& b) noexcept {
  return {max(a.x, b.x), max(a.y, b.y), max(a.z, b.z)};
}
/// `a` where `mask` is on, else `b`.
template <int W>
[[gnu::always_inline]] inline vec3<W> select(const vmask<W>& mask, const vec3<W>& a, const vec3<W>& b) noexcept {
  return {select(mask, a.x, b.x), select(mask, a.y, b.y), select(mask, a.z, b.z)};
}
/// `value` on the lanes of `mask`, zero elsewhere.
template <int W>
[[gnu::always_inline]] inline vec3<W> keep(const vec3<W>& value, const vmask<W>& mask) noexcept {
  return {keep(value.x, mask), keep(value.y, mask), keep(value.z, mask)};
}
/// Sum over all lanes.
template <int W>
[[gnu::always_inline]] inline glm::vec3 reduce_add(const vec3<W>& a) noexcept {
  return {reduce_add(a.x), reduce_add(a.y), reduce_add(a.z)};
}
/// Sum over the lanes of `mask`.
template <int W>
[[gnu::always_inline]] inline glm::vec3 reduce_add(const vec3<W>& a, const vmask<W>& mask) noexcept {
  return reduce_add(keep(a, mask));
}
/// `base[index[i]]` on the lanes of `mask`, zero elsewhere.
template <int W>
[[gnu::always_inline]] inline vec3<W> gather(const glm::vec3* base, const vint<W>& index, const vmask<W>& mask) noexcept {
  vec3<W> r;
  for (int i = 0; i < W; ++i)
    if (mask[i]) r.set(i, base[index[i]]);
  return r;
}
/// Lane-wise `value * factor + offset` on GLM constants.
template <int W>
[[gnu::always_inline]] inline vec3<W> fma(const vec3<W>& value, const vfloat<W>& factor, const vec3<W>& offset) noexcept {
  return value * factor + offset;
}

}  // namespace igi
