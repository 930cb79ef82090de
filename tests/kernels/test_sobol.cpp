// The default sampler, Owen-scrambled Sobol points (kernels/math/sobol.h):
//  - exact: Sobol dimension 1 from its superset transform equals the
//    direction-number definition; bit reversal; the SIMD lanes of the level in
//    use equal the scalar points bit for bit;
//  - exact: the first 2^k points of a pixel's dimension pair, and any aligned
//    block of 2^k of them, are (0, k, 2)-nets (one point in every elementary
//    interval of area 2^-k), and a 1D dimension has one point in each of 2^k
//    intervals: the stratification a pixel keeps at every power of two;
//  - statistical: the hash scrambling has the error of true nested uniform
//    scrambling (a fair coin per node of the binary tree), on a step and across
//    two dimension pairs (which catches pairs that share their shuffle);
//  - rendered: on pixels straddling a step in radiance (the edges of emitters
//    seen directly), the error of every engine falls faster than 1/sqrt(N)
//    over N = 16..1024 (independent numbers, the power check, do not), and the
//    estimate is unbiased against the exact covered fraction.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "support/engines_under_test.h"
#include "kernels/scene/camera.h"
#include "kernels/simd/isa.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/math/sobol.h"
#include "support/lane_probes.h"
#include "support/scene_builders.h"
#include "support/statistics.h"

