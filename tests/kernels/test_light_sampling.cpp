// Light samplers the engines use, at one lane (kernels/scene/lights.h,
// kernels/transport/direct_light.h). Area light: the sampled points are
// uniform over the parallelogram (chi-square), every pdf equals
// dist^2 / (area |cos|) computed independently, and the Monte Carlo solid angle
// and cosine-weighted solid angle of a rectangle match their closed forms;
// light only on the emitting side; the test that lets a batch of points skip
// a light rules out only points that no sample reaches. Sky: chi-square
// against the uniform upper hemisphere. Point lights: exact direction and
// distance.
//
// Chi-square tests: 2^20 samples (fixed-seed mt19937), 16 x 16 or 16 x 32
// bins plus an overflow bin of expected 0, significance level 1e-6. Power:
// with 255 (511) degrees of freedom a noncentrality of 178 (238) is rejected
// with probability 0.95, so a density off by 1.3% (1.5%) of itself in every
// bin, or by 21% (34%) in a single bin, is detected.
// Closed-form comparisons: |mean - exact| <= 5 SE (false failure 5.7e-7 each),
// with SE < 0.2% of the exact value, so that a 1.3% bias is detected with
// probability 0.95 at the 5-sigma bound (measured SE 0.007-0.009%: 0.06%).
#include <cmath>
#include <cstdio>
#include <numbers>

#include <gtest/gtest.h>

#include "kernels/scene/lights.h"
#include "kernels/transport/direct_light.h"
#include "support/sampling_histogram.h"
#include "support/statistics.h"

