#pragma once
/// \file
/// Width-generic SIMD packets: `vfloat<W>`, `vint<W>`, `vuint<W>` and `vmask<W>` built on
/// libstdc++'s `std::experimental::simd`. A packet of W lanes is an array of chunks, each one
/// native register of the target (`simd_abi::deduce_t`): 4 floats with SSE, 8 with AVX2, 16 with
/// AVX-512. So W = 16 is two ymm registers under AVX2 and W = 64 (SaarCOR's 8x8 packets) works
/// although libstdc++ caps fixed-size simd at 32 lanes.
///
/// Chunks are native ABIs, not `fixed_size_simd`, because libstdc++ 12 marks every native-ABI
/// operation always-inline but leaves the fixed-size ones as plain `inline`: GCC then kept
/// `_SimdImplFixedSize::_S_multiplies` and friends as out-of-line calls with memory round trips,
/// 20% of a Cornell frame in perf. For the same reason every operation here is
/// `[[gnu::always_inline]]`, and so is every lambda handed to `lanewise` (GNU attribute syntax:
/// `[[gnu::always_inline]]` in that place would apply to the lambda's type, not its call operator).

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>

// GCC 12 reports two kinds of uninitialised reads inside these two headers that cannot happen:
// - x86 intrinsics that take no merge source (_mm512_cvtepi32_pd, _mm512_cvttpd_epi32,
//   _mm512_roundscale_pd, _mm512_inserti64x4, ...) pass the builtin one a variable initialised
//   with itself on purpose (`__m512d __Y = __Y;` in _mm512_undefined_pd() and its kin), which
//   their all-lanes mask never reads; GCC 12 reports it wherever they are inlined (GCC 13 no
//   longer does). libstdc++'s simd calls them under AVX-512 in integer division and remainder and
//   in sin and cos, in conversions igi cannot choose.
// - Writing one lane of a packet (libstdc++'s _SimdWrapper::_M_set, `_M_data[__i] = __x`) is
//   reported as reading the packet uninitialised when a default vec3<4> is filled lane by lane at
//   AVX-512, although lanes' default constructor below has zeroed every chunk.
// Both are located in these headers' lines, which the pragmas cover wherever the headers are
// first included (here, in igi's programs); igi's own lines below, and the code that includes
// this file, keep -Wuninitialized and -Wmaybe-uninitialized.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wuninitialized"
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#if defined(__AVX2__)
#include <immintrin.h>
#endif
#include <experimental/simd>
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

// libstdc++'s <experimental/simd> uses AVX-512 mask registers (the bitmask ABIs) whenever AVX-512
// is on, and clang compiles their masked assignment wrongly: with clang 14 and libstdc++ 12,
// `where(mask, v) = x` leaves v unchanged on every lane, so packets would silently ignore their
// masks. Newer pairs fail to compile instead (vir-simd pins its clang CI below AVX-512 for this).
// Below AVX-512 clang 14 compiles correct code, but erratically: on tests/simd/lanes_test.cpp its
// template instantiation of this header sometimes crashes, sometimes runs for many minutes, and
// sometimes finishes in seconds, with the same flags. igi's builds and sanitizer suite use GCC.
#if defined(__clang__) && defined(__AVX512F__)
#error "igi: libstdc++'s <experimental/simd> miscompiles masked assignment under clang with AVX-512 enabled; build igi with GCC, or with clang for AVX2 (-march=x86-64-v3 or IGI_ISA=avx2)"
#endif
#include <limits>
#include <type_traits>