namespace pt {
namespace {

// ------------------------------------------------------------ exact structure

/// Sobol dimension 1 from its direction numbers (primitive polynomial x + 1):
/// v[0] = 2^31, v[k] = v[k-1] ^ (v[k-1] >> 1); the point is the xor of v[b]
/// over the index's set bits b.
uint32_t sobol_dimension1_by_definition(uint32_t index) {
  uint32_t v = 1u << 31, x = 0;
  for (int bit = 0; bit < 32; ++bit, v ^= v >> 1)
    if (index >> bit & 1u) x ^= v;
  return x;
}

TEST(Sobol, DimensionOneEqualsItsDirectionNumbers) {
  for (uint32_t i = 0; i < (1u << 20); ++i) ASSERT_EQ(sobol_dimension1(i), sobol_dimension1_by_definition(i)) << i;
  for (uint32_t k = 0, i = 12345; k < (1u << 20); ++k, i = hash32(i))
    ASSERT_EQ(sobol_dimension1(i), sobol_dimension1_by_definition(i)) << i;
}

TEST(Sobol, ReverseBits) {
  for (uint32_t k = 0, x = 1; k < (1u << 20); ++k, x = hash32(x + k)) {
    uint32_t r = 0;
    for (int b = 0; b < 32; ++b) r |= (x >> b & 1u) << (31 - b);
    ASSERT_EQ(reverse_bits32(x), r);
    ASSERT_EQ(reverse_bits32<uint64_t>(x) & 0xFFFFFFFFu, r);  // the generic lane form
  }
}

RenderSettings sobol_settings(uint32_t seed = 3) {
  return RenderSettings{.sampler = PixelSampler::kSobol, .seed = seed};
}

// The SIMD stages draw exactly the scalar points (the level in use).
TEST(Sobol, SimdLanesEqualTheScalarPoints) {
  const test::LaneProbes& probes = test::lane_probes(active_isa());
  const size_t n = 65536 / probes.lanes * probes.lanes;
  std::vector<uint32_t> pixels(n), samples(n);
  std::vector<float> u(n), v(n), w(n);
  for (uint32_t i = 0; i < n; ++i) {
    pixels[i] = hash32(i) % 100000u;
    samples[i] = i % 7 == 0 ? hash32(i * 3u) : i / 5;  // also indices with high bits set
  }
  const RenderSettings rs = sobol_settings();
  for (uint32_t bounce : {0u, 3u}) {
    probes.sobol_points(rs.seed, pixels.data(), samples.data(), bounce, 1, n, u.data(), v.data(), w.data());
    for (size_t i = 0; i < n; ++i) {
      PathSampler ps(rs, pixels[i], samples[i]);
      float a, b;
      ps.get2d(bounce, 1, a, b);
      ASSERT_EQ(u[i], a) << "lane " << i % probes.lanes;
      ASSERT_EQ(v[i], b) << "lane " << i % probes.lanes;
      ASSERT_EQ(w[i], ps.get1d(bounce, 3)) << "lane " << i % probes.lanes;
    }
  }
}

/// Whether points [first, first + 2^k) of a pixel's pair (bounce, dim) put one
/// point in every elementary interval 2^-a x 2^-(k-a), a = 0..k, and the 1D
/// dimension (bounce, dim + 2) one in each of 2^k intervals.
::testing::AssertionResult is_net(const RenderSettings& rs, uint32_t pixel, uint32_t bounce, uint32_t dim,
                                  uint32_t first, int k) {
  const uint32_t n = 1u << k;
  std::vector<float> x(n), y(n), z(n);
  for (uint32_t i = 0; i < n; ++i) {
    PathSampler ps(rs, pixel, first + i);
    ps.get2d(bounce, dim, x[i], y[i]);
    z[i] = ps.get1d(bounce, dim + 2);
  }
  for (int a = 0; a <= k; ++a) {
    std::vector<uint8_t> seen(n, 0);
    for (uint32_t i = 0; i < n; ++i) {
      uint32_t cell = uint32_t(std::ldexp(x[i], a)) << (k - a) | uint32_t(std::ldexp(y[i], k - a));
      if (seen[cell]++)
        return ::testing::AssertionFailure() << "two points in one " << (1u << a) << " x " << (1u << (k - a))
                                             << " interval (points " << first << ".." << first + n - 1 << ")";
    }
  }
  std::vector<uint8_t> seen(n, 0);
  for (uint32_t i = 0; i < n; ++i)
    if (seen[uint32_t(std::ldexp(z[i], k))]++)
      return ::testing::AssertionFailure() << "two 1D points in one interval of 2^-" << k;
  return ::testing::AssertionSuccess();
}

// Catches: a shuffle that does not map aligned blocks onto aligned blocks (an
// xor of the whole index with a hash of the sample, or a plain hash), a
// scramble that is not nested (bit k depending on higher bits), a wrong
// dimension-1 matrix, and a float conversion that loses the top bits.
TEST(Sobol, EveryPowerOfTwoPrefixAndAlignedBlockIsANet) {
  for (uint32_t seed : {0u, 3u, 77u}) {
    const RenderSettings rs = sobol_settings(seed);
    for (uint32_t pixel : {0u, 1u, 479u, 172799u})
      for (uint32_t bounce : {0u, 1u, 5u})
        for (uint32_t dim : {0u, 3u}) {
          for (int k = 0; k <= 12; ++k) ASSERT_TRUE(is_net(rs, pixel, bounce, dim, 0, k)) << "prefix 2^" << k;
          ASSERT_TRUE(is_net(rs, pixel, bounce, dim, 64, 6));
          ASSERT_TRUE(is_net(rs, pixel, bounce, dim, 3 * 1024, 10));
        }
  }
}

// Power: independent numbers are not nets (the first 64 points of a pair put
// two points in one interval somewhere, with overwhelming probability).
TEST(Sobol, TheNetCheckRejectsIndependentNumbers) {
  RenderSettings rs = sobol_settings();
  rs.sampler = PixelSampler::kIndependent;
  EXPECT_FALSE(is_net(rs, 5, 1, 0, 0, 6));
}

// ------------------------------------------------------- scrambling quality

/// True nested uniform scrambling of x's top `levels` bits, most significant
/// first: bit 31 - k flips by a fair coin drawn from a strong hash of the k
/// bits above it, the level and the seed (an independent coin per node of the
/// binary tree).
uint32_t true_owen_scramble(uint32_t x, uint32_t seed, int levels = 32) {
  uint32_t out = x;
  for (int k = 0; k < levels; ++k) {
    const uint32_t above = k == 0 ? 0u : x >> (32 - k);
    const uint32_t coin = hash32(hash32(above ^ hash32(seed + uint32_t(k) * 0x9e3779b9u)) ^ uint32_t(k));
    out ^= (coin & 1u) << (31 - k);
  }
  return out;
}

/// Point `index` of a 2D sequence scrambled by true nested uniform scrambling:
/// the shuffle, then each coordinate, with three independent seeds.
void true_owen_point(uint32_t index, uint32_t seed, float& u, float& v) {
  const uint32_t i = true_owen_scramble(index, hash32(seed ^ 0x1u));
  // A coordinate's bits below the top 24 never reach its float.
  u = bits_to_unit<uint32_t, float>(true_owen_scramble(reverse_bits32(i), hash32(seed ^ 0x2u), 24));
  v = bits_to_unit<uint32_t, float>(true_owen_scramble(sobol_dimension1(i), hash32(seed ^ 0x3u), 24));
}

void hashed_point(uint32_t index, uint32_t seed, float& u, float& v) {
  owen_sobol_2d<uint32_t, float>(index, seed, u, v);
}

/// Squared errors over `pixels` independent seeds of an N-point estimate of
/// integrand(point of pair A, point of pair B), whose exact value is `exact`;
/// the two pairs have the seeds a pixel's dimension pairs get.
template <class Point, class F>
std::vector<double> squared_errors(Point&& point, F&& integrand, double exact, uint32_t n, uint32_t pixels) {
  std::vector<double> e(pixels);
  for (uint32_t p = 0; p < pixels; ++p) {
    const uint32_t pixel = pixel_key<uint32_t>(1, p);
    const uint32_t seed_a = hash32(pixel ^ dimension_key(1, 0)), seed_b = hash32(pixel ^ dimension_key(1, 3));
    double sum = 0.0;
    for (uint32_t i = 0; i < n; ++i) {
      float ax, ay, bx, by;
      point(i, seed_a, ax, ay);
      point(i, seed_b, bx, by);
      sum += integrand(ax, ay, bx, by);
    }
    e[p] = (sum / n - exact) * (sum / n - exact);
  }
  return e;
}

/// The ratio of the mean squared errors a / b and its standard error (delta
/// method over independent seeds).
struct Ratio {
  double value, standard_error;
};
Ratio mse_ratio(const std::vector<double>& a, const std::vector<double>& b) {
  test::MeanError ma = test::mean_and_error(a), mb = test::mean_and_error(b);
  double r = ma.mean / mb.mean;
  double rel = std::sqrt(std::pow(ma.standard_error / ma.mean, 2) + std::pow(mb.standard_error / mb.mean, 2));
  return {r, r * rel};
}

// The hash scrambling (2 multiplies per Laine-Karras permutation, scramble
// seeds derived from one hash) has the error of true Owen scrambling at 256
// points, over 4096 seeds: |ratio - 1| < 5 standard errors (false failure
// 5.7e-7 per check under the normal approximation of the delta method), and
// the standard error is below 5%, so an error 33% higher or lower is caught
// with probability 0.95 (measured SE 2.9% on the step, 4.8% on the cross
// term: 19% and 32%).
// The step (x + y < 1.3 on pair A) checks the scramble of one pair; the cross
// term (x_A < x_B) checks that two pairs are independent: pairs sharing their
// shuffle (the same seed, or seeds differing by a constant xor) give it about
// 4x the error (shuffles are what decorrelates the pairs).
TEST(Sobol, HashScramblingHasTheErrorOfTrueOwenScrambling) {
  constexpr uint32_t kN = 256, kPixels = 4096;
  auto step = [](float ax, float ay, float, float) { return ax + ay < 1.3f ? 1.0 : 0.0; };
  auto cross = [](float ax, float, float bx, float) { return ax < bx ? 1.0 : 0.0; };
  const double step_exact = 1.0 - 0.7 * 0.7 / 2.0;
  for (auto [name, integrand, exact] : {std::tuple{"step", +step, step_exact}, std::tuple{"cross", +cross, 0.5}}) {
    Ratio r = mse_ratio(squared_errors(hashed_point, integrand, exact, kN, kPixels),
                        squared_errors(true_owen_point, integrand, exact, kN, kPixels));
    EXPECT_LT(std::fabs(r.value - 1.0), test::kZ5 * r.standard_error)
        << name << ": MSE ratio " << r.value << " +- " << r.standard_error;
    EXPECT_LT(r.standard_error, 0.05) << name;
    std::printf("%s: MSE ratio hashed / true Owen %.4f +- %.4f\n", name, r.value, r.standard_error);
  }
  // Power: pairs that share one shuffle (each still scrambled by its own seed)
  // are caught on the cross term.
  auto shared = [](uint32_t index, uint32_t seed, float& u, float& v) {
    const uint32_t i = nested_uniform_scramble(index, 0x5eedu);
    u = bits_to_unit<uint32_t, float>(reverse_bits32(laine_karras_permutation(i, hash32(seed))));
    v = bits_to_unit<uint32_t, float>(
        reverse_bits32(laine_karras_permutation(sobol_dimension1_reversed(i), hash32(seed ^ 1u))));
  };
  Ratio r = mse_ratio(squared_errors(shared, cross, 0.5, kN, kPixels),
                      squared_errors(true_owen_point, cross, 0.5, kN, kPixels));
  EXPECT_GT(std::fabs(r.value - 1.0), test::kZ5 * r.standard_error) << "shared shuffle: MSE ratio " << r.value;
}

// ------------------------------------------------- rendered step in radiance

constexpr int kImage = 64;
constexpr float kRadiance = 1.0f;

/// Parallel emitting strips in the plane z = 0, rotated so that their edges
/// cross the pixel grid at an angle, seen head-on from z = 2 (so the map from
/// the film to the plane is affine).
struct Vec2 {
  float x, y;
  Vec2 operator*(float s) const { return {x * s, y * s}; }
};

struct Strips {
  static constexpr int kCount = 6;
  static constexpr float kAngle = 0.37f, kHalfWidth = 0.03f, kHalfLength = 0.8f, kSpacing = 0.25f;
  Vec2 along{std::cos(kAngle), std::sin(kAngle)}, across{-std::sin(kAngle), std::cos(kAngle)};
  Vec2 centre(int k) const { return across * (kSpacing * (k - 0.5f * (kCount - 1))); }

