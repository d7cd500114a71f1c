// Every operation of igi/simd/lanes.hpp at W = 1, 4, 8, 16 and 64, with lane-distinct inputs,
// against the same operation done one scalar at a time.

#include <algorithm>
#include <bit>
#include <climits>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include <catch2/catch.hpp>

#include "igi/simd/lanes.hpp"
#include "simd_test_support.hpp"

using namespace igi;
using namespace igi::testing;

TEMPLATE_TEST_CASE_SIG("lanes: construction, lane access, load and store", "[simd][lanes]", ((int W), W), 1, 4, 8,
                       16, 64) {
  STATIC_REQUIRE(vfloat<W>::width == W);
  STATIC_REQUIRE(vfloat<W>::chunks * vfloat<W>::chunk_size == W);
  const vfloat<W> zero;
  const vfloat<W> broadcast(2.5f);
  const vint<W> indices = lane_index<W>();
  const vfloat<W> generated([](int i) { return static_cast<float>(i) * 1.5f - 3.0f; });
  for (int i = 0; i < W; ++i) {
    CHECK(zero[i] == 0.0f);
    CHECK(broadcast[i] == 2.5f);
    CHECK(indices[i] == i);
    CHECK(generated[i] == static_cast<float>(i) * 1.5f - 3.0f);
  }

  const auto values = distinct_floats<W>(1);
  const vfloat<W> loaded = vfloat<W>::load(values.data());
  check_lanes(loaded, values);
  std::array<float, W> stored{};
  loaded.store(stored.data());
  CHECK(stored == values);

  vuint<W> written;
  const auto words = distinct_uints<W>(3);
  for (int i = 0; i < W; ++i) written.set(i, words[static_cast<std::size_t>(i)]);
  check_lanes(written, words);
}

TEMPLATE_TEST_CASE_SIG("lanes: float arithmetic matches a scalar loop", "[simd][lanes]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto a = distinct_floats<W>(1);
  const auto b = distinct_floats<W>(2);
  const vfloat<W> va = to_lanes(a), vb = to_lanes(b);
  check_lanes(va + vb, scalar_loop<float>(a, b, [](float x, float y) { return x + y; }));
  check_lanes(va - vb, scalar_loop<float>(a, b, [](float x, float y) { return x - y; }));
  check_lanes(va * vb, scalar_loop<float>(a, b, [](float x, float y) { return x * y; }));
  check_lanes(va / vb, scalar_loop<float>(a, b, [](float x, float y) { return x / y; }));
  check_lanes(-va, scalar_loop<float>(a, [](float x) { return -x; }));

  vfloat<W> accumulated = va;
  accumulated += vb;
  check_lanes(accumulated, scalar_loop<float>(a, b, [](float x, float y) { return x + y; }));
  accumulated -= vb;
  check_lanes(accumulated, a);  // (a + b) - b is exact for these inputs (multiples of 1/32)
  accumulated *= vb;
  check_lanes(accumulated, scalar_loop<float>(a, b, [](float x, float y) { return x * y; }));
  accumulated /= vb;
  check_lanes(accumulated, scalar_loop<float>(a, b, [](float x, float y) { return (x * y) / y; }));
}