namespace igi {

namespace stdx = std::experimental;

namespace detail {
/// Lanes of one native register on the target, for floats and 32-bit integers alike: 4 (SSE),
/// 8 (AVX2) or 16 (AVX-512). Plain AVX (Sandy and Ivy Bridge) has 8-float but only 4-int
/// registers; a packet's chunks must pair one float with one int register (masks and bit casts
/// convert between them), so there it is 4, the width both have.
inline constexpr int native_lanes =
    int(std::min(stdx::native_simd<float>::size(), stdx::native_simd<std::int32_t>::size()));
/// Lanes in one chunk of a W-lane packet.
template <int W>
inline constexpr int chunk_lanes = W < native_lanes ? W : native_lanes;
/// Chunks in a W-lane packet.
template <int W>
inline constexpr int chunk_count = W / chunk_lanes<W>;
/// One chunk of a W-lane packet of T: a native register, or part of one for small W.
template <class T, int W>
using chunk = stdx::simd<T, stdx::simd_abi::deduce_t<T, chunk_lanes<W>>>;
/// A float-typed mask chunk as the mask type of T's chunks (int and float masks are distinct types).
template <class T, class Mask>
[[gnu::always_inline]] inline auto mask_as(const Mask& mask) noexcept {
  using target = typename stdx::simd<T, stdx::simd_abi::deduce_t<T, int(Mask::size())>>::mask_type;
  if constexpr (std::is_same_v<target, Mask>)
    return mask;
  else
    return stdx::__proposed::static_simd_cast<target>(mask);
}

}  // namespace detail

/// The packet width W of one native register of floats of the build's ISA: 4 (SSE), 8 (AVX2) or
/// 16 (AVX-512), igi's programs' default.
inline constexpr int native_packet_width = detail::native_lanes;

/// True for the packet widths igi supports (1, 2, 4, 8, 16, 32 and 64 lanes).
template <int W>
concept PacketWidth = W == 1 || W == 2 || W == 4 || W == 8 || W == 16 || W == 32 || W == 64;

/// A W-lane boolean mask; the lane set of every per-lane call.
template <int W>
  requires PacketWidth<W>
class vmask {
 public:
  /// One native mask chunk.
  using chunk_type = typename detail::chunk<float, W>::mask_type;
  /// Lanes per chunk.
  static constexpr int chunk_size = detail::chunk_lanes<W>;
  /// Number of chunks.
  static constexpr int chunks = detail::chunk_count<W>;
  /// Number of lanes.
  static constexpr int width = W;

  /// All lanes off.
  [[gnu::always_inline]] constexpr vmask() noexcept : chunk_{} {
    for (auto& c : chunk_) c = chunk_type(false);
  }
  /// Every lane set to `value`.
  [[gnu::always_inline]] constexpr vmask(bool value) noexcept {  // NOLINT(google-explicit-constructor): broadcast
    for (auto& c : chunk_) c = chunk_type(value);
  }
  /// Lanes `0 .. count-1` on, the rest off: the mask of a partial packet.
  [[gnu::always_inline]] static vmask first(int count) noexcept {
    vmask m;
    for (int c = 0; c < chunks; ++c)
      m.chunk_[c] = detail::chunk<float, W>([](auto i) { return float(i); }) <
                    detail::chunk<float, W>(float(count - c * chunk_size));
    return m;
  }
  /// Lane `i`.
  [[gnu::always_inline]] bool operator[](int i) const noexcept { return chunk_[i / chunk_size][i % chunk_size]; }
  /// Sets lane `i`.
  [[gnu::always_inline]] void set(int i, bool value) noexcept { chunk_[i / chunk_size][i % chunk_size] = value; }
  /// Chunk `c`.
  [[gnu::always_inline]] const chunk_type& chunk(int c) const noexcept { return chunk_[c]; }
  /// Chunk `c`, writable.
  [[gnu::always_inline]] chunk_type& chunk(int c) noexcept { return chunk_[c]; }

  /// Lane-wise and.
  [[gnu::always_inline]] friend vmask operator&(vmask a, const vmask& b) noexcept { return a &= b; }
  /// Lane-wise or.
  [[gnu::always_inline]] friend vmask operator|(vmask a, const vmask& b) noexcept { return a |= b; }
  /// Lane-wise exclusive or.
  [[gnu::always_inline]] friend vmask operator^(vmask a, const vmask& b) noexcept {
    for (int c = 0; c < chunks; ++c) a.chunk_[c] = a.chunk_[c] ^ b.chunk_[c];
    return a;
  }
  /// Lane-wise not.
  [[gnu::always_inline]] friend vmask operator!(vmask a) noexcept {
    for (auto& c : a.chunk_) c = !c;
    return a;
  }
  /// Narrows to the lanes also in `b`.
  [[gnu::always_inline]] vmask& operator&=(const vmask& b) noexcept {
    for (int c = 0; c < chunks; ++c) chunk_[c] = chunk_[c] && b.chunk_[c];
    return *this;
  }
  /// Widens by the lanes of `b`.
  [[gnu::always_inline]] vmask& operator|=(const vmask& b) noexcept {
    for (int c = 0; c < chunks; ++c) chunk_[c] = chunk_[c] || b.chunk_[c];
    return *this;
  }
  /// Lanes equal in both masks.
  [[gnu::always_inline]] friend bool operator==(const vmask& a, const vmask& b) noexcept {
    for (int c = 0; c < chunks; ++c)
      if (!stdx::all_of(a.chunk_[c] == b.chunk_[c])) return false;
    return true;
  }

