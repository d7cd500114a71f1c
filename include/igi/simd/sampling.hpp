#pragma once
/// \file
/// Quasi-Monte Carlo and pseudo-random sampling: radical inverses and a seeded (scrambled) Halton
/// sequence over the first 32 prime bases, an integer hash, and hash-based random number
/// generators for one lane (`Rng`) and for W lanes (`LaneRng<W>`) that produce the same sequence.
///
/// Everything here is a pure function of its arguments and seeds: no global state, no clock.

#include <array>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "igi/simd/lanes.hpp"

namespace igi {

/// The first 32 primes: the bases of the 32 Halton dimensions.
inline constexpr std::array<std::uint32_t, 32> primes = {2,  3,  5,  7,  11, 13, 17, 19, 23, 29, 31,
                                                         37, 41, 43, 47, 53, 59, 61, 67, 71, 73, 79,
                                                         83, 89, 97, 101, 103, 107, 109, 113, 127, 131};

/// The largest float below 1: sampling results are clamped to it so that they stay in [0, 1).
inline constexpr float one_minus_epsilon = 0x1.fffffep-1f;

namespace detail {
/// Throws the error for a prime index / dimension outside [0, 32).
[[noreturn]] inline void throw_bad_prime_index(int prime_index, const char* caller) {
  throw std::invalid_argument(std::string(caller) + ": prime index / dimension " + std::to_string(prime_index) +
                              " is outside [0, " + std::to_string(primes.size()) + ")");
}
/// Division of 32-bit words by a fixed divisor d >= 2 without a division instruction (20-90
/// cycles each on x86-64): Lemire, Kaser and Kurz's direct computation ("Faster remainder by
/// direct computation", 2019) from the 64-bit constant ceil(2^64 / d), exact for every 32-bit
/// dividend and every divisor d >= 2 (tests/simd/sampling_test.cpp checks it against / and %).
struct WordDivisor {
  std::uint32_t divisor;  ///< d.
  std::uint64_t inverse;  ///< ceil(2^64 / d).
  /// The divisor `d` (>= 2).
  explicit constexpr WordDivisor(std::uint32_t d) noexcept : divisor(d), inverse(~std::uint64_t{0} / d + 1) {}
  /// n / d, rounded down.
  constexpr std::uint32_t quotient(std::uint32_t n) const noexcept {
    __extension__ using wide = unsigned __int128;
    return static_cast<std::uint32_t>((static_cast<wide>(inverse) * n) >> 64);
  }
  /// n mod d.
  constexpr std::uint32_t remainder(std::uint32_t n) const noexcept {
    __extension__ using wide = unsigned __int128;
    const std::uint64_t fraction = inverse * n;  // wraps: the fractional part of n / d, times 2^64
    return static_cast<std::uint32_t>((static_cast<wide>(fraction) * divisor) >> 64);
  }
};
/// A WordDivisor per prime base.
inline constexpr std::array<WordDivisor, primes.size()> prime_divisors =
    []<std::size_t... Index>(std::index_sequence<Index...>) {
      return std::array<WordDivisor, sizeof...(Index)>{WordDivisor(primes[Index])...};
    }(std::make_index_sequence<primes.size()>());
/// The prime `primes[prime_index]`, or an exception naming `caller` when the index is invalid.
inline std::uint32_t prime_base(int prime_index, const char* caller) {
  if (prime_index < 0 || prime_index >= static_cast<int>(primes.size())) throw_bad_prime_index(prime_index, caller);
  return primes[static_cast<std::size_t>(prime_index)];
}
}  // namespace detail

/// Radical inverse of `index` in base `primes[prime_index]`, prime_index in [0, 32), result in [0, 1).
// The base-b digits of `index` mirrored about the radix point (van der Corput).
inline float radical_inverse(int prime_index, std::uint64_t index) {
  const std::uint64_t base = detail::prime_base(prime_index, "radical_inverse");
  // Accumulated in double: 64 base-2 digits need more than float's 24 bits before the final
  // rounding, and the sum of digit * base^-k is exact in double for every index below 2^53.
  const double inverse_base = 1.0 / static_cast<double>(base);
  double weight = inverse_base;
  double value = 0.0;
  while (index > 0) {
    value += static_cast<double>(index % base) * weight;
    index /= base;
    weight *= inverse_base;
  }
  const float rounded = static_cast<float>(value);
  return rounded < one_minus_epsilon ? rounded : one_minus_epsilon;
}

/// Integer mixer: a bijection on 32-bit words whose output bits each depend on every input bit.
inline constexpr std::uint32_t hash(std::uint32_t x) noexcept {
  // xorshift-multiply rounds; the two odd multipliers are the low-bias pair found by Chris
  // Wellons' hash-prospector search ("lowbias32", bias ~0.17 against an ideal avalanche of 0).
  x ^= x >> 16;
  x *= 0x7feb352dU;
  x ^= x >> 15;
  x *= 0x846ca68bU;
  x ^= x >> 16;
  return x;
}

/// Order-dependent combination of two words into one hash (hash(a, b) != hash(b, a) in general).
inline constexpr std::uint32_t hash(std::uint32_t a, std::uint32_t b) noexcept {
  // hash(a) is a bijection of a, and xor with b is a bijection of b, so for a fixed a the result
  // is a bijection of b and vice versa.
  return hash(hash(a) ^ b);
}

/// Maps a 32-bit word to [0, 1) using its 24 high bits (every result is exact in float).
inline constexpr float to_unit_float(std::uint32_t bits) noexcept {
  // 2^-24: the 24 high bits form an integer in [0, 2^24), exactly representable as a float.
  return static_cast<float>(bits >> 8) * 0x1p-24f;
}

/// `hash` on every lane of a packet (the same bijection as the scalar `hash`).
template <int W>
inline vuint<W> hash(vuint<W> x) noexcept {
  // Same rounds and multipliers as the scalar hash above.
  x = x ^ (x >> 16);
  x *= vuint<W>(0x7feb352dU);
  x = x ^ (x >> 15);
  x *= vuint<W>(0x846ca68bU);
  x = x ^ (x >> 16);
  return x;
}

/// `to_unit_float` on every lane of a packet.
template <int W>
inline vfloat<W> to_unit_float(const vuint<W>& bits) noexcept {
  // 2^-24 as in the scalar version; values below 2^24 convert to float exactly.
  return convert<float>(bits >> 8) * vfloat<W>(0x1p-24f);
}

namespace detail {
/// Weyl-sequence step of the hash RNGs.
// The golden-ratio constant 2^32 / phi, rounded to odd so the counter visits all 2^32 states.
inline constexpr std::uint32_t rng_increment = 0x9e3779b9U;
}  // namespace detail

/// Scalar counter-based RNG (period 2^32 per seed; also a C++ UniformRandomBitGenerator).
// Output k (k = 1, 2, ...) is hash(k * step ^ key) with key = hash(seed) and the Weyl step of
// rng_increment. Seeds differ in the key, not in a starting point on one shared cycle, so the
// streams of two seeds are not shifted copies of each other (they never share a run of outputs
// beyond chance coincidences of single values).
class Rng {
 public:
  /// Generated word type.
  using result_type = std::uint32_t;

