// igi/simd/sampling.hpp: radical inverse, scrambled Halton, hash and the scalar / lane RNGs.

#include <algorithm>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/simd/sampling.hpp"

using namespace igi;

namespace {

/// Star discrepancy of 2-D points, exactly: the largest gap between the fraction of points in
/// an anchored box [0, u) x [0, v) (or its closure) and the box's area, over the boxes whose
/// corners lie on point coordinates or 1 (where the supremum is attained).
double star_discrepancy(const std::vector<std::array<double, 2>>& points) {
  std::vector<double> us{1.0}, vs{1.0};
  for (const auto& p : points) {
    us.push_back(p[0]);
    vs.push_back(p[1]);
  }
  const double n = static_cast<double>(points.size());
  double worst = 0.0;
  for (const double u : us)
    for (const double v : vs) {
      int open = 0, closed = 0;
      for (const auto& p : points) {
        open += p[0] < u && p[1] < v;
        closed += p[0] <= u && p[1] <= v;
      }
      worst = std::max({worst, u * v - open / n, closed / n - u * v});
    }
  return worst;
}

/// Pearson correlation of two equally long sequences.
double correlation(const std::vector<double>& a, const std::vector<double>& b) {
  const double n = static_cast<double>(a.size());
  double mean_a = 0, mean_b = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    mean_a += a[i] / n;
    mean_b += b[i] / n;
  }
  double covariance = 0, variance_a = 0, variance_b = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    covariance += (a[i] - mean_a) * (b[i] - mean_b);
    variance_a += (a[i] - mean_a) * (a[i] - mean_a);
    variance_b += (b[i] - mean_b) * (b[i] - mean_b);
  }
  return covariance / std::sqrt(variance_a * variance_b);
}

/// Pearson's chi-square statistic of `samples` in [0, 1) against `bins` equal bins.
double chi_square_uniform(const std::vector<double>& samples, int bins) {
  std::vector<int> counts(static_cast<std::size_t>(bins), 0);
  for (const double x : samples) ++counts[static_cast<std::size_t>(std::min(bins - 1, static_cast<int>(x * bins)))];
  const double expected = static_cast<double>(samples.size()) / bins;
  double chi2 = 0;
  for (const int c : counts) chi2 += (c - expected) * (c - expected) / expected;
  return chi2;
}

// 99.9 % quantile of the chi-square distribution with 15 degrees of freedom (16 bins): a correct
// uniform sampler exceeds it once in a thousand seeds, and these tests use fixed seeds.
constexpr double chi_square_15_dof_999 = 37.70;

}  // namespace

TEST_CASE("sampling: primes are the first 32 primes", "[simd][sampling]") {
  std::vector<std::uint32_t> found;
  for (std::uint32_t candidate = 2; found.size() < 32; ++candidate) {
    bool prime = true;
    for (std::uint32_t d = 2; d * d <= candidate; ++d) prime = prime && candidate % d != 0;
    if (prime) found.push_back(candidate);
  }
  CHECK(std::equal(found.begin(), found.end(), primes.begin(), primes.end()));
}

TEST_CASE("sampling: radical inverse mirrors the digits of the index", "[simd][sampling]") {
  // Base 2: 1 = 1b -> .1b, 6 = 110b -> .011b = 3/8, 11 = 1011b -> .1101b = 13/16.
  CHECK(radical_inverse(0, 0) == 0.0f);
  CHECK(radical_inverse(0, 1) == 0.5f);
  CHECK(radical_inverse(0, 2) == 0.25f);
  CHECK(radical_inverse(0, 3) == 0.75f);
  CHECK(radical_inverse(0, 6) == 0.375f);
  CHECK(radical_inverse(0, 11) == 0.8125f);
  // Base 3: 5 = 12 (base 3) -> .21 = 2/3 + 1/9 = 7/9; base 5: 7 = 12 (base 5) -> .21 = 11/25.
  // The exact value is rounded once to float: within half an ulp (2^-25 below 1).
  CHECK(std::abs(radical_inverse(1, 5) - 7.0 / 9.0) <= 0x1p-25);
  CHECK(std::abs(radical_inverse(2, 7) - 11.0 / 25.0) <= 0x1p-25);
  // Base 131 (the 32nd prime): 131 + 1 = 11 (base 131) -> .11 = 1/131 + 1/131^2, and
  // 131 + 2 = 12 (base 131) -> .21 = 2/131 + 1/131^2.
  CHECK(std::abs(radical_inverse(31, 132) - (1.0 / 131 + 1.0 / (131.0 * 131.0))) <= 0x1p-25);
  CHECK(std::abs(radical_inverse(31, 133) - (2.0 / 131 + 1.0 / (131.0 * 131.0))) <= 0x1p-25);
  // The largest index's radical inverse rounds to 1 in float and is clamped below it.
  CHECK(radical_inverse(0, std::numeric_limits<std::uint64_t>::max()) < 1.0f);
  CHECK(radical_inverse(0, std::numeric_limits<std::uint64_t>::max()) == one_minus_epsilon);
}