 private:
  std::array<chunk_type, chunks> chunk_;
};

/// True if any lane of `m` is on.
template <int W>
[[gnu::always_inline]] inline bool any(const vmask<W>& m) noexcept {
  for (int c = 0; c < vmask<W>::chunks; ++c)
    if (stdx::any_of(m.chunk(c))) return true;
  return false;
}
/// True if every lane of `m` is on.
template <int W>
[[gnu::always_inline]] inline bool all(const vmask<W>& m) noexcept {
  for (int c = 0; c < vmask<W>::chunks; ++c)
    if (!stdx::all_of(m.chunk(c))) return false;
  return true;
}
/// True if no lane of `m` is on.
template <int W>
[[gnu::always_inline]] inline bool none(const vmask<W>& m) noexcept {
  return !any(m);
}
/// Number of lanes on.
template <int W>
[[gnu::always_inline]] inline int popcount(const vmask<W>& m) noexcept {
  int n = 0;
  for (int c = 0; c < vmask<W>::chunks; ++c) n += stdx::popcount(m.chunk(c));
  return n;
}

/// W lanes of arithmetic type T (float, int32 or uint32), stored as native chunks.
template <class T, int W>
  requires PacketWidth<W> && std::is_arithmetic_v<T>
class lanes {
 public:
  /// Element type.
  using value_type = T;
  /// One native chunk.
  using chunk_type = detail::chunk<T, W>;
  /// Lanes per chunk.
  static constexpr int chunk_size = detail::chunk_lanes<W>;
  /// Number of chunks.
  static constexpr int chunks = detail::chunk_count<W>;
  /// Number of lanes.
  static constexpr int width = W;

  /// All lanes zero.
  [[gnu::always_inline]] constexpr lanes() noexcept {
    for (auto& c : chunk_) c = chunk_type(T(0));
  }
  /// Every lane `value`.
  [[gnu::always_inline]] constexpr lanes(T value) noexcept {  // NOLINT(google-explicit-constructor): broadcast
    for (auto& c : chunk_) c = chunk_type(value);
  }
  /// Lane `i` is `generator(i)`.
  template <class F>
    requires std::is_invocable_r_v<T, F, int>
  [[gnu::always_inline]] explicit lanes(F&& generator) noexcept {
    for (int c = 0; c < chunks; ++c)
      chunk_[c] = chunk_type([&](auto i) { return static_cast<T>(generator(c * chunk_size + int(i))); });
  }
  /// Loads W consecutive values.
  [[gnu::always_inline]] static lanes load(const T* source) noexcept {
    lanes v;
    for (int c = 0; c < chunks; ++c) v.chunk_[c].copy_from(source + c * chunk_size, stdx::element_aligned);
    return v;
  }
  /// Stores W consecutive values.
  [[gnu::always_inline]] void store(T* target) const noexcept {
    for (int c = 0; c < chunks; ++c) chunk_[c].copy_to(target + c * chunk_size, stdx::element_aligned);
  }
  /// Lane `i`.
  [[gnu::always_inline]] T operator[](int i) const noexcept { return chunk_[i / chunk_size][i % chunk_size]; }
  /// Sets lane `i`.
  [[gnu::always_inline]] void set(int i, T value) noexcept { chunk_[i / chunk_size][i % chunk_size] = value; }
  /// Chunk `c`.
  [[gnu::always_inline]] const chunk_type& chunk(int c) const noexcept { return chunk_[c]; }
  /// Chunk `c`, writable.
  [[gnu::always_inline]] chunk_type& chunk(int c) noexcept { return chunk_[c]; }