namespace pt {
namespace {

using test::UniformSource;

constexpr int kSamples = 1 << 20;
constexpr double kAlpha = 1e-6;

AreaLight make_area_light(float3 position, float3 dim_x, float3 dim_y, float3 direction, float3 radiance) {
  float3 n = cross(dim_x, dim_y);
  return {position, dim_x, dim_y, normalize(direction), radiance, length(n)};
}

// A tilted, skewed parallelogram above and to the side of the shading point,
// facing down (dim_x x dim_y points to -y).
const AreaLight kSkewed = make_area_light({0.4f, 2.0f, -0.3f}, {1.2f, 0.3f, 0.0f}, {0.5f, 0.1f, 0.8f},
                                          cross(float3{1.2f, 0.3f, 0.0f}, float3{0.5f, 0.1f, 0.8f}), {3, 2, 1});
const float3 kShadingPoint{0.1f, 0.0f, 0.2f};

/// One area-light sample at one lane, as the engines draw it.
struct AreaSample {
  float3 wi;
  float dist, pdf;
  bool facing;
};
AreaSample area_sample(const AreaLight& l, const float3& p, float u1, float u2) {
  AreaLightSampleT<float> s = sample_area_light<float>(l, p.x, p.y, p.z, u1, u2);
  return {{s.wi.x, s.wi.y, s.wi.z}, s.dist, s.pdf, s.facing};
}

/// (s, t) in [0,1]^2 with q = position + dim_x (s - 1/2) + dim_y (t - 1/2), by least squares in double.
void light_coordinates(const AreaLight& l, const float3& q, double& s, double& t) {
  double r[3], a[3], b[3];
  for (int i = 0; i < 3; ++i) {
    r[i] = double(q[i]) - l.position[i];
    a[i] = l.dim_x[i];
    b[i] = l.dim_y[i];
  }
  double aa = 0, ab = 0, bb = 0, ar = 0, br = 0;
  for (int i = 0; i < 3; ++i) {
    aa += a[i] * a[i];
    ab += a[i] * b[i];
    bb += b[i] * b[i];
    ar += a[i] * r[i];
    br += b[i] * r[i];
  }
  double det = aa * bb - ab * ab;
  s = (ar * bb - br * ab) / det + 0.5;
  t = (br * aa - ar * ab) / det + 0.5;
}

// The point behind each sample (p + wi dist) must be uniform over the light.
// Catches: u in [0, 1) used without centring (the light shifts by half its
// size, samples land in the overflow bin); a warp that is not linear in u;
// dist or wi that do not lead back to the light.
TEST(AreaLightSampling, PointsAreUniformOverTheParallelogram) {
  const int n = 16;
  std::vector<double> counts(n * n + 1, 0.0), expected(n * n + 1, double(kSamples) / (n * n));
  expected.back() = 0.0;
  UniformSource u(21);
  for (int i = 0; i < kSamples; ++i) {
    float u1 = u.next(), u2 = u.next();
    AreaSample ls = area_sample(kSkewed, kShadingPoint, u1, u2);
    double s, t;
    light_coordinates(kSkewed, kShadingPoint + ls.wi * ls.dist, s, t);
    const double slack = 1e-5;  // float rounding of the sample point
    if (s < -slack || s > 1 + slack || t < -slack || t > 1 + slack) {
      ++counts.back();
      continue;
    }
    int is = std::clamp(int(s * n), 0, n - 1), it = std::clamp(int(t * n), 0, n - 1);
    ++counts[is * n + it];
  }
  test::ChiSquareResult r = test::chi_square_test(counts, expected);
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
}

// Each sample's pdf against dist^2 / (|dim_x x dim_y| |cos|) computed here in
// double, and against area_light_pdf. Catches a missing cos, dist instead of
// dist^2, the area of the unit square instead of the light's.
TEST(AreaLightSampling, PdfIsTheSolidAngleDensityOfUniformAreaSampling) {
  UniformSource u(22);
  const float3 normal = normalize(cross(kSkewed.dim_x, kSkewed.dim_y));
  const double area = length(cross(kSkewed.dim_x, kSkewed.dim_y));
  for (int i = 0; i < 100000; ++i) {
    float u1 = u.next(), u2 = u.next();
    AreaSample ls = area_sample(kSkewed, kShadingPoint, u1, u2);
    ASSERT_NEAR(length(ls.wi), 1.0f, 1e-6f);
    double cos_light = std::fabs(dot(ls.wi, normal));
    double pdf = double(ls.dist) * ls.dist / (area * cos_light);
    ASSERT_NEAR(ls.pdf, pdf, 1e-5 * pdf) << i;
    ASSERT_NEAR(area_light_pdf(kSkewed, ls.wi, ls.dist), pdf, 1e-5 * pdf) << i;
    ASSERT_TRUE(ls.facing) << "the point faces the emitting side";
  }
}

// A rectangle a x b parallel to the shading plane, centred at height d above
// the point: E[1 / pdf] is its solid angle 4 asin(ab / sqrt((a^2 + 4d^2)(b^2 + 4d^2)))
// and E[cos / pdf] is pi times the point-to-rectangle form factor (four corner
// rectangles). Catches any error in the pdf's value that the sampler's own
// formula would share (a wrong area, a wrong power of the distance).
TEST(AreaLightSampling, SolidAngleAndIrradianceMatchClosedForms) {
  const double a = 1.2, b = 0.8, d = 1.5;
  const AreaLight l = make_area_light({0, float(d), 0}, {float(a), 0, 0}, {0, 0, float(b)}, {0, -1, 0}, {1, 1, 1});
  const double solid_angle = 4 * std::asin(a * b / std::sqrt((a * a + 4 * d * d) * (b * b + 4 * d * d)));
  auto corner = [&](double x, double y) {
    double A = x / d, B = y / d, sa = std::sqrt(1 + A * A), sb = std::sqrt(1 + B * B);
    return 0.5 * (A / sa * std::atan(B / sa) + B / sb * std::atan(A / sb));
  };
  const double projected = 4 * corner(a / 2, b / 2);
  std::vector<double> inv_pdf, cos_over_pdf;
  UniformSource u(23);
  for (int i = 0; i < kSamples; ++i) {
    float u1 = u.next(), u2 = u.next();
    AreaSample ls = area_sample(l, {0, 0, 0}, u1, u2);
    inv_pdf.push_back(1.0 / ls.pdf);
    cos_over_pdf.push_back(ls.wi.y / ls.pdf);
  }
  test::MeanError omega = test::mean_and_error(inv_pdf), proj = test::mean_and_error(cos_over_pdf);
  EXPECT_LT(std::fabs(test::z_score(omega, solid_angle)), test::kZ5) << omega.mean << " vs " << solid_angle;
  EXPECT_LT(std::fabs(test::z_score(proj, projected)), test::kZ5) << proj.mean << " vs " << projected;
  EXPECT_LT(omega.standard_error, 2e-3 * solid_angle);
  EXPECT_LT(proj.standard_error, 2e-3 * projected);
  std::printf("solid angle SE %.3g%%, projected SE %.3g%% of exact\n", 100 * omega.standard_error / solid_angle,
              100 * proj.standard_error / projected);
}

// Facing only where dot(sample - p, direction) < 0, and never with a NaN or an
// infinite pdf (points in the light's plane).
TEST(AreaLightSampling, EmitsOnlyTowardsItsDirection) {
  const AreaLight l = make_area_light({0, 1, 0}, {1, 0, 0}, {0, 0, 1}, {0, -1, 0}, {5, 5, 5});
  UniformSource u(24);
  for (int i = 0; i < 10000; ++i) {
    float u1 = u.next(), u2 = u.next();
    EXPECT_TRUE(area_sample(l, {0.2f, 0, 0.1f}, u1, u2).facing);
    EXPECT_FALSE(area_sample(l, {0.2f, 2, 0.1f}, u1, u2).facing) << "behind the light";
    EXPECT_FALSE(area_sample(l, {3, 1, 0}, u1, u2).facing) << "in the light's plane";
  }
}

/// Whether some sample of the area light reaches shading point sp as
/// sample_light_sources lets it through: facing it and above both normals
/// (the same tests, in the same float operations). 4096 random samples and
/// the four corners.
bool some_sample_passes(const AreaLight& l, const ShadingPointT<float>& sp, UniformSource& u) {
  const float last = 0x1.fffffep-1f;  // the largest u below 1
  const float corners[4][2] = {{0.0f, 0.0f}, {last, 0.0f}, {0.0f, last}, {last, last}};
  for (int i = 0; i < 4096 + 4; ++i) {
    const float u1 = i < 4 ? corners[i][0] : u.next(), u2 = i < 4 ? corners[i][1] : u.next();
    AreaLightSampleT<float> s = sample_area_light<float>(l, sp.p.x, sp.p.y, sp.p.z, u1, u2);
    if (s.facing && dot3(sp.ns, s.wi) > 0.0f && dot3(sp.ng, s.wi) > 0.0f) return true;
  }
  return false;
}

Vec3T<float> random_unit(UniformSource& u) {
  const float u1 = u.next();  // one statement each: the order of the draws is fixed
  const float u2 = u.next();
  const bool down = u.next() < 0.5f;
  Vec3T<float> w = sample_uniform_hemisphere(u1, u2);
  return down ? Vec3T<float>{w.x, w.y, -w.z} : w;
}

// area_light_may_reach, which lets sample_light_sources skip a light for a
// batch of points that none of its samples can reach, rules out only such
// points: for kSkewed and for a light whose direction leans off its plane's
// normal (so that its own direction varies over the parallelogram), 30,000
// random points each, a third within 2e-6 of the light's plane (the
// rounding's scale), a third within 2e-3 (its margin's) and a third farther,
// on both sides and out to half the light's size beyond its outline, with
// random normals; every point it rules out is sampled 4100 times and never
// reached. It fails with the margin at 1e-8 of the coordinates or none
// instead of 1e-4, and with either spread over the parallelogram (of the
// light's direction or of a normal) taken with the wrong sign. And it does
// rule out what it is for: the ceiling of a Cornell box above its light, and
// points whose normals face away.
TEST(AreaLightSampling, RuledOutPointsGetNoSample) {
  const float3 ex{1.2f, 0.3f, 0.0f}, ey{0.5f, 0.1f, 0.8f};
  const AreaLight leaning = make_area_light({0.4f, 2.0f, -0.3f}, ex, ey, cross(ex, ey) + ex * 0.8f, {3, 2, 1});
  for (const AreaLight& l : {kSkewed, leaning}) {
    UniformSource u(26);
    int ruled_out = 0;
    for (int i = 0; i < 30000; ++i) {
      const float s = 2.0f * u.next() - 0.5f;
      const float t = 2.0f * u.next() - 0.5f;
      const float band = i % 3 == 0 ? 2e-6f : i % 3 == 1 ? 2e-3f : 2.0f;
      const float h = band * (2.0f * u.next() - 1.0f);  // along the light's direction, either side
      const float3 q = l.position + l.dim_x * (s - 0.5f) + l.dim_y * (t - 0.5f) + l.direction * h;
      const Vec3T<float> ng = random_unit(u);
      Vec3T<float> ns = random_unit(u);
      if (dot3(ns, ng) < 0.0f) ns = {-ns.x, -ns.y, -ns.z};  // as surfaces keep them
      const ShadingPointT<float> sp{{q.x, q.y, q.z}, ng, ns, 0.0f, true};
      if (area_light_may_reach(l, sp)) continue;
      ++ruled_out;
      ASSERT_FALSE(some_sample_passes(l, sp, u)) << "point " << q.x << " " << q.y << " " << q.z << " ruled out";
    }
    EXPECT_GT(ruled_out, 7500);  // half the points lie behind the light, and half of the others face away
  }

  const AreaLight ceiling_light = make_area_light({0, 1.49f, 0}, {0.8f, 0, 0}, {0, 0, 0.6f}, {0, -1, 0}, {1, 1, 1});
  const Vec3T<float> down{0, -1, 0}, up{0, 1, 0};
  EXPECT_FALSE(area_light_may_reach(ceiling_light, ShadingPointT<float>{{0.3f, 1.5f, 0.2f}, down, down, 0.0f, true}))
      << "the ceiling, 0.01 above the light";
  EXPECT_FALSE(area_light_may_reach(ceiling_light, ShadingPointT<float>{{0.3f, 0.5f, 0.2f}, down, down, 0.0f, true}))
      << "facing away, below the light";
  EXPECT_TRUE(area_light_may_reach(ceiling_light, ShadingPointT<float>{{0.3f, 0.0f, 0.2f}, up, up, 0.0f, true}))
      << "the floor";
  EXPECT_FALSE(area_light_may_reach(ceiling_light, ShadingPointT<float>{{0.3f, 0.0f, 0.2f}, up, up, 0.0f, false}))
      << "a lane that does not shade";
}

// Stated: uniform over the +Y hemisphere (pdf 1 / (2 pi), which direct_light.h
// divides by). Histogram of (y, atan2(z, x)). Catches the
// pole left on local z (+Z in world: half the samples below the horizon fill
// the overflow bin) and a cosine-weighted warp.
TEST(SkyLightSampling, UniformOverTheUpperHemisphere) {
  const SkyLight sky{{0.3f, 0.6f, 0.9f}};
  test::DirectionHistogram h(16, 32, 0.0);
  UniformSource u(25);
  for (int i = 0; i < kSamples; ++i) {
    float u1 = u.next(), u2 = u.next();
    Vec3T<float> wi = sample_sky_direction(u1, u2);
    h.add(wi.x, wi.z, wi.y);
  }
  test::ChiSquareResult r =
      test::chi_square_test(h.counts(), h.expected(kSamples, [](double z0, double z1, double p0, double p1) {
        return (z1 - z0) * (p1 - p0) / (2 * std::numbers::pi);
      }));
  EXPECT_GT(r.p_value, kAlpha) << r.summary;
  EXPECT_EQ(sky_radiance(sky, {0, 1, 0}), sky.radiance);
  EXPECT_TRUE(is_black(sky_radiance(sky, {0, -1, 0})));
  EXPECT_TRUE(is_black(sky_radiance(sky, {1, 0, 0}))) << "the horizon itself is not sky";
}

// A point light's sample: the unit direction to it and its distance (the
// course's convention of no distance falloff is checked by rendering, in
// tests/engines/test_direct_light_closed_form.cpp).
TEST(DeltaLightSampling, PointLightDirectionAndDistance) {
  const PointLight pl{{1, 4, 2}, {2, 3, 4}};
  for (float3 p : {float3{1, 3.9f, 2}, float3{0, 0, 0}, float3{-500, 100, 800}}) {
    DeltaLightSampleT<float> ls = sample_point_light<float>(pl, Vec3T<float>{p.x, p.y, p.z});
    float3 d = pl.position - p, wi{ls.wi.x, ls.wi.y, ls.wi.z};
    EXPECT_TRUE(ls.ok);
    EXPECT_NEAR(ls.dist, length(d), 1e-6f * length(d));
    EXPECT_NEAR(dot(wi, normalize(d)), 1.0f, 1e-6f);
  }
  EXPECT_FALSE(sample_point_light<float>(pl, Vec3T<float>{1, 4, 2}).ok) << "at the light itself";
}

}  // namespace
}  // namespace pt