TEST_CASE("sampling: bad prime indices and dimensions are rejected with a message", "[simd][sampling]") {
  CHECK_THROWS_WITH(radical_inverse(-1, 3), Catch::Contains("-1") && Catch::Contains("outside [0, 32)"));
  CHECK_THROWS_AS(radical_inverse(32, 3), std::invalid_argument);
  CHECK_THROWS_WITH(Halton(1).sample(32, 0), Catch::Contains("Halton::sample") && Catch::Contains("32"));
  CHECK_THROWS_AS(Halton(1).sample(-3, 0), std::invalid_argument);
}

TEST_CASE("sampling: division by multiplication equals / and % for every prime base", "[simd][sampling]") {
  // Every dividend below 2^20, the largest ones, the multiples of the base and their neighbours
  // near 2^32 (where a wrong rounding of the constant shows first), and a million random words.
  std::mt19937 random(7);
  for (std::size_t i = 0; i < primes.size(); ++i) {
    const detail::WordDivisor& divide = detail::prime_divisors[i];
    const std::uint32_t base = primes[i];
    REQUIRE(divide.divisor == base);
    std::vector<std::uint32_t> dividends;
    for (std::uint32_t n = 0; n < (1u << 20); ++n) dividends.push_back(n);
    for (std::uint32_t k = 0; k < 4096; ++k) {
      const std::uint32_t multiple = (std::numeric_limits<std::uint32_t>::max() / base - k) * base;
      for (const std::uint32_t offset : {0u, 1u, base - 1}) dividends.push_back(multiple + offset);
      dividends.push_back(multiple - 1);
      dividends.push_back(std::numeric_limits<std::uint32_t>::max() - k);
    }
    for (int k = 0; k < 1000000; ++k) dividends.push_back(static_cast<std::uint32_t>(random()));
    std::size_t wrong = 0;
    for (const std::uint32_t n : dividends)
      if (divide.quotient(n) != n / base || divide.remainder(n) != n % base) ++wrong;
    INFO("base " << base);
    CHECK(wrong == 0);
  }
}

TEST_CASE("sampling: scrambled Halton samples are the digit-by-digit definition's, bit for bit", "[simd][sampling]") {
  // The definition in Halton's comment, computed with the processor's division: the sequence
  // every VPL set and path depends on must not move when its arithmetic is made faster.
  const auto defined = [](std::uint32_t seed, int dimension, std::uint64_t index) {
    const std::uint32_t base = primes[static_cast<std::size_t>(dimension)];
    const double inverse_base = 1.0 / static_cast<double>(base);
    std::uint32_t key = hash(seed, static_cast<std::uint32_t>(dimension));
    double weight = inverse_base, value = 0.0;
    while (index > 0 || weight >= 0x1p-24) {
      const auto digit = static_cast<std::uint32_t>(index % base);
      index /= base;
      const std::uint32_t bits = hash(key);
      const std::uint32_t offset = static_cast<std::uint32_t>((std::uint64_t{bits} * base) >> 32);
      const std::uint32_t rotated = (bits << 16) | (bits >> 16);
      const std::uint32_t factor = 1 + static_cast<std::uint32_t>((std::uint64_t{rotated} * (base - 1)) >> 32);
      value += static_cast<double>((factor * digit + offset) % base) * weight;
      weight *= inverse_base;
      key = bits ^ ((digit + 1) * 0x9e3779b9u);
    }
    value += static_cast<double>(hash(key)) * 0x1p-32 * weight * static_cast<double>(base);
    return std::min(static_cast<float>(value), one_minus_epsilon);
  };
  std::mt19937_64 random(11);
  std::size_t wrong = 0, compared = 0;
  for (const std::uint32_t seed : {0u, 1u, 0x6b656570u, 0xffffffffu})
    for (int dimension = 0; dimension < 32; ++dimension) {
      std::vector<std::uint64_t> indices;
      for (std::uint64_t i = 0; i < 2000; ++i) indices.push_back(i);
      for (int k = 0; k < 2000; ++k) indices.push_back(random() >> (k % 64));  // every magnitude, past 2^32 too
      indices.push_back(std::numeric_limits<std::uint64_t>::max());
      const Halton halton(seed);
      for (const std::uint64_t index : indices) {
        ++compared;
        if (halton.sample(dimension, index) != defined(seed, dimension, index)) ++wrong;
      }
    }
  INFO(compared << " samples compared");
  CHECK(wrong == 0);
}