  /// Sets the lanes of `mask` to `value`, leaves the others.
  [[gnu::always_inline]] void assign(const lanes& value, const vmask<W>& mask) noexcept {
    for (int c = 0; c < chunks; ++c) stdx::where(detail::mask_as<T>(mask.chunk(c)), chunk_[c]) = value.chunk_[c];
  }

  /// Applies `op` chunk by chunk: the one loop all lane-wise operations go through.
  template <class F>
  [[gnu::always_inline]] friend lanes lanewise(const lanes& a, F&& op) noexcept {
    lanes r;
    for (int c = 0; c < chunks; ++c) r.chunk_[c] = op(a.chunk_[c]);
    return r;
  }
  /// Applies `op` chunk by chunk to two packets.
  template <class F>
  [[gnu::always_inline]] friend lanes lanewise(const lanes& a, const lanes& b, F&& op) noexcept {
    lanes r;
    for (int c = 0; c < chunks; ++c) r.chunk_[c] = op(a.chunk_[c], b.chunk_[c]);
    return r;
  }
  /// Compares chunk by chunk into a mask.
  template <class F>
  [[gnu::always_inline]] friend vmask<W> compare(const lanes& a, const lanes& b, F&& op) noexcept {
    vmask<W> m;
    for (int c = 0; c < chunks; ++c) m.chunk(c) = detail::mask_as<float>(op(a.chunk_[c], b.chunk_[c]));
    return m;
  }

  [[gnu::always_inline]] friend lanes operator+(const lanes& a, const lanes& b) noexcept {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x + y; });
  }
  [[gnu::always_inline]] friend lanes operator-(const lanes& a, const lanes& b) noexcept {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x - y; });
  }
  [[gnu::always_inline]] friend lanes operator*(const lanes& a, const lanes& b) noexcept {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x * y; });
  }
  [[gnu::always_inline]] friend lanes operator/(const lanes& a, const lanes& b) noexcept {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x / y; });
  }
  [[gnu::always_inline]] friend lanes operator-(const lanes& a) noexcept {
    return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return -x; });
  }
  /// Lane-wise compound assignment, the binary operator above applied to every lane.
  ///@{
  [[gnu::always_inline]] lanes& operator+=(const lanes& b) noexcept { return *this = *this + b; }
  [[gnu::always_inline]] lanes& operator-=(const lanes& b) noexcept { return *this = *this - b; }
  [[gnu::always_inline]] lanes& operator*=(const lanes& b) noexcept { return *this = *this * b; }
  [[gnu::always_inline]] lanes& operator/=(const lanes& b) noexcept { return *this = *this / b; }
  ///@}

  [[gnu::always_inline]] friend lanes operator&(const lanes& a, const lanes& b) noexcept requires std::is_integral_v<T> {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x & y; });
  }
  [[gnu::always_inline]] friend lanes operator|(const lanes& a, const lanes& b) noexcept requires std::is_integral_v<T> {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x | y; });
  }
  [[gnu::always_inline]] friend lanes operator^(const lanes& a, const lanes& b) noexcept requires std::is_integral_v<T> {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x ^ y; });
  }
  [[gnu::always_inline]] friend lanes operator<<(const lanes& a, int bits) noexcept requires std::is_integral_v<T> {
    return lanewise(a, [bits](const chunk_type& x) __attribute__((always_inline)) { return x << bits; });
  }
  [[gnu::always_inline]] friend lanes operator>>(const lanes& a, int bits) noexcept requires std::is_integral_v<T> {
    return lanewise(a, [bits](const chunk_type& x) __attribute__((always_inline)) { return x >> bits; });
  }
  [[gnu::always_inline]] friend lanes operator%(const lanes& a, const lanes& b) noexcept requires std::is_integral_v<T> {
    return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x % y; });
  }

  [[gnu::always_inline]] friend vmask<W> operator<(const lanes& a, const lanes& b) noexcept {
    return compare(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x < y; });
  }
  [[gnu::always_inline]] friend vmask<W> operator<=(const lanes& a, const lanes& b) noexcept {
    return compare(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x <= y; });
  }
  [[gnu::always_inline]] friend vmask<W> operator>(const lanes& a, const lanes& b) noexcept {
    return compare(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x > y; });
  }
  [[gnu::always_inline]] friend vmask<W> operator>=(const lanes& a, const lanes& b) noexcept {
    return compare(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x >= y; });
  }
  [[gnu::always_inline]] friend vmask<W> operator==(const lanes& a, const lanes& b) noexcept {
    return compare(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x == y; });
  }
  [[gnu::always_inline]] friend vmask<W> operator!=(const lanes& a, const lanes& b) noexcept {
    return compare(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return x != y; });
  }

 private:
  std::array<chunk_type, chunks> chunk_;
};

