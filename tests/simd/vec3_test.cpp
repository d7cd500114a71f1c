// Every operation of igi/simd/vec3.hpp at W = 1, 4, 8, 16 and 64, with lane-distinct inputs,
// against GLM computing the same thing one lane at a time.

#include <climits>
#include <cmath>
#include <vector>

#include <catch2/catch.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "igi/simd/vec3.hpp"
#include "simd_test_support.hpp"

using namespace igi;
using namespace igi::testing;

namespace {

/// W distinct vectors; components are multiples of 1/32 below 64 in magnitude, so sums,
/// products, dot and cross products are exact in float (no dependence on FMA contraction).
template <int W>
std::array<glm::vec3, W> distinct_vectors(int salt) {
  const auto x = distinct_floats<W>(salt), y = distinct_floats<W>(salt + 1), z = distinct_floats<W>(salt + 2);
  std::array<glm::vec3, W> v{};
  for (std::size_t i = 0; i < static_cast<std::size_t>(W); ++i) v[i] = {x[i], y[i], -z[i]};
  return v;
}

/// The packet holding `values`.
template <std::size_t N>
vec3<static_cast<int>(N)> to_vec3(const std::array<glm::vec3, N>& values) {
  vec3<static_cast<int>(N)> packet;
  for (int i = 0; i < static_cast<int>(N); ++i) packet.set(i, values[static_cast<std::size_t>(i)]);
  return packet;
}

/// Checks every lane of `actual` equals `expected` exactly.
template <int W, std::size_t N>
void check_vectors(const vec3<W>& actual, const std::array<glm::vec3, N>& expected) {
  static_assert(N == static_cast<std::size_t>(W), "one expected vector per lane");
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i << " of " << W);
    const glm::vec3 lane = actual[i], want = expected[static_cast<std::size_t>(i)];
    CHECK(lane.x == want.x);
    CHECK(lane.y == want.y);
    CHECK(lane.z == want.z);
  }
}

/// `op(a[i], b[i])` per lane with GLM.
template <std::size_t N, class F>
auto per_lane(const std::array<glm::vec3, N>& a, const std::array<glm::vec3, N>& b, F&& op) {
  std::array<decltype(op(a[0], b[0])), N> r{};
  for (std::size_t i = 0; i < N; ++i) r[i] = op(a[i], b[i]);
  return r;
}

}  // namespace

TEMPLATE_TEST_CASE_SIG("vec3: construction, lane access and arithmetic", "[simd][vec3]", ((int W), W), 1, 4, 8, 16, 64) {
  const vec3<W> zero;
  const vec3<W> broadcast(glm::vec3(1.0f, -2.0f, 3.5f));
  for (int i = 0; i < W; ++i) {
    CHECK(zero[i] == glm::vec3(0.0f));
    CHECK(broadcast[i] == glm::vec3(1.0f, -2.0f, 3.5f));
  }
  const auto a = distinct_vectors<W>(1);
  const auto b = distinct_vectors<W>(4);
  const vec3<W> va = to_vec3(a), vb = to_vec3(b);
  const vec3<W> from_packets(va.x, va.y, va.z);
  check_vectors(from_packets, a);

  check_vectors(va + vb, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x + y; }));
  check_vectors(va - vb, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x - y; }));
  check_vectors(va * vb, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x * y; }));
  check_vectors(va / vb, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x / y; }));
  check_vectors(-va, per_lane(a, b, [](glm::vec3 x, glm::vec3) { return -x; }));

  const vfloat<W> scale = vb.x;
  check_vectors(va * scale, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x * y.x; }));
  check_vectors(scale * va, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return y.x * x; }));
  // Division by a packet multiplies by its reciprocal (one division instead of three).
  check_vectors(va / scale, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x * (1.0f / y.x); }));

  vec3<W> accumulated = va;
  accumulated += vb;
  check_vectors(accumulated, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x + y; }));
  accumulated -= vb;
  check_vectors(accumulated, a);  // exact: (a + b) - b for multiples of 1/32
  accumulated *= vb;
  check_vectors(accumulated, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x * y; }));
  accumulated = va;
  accumulated *= scale;
  check_vectors(accumulated, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x * y.x; }));

  const vec3<W> fused = fma(va, scale, vb);
  check_vectors(fused, per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return x * y.x + y; }));
}