TEST_CASE("sampling: first b^k points of every dimension fill the b^k intervals once each", "[simd][sampling]") {
  // Holds for the plain radical inverse and, because the digit scrambling is nested, for every
  // seed of the scrambled sequence. Interval counts stay <= 512 so the chance that float
  // rounding pushes a scrambled point onto its interval's upper end (n^2 2^-25 per set) is
  // below 1 %; the seeds are fixed, so the result is deterministic either way.
  for (int dimension = 0; dimension < 32; ++dimension) {
    const std::uint64_t base = primes[static_cast<std::size_t>(dimension)];
    for (std::uint64_t n = base; n <= 512; n *= base) {
      for (int variant = -1; variant < 3; ++variant) {  // -1: plain; 0..2: scrambled seeds
        INFO("dimension " << dimension << ", n = " << n << ", variant " << variant);
        const Halton halton(static_cast<std::uint32_t>(variant * 7919 + 11));
        std::vector<int> hits(n, 0);
        for (std::uint64_t i = 0; i < n; ++i) {
          const float x = variant < 0 ? radical_inverse(dimension, i) : halton.sample(dimension, i);
          // Plain points lie on interval starts m/n, which float may round a hair below m/n:
          // round those to the nearest start; scrambled points are interior, floor them.
          const double scaled = static_cast<double>(x) * static_cast<double>(n);
          const auto bin = static_cast<std::size_t>(variant < 0 ? std::round(scaled) : std::floor(scaled));
          REQUIRE(bin < n);
          ++hits[bin];
        }
        CHECK(std::all_of(hits.begin(), hits.end(), [](int h) { return h == 1; }));
      }
    }
  }
}

TEST_CASE("sampling: 2-D Halton points have far lower star discrepancy than random points", "[simd][sampling]") {
  constexpr int n = 256;
  auto halton_points = [&](const Halton* halton) {
    std::vector<std::array<double, 2>> points;
    for (int i = 0; i < n; ++i)
      points.push_back({halton ? halton->sample(0, i) : radical_inverse(0, i), halton ? halton->sample(1, i) : radical_inverse(1, i)});
    return points;
  };
  double best_random = 1.0;
  for (std::uint32_t seed = 1; seed <= 8; ++seed) {
    Rng rng(seed);
    std::vector<std::array<double, 2>> points;
    for (int i = 0; i < n; ++i) points.push_back({rng.next(), rng.next()});
    best_random = std::min(best_random, star_discrepancy(points));
  }
  // Random points: D* ~ 0.6..1.4 / sqrt(n) (Kolmogorov-Smirnov scale), i.e. ~0.04..0.09 here.
  // Halton in bases 2, 3: D* = O(log^2 n / n), a few times 1/n. Require Halton to beat the best
  // of 8 random sets by a factor of 2 (it does by much more) and to stay below 10 / n.
  const double plain = star_discrepancy(halton_points(nullptr));
  INFO("plain Halton D* = " << plain << ", best random D* = " << best_random);
  CHECK(plain < 10.0 / n);
  CHECK(plain < 0.5 * best_random);
  for (std::uint32_t seed : {0U, 1U, 12345U}) {
    const Halton halton(seed);
    const double scrambled = star_discrepancy(halton_points(&halton));
    INFO("seed " << seed << ": scrambled Halton D* = " << scrambled);
    CHECK(scrambled < 10.0 / n);
    CHECK(scrambled < 0.5 * best_random);
  }
}