/// W floats.
template <int W>
using vfloat = lanes<float, W>;
/// W signed 32-bit integers (indices, ids).
template <int W>
using vint = lanes<std::int32_t, W>;
/// W unsigned 32-bit integers (hashing, bit patterns: wrap-around is defined).
template <int W>
using vuint = lanes<std::uint32_t, W>;

/// `a` where `mask` is on, else `b`.
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> select(const vmask<W>& mask, const lanes<T, W>& a, const lanes<T, W>& b) noexcept {
  lanes<T, W> r = b;
  r.assign(a, mask);
  return r;
}
/// `value` on the lanes of `mask`, zero elsewhere: how inactive lanes yield zeros.
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> keep(const lanes<T, W>& value, const vmask<W>& mask) noexcept {
  return select(mask, value, lanes<T, W>(T(0)));
}
/// Lane-wise minimum.
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> min(const lanes<T, W>& a, const lanes<T, W>& b) noexcept {
  return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return stdx::min(x, y); });
}
/// Lane-wise maximum.
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> max(const lanes<T, W>& a, const lanes<T, W>& b) noexcept {
  return lanewise(a, b, [](const auto& x, const auto& y) __attribute__((always_inline)) { return stdx::max(x, y); });
}
/// `value` limited to `[low, high]`.
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> clamp(const lanes<T, W>& value, const lanes<T, W>& low, const lanes<T, W>& high) noexcept {
  return min(max(value, low), high);
}
/// Lane-wise absolute value.
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> abs(const lanes<T, W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return stdx::abs(x); });
}
namespace detail {
// GCC 12's AVX-512 intrinsics that take no merge source (_mm512_sqrt_ps, _mm512_roundscale_ps,
// _mm512_i32gather_ps, ...) pass an undefined one, which GCC 12 reports wherever they are inlined
// (see the includes at the top of this file). libstdc++'s simd sqrt and floor call two of them.
// Their zero-masking forms with every lane selected compile to the same unmasked instruction but
// pass a zero source, so igi uses those on 16-float registers: nothing to report even in a
// program that included <immintrin.h> before igi, where the pragmas around igi's includes do not
// cover the intrinsics' lines.
#if defined(__AVX512F__)
/// Every lane of a 16-lane register: the mask that makes a zero-masking AVX-512 form unmasked.
inline constexpr __mmask16 every_lane_of_16 = 0xFFFF;
/// True for a chunk that is one 512-bit register.
template <class Chunk>
inline constexpr bool is_512_bit = sizeof(Chunk) == sizeof(__m512);
#endif
/// Square root of one float chunk.
template <class Chunk>
[[gnu::always_inline]] inline Chunk sqrt_chunk(const Chunk& x) noexcept {
#if defined(__AVX512F__)
  if constexpr (is_512_bit<Chunk>)
    return Chunk(_mm512_maskz_sqrt_ps(every_lane_of_16, static_cast<__m512>(x)));
  else
#endif
    return stdx::sqrt(x);
}
/// Floor of one float chunk.
template <class Chunk>
[[gnu::always_inline]] inline Chunk floor_chunk(const Chunk& x) noexcept {
#if defined(__AVX512F__)
  // Round towards -infinity without raising the inexact exception, as libstdc++'s floor does.
  if constexpr (is_512_bit<Chunk>)
    return Chunk(_mm512_maskz_roundscale_ps(every_lane_of_16, static_cast<__m512>(x), _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC));
  else
#endif
    return stdx::floor(x);
}
}  // namespace detail