TEMPLATE_TEST_CASE_SIG("lanes: integer arithmetic and bit operations match a scalar loop", "[simd][lanes]", ((int W), W),
                       1, 4, 8, 16, 64) {
  const auto a = distinct_ints<W>(1);
  auto b = distinct_ints<W>(2);
  for (auto& value : b)
    if (value == 0) value = 7;  // divisors must be non-zero
  const vint<W> va = to_lanes(a), vb = to_lanes(b);
  check_lanes(va + vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x + y; }));
  check_lanes(va - vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x - y; }));
  check_lanes(va * vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x * y; }));
  check_lanes(va / vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x / y; }));
  check_lanes(va % vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x % y; }));
  check_lanes(-va, scalar_loop<std::int32_t>(a, [](std::int32_t x) { return -x; }));
  check_lanes(va & vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x & y; }));
  check_lanes(va | vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x | y; }));
  check_lanes(va ^ vb, scalar_loop<std::int32_t>(a, b, [](std::int32_t x, std::int32_t y) { return x ^ y; }));
  check_lanes(va << 3, scalar_loop<std::int32_t>(a, [](std::int32_t x) { return static_cast<std::int32_t>(static_cast<std::uint32_t>(x) << 3); }));
  // Right shift of a negative int is arithmetic (sign-filling) in C++20, and so in the packet.
  check_lanes(va >> 2, scalar_loop<std::int32_t>(a, [](std::int32_t x) { return x >> 2; }));

  // Unsigned lanes wrap around modulo 2^32 and shift in zeros.
  const auto u = distinct_uints<W>(1);
  const auto v = distinct_uints<W>(5);
  const vuint<W> vu = to_lanes(u), vv = to_lanes(v);
  check_lanes(vu * vv, scalar_loop<std::uint32_t>(u, v, [](std::uint32_t x, std::uint32_t y) { return x * y; }));
  check_lanes(vu + vv, scalar_loop<std::uint32_t>(u, v, [](std::uint32_t x, std::uint32_t y) { return x + y; }));
  check_lanes(vu - vv, scalar_loop<std::uint32_t>(u, v, [](std::uint32_t x, std::uint32_t y) { return x - y; }));
  check_lanes(vu >> 13, scalar_loop<std::uint32_t>(u, [](std::uint32_t x) { return x >> 13; }));
  check_lanes(vu << 7, scalar_loop<std::uint32_t>(u, [](std::uint32_t x) { return x << 7; }));
  check_lanes(vu ^ vv, scalar_loop<std::uint32_t>(u, v, [](std::uint32_t x, std::uint32_t y) { return x ^ y; }));
  check_lanes(vu % vuint<W>(1000U), scalar_loop<std::uint32_t>(u, [](std::uint32_t x) { return x % 1000U; }));
}

TEMPLATE_TEST_CASE_SIG("lanes: comparisons give the scalar loop's masks", "[simd][lanes]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto a = distinct_floats<W>(1);
  auto b = distinct_floats<W>(2);
  for (int i = 0; i < W; i += 3) b[static_cast<std::size_t>(i)] = a[static_cast<std::size_t>(i)];  // some equal lanes
  const vfloat<W> va = to_lanes(a), vb = to_lanes(b);
  check_mask(va < vb, scalar_loop<bool>(a, b, [](float x, float y) { return x < y; }));
  check_mask(va <= vb, scalar_loop<bool>(a, b, [](float x, float y) { return x <= y; }));
  check_mask(va > vb, scalar_loop<bool>(a, b, [](float x, float y) { return x > y; }));
  check_mask(va >= vb, scalar_loop<bool>(a, b, [](float x, float y) { return x >= y; }));
  check_mask(va == vb, scalar_loop<bool>(a, b, [](float x, float y) { return x == y; }));
  check_mask(va != vb, scalar_loop<bool>(a, b, [](float x, float y) { return x != y; }));

  const auto ia = distinct_ints<W>(1);
  auto ib = distinct_ints<W>(4);
  for (int i = 1; i < W; i += 3) ib[static_cast<std::size_t>(i)] = ia[static_cast<std::size_t>(i)];
  const vint<W> via = to_lanes(ia), vib = to_lanes(ib);
  check_mask(via < vib, scalar_loop<bool>(ia, ib, [](int x, int y) { return x < y; }));
  check_mask(via <= vib, scalar_loop<bool>(ia, ib, [](int x, int y) { return x <= y; }));
  check_mask(via > vib, scalar_loop<bool>(ia, ib, [](int x, int y) { return x > y; }));
  check_mask(via >= vib, scalar_loop<bool>(ia, ib, [](int x, int y) { return x >= y; }));
  check_mask(via == vib, scalar_loop<bool>(ia, ib, [](int x, int y) { return x == y; }));
  check_mask(via != vib, scalar_loop<bool>(ia, ib, [](int x, int y) { return x != y; }));

  // Unsigned comparisons are unsigned: 0x80000000 > 1.
  const auto ua = distinct_uints<W>(0);
  const auto ub = distinct_uints<W>(9);
  check_mask(to_lanes(ua) < to_lanes(ub), scalar_loop<bool>(ua, ub, [](std::uint32_t x, std::uint32_t y) { return x < y; }));
  CHECK(all(vuint<W>(0x80000000U) > vuint<W>(1U)));
}