  /// A generator whose sequence is a pure function of `seed`.
  explicit constexpr Rng(std::uint32_t seed = 0) noexcept : key_(hash(seed)) {}

  /// Next 32 uniformly distributed bits.
  constexpr std::uint32_t next_uint() noexcept {
    counter_ += detail::rng_increment;
    return hash(counter_ ^ key_);
  }
  /// Next uniform float in [0, 1).
  constexpr float next() noexcept { return to_unit_float(next_uint()); }
  /// Same as `next_uint()` (UniformRandomBitGenerator).
  constexpr result_type operator()() noexcept { return next_uint(); }
  /// Smallest value of `next_uint()`.
  static constexpr result_type min() noexcept { return 0; }
  /// Largest value of `next_uint()`.
  static constexpr result_type max() noexcept { return std::numeric_limits<result_type>::max(); }

 private:
  std::uint32_t counter_ = 0;
  std::uint32_t key_;
};

/// W independent `Rng`s, one per lane: lane i produces exactly the sequence of `Rng(seed[i])`.
template <int W>
class LaneRng {
 public:
  /// Lane i is seeded with `seed[i]`.
  explicit LaneRng(const vuint<W>& seed) noexcept : key_(hash(seed)) {}

  /// Next 32 uniformly distributed bits on every lane.
  vuint<W> next_uint() noexcept {
    counter_ += detail::rng_increment;  // the same counter on every lane: a scalar
    return hash(vuint<W>(counter_) ^ key_);
  }
  /// Next uniform float in [0, 1) on every lane.
  vfloat<W> next() noexcept { return to_unit_float(next_uint()); }