/// Lane-wise square root.
template <int W>
[[gnu::always_inline]] inline vfloat<W> sqrt(const vfloat<W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return detail::sqrt_chunk(x); });
}
/// Lane-wise floor.
template <int W>
[[gnu::always_inline]] inline vfloat<W> floor(const vfloat<W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return detail::floor_chunk(x); });
}
/// Lane-wise e^x.
template <int W>
[[gnu::always_inline]] inline vfloat<W> exp(const vfloat<W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return stdx::exp(x); });
}
/// Lane-wise natural logarithm.
template <int W>
[[gnu::always_inline]] inline vfloat<W> log(const vfloat<W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return stdx::log(x); });
}
/// Lane-wise sine.
template <int W>
[[gnu::always_inline]] inline vfloat<W> sin(const vfloat<W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return stdx::sin(x); });
}
/// Lane-wise cosine.
template <int W>
[[gnu::always_inline]] inline vfloat<W> cos(const vfloat<W>& a) noexcept {
  return lanewise(a, [](const auto& x) __attribute__((always_inline)) { return stdx::cos(x); });
}
/// Lane-wise base^exponent (base >= 0).
template <int W>
[[gnu::always_inline]] inline vfloat<W> pow(const vfloat<W>& base, const vfloat<W>& exponent) noexcept {
  return lanewise(base, exponent, [](const auto& x, const auto& y) __attribute__((always_inline)) { return stdx::pow(x, y); });
}
/// True where a lane is neither NaN nor infinite.
template <int W>
[[gnu::always_inline]] inline vmask<W> isfinite(const vfloat<W>& a) noexcept {
  vmask<W> m;
  for (int c = 0; c < vfloat<W>::chunks; ++c) m.chunk(c) = stdx::isfinite(a.chunk(c));
  return m;
}

/// Converts lane types with C++ rules (float to int truncates towards zero).
template <class To, class From, int W>
[[gnu::always_inline]] inline lanes<To, W> convert(const lanes<From, W>& a) noexcept {
  lanes<To, W> r;
  for (int c = 0; c < lanes<To, W>::chunks; ++c)
    r.chunk(c) = stdx::static_simd_cast<typename lanes<To, W>::chunk_type>(a.chunk(c));
  return r;
}
/// Reinterprets the bits of each lane (float <-> uint32 for hashing).
template <class To, class From, int W>
  requires(sizeof(To) == sizeof(From))
[[gnu::always_inline]] inline lanes<To, W> bit_cast(const lanes<From, W>& a) noexcept {
  lanes<To, W> r;
  for (int c = 0; c < lanes<To, W>::chunks; ++c)
    r.chunk(c) = stdx::__proposed::simd_bit_cast<typename lanes<To, W>::chunk_type>(a.chunk(c));
  return r;
}

/// Sum of all lanes.
template <class T, int W>
[[gnu::always_inline]] inline T reduce_add(const lanes<T, W>& a) noexcept {
  T sum = 0;
  for (int c = 0; c < lanes<T, W>::chunks; ++c) sum += stdx::reduce(a.chunk(c));
  return sum;
}
/// Sum of the lanes of `mask` (zero when none is on).
template <class T, int W>
[[gnu::always_inline]] inline T reduce_add(const lanes<T, W>& a, const vmask<W>& mask) noexcept {
  return reduce_add(keep(a, mask));
}
/// Smallest lane.
template <class T, int W>
[[gnu::always_inline]] inline T reduce_min(const lanes<T, W>& a) noexcept {
  T m = stdx::hmin(a.chunk(0));
  for (int c = 1; c < lanes<T, W>::chunks; ++c) m = std::min(m, T(stdx::hmin(a.chunk(c))));
  return m;
}
/// Largest lane.
template <class T, int W>
[[gnu::always_inline]] inline T reduce_max(const lanes<T, W>& a) noexcept {
  T m = stdx::hmax(a.chunk(0));
  for (int c = 1; c < lanes<T, W>::chunks; ++c) m = std::max(m, T(stdx::hmax(a.chunk(c))));
  return m;
}