TEMPLATE_TEST_CASE_SIG("lanes: mask logic, counts and partial-packet masks", "[simd][lanes]", ((int W), W), 1, 4, 8, 16,
                       64) {
  const auto p = pattern_mask<W>(0);
  const auto q = pattern_mask<W>(2);
  const vmask<W> mp = to_mask(p), mq = to_mask(q);
  check_mask(mp & mq, scalar_loop<bool>(p, q, [](bool x, bool y) { return x && y; }));
  check_mask(mp | mq, scalar_loop<bool>(p, q, [](bool x, bool y) { return x || y; }));
  check_mask(mp ^ mq, scalar_loop<bool>(p, q, [](bool x, bool y) { return x != y; }));
  check_mask(!mp, scalar_loop<bool>(p, [](bool x) { return !x; }));
  vmask<W> narrowed = mp;
  narrowed &= mq;
  check_mask(narrowed, scalar_loop<bool>(p, q, [](bool x, bool y) { return x && y; }));
  vmask<W> widened = mp;
  widened |= mq;
  check_mask(widened, scalar_loop<bool>(p, q, [](bool x, bool y) { return x || y; }));

  const int on = static_cast<int>(std::count(p.begin(), p.end(), true));
  CHECK(popcount(mp) == on);
  CHECK(any(mp) == (on > 0));
  CHECK(all(mp) == (on == W));
  CHECK(none(mp) == (on == 0));
  CHECK(mp == to_mask(p));
  CHECK_FALSE(mp == !mp);

  const vmask<W> all_off, all_on(true);
  CHECK(none(all_off));
  CHECK_FALSE(any(all_off));
  CHECK(all(all_on));
  CHECK(popcount(all_on) == W);
  CHECK(popcount(all_off) == 0);

  for (int count = 0; count <= W; ++count) {
    INFO("first(" << count << ")");
    const vmask<W> first = vmask<W>::first(count);
    CHECK(popcount(first) == count);
    for (int i = 0; i < W; ++i) CHECK(first[i] == (i < count));
  }
}

TEMPLATE_TEST_CASE_SIG("lanes: select, keep and masked assignment", "[simd][lanes]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto a = distinct_floats<W>(1);
  const auto b = distinct_floats<W>(2);
  const auto p = pattern_mask<W>(1);
  const vfloat<W> va = to_lanes(a), vb = to_lanes(b);
  const vmask<W> mask = to_mask(p);
  std::array<float, W> selected{}, kept{};
  for (std::size_t i = 0; i < static_cast<std::size_t>(W); ++i) {
    selected[i] = p[i] ? a[i] : b[i];
    kept[i] = p[i] ? a[i] : 0.0f;
  }
  check_lanes(select(mask, va, vb), selected);
  check_lanes(keep(va, mask), kept);
  vfloat<W> assigned = vb;
  assigned.assign(va, mask);
  check_lanes(assigned, selected);

  const auto ia = distinct_ints<W>(1);
  const auto ib = distinct_ints<W>(3);
  std::array<std::int32_t, W> iselected{}, ikept{};
  for (std::size_t i = 0; i < static_cast<std::size_t>(W); ++i) {
    iselected[i] = p[i] ? ia[i] : ib[i];
    ikept[i] = p[i] ? ia[i] : 0;
  }
  check_lanes(select(mask, to_lanes(ia), to_lanes(ib)), iselected);
  check_lanes(keep(to_lanes(ia), mask), ikept);
  vint<W> iassigned = to_lanes(ib);
  iassigned.assign(to_lanes(ia), mask);
  check_lanes(iassigned, iselected);

  // Edge masks: all on takes a, all off takes b.
  check_lanes(select(vmask<W>(true), va, vb), a);
  check_lanes(select(vmask<W>(false), va, vb), b);
}

TEMPLATE_TEST_CASE_SIG("lanes: min, max, clamp and abs", "[simd][lanes]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto a = distinct_floats<W>(1);
  const auto b = distinct_floats<W>(2);
  const vfloat<W> va = to_lanes(a), vb = to_lanes(b);
  check_lanes(min(va, vb), scalar_loop<float>(a, b, [](float x, float y) { return std::min(x, y); }));
  check_lanes(max(va, vb), scalar_loop<float>(a, b, [](float x, float y) { return std::max(x, y); }));
  check_lanes(abs(va), scalar_loop<float>(a, [](float x) { return std::abs(x); }));
  check_lanes(clamp(va, vfloat<W>(-2.0f), vfloat<W>(3.0f)),
              scalar_loop<float>(a, [](float x) { return std::clamp(x, -2.0f, 3.0f); }));

  const auto ia = distinct_ints<W>(1);
  const auto ib = distinct_ints<W>(2);
  const vint<W> via = to_lanes(ia), vib = to_lanes(ib);
  check_lanes(min(via, vib), scalar_loop<std::int32_t>(ia, ib, [](int x, int y) { return std::min(x, y); }));
  check_lanes(max(via, vib), scalar_loop<std::int32_t>(ia, ib, [](int x, int y) { return std::max(x, y); }));
  check_lanes(abs(via), scalar_loop<std::int32_t>(ia, [](int x) { return std::abs(x); }));
  check_lanes(clamp(via, vint<W>(-5), vint<W>(4)), scalar_loop<std::int32_t>(ia, [](int x) { return std::clamp(x, -5, 4); }));

  const auto ua = distinct_uints<W>(1);
  const auto ub = distinct_uints<W>(2);
  check_lanes(min(to_lanes(ua), to_lanes(ub)),
              scalar_loop<std::uint32_t>(ua, ub, [](std::uint32_t x, std::uint32_t y) { return std::min(x, y); }));
  check_lanes(max(to_lanes(ua), to_lanes(ub)),
              scalar_loop<std::uint32_t>(ua, ub, [](std::uint32_t x, std::uint32_t y) { return std::max(x, y); }));
}

