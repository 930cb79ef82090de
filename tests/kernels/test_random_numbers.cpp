// The counter-based random numbers (kernels/math/random.h): uniform in [0, 1) per
// dimension (1-D chi-square), independent between the dimensions of a path,
// between bounces, between neighbouring pixels, neighbouring samples and
// seeds (2-D chi-square of pairs), exactly representable with 1 excluded, and
// the same from the SIMD instantiation as from the scalar one.
//
// Every chi-square test: 2^20 values or pairs (4096 pixels x 256 samples),
// 1024 bins (1-D: 1024 equal bins; 2-D: 32 x 32), about 1024 per bin,
// significance level 1e-6 (false-failure probability 1e-6 per test, 1.3e-5 for
// the 13 of this file). Power: with 1023 degrees of freedom a noncentrality of
// 323 is rejected with probability 0.95, so a density (or joint density) off
// by 1.8% of itself in every bin, or by 56% in a single bin, is detected. The
// other tests are exact. Each runs in a few milliseconds.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/simd/isa.h"
#include "kernels/math/random.h"
#include "kernels/transport/sample_dimensions.h"
#include "support/lane_probes.h"
#include "support/statistics.h"

// Its own namespace: its file-local names would clash with another file's of the
// program, which is compiled as one unity file (tests/CMakeLists.txt).
namespace pt::random_numbers_test {
namespace {

constexpr uint32_t kSeed = 7;
constexpr uint32_t kPixels = 4096, kSamplesPerPixel = 256;
constexpr double kAlpha = 1e-6;

float number(uint32_t seed, uint32_t pixel, uint32_t sample, uint32_t bounce, uint32_t dim) {
  return random_uniform(pixel_key<uint32_t>(seed, pixel), sample_key<uint32_t>(sample), bounce, dim);
}

test::ChiSquareResult uniformity(uint32_t bounce, uint32_t dim) {
  const int bins = 1024;
  std::vector<double> counts(bins, 0.0), expected(bins, double(kPixels) * kSamplesPerPixel / bins);
  for (uint32_t p = 0; p < kPixels; ++p)
    for (uint32_t s = 0; s < kSamplesPerPixel; ++s) ++counts[int(number(kSeed, p, s, bounce, dim) * bins)];
  return test::chi_square_test(counts, expected);
}

/// 2-D chi-square of pair(pixel, sample) = (a, b) over 32 x 32 cells.
test::ChiSquareResult independence(const std::function<std::pair<float, float>(uint32_t, uint32_t)>& pair) {
  const int n = 32;
  std::vector<double> counts(n * n, 0.0), expected(n * n, double(kPixels) * kSamplesPerPixel / (n * n));
  for (uint32_t p = 0; p < kPixels; ++p)
    for (uint32_t s = 0; s < kSamplesPerPixel; ++s) {
      auto [a, b] = pair(p, s);
      ++counts[int(a * n) * n + int(b * n)];
    }
  return test::chi_square_test(counts, expected);
}

// Catches: a float conversion that keeps fewer than the top bits (values only
// in [0, 1/2)), a biased key for low pixel/sample counts, a dimension key that
// leaves some dimensions constant.
TEST(RandomNumbers, UniformInEachDimension) {
  const std::pair<uint32_t, uint32_t> dims[] = {{dims::kCameraBounce, dims::kPixelJitter},
                                                {dims::kCameraBounce, dims::kPixelJitter + 1},
                                                {1, dims::kBsdf},
                                                {2, dims::kRoulette},
                                                {3, dims::light_dim(5) + 1}};
  for (auto [bounce, dim] : dims) {
    test::ChiSquareResult r = uniformity(bounce, dim);
    EXPECT_GT(r.p_value, kAlpha) << "bounce " << bounce << " dim " << dim << ": " << r.summary;
  }
}

// The two numbers of one 2-D sample (the BSDF direction). Catches a dimension
// mixed in after the hash (hash(key) ^ dim: the top 24 bits, hence the floats,
// of dims 0 and 1 coincide).
TEST(RandomNumbers, IndependentBetweenDimensionsOfAPath) {
  auto r = independence([](uint32_t p, uint32_t s) {
    return std::pair{number(kSeed, p, s, 1, dims::kBsdf), number(kSeed, p, s, 1, dims::kBsdf + 1)};
  });
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// The same dimension at consecutive bounces, and the diagonal pair
// (bounce b, dim d + 1) / (bounce b + 1, dim d), which coincide when the
// dimension key adds bounce and dim instead of keeping them apart.
TEST(RandomNumbers, IndependentBetweenBounces) {
  auto same_dim = independence([](uint32_t p, uint32_t s) {
    return std::pair{number(kSeed, p, s, 1, dims::kBsdf), number(kSeed, p, s, 2, dims::kBsdf)};
  });
  EXPECT_GT(same_dim.p_value, kAlpha) << same_dim.summary;
  auto diagonal = independence([](uint32_t p, uint32_t s) {
    return std::pair{number(kSeed, p, s, 2, dims::kBsdf + 1), number(kSeed, p, s, 3, dims::kBsdf)};
  });
  EXPECT_GT(diagonal.p_value, kAlpha) << diagonal.summary;
}

// Neighbouring pixels (left-right, and up-down in an 800-wide image),
// neighbouring samples of one pixel, and the diagonal (pixel + 1, sample) /
// (pixel, sample + 1), which coincide when the path key adds pixel and sample.
TEST(RandomNumbers, IndependentBetweenNeighbouringPixelsAndSamples) {
  struct Neighbour {
    const char* name;
    uint32_t dp1, ds1, dp2, ds2;
  };
  const Neighbour neighbours[] = {{"pixel, pixel + 1", 0, 0, 1, 0},
                                  {"pixel, pixel + 800", 0, 0, 800, 0},
                                  {"sample, sample + 1", 0, 0, 0, 1},
                                  {"(p + 1, s), (p, s + 1)", 1, 0, 0, 1}};
  for (const Neighbour& n : neighbours) {
    auto r = independence([&](uint32_t p, uint32_t s) {
      return std::pair{number(kSeed, p + n.dp1, s + n.ds1, 1, dims::kBsdf),
                       number(kSeed, p + n.dp2, s + n.ds2, 1, dims::kBsdf)};
    });
    EXPECT_GT(r.p_value, kAlpha) << n.name << ": " << r.summary;
  }
}

TEST(RandomNumbers, IndependentBetweenSeeds) {
  auto r = independence([](uint32_t p, uint32_t s) {
    return std::pair{number(kSeed, p, s, 0, dims::kPixelJitter), number(kSeed + 1, p, s, 0, dims::kPixelJitter)};
  });
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// The test's power: the same numbers paired with themselves must be rejected.
TEST(RandomNumbers, IndependenceTestRejectsIdenticalStreams) {
  auto r = independence([](uint32_t p, uint32_t s) {
    float a = number(kSeed, p, s, 1, dims::kBsdf);
    return std::pair{a, a};
  });
  EXPECT_LT(r.p_value, kAlpha) << r.summary;
}

/// Inverse of hash32 (lowbias32), so that a test can ask for given output bits.
uint32_t unhash32(uint32_t x) {
  x ^= x >> 16;
  x *= 0x43021123u;
  x ^= (x >> 15) ^ (x >> 30);
  x *= 0x1d69e2a5u;
  x ^= x >> 16;
  return x;
}

// hash32 is a bijection (it has an inverse), so every 24-bit float value is
// reached; the extremes are exactly 0 and 1 - 2^-24. Catches a conversion by
// 2^-32 of all 32 bits, which rounds the top values to 1.0.
TEST(RandomNumbers, ValuesAreMultiplesOfTwoToTheMinus24BelowOne) {
  for (uint32_t x = 0; x < (1u << 20); ++x) ASSERT_EQ(unhash32(hash32(x * 4099u)), x * 4099u);
  // random_float(pk, sk, dk) = top 24 bits of hash32(hash32(pk ^ dk) ^ sk): with
  // pk = dk the inner hash is hash32(0) = 0, so sk = unhash32(bits) gives `bits`.
  const uint32_t dk = dimension_key(1, dims::kBsdf);
  EXPECT_EQ((random_float<uint32_t, float>(dk, unhash32(0xFFFFFFFFu), dk)), 1.0f - 0x1p-24f);
  EXPECT_EQ((random_float<uint32_t, float>(dk, unhash32(0x000000FFu), dk)), 0.0f);
  EXPECT_EQ((random_float<uint32_t, float>(dk, unhash32(0x00000100u), dk)), 0x1p-24f);
  for (uint32_t p = 0; p < 65536; ++p) {
    float v = number(kSeed, p, 3, 1, dims::kRoulette);
    ASSERT_TRUE(v >= 0.0f && v < 1.0f);
    ASSERT_EQ(v * 0x1p24f, std::floor(v * 0x1p24f));
  }
}

// SIMD stages must draw exactly the numbers the scalar reference draws (at
// the instruction-set level in use).
TEST(RandomNumbers, SimdLanesEqualTheScalarNumbers) {
  const test::LaneProbes& probes = test::lane_probes(active_isa());
  const uint32_t dk = dimension_key(2, dims::light_dim(1));
  const size_t n = 100000 / probes.lanes * probes.lanes;
  std::vector<uint32_t> pixels(n), samples(n), keys(n);
  std::vector<float> values(n);
  for (uint32_t i = 0; i < n; ++i) {
    pixels[i] = i / uint32_t(probes.lanes) * uint32_t(probes.lanes) + (i % uint32_t(probes.lanes)) * 7;
    samples[i] = i / 3;
  }
  probes.random_numbers(kSeed, pixels.data(), samples.data(), dk, n, keys.data(), values.data());
  for (size_t i = 0; i < n; ++i) {
    uint32_t scalar_pk = pixel_key<uint32_t>(kSeed, pixels[i]);
    ASSERT_EQ(keys[i], scalar_pk) << "lane " << i % probes.lanes;
    ASSERT_EQ(values[i], (random_float<uint32_t, float>(scalar_pk, sample_key<uint32_t>(samples[i]), dk)));
  }
}

// Distinct paths never draw the same numbers in every dimension. With one
// 32-bit key per path, the ~5e8 paths of an 800x600 image at 1024 spp would
// share keys by the birthday bound (~6% of paths repeating another path's
// numbers). Here: 2^21 paths (8192 pixels x 256 samples); the first three
// dimensions together form 72 bits, so any repeated triple means shared keys
// (chance of an honest repeat: 2^42 / 2^73 < 1e-9).
TEST(RandomNumbers, NoTwoPathsShareAllTheirNumbers) {
  std::vector<std::array<uint32_t, 3>> triples;
  triples.reserve(8192u * 256u);
  for (uint32_t p = 0; p < 8192; ++p)
    for (uint32_t s = 0; s < 256; ++s)
      triples.push_back({uint32_t(number(kSeed, p, s, 0, 0) * 0x1p24f), uint32_t(number(kSeed, p, s, 0, 1) * 0x1p24f),
                         uint32_t(number(kSeed, p, s, 1, 0) * 0x1p24f)});
  std::sort(triples.begin(), triples.end());
  EXPECT_EQ(std::adjacent_find(triples.begin(), triples.end()), triples.end());
}

}  // namespace
}  // namespace pt::random_numbers_test