namespace detail {
/// The identity of `min` over T: +infinity for floats, the largest value for integers.
template <class T>
inline constexpr T min_identity =
    std::numeric_limits<T>::has_infinity ? std::numeric_limits<T>::infinity() : std::numeric_limits<T>::max();
/// The identity of `max` over T: -infinity for floats, the lowest value for integers.
template <class T>
inline constexpr T max_identity =
    std::numeric_limits<T>::has_infinity ? -std::numeric_limits<T>::infinity() : std::numeric_limits<T>::lowest();
}  // namespace detail

/// Smallest lane of `mask` (+infinity for float, the largest value for integers, when none is on).
template <class T, int W>
[[gnu::always_inline]] inline T reduce_min(const lanes<T, W>& a, const vmask<W>& mask) noexcept {
  return reduce_min(select(mask, a, lanes<T, W>(detail::min_identity<T>)));
}
/// Largest lane of `mask` (-infinity for float, the lowest value for integers, when none is on).
template <class T, int W>
[[gnu::always_inline]] inline T reduce_max(const lanes<T, W>& a, const vmask<W>& mask) noexcept {
  return reduce_max(select(mask, a, lanes<T, W>(detail::max_identity<T>)));
}

/// `base[index[i]]` on the lanes of `mask`, zero elsewhere (inactive indices are never read).
template <class T, int W>
[[gnu::always_inline]] inline lanes<T, W> gather(const T* base, const vint<W>& index, const vmask<W>& mask) noexcept {
  return lanes<T, W>([&](int i) { return mask[i] ? base[index[i]] : T(0); });
}

/// `base[index[i]]` on every lane, for 32-bit T: every lane's index must address an element
/// (give inactive lanes a valid one). One hardware gather per register with AVX2 or AVX-512
/// (a texture lookup's 16 texel loads per lane took a third of the glTF shader's time as lane
/// by lane loads), lane by lane loads below.
template <class T, int W>
  requires(sizeof(T) == 4)
[[gnu::always_inline]] inline lanes<T, W> gather_every(const T* base, const vint<W>& index) noexcept {
  using chunk_type = typename lanes<T, W>::chunk_type;
  lanes<T, W> result;
  for (int c = 0; c < lanes<T, W>::chunks; ++c) {
#if defined(__AVX512F__)
    if constexpr (lanes<T, W>::chunk_size == 16) {
      // The merging forms from a zero register with every lane gathered: the plain forms pass
      // GCC 12's undefined source (see detail::sqrt_chunk).
      const __m512i at = static_cast<__m512i>(index.chunk(c));
      if constexpr (std::is_same_v<T, float>)
        result.chunk(c) = chunk_type(_mm512_mask_i32gather_ps(_mm512_setzero_ps(), detail::every_lane_of_16, at, base, 4));
      else
        result.chunk(c) = chunk_type(
            __m512i(_mm512_mask_i32gather_epi32(_mm512_setzero_si512(), detail::every_lane_of_16, at, base, 4)));
      continue;
    }
#endif
#if defined(__AVX2__)
    if constexpr (lanes<T, W>::chunk_size == 8) {
      const __m256i at = static_cast<__m256i>(index.chunk(c));
      if constexpr (std::is_same_v<T, float>)
        result.chunk(c) = chunk_type(_mm256_i32gather_ps(base, at, 4));
      else
        result.chunk(c) = chunk_type(_mm256_i32gather_epi32(reinterpret_cast<const int*>(base), at, 4));
      continue;
    }
    if constexpr (lanes<T, W>::chunk_size == 4) {
      const __m128i at = static_cast<__m128i>(index.chunk(c));
      if constexpr (std::is_same_v<T, float>)
        result.chunk(c) = chunk_type(_mm_i32gather_ps(base, at, 4));
      else
        result.chunk(c) = chunk_type(_mm_i32gather_epi32(reinterpret_cast<const int*>(base), at, 4));
      continue;
    }
#endif
    result.chunk(c) = chunk_type([&](auto i) {
      T value;  // copied, not read through T: base may view bytes of another type (RGBA8 texels)
      std::memcpy(&value, base + index.chunk(c)[int(i)], sizeof(T));
      return value;
    });
  }
  return result;
}

/// Lane indices 0, 1, ..., W-1.
template <int W>
[[gnu::always_inline]] inline vint<W> lane_index() noexcept {
  return vint<W>([](int i) { return i; });
}

}  // namespace igi