TEMPLATE_TEST_CASE_SIG("vec3: dot, cross, length and normalize", "[simd][vec3]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto a = distinct_vectors<W>(1);
  const auto b = distinct_vectors<W>(3);
  const vec3<W> va = to_vec3(a), vb = to_vec3(b);
  check_vectors(cross(va, vb), per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return glm::cross(x, y); }));
  const vfloat<W> dots = dot(va, vb), squared = length_squared(va), lengths = length(va);
  const vec3<W> unit = normalize(va);
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    const glm::vec3 x = a[static_cast<std::size_t>(i)], y = b[static_cast<std::size_t>(i)];
    CHECK(dots[i] == glm::dot(x, y));  // exact inputs: no rounding anywhere
    CHECK(squared[i] == glm::dot(x, x));
    CHECK(lengths[i] == std::sqrt(glm::dot(x, x)));  // one correctly rounded sqrt on both sides
    // normalize = a * (1 / sqrt(|a|^2)): three roundings (sqrt, reciprocal, product) of at most
    // half an ulp each, so each component is within 2 ulp (2^-22 relative) of GLM's a / |a|.
    const glm::vec3 want = glm::normalize(x), got = unit[i];
    CHECK(std::abs(got.x - want.x) <= 0x1p-22f * std::abs(want.x));
    CHECK(std::abs(got.y - want.y) <= 0x1p-22f * std::abs(want.y));
    CHECK(std::abs(got.z - want.z) <= 0x1p-22f * std::abs(want.z));
    // And |normalize(a)| = 1 within the same three roundings plus those of the length (4 ulp).
    CHECK(std::abs(glm::length(got) - 1.0f) <= 0x1p-21f);
  }
}

TEMPLATE_TEST_CASE_SIG("vec3: normalize keeps zero vectors zero, without NaN", "[simd][vec3]", ((int W), W), 1, 4, 8, 16,
                       64) {
  auto a = distinct_vectors<W>(2);
  for (int i = 0; i < W; i += 2) a[static_cast<std::size_t>(i)] = glm::vec3(0.0f);  // every other lane is zero
  const vec3<W> unit = normalize(to_vec3(a));
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    const glm::vec3 got = unit[i];
    CHECK(std::isfinite(got.x));
    CHECK(std::isfinite(got.y));
    CHECK(std::isfinite(got.z));
    if (i % 2 == 0)
      CHECK(got == glm::vec3(0.0f));
    else
      CHECK(std::abs(glm::length(got) - 1.0f) <= 0x1p-21f);  // 4 ulp, as in the test above
  }
}

TEMPLATE_TEST_CASE_SIG("vec3: min, max, select, keep and masked assignment", "[simd][vec3]", ((int W), W), 1, 4, 8, 16,
                       64) {
  const auto a = distinct_vectors<W>(1);
  const auto b = distinct_vectors<W>(5);
  const auto p = pattern_mask<W>(2);
  const vec3<W> va = to_vec3(a), vb = to_vec3(b);
  const vmask<W> mask = to_mask(p);
  check_vectors(min(va, vb), per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return glm::min(x, y); }));
  check_vectors(max(va, vb), per_lane(a, b, [](glm::vec3 x, glm::vec3 y) { return glm::max(x, y); }));
  std::array<glm::vec3, W> selected{}, kept{};
  for (std::size_t i = 0; i < static_cast<std::size_t>(W); ++i) {
    selected[i] = p[i] ? a[i] : b[i];
    kept[i] = p[i] ? a[i] : glm::vec3(0.0f);
  }
  check_vectors(select(mask, va, vb), selected);
  check_vectors(keep(va, mask), kept);
  vec3<W> assigned = vb;
  assigned.assign(va, mask);
  check_vectors(assigned, selected);
}

TEMPLATE_TEST_CASE_SIG("vec3: horizontal sums, plain and masked", "[simd][vec3]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto a = distinct_vectors<W>(1);
  const auto p = pattern_mask<W>(4);
  glm::vec3 sum(0.0f), masked(0.0f);
  for (std::size_t i = 0; i < static_cast<std::size_t>(W); ++i) {
    sum += a[i];
    if (p[i]) masked += a[i];
  }
  // Exact: partial sums of multiples of 1/32 below 2^10 are exact in any order.
  CHECK(reduce_add(to_vec3(a)) == sum);
  CHECK(reduce_add(to_vec3(a), to_mask(p)) == masked);
  CHECK(reduce_add(to_vec3(a), vmask<W>(false)) == glm::vec3(0.0f));
}

TEMPLATE_TEST_CASE_SIG("vec3: gather reads active lanes only and zeroes the rest", "[simd][vec3]", ((int W), W), 1, 4,
                       8, 16, 64) {
  std::vector<glm::vec3> table(2 * W + 1);
  for (std::size_t k = 0; k < table.size(); ++k) table[k] = glm::vec3(float(k), -0.5f * float(k), float(k * k));
  const auto p = pattern_mask<W>(0);
  vint<W> index;
  for (int i = 0; i < W; ++i)  // inactive lanes point far outside the table: reading them would fault
    index.set(i, p[static_cast<std::size_t>(i)] ? (i * 3 + 1) % (2 * W + 1) : INT_MAX / 4);
  const vec3<W> gathered = gather(table.data(), index, to_mask(p));
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    CHECK(gathered[i] == (p[static_cast<std::size_t>(i)] ? table[static_cast<std::size_t>(index[i])] : glm::vec3(0.0f)));
  }
}
