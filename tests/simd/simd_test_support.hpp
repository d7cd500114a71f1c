#pragma once
// Lane-distinct inputs for the SIMD tests and a lane-by-lane comparison against a scalar loop.

#include <array>
#include <cstdint>

#include <catch2/catch.hpp>

#include "igi/simd/lanes.hpp"

namespace igi::testing {

/// W distinct floats, a permutation of an arithmetic progression that crosses zero.
// Every value is a multiple of 1/32 with magnitude below 64, so sums of up to 64 of them and
// products of two of them are exact in float: results can be compared bit for bit with a scalar
// loop however the compiler orders or fuses (FMA) the operations.
template <int W>
std::array<float, W> distinct_floats(int salt) {
  std::array<float, W> values{};
  for (int i = 0; i < W; ++i) {
    // 7 is odd and W a power of two, so j runs through a permutation of 0 .. W-1.
    const int j = (i * 7 + salt * 3) % W;
    values[static_cast<std::size_t>(i)] = static_cast<float>(j - W / 2) * 0.75f + 0.125f * static_cast<float>(salt) + 0.03125f;
  }
  return values;
}

/// W distinct signed integers (both signs), a permutation of a progression.
template <int W>
std::array<std::int32_t, W> distinct_ints(int salt) {
  std::array<std::int32_t, W> values{};
  for (int i = 0; i < W; ++i) {
    const int j = (i * 5 + salt) % W;  // 5 is odd: a permutation of 0 .. W-1
    values[static_cast<std::size_t>(i)] = (j - W / 2) * 3 + salt;
  }
  return values;
}

/// W distinct unsigned integers that use all 32 bits (so products and shifts wrap around).
template <int W>
std::array<std::uint32_t, W> distinct_uints(std::uint32_t salt) {
  std::array<std::uint32_t, W> values{};
  // Multiplication by an odd constant is a bijection mod 2^32: distinct i give distinct values.
  for (int i = 0; i < W; ++i) values[static_cast<std::size_t>(i)] = (static_cast<std::uint32_t>(i) + salt) * 0x9e3779b1U;
  return values;
}

/// A mask with lane-dependent (irregular) pattern: lanes where (i * 3 + salt) % 5 < 2.
template <int W>
std::array<bool, W> pattern_mask(int salt) {
  std::array<bool, W> bits{};
  for (int i = 0; i < W; ++i) bits[static_cast<std::size_t>(i)] = (i * 3 + salt) % 5 < 2;
  return bits;
}

/// The packet holding `values`.
template <class T, std::size_t N>
lanes<T, static_cast<int>(N)> to_lanes(const std::array<T, N>& values) {
  return lanes<T, static_cast<int>(N)>::load(values.data());
}

/// The mask holding `bits`.
template <std::size_t N>
vmask<static_cast<int>(N)> to_mask(const std::array<bool, N>& bits) {
  vmask<static_cast<int>(N)> mask;
  for (int i = 0; i < static_cast<int>(N); ++i) mask.set(i, bits[static_cast<std::size_t>(i)]);
  return mask;
}

/// Checks every lane of `actual` equals `expected` exactly.
template <class T, int W, std::size_t N>
void check_lanes(const lanes<T, W>& actual, const std::array<T, N>& expected) {
  static_assert(N == static_cast<std::size_t>(W), "one expected value per lane");
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i << " of " << W);
    CHECK(actual[i] == expected[static_cast<std::size_t>(i)]);
  }
}

/// Checks every lane of `actual` equals `expected`.
template <int W, std::size_t N>
void check_mask(const vmask<W>& actual, const std::array<bool, N>& expected) {
  static_assert(N == static_cast<std::size_t>(W), "one expected value per lane");
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i << " of " << W);
    CHECK(actual[i] == expected[static_cast<std::size_t>(i)]);
  }
}

/// `op(a[i], b[i])` for every lane, computed one scalar at a time.
template <class R, class T, std::size_t N, class F>
std::array<R, N> scalar_loop(const std::array<T, N>& a, const std::array<T, N>& b, F&& op) {
  std::array<R, N> r{};
  for (std::size_t i = 0; i < N; ++i) r[i] = static_cast<R>(op(a[i], b[i]));
  return r;
}

/// `op(a[i])` for every lane, computed one scalar at a time.
template <class R, class T, std::size_t N, class F>
std::array<R, N> scalar_loop(const std::array<T, N>& a, F&& op) {
  std::array<R, N> r{};
  for (std::size_t i = 0; i < N; ++i) r[i] = static_cast<R>(op(a[i]));
  return r;
}

}  // namespace igi::testing
