// Chi-square goodness-of-fit tests of the direction samplers (kernels/math/sampling.h)
// against the densities their contracts state, plus exact properties (unit
// length, the right half space, finite at the edges of the unit square) and
// agreement of the SIMD instantiation with the scalar one.
//
// Every chi-square test here: 2^20 samples from a fixed-seed mt19937, 16 bins in
// cos(theta) x 32 bins in phi (512 bins, about 2048 samples each) plus one
// overflow bin of expected count 0, and rejection at significance level 1e-6:
// a correct sampler fails with probability 1e-6 (over the choice of seed).
// Power: with 511 degrees of freedom a noncentrality N sum (p' - p)^2 / p of
// 238 is rejected with probability 0.95, so a density off by 1.5% of itself
// in every bin (more in some, less in others), or by 34% in a single bin, is
// detected. Each runs in about 30 ms.
#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "kernels/simd/isa.h"
#include "kernels/math/sampling.h"
#include "support/lane_probes.h"
#include "support/sampling_histogram.h"
#include "support/statistics.h"

// Its own namespace: its file-local names would clash with another file's of the
// program, which is compiled as one unity file (tests/CMakeLists.txt).
namespace pt::sampling_warps_test {
namespace {

using test::ChiSquareResult;
using test::DirectionHistogram;
using test::UniformSource;

constexpr int kSamples = 1 << 20;
constexpr double kAlpha = 1e-6;
constexpr double kPi = std::numbers::pi;

template <class Warp>
ChiSquareResult chi_square_of(Warp warp, double z_min, uint32_t seed,
                              const std::function<double(double, double, double, double)>& mass) {
  DirectionHistogram h(16, 32, z_min);
  UniformSource u(seed);
  for (int i = 0; i < kSamples; ++i) {
    float u1 = u.next(), u2 = u.next();
    Vec3T<float> d = warp(u1, u2);
    h.add(d.x, d.y, d.z);
  }
  return test::chi_square_test(h.counts(), h.expected(kSamples, mass));
}

// Stated pdf 1 / (2 pi) per steradian; d(omega) = dz dphi, so a bin's mass is
// dz dphi / (2 pi). Catches: theta (not cos theta) drawn uniformly, so that
// directions crowd the pole; phi over [0, pi) only; the full sphere (z from
// 2 u - 1, which fills the overflow bin); the cosine warp's radius sqrt(u).
TEST(UniformHemisphere, ChiSquareAgainstItsStatedDensity) {
  ChiSquareResult r =
      chi_square_of([](float a, float b) { return sample_uniform_hemisphere(a, b); }, 0.0, 1,
                    [](double z0, double z1, double p0, double p1) { return (z1 - z0) * (p1 - p0) / (2 * kPi); });
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// Stated pdf z / pi: a bin's mass is (z1^2 - z0^2) / 2 * dphi / pi. Catches:
// the disk radius u instead of sqrt(u) (Malley's method then favours the pole);
// z = 1 - u instead of sqrt(1 - u); a uniform warp; phi over half the circle.
TEST(CosineHemisphere, ChiSquareAgainstItsStatedDensity) {
  ChiSquareResult r = chi_square_of(
      [](float a, float b) { return sample_cosine_hemisphere(a, b); }, 0.0, 2,
      [](double z0, double z1, double p0, double p1) { return (z1 * z1 - z0 * z0) / 2 * (p1 - p0) / kPi; });
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// Stated pdf 1 / (4 pi) over z in [-1, 1]. Catches a hemisphere-only or
// pole-crowding warp, as above.
TEST(UniformSphere, ChiSquareAgainstItsStatedDensity) {
  ChiSquareResult r =
      chi_square_of([](float a, float b) { return sample_uniform_sphere(a, b); }, -1.0, 3,
                    [](double z0, double z1, double p0, double p1) { return (z1 - z0) * (p1 - p0) / (4 * kPi); });
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// The chi-square test itself must reject a wrong warp at this sample size:
// cosine-weighted samples tested against the uniform density.
TEST(SamplerChiSquare, RejectsAWrongDensity) {
  ChiSquareResult r =
      chi_square_of([](float a, float b) { return sample_cosine_hemisphere(a, b); }, 0.0, 4,
                    [](double z0, double z1, double p0, double p1) { return (z1 - z0) * (p1 - p0) / (2 * kPi); });
  EXPECT_LT(r.p_value, kAlpha) << r.summary;
}

// Exact properties on a grid that includes the edges of [0, 1)^2 (0 and the
// largest float below 1): unit length to float accuracy, z >= 0 for the
// hemispheres, no NaN.
TEST(Warps, UnitLengthAndInTheirDomainAtTheEdgesOfTheSquare) {
  const float last = 1.0f - 0x1p-24f;
  std::vector<float> grid = {0.0f, 0x1p-24f, 0.25f, 0.5f, 0.75f, last};
  for (int i = 1; i < 64; ++i) grid.push_back(i / 64.0f);
  for (float a : grid)
    for (float b : grid) {
      const Vec3T<float> warped[] = {sample_uniform_hemisphere(a, b), sample_cosine_hemisphere(a, b),
                                     sample_uniform_sphere(a, b)};
      for (const Vec3T<float>& d : warped) {
        float len = std::sqrt(d.x * d.x + d.y * d.y + d.z * d.z);
        ASSERT_NEAR(len, 1.0f, 1e-6f) << a << ", " << b;
      }
      ASSERT_GE(sample_uniform_hemisphere(a, b).z, 0.0f);
      ASSERT_GT(sample_cosine_hemisphere(a, b).z, 0.0f) << "cosine samples never graze (u < 1)";
    }
}

// The SIMD instantiation (vfloatK, at the instruction-set level in use) draws
// the directions the scalar one draws, to within the difference of xsimd's
// and libm's sin/cos.
TEST(Warps, SimdLanesMatchTheScalarInstantiation) {
  const test::LaneProbes& probes = test::lane_probes(active_isa());
  UniformSource u(5);
  const size_t n = 4096 * probes.lanes;
  std::vector<float> a(n), b(n), x(n), y(n), z(n);
  for (size_t i = 0; i < n; ++i) {
    a[i] = u.next();
    b[i] = u.next();
  }
  for (int w = 0; w < 3; ++w) {
    probes.warp(w, a.data(), b.data(), n, x.data(), y.data(), z.data());
    for (size_t i = 0; i < n; ++i) {
      Vec3T<float> s = w == 0 ? sample_uniform_hemisphere(a[i], b[i])
                              : (w == 1 ? sample_cosine_hemisphere(a[i], b[i]) : sample_uniform_sphere(a[i], b[i]));
      ASSERT_NEAR(x[i], s.x, 2e-6f) << "warp " << w;
      ASSERT_NEAR(y[i], s.y, 2e-6f) << "warp " << w;
      ASSERT_NEAR(z[i], s.z, 2e-6f) << "warp " << w;
    }
  }
}

}  // namespace
}  // namespace pt::sampling_warps_test
