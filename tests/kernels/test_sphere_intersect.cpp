// Sphere test (kernels/scene/sphere_intersect.h): hand-computed hits from outside
// and inside, the nearest root in [tmin, tmax), tangent and near-tangent rays,
// misses, unnormalised directions, and the precision for small spheres far
// from the origin that the textbook quadratic loses.
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "kernels/math/ray.h"
#include "kernels/scene/sphere_intersect.h"

namespace pt {
namespace {

struct SphereHit {
  bool hit = false;
  float t = 0;
};

SphereHit hit_sphere(float3 org, float3 dir, float3 center, float radius, float tmin = 0.0f, float tmax = kInfinity) {
  SphereHit h;
  h.hit = intersect_sphere(org, dir, tmin, tmax, center, radius, h.t);
  return h;
}

TEST(SphereIntersect, FromOutsideTheNearRootIsReturned) {
  SphereHit h = hit_sphere({0, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 4.0f);
  h = hit_sphere({3, -2, 7}, {0, 1, 0}, {3, 4, 7}, 2.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 4.0f);
}

TEST(SphereIntersect, FromInsideTheFarRootIsReturned) {
  SphereHit h = hit_sphere({0, 0, 0}, {0, 0, 1}, {0, 0, 0}, 1.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 1.0f);
  h = hit_sphere({0, 0, 0.5f}, {0, 0, -1}, {0, 0, 0}, 2.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 2.5f);
}

TEST(SphereIntersect, DistanceIsInUnitsOfTheDirectionLength) {
  SphereHit h = hit_sphere({0, 0, -5}, {0, 0, 2}, {0, 0, 0}, 1.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 2.0f);
}

TEST(SphereIntersect, TRangeSelectsTheRootAndIsHalfOpen) {
  const float3 org{0, 0, -5}, dir{0, 0, 1}, c{0, 0, 0};
  const float above4 = std::nextafter(4.0f, 5.0f);
  EXPECT_FALSE(hit_sphere(org, dir, c, 1.0f, 0.0f, 4.0f).hit) << "t == tmax is outside";
  EXPECT_TRUE(hit_sphere(org, dir, c, 1.0f, 0.0f, above4).hit);
  SphereHit h = hit_sphere(org, dir, c, 1.0f, 4.0f, kInfinity);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 4.0f) << "t == tmin is inside";
  h = hit_sphere(org, dir, c, 1.0f, above4, kInfinity);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 6.0f) << "tmin past the near root gives the far root";
  EXPECT_FALSE(hit_sphere(org, dir, c, 1.0f, 0.0f, 3.0f).hit) << "both roots beyond tmax";
  EXPECT_FALSE(hit_sphere(org, dir, c, 1.0f, 6.5f, kInfinity).hit) << "both roots before tmin";
  EXPECT_FALSE(hit_sphere({0, 0, 5}, dir, c, 1.0f).hit) << "sphere behind the origin";
}

TEST(SphereIntersect, TangentRayTouchesAndAParallelRayJustOutsideMisses) {
  SphereHit h = hit_sphere({1, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_EQ(h.t, 5.0f);
  EXPECT_FALSE(hit_sphere({1.0001f, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f).hit);
  EXPECT_FALSE(hit_sphere({0, 2, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f).hit);
  EXPECT_FALSE(hit_sphere({0, 0, -5}, {0, 1, 0}, {0, 0, 0}, 1.0f).hit);
}

TEST(SphereIntersect, NearTangentRayHasTheAnalyticDistance) {
  // Offset 0.999 from the axis: the chord's half length is sqrt(1 - 0.999^2) = 0.0447.
  double off = 0.999, half = std::sqrt(1.0 - off * off);
  SphereHit h = hit_sphere({float(off), 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f);
  ASSERT_TRUE(h.hit);
  EXPECT_NEAR(h.t, 5.0 - half, 1e-5);
}

TEST(SphereIntersect, InvalidRaysMiss) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  EXPECT_FALSE(hit_sphere({0, 0, -5}, {nan, 0, 1}, {0, 0, 0}, 1.0f).hit);
  EXPECT_FALSE(hit_sphere({nan, 0, -5}, {0, 0, 1}, {0, 0, 0}, 1.0f).hit);
  EXPECT_FALSE(hit_sphere({0, 0, -5}, {0, 0, 0}, {0, 0, 0}, 1.0f).hit);
}

// A unit sphere 10^4 away, hit off-axis: the textbook discriminant b^2 - c subtracts two
// numbers near 1e8 (float spacing 8) whose difference is below 1, so it returns t wrong by
// up to about 3; the closest-approach form keeps t to float accuracy. Checked in double.
TEST(SphereIntersect, SmallSphereFarAwayKeepsItsPrecision) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> offset(-0.95f, 0.95f);
  const float3 center{0, 0, 1e4f};
  for (int i = 0; i < 1000; ++i) {
    float ox = offset(rng), oy = offset(rng);
    if (ox * ox + oy * oy > 0.9f) continue;
    float3 org{ox, oy, 0};
    SphereHit h = hit_sphere(org, {0, 0, 1}, center, 1.0f);
    ASSERT_TRUE(h.hit);
    double t_exact = 1e4 - std::sqrt(1.0 - double(ox) * ox - double(oy) * oy);
    // Float spacing at 1e4 is 9.8e-4: allow two ulps.
    ASSERT_NEAR(h.t, t_exact, 2e-3) << "offset (" << ox << ", " << oy << ")";
  }
}

TEST(SphereIntersect, HitPointsLieOnTheSphere) {
  std::mt19937 rng(5);
  std::normal_distribution<float> gauss;
  std::uniform_real_distribution<float> coord(-20.0f, 20.0f), radius(0.1f, 5.0f);
  int hits = 0;
  for (int i = 0; i < 20000; ++i) {
    float3 c{coord(rng), coord(rng), coord(rng)}, org{coord(rng), coord(rng), coord(rng)};
    float r = radius(rng);
    float3 target = c + normalize(float3{gauss(rng), gauss(rng), gauss(rng)}) * (0.99f * r);
    SphereHit h = hit_sphere(org, target - org, c, r);
    ASSERT_TRUE(h.hit) << i;
    float3 p = org + (target - org) * h.t;
    ASSERT_NEAR(length(p - c), r, 1e-4f * (r + length(c) + length(org))) << i;
    ++hits;
  }
  EXPECT_EQ(hits, 20000);
}

}  // namespace
}  // namespace pt
