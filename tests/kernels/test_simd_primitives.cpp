// The SIMD primitives of kernels/simd/simd.h at the instruction-set level in use
// (PT_ISA), against their definitions lane by lane: mask extraction and
// conversion (also for integer lanes whose bits read as NaN floats),
// compaction, gathers and horizontal min / max.
#include <gtest/gtest.h>

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <random>
#include <vector>

#include "kernels/simd/isa.h"
#include "kernels/simd/simd.h"
#include "support/lane_probes.h"

namespace pt {
namespace {

const test::LaneProbes& probes() { return test::lane_probes(active_isa()); }

TEST(SimdPrimitives, TheLevelInUseHasItsLaneCount) {
  EXPECT_EQ(probes().isa, active_isa());
  EXPECT_EQ(probes().lanes, isa_lanes(active_isa()));
}

TEST(SimdPrimitives, LaneMasksRoundTripEveryPattern) {
  const size_t k = probes().lanes;
  std::mt19937 rng(1);
  for (int i = 0; i < 4096; ++i) {
    uint32_t bits = i < 256 ? uint32_t(i) : uint32_t(rng());
    ASSERT_EQ(probes().mask_round_trip(bits), bits & lanes_below(k)) << std::hex << bits;
  }
}

// Integer lanes of all-ones are NaN when read as floats: a mask conversion
// through float values loses them (an ordered float compare says NaN != 0 is
// false), which once blacked out every 8-lane render.
TEST(SimdPrimitives, IntegerComparisonsBecomeFloatMasksForAnyBitPattern) {
  const size_t k = probes().lanes;
  const uint32_t patterns[] = {0u, 1u, 0x7FC00000u, 0xFFFFFFFFu, 0x80000000u, 0x7F800000u, 0xFF800001u, 12345u};
  std::mt19937 rng(2);
  for (int rep = 0; rep < 2000; ++rep) {
    std::vector<uint32_t> a(k), b(k);
    uint32_t expected = 0;
    for (size_t l = 0; l < k; ++l) {
      a[l] = patterns[rng() % 8];
      b[l] = rng() % 2 ? a[l] : patterns[rng() % 8];
      expected |= uint32_t(a[l] == b[l]) << l;
    }
    ASSERT_EQ(probes().equal_uint_lanes(a.data(), b.data()), expected);
  }
}

TEST(SimdPrimitives, FloatMasksSurviveTheTripThroughIntegerMasks) {
  const size_t k = probes().lanes;
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> u(-1.0f, 1.0f);
  for (int rep = 0; rep < 2000; ++rep) {
    std::vector<float> x(k), y(k);
    uint32_t expected = 0;
    for (size_t l = 0; l < k; ++l) {
      x[l] = u(rng);
      y[l] = rep % 7 == 0 ? NAN : u(rng);
      expected |= uint32_t(x[l] < y[l]) << l;
    }
    ASSERT_EQ(probes().less_through_int_mask(x.data(), y.data()), expected);
  }
}

TEST(SimdPrimitives, CompressionKeepsTheSelectedLanesInOrder) {
  const size_t k = probes().lanes;
  std::vector<float> in(k), out(k);
  for (size_t l = 0; l < k; ++l) in[l] = 100.0f + float(l);
  std::mt19937 rng(4);
  for (int i = 0; i < 4096; ++i) {
    uint32_t mask = (i < 256 ? uint32_t(i) : uint32_t(rng())) & lanes_below(k);
    std::fill(out.begin(), out.end(), -1.0f);
    probes().compress(in.data(), mask, out.data());
    size_t at = 0;
    for (size_t l = 0; l < k; ++l) {
      if (!(mask >> l & 1)) continue;
      ASSERT_EQ(out[at++], in[l]) << "mask " << std::hex << mask;
    }
    ASSERT_EQ(at, size_t(std::popcount(mask)));
  }
}

TEST(SimdPrimitives, GathersReadEveryLanesOwnIndex) {
  const size_t k = probes().lanes;
  std::vector<float> base(1000);
  for (size_t i = 0; i < base.size(); ++i) base[i] = float(i) * 0.5f;
  std::mt19937 rng(5);
  std::vector<int32_t> index(k);
  std::vector<float> out(k);
  for (int rep = 0; rep < 1000; ++rep) {
    for (size_t l = 0; l < k; ++l) index[l] = int32_t(rng() % base.size());
    probes().gather(base.data(), index.data(), out.data());
    for (size_t l = 0; l < k; ++l) ASSERT_EQ(out[l], base[size_t(index[l])]);
  }
}

// The records are read with 16-byte loads where that stays inside the array
// (the sanitizer build checks each load against the exact allocation), and
// every bit pattern, NaNs included, must arrive unchanged.
TEST(SimdPrimitives, RecordGathersReadEveryLanesOwnRecordUpToTheLast) {
  const size_t k = probes().lanes;
  std::mt19937 rng(11);
  for (int32_t records : {1, 2, 5, 97, 4096}) {
    std::vector<int32_t> bits(3 * size_t(records));  // exactly the records, no slack
    for (int32_t& b : bits) b = int32_t(rng());
    bits[0] = int32_t(0x7fc00001u), bits[1] = int32_t(0xffffffffu);  // NaN patterns
    std::vector<float> floats(bits.size());
    std::memcpy(floats.data(), bits.data(), bits.size() * sizeof(float));
    std::vector<int32_t> index(k), out_bits(3 * k), float_bits(3 * k);
    std::vector<float> out_floats(3 * k);
    for (int rep = 0; rep < 2000; ++rep) {
      const int kind = rep % 4;  // random; with the last record; all the last; all the first
      for (size_t l = 0; l < k; ++l)
        index[l] = kind == 2 ? records - 1 : kind == 3 ? 0 : int32_t(rng() % uint32_t(records));
      if (kind == 1) index[rng() % k] = records - 1;
      probes().gather_int_records3(bits.data(), index.data(), records, out_bits.data());
      probes().gather_records3(floats.data(), index.data(), records, out_floats.data());
      std::memcpy(float_bits.data(), out_floats.data(), float_bits.size() * sizeof(float));
      for (size_t c = 0; c < 3; ++c)
        for (size_t l = 0; l < k; ++l) {
          const int32_t want = bits[3 * size_t(index[l]) + c];
          ASSERT_EQ(out_bits[c * k + l], want) << "records " << records << " lane " << l << " field " << c;
          ASSERT_EQ(float_bits[c * k + l], want) << "records " << records << " lane " << l << " field " << c;
        }
    }
  }
}

TEST(SimdPrimitives, HorizontalMinimumAndMaximumSeeEveryLane) {
  const size_t k = probes().lanes;
  std::vector<float> v(k);
  for (size_t hot = 0; hot < k; ++hot) {
    for (size_t l = 0; l < k; ++l) v[l] = float(l) + 1.0f;
    v[hot] = -5.0f;
    ASSERT_EQ(probes().reduce_min(v.data()), -5.0f) << "lane " << hot;
    v[hot] = 1000.0f;
    ASSERT_EQ(probes().reduce_max(v.data()), 1000.0f) << "lane " << hot;
    v[hot] = -INFINITY;
    ASSERT_EQ(probes().reduce_min(v.data()), -INFINITY);
  }
}

}  // namespace
}  // namespace pt