TEMPLATE_TEST_CASE_SIG("lanes: sqrt, floor, exp, log, pow, sin, cos and isfinite", "[simd][lanes]", ((int W), W), 1, 4,
                       8, 16, 64) {
  const auto signed_values = distinct_floats<W>(1);
  const auto positive = scalar_loop<float>(signed_values, [](float x) { return std::abs(x) + 0.5f; });
  const vfloat<W> vs = to_lanes(signed_values), vp = to_lanes(positive);
  // libstdc++ computes these lane by lane with the C library (or, for sqrt and floor, with the
  // correctly rounded instructions), so they equal the scalar float functions bit for bit.
  check_lanes(sqrt(vp), scalar_loop<float>(positive, [](float x) { return std::sqrt(x); }));
  check_lanes(floor(vs), scalar_loop<float>(signed_values, [](float x) { return std::floor(x); }));
  const auto exponent_arguments = scalar_loop<float>(signed_values, [](float x) { return x * 0.125f; });
  check_lanes(exp(to_lanes(exponent_arguments)), scalar_loop<float>(exponent_arguments, [](float x) { return std::exp(x); }));
  check_lanes(log(vp), scalar_loop<float>(positive, [](float x) { return std::log(x); }));
  const auto exponents = distinct_floats<W>(3);
  const auto scaled_exponents = scalar_loop<float>(exponents, [](float x) { return x * 0.25f; });
  check_lanes(pow(vp, to_lanes(scaled_exponents)),
              scalar_loop<float>(positive, scaled_exponents, [](float x, float y) { return std::pow(x, y); }));

  // sin and cos have their own polynomial kernels in libstdc++'s simd: compared with the exact
  // (double) value, allow 2 ulp of the result plus 2^-24 absolute near the zeros, the accuracy
  // those kernels are written to (documented as ~1 ulp; one more for the argument reduction).
  const vfloat<W> sines = sin(vs), cosines = cos(vs);
  for (int i = 0; i < W; ++i) {
    const double x = signed_values[static_cast<std::size_t>(i)];
    INFO("lane " << i << ", x = " << x);
    const double exact_sin = std::sin(x), exact_cos = std::cos(x);
    CHECK(std::abs(sines[i] - exact_sin) <= 2.0 * std::abs(exact_sin) * 0x1p-23 + 0x1p-24);
    CHECK(std::abs(cosines[i] - exact_cos) <= 2.0 * std::abs(exact_cos) * 0x1p-23 + 0x1p-24);
  }

  // isfinite: plant infinities and a NaN on some lanes.
  std::array<float, W> special = signed_values;
  special[0] = std::numeric_limits<float>::infinity();
  if (W > 1) special[static_cast<std::size_t>(W - 1)] = std::numeric_limits<float>::quiet_NaN();
  if (W > 4) special[3] = -std::numeric_limits<float>::infinity();
  check_mask(isfinite(to_lanes(special)), scalar_loop<bool>(special, [](float x) { return std::isfinite(x); }));
}