TEST_CASE("sampling: scrambled Halton samples stay below 1 and depend on the seed", "[simd][sampling]") {
  const Halton a(1), b(2), a_again(1);
  int differing = 0;
  for (int dimension = 0; dimension < 32; ++dimension)
    for (std::uint64_t index : {std::uint64_t{0}, std::uint64_t{1}, std::uint64_t{1000}, std::uint64_t{1} << 40,
                                std::numeric_limits<std::uint64_t>::max()}) {
      const float x = a.sample(dimension, index);
      CHECK(x >= 0.0f);
      CHECK(x < 1.0f);
      CHECK(x == a_again.sample(dimension, index));  // a pure function of (seed, dimension, index)
      differing += x != b.sample(dimension, index);
    }
  CHECK(differing >= 155);  // of 160: a coincidence has probability ~2^-24 per sample
  CHECK(Halton(7).seed() == 7U);
}

TEST_CASE("sampling: each scrambled sample is uniform over the seeds", "[simd][sampling]") {
  // Owen scrambling makes every single point uniform on [0, 1): the fixed index 5 (and index 0,
  // whose digits are all zero) over 4096 seeds, in 16 bins, passes a chi-square test.
  for (std::uint64_t index : {std::uint64_t{0}, std::uint64_t{5}, std::uint64_t{123456}})
    for (int dimension : {0, 1, 7, 31}) {
      std::vector<double> samples;
      for (std::uint32_t seed = 0; seed < 4096; ++seed) samples.push_back(Halton(seed).sample(dimension, index));
      INFO("index " << index << ", dimension " << dimension);
      CHECK(chi_square_uniform(samples, 16) < chi_square_15_dof_999);
    }
}

TEST_CASE("sampling: randomized Halton estimates are unbiased for known integrals", "[simd][sampling]") {
  // Smooth: f(x, y, z) = x^2 y e^z over the unit cube, integral (1/3)(1/2)(e - 1).
  // Discontinuous: the indicator of x + y < 1, integral 1/2.
  const double smooth_exact = (1.0 / 3.0) * 0.5 * (std::exp(1.0) - 1.0);
  constexpr int points = 16;   // few points: each estimate has a visible error
  constexpr int seeds = 512;   // estimates averaged over this many independent randomizations
  std::vector<double> smooth, indicator;
  for (std::uint32_t seed = 0; seed < seeds; ++seed) {
    const Halton halton(seed);
    double s = 0, d = 0;
    for (int i = 0; i < points; ++i) {
      const double x = halton.sample(0, i), y = halton.sample(1, i), z = halton.sample(2, i);
      s += x * x * y * std::exp(z);
      d += x + y < 1.0 ? 1.0 : 0.0;
    }
    smooth.push_back(s / points);
    indicator.push_back(d / points);
  }
  auto check_unbiased = [&](const std::vector<double>& estimates, double exact) {
    double mean = 0, variance = 0;
    for (const double e : estimates) mean += e / seeds;
    for (const double e : estimates) variance += (e - mean) * (e - mean) / (seeds - 1);
    const double standard_error = std::sqrt(variance / seeds);
    INFO("mean " << mean << ", exact " << exact << ", standard error " << standard_error);
    // Unbiased: the mean of independent randomizations is within 4 standard errors of the
    // integral (a 6e-5 two-sided chance for an unbiased estimator, by the central limit theorem).
    CHECK(std::abs(mean - exact) < 4.0 * standard_error);
    // The single estimates really do vary (otherwise the bound above would prove nothing).
    CHECK(standard_error > 0.0);
  };
  check_unbiased(smooth, smooth_exact);
  check_unbiased(indicator, 0.5);

  // The plain sequence with the same 16 points is off by a fixed amount that the randomized
  // mean does not share: its error on the indicator integral is 1/16 or more.
  double plain = 0;
  for (int i = 0; i < points; ++i) plain += radical_inverse(0, i) + radical_inverse(1, i) < 1.0f ? 1.0 : 0.0;
  CHECK(std::abs(plain / points - 0.5) >= 1.0 / 16);
}