 private:
  std::uint32_t counter_ = 0;
  vuint<W> key_;
};

namespace detail {
/// Maps 32 random bits to [0, n) by the high word of a 32 x 32-bit product (Lemire's range
/// reduction: no division; bias at most n / 2^32, as for `bits % n`).
inline constexpr std::uint32_t fast_range(std::uint32_t bits, std::uint32_t n) noexcept {
  return static_cast<std::uint32_t>((std::uint64_t{bits} * n) >> 32);
}
}  // namespace detail

/// Halton sequence over the 32 prime bases, randomized by nested (Owen-style) digit scrambling.
//
// Every seed, 0 included, gives a scrambled sequence; the plain sequence is `radical_inverse`.
// Digit k of the radical inverse (weight b^-(k+1)) is permuted by d -> (a d + c) mod b, with
// 1 <= a < b and 0 <= c < b drawn from a hash of (seed, dimension, digits 0..k-1 of the index).
// Because b is prime this is a permutation, and because c is uniform each scrambled digit is
// uniform given the previous ones: every sample is uniformly distributed in [0, 1), so estimates
// stay unbiased, while the permutations, being nested, keep the stratification of the plain
// sequence (the first b^k points still fill the b^k intervals of width b^-k once each). Digits
// past the last non-zero digit of the index are scrambled too, down to a weight of 2^-24 (float
// resolution: stratification holds for every prefix of up to 2^24 points); everything below is
// one uniform random number from the same hash chain.
class Halton {
 public:
  /// The scrambled sequence selected by `seed`.
  explicit constexpr Halton(std::uint32_t seed = 0) noexcept : seed_(seed) {}

  /// The seed this sequence was built from.
  constexpr std::uint32_t seed() const noexcept { return seed_; }

  /// Sample `index` of dimension `dimension` (in [0, 32)); strictly in [0, 1).
  float sample(int dimension, std::uint64_t index) const {
    const std::uint32_t base = detail::prime_base(dimension, "Halton::sample");
    const detail::WordDivisor& divide = detail::prime_divisors[static_cast<std::size_t>(dimension)];
    const double inverse_base = 1.0 / static_cast<double>(base);
    // 2^-24: float's resolution just below 1; digits of smaller weight are drawn in one go.
    constexpr double smallest_digit_weight = 0x1p-24;
    // The chain of keys: key_0 from (seed, dimension), key_{k+1} from key_k and digit k, so the
    // permutation of digit k depends on all less significant index digits (the nesting).
    std::uint32_t key = hash(seed_, static_cast<std::uint32_t>(dimension));
    double weight = inverse_base;
    double value = 0.0;
    while (index > 0 || weight >= smallest_digit_weight) {
      std::uint32_t digit;
      if (index <= 0xffffffffU) {  // 32-bit words divide by multiplication (WordDivisor)
        const auto narrow = static_cast<std::uint32_t>(index);
        digit = divide.remainder(narrow);
        index = divide.quotient(narrow);
      } else {
        digit = static_cast<std::uint32_t>(index % base);
        index /= base;
      }
      const std::uint32_t bits = hash(key);
      const std::uint32_t offset = detail::fast_range(bits, base);  // c: uniform, makes the digit uniform
      // a from the other half-word order of the same bits (only its spread matters, not its law).
      const std::uint32_t factor = 1 + detail::fast_range((bits << 16) | (bits >> 16), base - 1);
      // factor * digit + offset < base^2 + base fits a word for every base (131^2 + 131).
      value += static_cast<double>(divide.remainder(factor * digit + offset)) * weight;
      weight *= inverse_base;
      // Distinct digits give distinct next keys (digit * odd constant is injective mod 2^32).
      key = bits ^ ((digit + 1) * detail::rng_increment);
    }
    // The remaining digits, of total weight below base * weight: one uniform number (2^-32 steps).
    value += static_cast<double>(hash(key)) * 0x1p-32 * weight * static_cast<double>(base);
    const float rounded = static_cast<float>(value);
    return rounded < one_minus_epsilon ? rounded : one_minus_epsilon;
  }

 private:
  std::uint32_t seed_;
};

}  // namespace igi