  Scene scene() const {
    Scene s;
    for (int k = 0; k < kCount; ++k) {
      Vec2 c = centre(k);
      test::add_area_light(s, {c.x, c.y, 0}, float3{along.x, along.y, 0} * (2 * kHalfLength),
                           float3{across.x, across.y, 0} * (2 * kHalfWidth), {0, 0, 1}, float3(kRadiance));
    }
    test::finish_scene(s);
    return s;
  }
};

using Polygon = std::vector<std::array<double, 2>>;

/// The part of `poly` where dot(q, n) <= d (Sutherland-Hodgman).
Polygon clip(const Polygon& poly, double nx, double ny, double d) {
  Polygon out;
  for (size_t i = 0; i < poly.size(); ++i) {
    auto a = poly[i], b = poly[(i + 1) % poly.size()];
    double da = a[0] * nx + a[1] * ny - d, db = b[0] * nx + b[1] * ny - d;
    if (da <= 0) out.push_back(a);
    if ((da < 0) != (db < 0) && da != db) {
      double t = da / (da - db);
      out.push_back({a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])});
    }
  }
  return out;
}

double area(const Polygon& poly) {
  double twice = 0.0;
  for (size_t i = 0; i < poly.size(); ++i) {
    auto a = poly[i], b = poly[(i + 1) % poly.size()];
    twice += a[0] * b[1] - a[1] * b[0];
  }
  return std::fabs(twice) / 2.0;
}