TEST_CASE("sampling: different seeds give uncorrelated samples", "[simd][sampling]") {
  // For n independent pairs the sample correlation has standard deviation ~1/sqrt(n);
  // 4 / sqrt(n) = 0.0625 for n = 4096 leaves room for no more than chance.
  constexpr int n = 4096;
  const double bound = 4.0 / std::sqrt(static_cast<double>(n));

  // The randomizations of seeds s and s + 1 are independent: at a fixed dimension and index,
  // the samples of consecutive seeds, over n seeds, are uncorrelated.
  for (int dimension : {0, 1, 5, 31})
    for (std::uint64_t index : {std::uint64_t{0}, std::uint64_t{3}, std::uint64_t{1000}}) {
      std::vector<double> a, b;
      for (std::uint32_t seed = 0; seed < n; ++seed) {
        a.push_back(Halton(seed).sample(dimension, index));
        b.push_back(Halton(seed + 1).sample(dimension, index));
      }
      INFO("dimension " << dimension << ", index " << index);
      CHECK(std::abs(correlation(a, b)) < bound);
    }

  // Two whole sequences paired by index are NOT uncorrelated for one pair of seeds: nested
  // scrambling applies one permutation to the top digit of every point of a seed, so in base 2
  // the top digits of seeds s and s' agree on every index or disagree on every index
  // (correlation near +0.75 or -0.75). That is inherent to any randomization that keeps every
  // prefix of b^k points stratified. What vanishes is the expectation over seed pairs: the mean
  // by-index correlation over 256 pairs is zero within 4 standard errors.
  for (int dimension : {0, 1, 5}) {
    std::vector<double> correlations;
    for (std::uint32_t seed = 0; seed < 256; ++seed) {
      const Halton first(2 * seed), second(2 * seed + 1);
      std::vector<double> a, b;
      for (int i = 0; i < 1024; ++i) {
        a.push_back(first.sample(dimension, i));
        b.push_back(second.sample(dimension, i));
      }
      correlations.push_back(correlation(a, b));
    }
    double mean = 0, variance = 0;
    for (const double r : correlations) mean += r / 256;
    for (const double r : correlations) variance += (r - mean) * (r - mean) / 255;
    INFO("dimension " << dimension << ": mean correlation " << mean << ", spread " << std::sqrt(variance));
    CHECK(std::abs(mean) < 4.0 * std::sqrt(variance / 256));
  }

  // The scalar Rng: streams of consecutive seeds are uncorrelated index by index, and so are
  // consecutive values of one stream (lag-1 autocorrelation).
  for (std::uint32_t seed : {0U, 1U, 2U, 1000U}) {
    Rng rng_a(seed), rng_b(seed + 1);
    std::vector<double> a, b;
    for (int i = 0; i < n; ++i) {
      a.push_back(rng_a.next());
      b.push_back(rng_b.next());
    }
    INFO("Rng seeds " << seed << " and " << seed + 1);
    CHECK(std::abs(correlation(a, b)) < bound);
  }
  Rng rng(99);
  std::vector<double> values;
  for (int i = 0; i <= n; ++i) values.push_back(rng.next());
  const std::vector<double> head(values.begin(), values.end() - 1), tail(values.begin() + 1, values.end());
  CHECK(std::abs(correlation(head, tail)) < bound);
}

TEST_CASE("sampling: hash is a well-mixing bijection", "[simd][sampling]") {
  // No collisions over 2^20 consecutive inputs (a bijection has none anywhere).
  std::vector<std::uint32_t> outputs;
  for (std::uint32_t x = 0; x < (1U << 20); ++x) outputs.push_back(hash(x));
  std::sort(outputs.begin(), outputs.end());
  CHECK(std::adjacent_find(outputs.begin(), outputs.end()) == outputs.end());

  // Avalanche: flipping any input bit flips each output bit about half the time. Over 4096
  // inputs a fair coin's frequency has standard deviation 0.008; [0.4, 0.6] is > 12 of those,
  // so only a systematic bias (a poor mixer) fails.
  Rng rng(5);
  std::array<std::array<int, 32>, 32> flips{};
  constexpr int trials = 4096;
  for (int t = 0; t < trials; ++t) {
    const std::uint32_t x = rng.next_uint(), hx = hash(x);
    for (int in = 0; in < 32; ++in) {
      const std::uint32_t difference = hx ^ hash(x ^ (1U << in));
      for (int out = 0; out < 32; ++out) flips[in][out] += (difference >> out) & 1U;
    }
  }
  double worst = 0;
  for (const auto& row : flips)
    for (const int count : row) worst = std::max(worst, std::abs(count / double(trials) - 0.5));
  INFO("largest avalanche bias " << worst);
  CHECK(worst < 0.1);

  // The combiner depends on both words and on their order.
  CHECK(hash(1, 2) != hash(2, 1));
  CHECK(hash(1, 2) != hash(1, 3));
  CHECK(hash(1, 2) != hash(4, 2));
  // to_unit_float covers [0, 1) and never reaches 1.
  CHECK(to_unit_float(0) == 0.0f);
  CHECK(to_unit_float(0xffffffffU) == 1.0f - 0x1p-24f);
  CHECK(to_unit_float(0x80000000U) == 0.5f);
}