TEMPLATE_TEST_CASE_SIG("lanes: convert and bit_cast", "[simd][lanes]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto f = distinct_floats<W>(1);
  // float -> int truncates towards zero (negative values too).
  check_lanes(convert<std::int32_t>(to_lanes(f)), scalar_loop<std::int32_t>(f, [](float x) { return static_cast<std::int32_t>(x); }));
  const auto i = distinct_ints<W>(2);
  check_lanes(convert<float>(to_lanes(i)), scalar_loop<float>(i, [](std::int32_t x) { return static_cast<float>(x); }));
  // uint -> float rounds to nearest, including values above 2^31 (not representable as int).
  const auto u = distinct_uints<W>(3);
  check_lanes(convert<float>(to_lanes(u)), scalar_loop<float>(u, [](std::uint32_t x) { return static_cast<float>(x); }));
  const auto positive = scalar_loop<float>(f, [](float x) { return std::abs(x) * 1000.0f; });
  check_lanes(convert<std::uint32_t>(to_lanes(positive)),
              scalar_loop<std::uint32_t>(positive, [](float x) { return static_cast<std::uint32_t>(x); }));
  check_lanes(convert<std::uint32_t>(to_lanes(i)),
              scalar_loop<std::uint32_t>(i, [](std::int32_t x) { return static_cast<std::uint32_t>(x); }));

  // bit_cast reinterprets: same bits as std::bit_cast, and back again.
  const vuint<W> bits = bit_cast<std::uint32_t>(to_lanes(f));
  check_lanes(bits, scalar_loop<std::uint32_t>(f, [](float x) { return std::bit_cast<std::uint32_t>(x); }));
  check_lanes(bit_cast<float>(bits), f);
  check_lanes(bit_cast<std::int32_t>(to_lanes(u)), scalar_loop<std::int32_t>(u, [](std::uint32_t x) { return std::bit_cast<std::int32_t>(x); }));
}

TEMPLATE_TEST_CASE_SIG("lanes: reductions, plain and masked", "[simd][lanes]", ((int W), W), 1, 4, 8, 16, 64) {
  const auto f = distinct_floats<W>(1);
  const auto p = pattern_mask<W>(3);
  const vmask<W> mask = to_mask(p);
  float sum = 0.0f, masked_sum = 0.0f;
  float lowest = f[0], highest = f[0];
  for (std::size_t i = 0; i < static_cast<std::size_t>(W); ++i) {
    sum += f[i];
    if (p[i]) masked_sum += f[i];
    lowest = std::min(lowest, f[i]);
    highest = std::max(highest, f[i]);
  }
  // Exact equality although the packet sums in a different order: every partial sum of these
  // inputs (multiples of 1/32 below 2^10 in magnitude) is exact in float.
  CHECK(reduce_add(to_lanes(f)) == sum);
  CHECK(reduce_add(to_lanes(f), mask) == masked_sum);
  CHECK(reduce_add(to_lanes(f), vmask<W>(false)) == 0.0f);
  CHECK(reduce_min(to_lanes(f)) == lowest);
  CHECK(reduce_max(to_lanes(f)) == highest);

  const auto i = distinct_ints<W>(2);
  std::int32_t isum = 0, imasked = 0;
  for (std::size_t k = 0; k < static_cast<std::size_t>(W); ++k) {
    isum += i[k];
    if (p[k]) imasked += i[k];
  }
  CHECK(reduce_add(to_lanes(i)) == isum);
  CHECK(reduce_add(to_lanes(i), mask) == imasked);
  CHECK(reduce_min(to_lanes(i)) == *std::min_element(i.begin(), i.end()));
  CHECK(reduce_max(to_lanes(i)) == *std::max_element(i.begin(), i.end()));

  // Masked min/max: over the active lanes, the type's identity element when none is on.
  float masked_lowest = std::numeric_limits<float>::infinity(), masked_highest = -std::numeric_limits<float>::infinity();
  for (std::size_t k = 0; k < static_cast<std::size_t>(W); ++k)
    if (p[k]) {
      masked_lowest = std::min(masked_lowest, f[k]);
      masked_highest = std::max(masked_highest, f[k]);
    }
  CHECK(reduce_min(to_lanes(f), mask) == masked_lowest);
  CHECK(reduce_max(to_lanes(f), mask) == masked_highest);
  CHECK(reduce_min(to_lanes(f), vmask<W>(false)) == std::numeric_limits<float>::infinity());
  CHECK(reduce_max(to_lanes(i), vmask<W>(false)) == std::numeric_limits<std::int32_t>::lowest());
}