/// The exact fraction of each pixel covered by the strips: the pixel's
/// corners mapped to the plane through the camera, clipped by each strip.
std::vector<double> covered_fractions(const Strips& strips, const Camera& cam) {
  std::vector<double> fraction(kImage * kImage);
  auto on_plane = [&](double sx, double sy) {
    Vec3T<float> d = camera_ray_direction(cam, float(sx), float(sy));
    double t = -double(cam.position.z) / d.z;
    return std::array<double, 2>{cam.position.x + t * d.x, cam.position.y + t * d.y};
  };
  for (int y = 0; y < kImage; ++y)
    for (int x = 0; x < kImage; ++x) {
      const double x0 = double(x) / kImage, x1 = double(x + 1) / kImage;
      const double y0 = 1.0 - double(y) / kImage, y1 = 1.0 - double(y + 1) / kImage;
      Polygon pixel = {on_plane(x0, y0), on_plane(x1, y0), on_plane(x1, y1), on_plane(x0, y1)};
      double covered = 0.0;
      for (int k = 0; k < Strips::kCount; ++k) {
        Vec2 c = strips.centre(k);
        double ca = c.x * strips.along.x + c.y * strips.along.y, cc = c.x * strips.across.x + c.y * strips.across.y;
        Polygon p = clip(pixel, strips.along.x, strips.along.y, ca + Strips::kHalfLength);
        p = clip(p, -strips.along.x, -strips.along.y, -ca + Strips::kHalfLength);
        p = clip(p, strips.across.x, strips.across.y, cc + Strips::kHalfWidth);
        p = clip(p, -strips.across.x, -strips.across.y, -cc + Strips::kHalfWidth);
        if (p.size() >= 3) covered += area(p);
      }
      fraction[size_t(y) * kImage + x] = covered / area(pixel);
    }
  return fraction;
}