TEST_CASE("sampling: Rng is seeded, deterministic, uniform and a standard bit generator", "[simd][sampling]") {
  STATIC_REQUIRE(std::uniform_random_bit_generator<Rng>);
  Rng a(42), b(42), c(43);
  int same_as_other_seed = 0;
  for (int i = 0; i < 1000; ++i) {
    const std::uint32_t x = a.next_uint();
    CHECK(x == b.next_uint());
    same_as_other_seed += x == c.next_uint();
  }
  CHECK(same_as_other_seed <= 1);  // 1000 draws: a 32-bit coincidence has probability 2^-22

  Rng rng(7);
  std::vector<double> samples;
  double mean = 0;
  for (int i = 0; i < 16384; ++i) {
    const float x = rng.next();
    REQUIRE(x >= 0.0f);
    REQUIRE(x < 1.0f);
    samples.push_back(x);
    mean += x / 16384.0;
  }
  // Mean of 16384 uniforms: standard deviation sqrt(1/12/16384) = 0.00226; 5 of them = 0.0113.
  CHECK(std::abs(mean - 0.5) < 0.0113);
  CHECK(chi_square_uniform(samples, 16) < chi_square_15_dof_999);
  // Usable with <random> distributions.
  std::uniform_int_distribution<int> die(1, 6);
  Rng dice(3);
  for (int i = 0; i < 100; ++i) {
    const int roll = die(dice);
    CHECK((roll >= 1 && roll <= 6));
  }
}

TEST_CASE("sampling: streams of different Rng seeds do not overlap", "[simd][sampling]") {
  // 2048 seeds x 4096 draws. If seeds only picked starting points on one shared 2^32 cycle, two
  // streams would overlap whenever their starts lie within 4096 steps: ~C(2048, 2) * 8192 / 2^32
  // = 4 overlapping pairs expected, each repeating thousands of consecutive output pairs. With
  // independent streams a repeated pair of consecutive 32-bit outputs has probability
  // ~(8.4e6)^2 / 2 / 2^64 = 2e-6.
  constexpr std::uint32_t seeds = 2048, draws = 4096;
  std::vector<std::uint64_t> pairs;
  pairs.reserve(std::size_t{seeds} * draws);
  for (std::uint32_t seed = 0; seed < seeds; ++seed) {
    Rng rng(seed);
    std::uint64_t previous = rng.next_uint();
    for (std::uint32_t i = 1; i < draws; ++i) {
      const std::uint64_t current = rng.next_uint();
      pairs.push_back(previous << 32 | current);
      previous = current;
    }
  }
  std::sort(pairs.begin(), pairs.end());
  CHECK(std::adjacent_find(pairs.begin(), pairs.end()) == pairs.end());
}

TEMPLATE_TEST_CASE_SIG("sampling: LaneRng lane i reproduces the scalar Rng of its seed", "[simd][sampling]", ((int W), W), 1, 4, 8, 16,
                       64) {
  // Lane-distinct seeds, including 0 and the largest seed.
  vuint<W> seeds([](int i) { return static_cast<std::uint32_t>(i) * 2654435761U; });
  seeds.set(W - 1, 0xffffffffU);
  LaneRng<W> lanes(seeds), lanes_bits(seeds);
  std::vector<Rng> scalars, scalars_bits;
  for (int i = 0; i < W; ++i) {
    scalars.emplace_back(seeds[i]);
    scalars_bits.emplace_back(seeds[i]);
  }
  for (int step = 0; step < 100; ++step) {
    const vfloat<W> values = lanes.next();
    const vuint<W> bits = lanes_bits.next_uint();
    for (int i = 0; i < W; ++i) {
      INFO("step " << step << ", lane " << i);
      REQUIRE(values[i] == scalars[static_cast<std::size_t>(i)].next());
      REQUIRE(bits[i] == scalars_bits[static_cast<std::size_t>(i)].next_uint());
      REQUIRE(values[i] >= 0.0f);
      REQUIRE(values[i] < 1.0f);
    }
  }
  // The packet hash equals the scalar hash lane by lane.
  const vuint<W> hashed = hash(seeds);
  for (int i = 0; i < W; ++i) CHECK(hashed[i] == hash(seeds[i]));
}