TEMPLATE_TEST_CASE_SIG("lanes: gather reads active lanes only and zeroes the rest", "[simd][lanes]", ((int W), W), 1, 4,
                       8, 16, 64) {
  std::vector<float> table(3 * W);
  for (std::size_t k = 0; k < table.size(); ++k) table[k] = 0.5f * static_cast<float>(k) + 1.0f;
  std::vector<std::int32_t> int_table(table.size());
  for (std::size_t k = 0; k < int_table.size(); ++k) int_table[k] = static_cast<std::int32_t>(k * k) - 7;

  const auto p = pattern_mask<W>(1);
  vint<W> index;
  for (int i = 0; i < W; ++i) {
    // Active lanes read a permutation of the table; inactive lanes hold indices far outside it
    // (a read there would fault, or be reported by the ASan preset).
    index.set(i, p[static_cast<std::size_t>(i)] ? (i * 5 + 2) % (3 * W) : (i % 2 == 0 ? INT_MAX / 2 : -INT_MAX / 2));
  }
  const vmask<W> mask = to_mask(p);
  const vfloat<W> gathered = gather(table.data(), index, mask);
  const vint<W> int_gathered = gather(int_table.data(), index, mask);
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    if (p[static_cast<std::size_t>(i)]) {
      CHECK(gathered[i] == table[static_cast<std::size_t>(index[i])]);
      CHECK(int_gathered[i] == int_table[static_cast<std::size_t>(index[i])]);
    } else {
      CHECK(gathered[i] == 0.0f);
      CHECK(int_gathered[i] == 0);
    }
  }
  // With every lane off nothing is read at all.
  const vint<W> wild(INT_MAX / 2);
  CHECK(none(gather(table.data(), wild, vmask<W>(false)) != vfloat<W>(0.0f)));
}

TEMPLATE_TEST_CASE_SIG("lanes: gather_every reads every lane, as the scalar loop does, and bytes as words", "[simd][lanes]",
                       ((int W), W), 1, 4, 8, 16, 64) {
  // Hardware gathers with AVX2 and AVX-512, loads lane by lane below: both must give every
  // lane its element, including the table's first and last (gathers take the index signed).
  std::vector<float> table(4 * W + 3);
  for (std::size_t k = 0; k < table.size(); ++k) table[k] = 0.25f * static_cast<float>(k) - 3.0f;
  std::vector<std::int32_t> int_table(table.size());
  for (std::size_t k = 0; k < int_table.size(); ++k) int_table[k] = static_cast<std::int32_t>(k * 7919) - 100000;
  const int last = static_cast<int>(table.size()) - 1;
  const vint<W> index([&](int i) { return i == 0 ? last : i == W - 1 ? 0 : (i * 13 + 5) % last; });
  const vfloat<W> gathered = gather_every(table.data(), index);
  const vint<W> int_gathered = gather_every(int_table.data(), index);
  for (int i = 0; i < W; ++i) {
    INFO("lane " << i);
    CHECK(gathered[i] == table[static_cast<std::size_t>(index[i])]);
    CHECK(int_gathered[i] == int_table[static_cast<std::size_t>(index[i])]);
  }
  // RGBA8 texels read as 32-bit words: byte k of word i is texel i's channel k (x86's byte order).
  std::vector<std::uint8_t> texels(4 * static_cast<std::size_t>(W));
  for (std::size_t k = 0; k < texels.size(); ++k) texels[k] = static_cast<std::uint8_t>(k * 37 + 11);
  const vint<W> words = gather_every(reinterpret_cast<const std::int32_t*>(texels.data()), lane_index<W>());
  for (int i = 0; i < W; ++i)
    for (int k = 0; k < 4; ++k) CHECK(((words[i] >> (8 * k)) & 0xff) == texels[static_cast<std::size_t>(4 * i + k)]);
}

TEST_CASE("lanes: one native packet is one float and one int register of the build's ISA", "[simd][lanes]") {
  constexpr int W = native_packet_width;
  STATIC_REQUIRE(vfloat<W>::chunks == 1);
  STATIC_REQUIRE(vint<W>::chunks == 1);
  STATIC_REQUIRE(int(vfloat<W>::chunk_type::size()) == W);
  STATIC_REQUIRE(int(vint<W>::chunk_type::size()) == W);
#if defined(__AVX512F__)
  STATIC_REQUIRE(W == 16);
#elif defined(__AVX2__)
  STATIC_REQUIRE(W == 8);
#else
  // SSE, and plain AVX, whose 8-float registers have no 8-int partner.
  STATIC_REQUIRE(W == 4);
#endif
#if defined(IGI_LANES_TEST_PLAIN_AVX)
  // This build is the plain-AVX one (tests/simd/CMakeLists.txt): it must be AVX without AVX2.
  STATIC_REQUIRE(stdx::native_simd<float>::size() == 8);
  STATIC_REQUIRE(stdx::native_simd<std::int32_t>::size() == 4);
#endif
}