struct EdgeErrors {
  double rmse;           ///< over the pixels that straddle an edge
  test::MeanError bias;  ///< of (estimate - exact) over those pixels
};

EdgeErrors edge_errors(const test::EngineUnderTest& e, const Scene& s, const Camera& cam,
                       const std::vector<double>& exact, PixelSampler sampler, int spp) {
  RenderSettings rs = test::fixed_settings(kImage, kImage, spp);
  rs.max_depth = 0;  // what the camera sees
  rs.sampler = sampler;
  Film film = e.render(s, cam, rs).film;
  std::vector<double> errors;
  for (size_t i = 0; i < exact.size(); ++i)
    if (exact[i] > 1e-3 && exact[i] < 1 - 1e-3) errors.push_back(film.radiance[i].x - kRadiance * exact[i]);
  double sq = 0.0;
  for (double d : errors) sq += d * d;
  return {std::sqrt(sq / errors.size()), test::mean_and_error(errors)};
}

/// Least-squares slope of log(rmse) against log(N).
double log_log_slope(const std::vector<int>& n, const std::vector<double>& rmse) {
  double mx = 0, my = 0;
  for (size_t i = 0; i < n.size(); ++i) mx += std::log(n[i]) / n.size(), my += std::log(rmse[i]) / n.size();
  double sxy = 0, sxx = 0;
  for (size_t i = 0; i < n.size(); ++i) {
    sxy += (std::log(n[i]) - mx) * (std::log(rmse[i]) - my);
    sxx += (std::log(n[i]) - mx) * (std::log(n[i]) - mx);
  }
  return sxy / sxx;
}

// Each straddling pixel estimates the area of a straight edge's side within
// it. Independent samples: RMSE ~ N^-0.5. Owen-scrambled nets: MSE ~ N^-1.5,
// RMSE ~ N^-0.75. The test asks for a slope below -0.65 for the default
// sampler and, as its power check, above -0.6 for independent numbers; over
// about 600 straddling pixels each RMSE is known to about 3%, so the fitted
// slope to about 0.01. At 1024 samples the estimate is unbiased: |mean error|
// < 5 standard errors (false failure 5.7e-7 per engine), with a standard
// error below 1e-3 of the radiance, so a bias of 0.66% of it is caught with
// probability 0.95 (measured SE 6e-5 of it: a bias of 0.04%).
TEST(Sobol, ErrorAtAStepInRadianceFallsFasterThanIndependentSampling) {
  const Strips strips;
  const Scene s = strips.scene();
  const Camera cam = test::look_at({0, 0, 2}, {0, 0, 0}, 0.5f, 0.5f);
  const std::vector<double> exact = covered_fractions(strips, cam);
  const int straddling =
      static_cast<int>(std::count_if(exact.begin(), exact.end(), [](double f) { return f > 1e-3 && f < 1 - 1e-3; }));
  ASSERT_GT(straddling, 500);
  const std::vector<int> counts = {16, 64, 256, 1024};
  for (const test::EngineUnderTest& e : test::engines_under_test()) {
    std::vector<double> rmse;
    EdgeErrors last{};
    for (int n : counts) {
      last = edge_errors(e, s, cam, exact, RenderSettings{}.sampler, n);
      rmse.push_back(last.rmse);
    }
    const double slope = log_log_slope(counts, rmse);
    EXPECT_LT(slope, -0.65) << e.name << ": RMSE " << rmse[0] << " .. " << rmse[3];
    EXPECT_LT(std::fabs(test::z_score(last.bias, 0.0)), test::kZ5)
        << e.name << ": mean error " << last.bias.mean << " +- " << last.bias.standard_error;
    EXPECT_LT(last.bias.standard_error, 1e-3 * kRadiance) << e.name;
    std::printf("%s: RMSE slope %.3f, mean error at 1024 samples %.3g +- %.3g of the radiance\n", e.name.c_str(), slope,
                last.bias.mean / kRadiance, last.bias.standard_error / kRadiance);
  }
  std::vector<double> rmse;
  for (int n : counts)
    rmse.push_back(edge_errors(test::engines_under_test()[1], s, cam, exact, PixelSampler::kIndependent, n).rmse);
  EXPECT_GT(log_log_slope(counts, rmse), -0.6) << "independent numbers: RMSE " << rmse[0] << " .. " << rmse[3];
}

}  // namespace
}  // namespace pt
