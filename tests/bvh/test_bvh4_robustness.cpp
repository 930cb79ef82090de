// Rays and scenes that break naive kernels: NaN and infinite ray components,
// zero direction components, degenerate triangles, origins on a surface, and
// the watertight test: from inside a closed sphere mesh no ray may miss, not
// even rays aimed exactly at vertices and edges.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "bench/bench_queries.h"
#include "bvh/scene_bvh4.h"
#include "kernels/math/sampling.h"
#include "support/bvh4_support.h"
#include "support/test_support.h"

namespace pt::test {
namespace {

Scene built_in_scene() { return load_collada_file(project_scene("cornell_spheres.dae")).scene; }

TEST(Bvh4Robustness, NonFiniteRaysHitNothing) {
  Scene scene = built_in_scene();
  SceneBvh4 bvh(scene);
  const Ray good = camera_rays(scene, 1, 1)[0];
  Hit hit;
  ASSERT_TRUE(bvh.intersect(good, hit));
  for (float bad : {NAN, INFINITY, -INFINITY}) {
    for (int field = 0; field < 6; ++field) {
      Ray r = good;
      (field < 3 ? r.org : r.dir)[field % 3] = bad;
      EXPECT_FALSE(bvh.intersect(r, hit)) << "field " << field << " = " << bad;
      EXPECT_EQ(hit.prim, kInvalidId);
      EXPECT_FALSE(bvh.occluded(r)) << "field " << field << " = " << bad;
    }
  }
  for (auto [tmin, tmax] : {std::pair{NAN, kInfinity}, {0.0f, NAN}, {NAN, NAN}, {5.0f, 1.0f}, {1.0f, 1.0f}}) {
    Ray r = good;
    r.tmin = tmin;
    r.tmax = tmax;
    EXPECT_FALSE(bvh.intersect(r, hit)) << tmin << " " << tmax;
    EXPECT_FALSE(bvh.occluded(r)) << tmin << " " << tmax;
  }
  Ray zero = good;
  zero.dir = {0, 0, 0};
  EXPECT_FALSE(bvh.intersect(zero, hit));
  EXPECT_FALSE(bvh.occluded(zero));
}

TEST(Bvh4Robustness, AxisAlignedRaysMatchBruteForce) {
  Scene scene = tessellated_sphere(3, {0, 0, 0}, 1.0f);
  Scene room = built_in_scene();  // axis-aligned walls: flat boxes
  for (const Scene* s : {&scene, &room}) {
    SceneBvh2 oracle(*s, Bvh2Mode::kBruteForce);
    const bench::WatertightBvh4 both(*s);
    auto check = [&](const auto& bvh, const char* form) {
      std::vector<Ray> rays = uniform_random_rays(*s, 300, 5);
      uint64_t tests = 0;
      for (size_t i = 0; i < rays.size(); ++i) {
        Ray r = rays[i];
        r.dir = float3{0.0f};
        r.dir[i % 3] = (i / 3) % 2 ? 1.0f : -1.0f;  // +-x, +-y, +-z; zero (and -0) elsewhere
        if (i % 7 == 0) r.dir[(i + 1) % 3] = -0.0f;
        Hit expected, actual;
        oracle.intersect(r, expected, tests);
        bvh.intersect(r, actual);
        EXPECT_TRUE(same_closest_hit(expected, actual, scene_scale(*s))) << form << " ray " << i;
        EXPECT_EQ(oracle.occluded(r, tests), bvh.occluded(r)) << form << " ray " << i;
      }
    };
    check(both.moller_trumbore(), "Moller-Trumbore");
    check(both, "watertight");
  }
}

TEST(Bvh4Robustness, DegenerateTrianglesNeverHit) {
  Scene s = tessellated_sphere(2, {0, 0, 0}, 1.0f);
  const uint32_t first_degenerate = static_cast<uint32_t>(s.triangles.size());
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> coord(-8, 8);
  std::vector<float3> targets;
  for (int i = 0; i < 60; ++i) {
    // Small integers: exactly collinear points stay exactly collinear in float.
    float3 a{float(coord(rng)), float(coord(rng)), float(coord(rng))}, d{float(coord(rng)), 1.0f, float(coord(rng))};
    a = a * 0.25f;
    uint32_t n = static_cast<uint32_t>(s.positions.size());
    s.positions.insert(s.positions.end(), {a, a + d * 2.0f, a + d * 0.5f});
    static const TriangleIndices kShapes[6] = {{0, 1, 2}, {0, 0, 1}, {0, 1, 1}, {1, 0, 1}, {2, 2, 2}, {1, 2, 0}};
    TriangleIndices t = kShapes[i % 6];
    s.triangles.push_back({n + t.v0, n + t.v1, n + t.v2});
    targets.push_back(a + d * 0.25f);  // on the segment of every shape but the point
  }
  const bench::WatertightBvh4 both(s);
  EXPECT_EQ(both.moller_trumbore().stats().triangles, first_degenerate);
  auto check = [&](const auto& bvh) {
    int hits = 0;
    std::uniform_real_distribution<float> u(-6.0f, 6.0f);
    for (const float3& target : targets)
      for (int k = 0; k < 16; ++k) {
        float3 from{u(rng), u(rng), u(rng)};
        Hit hit;
        if (!bvh.intersect(Ray{from, 0.0f, target - from, 2.0f}, hit)) continue;
        ++hits;
        EXPECT_LT(hit.prim, first_degenerate) << "degenerate triangle " << hit.prim << " was hit";
      }
    EXPECT_GT(hits, 0);  // some rays meet the sphere: the queries really ran
  };
  check(both.moller_trumbore());
  check(both);
}

TEST(Bvh4Robustness, RaysStartingOnASurfaceReturnValidHits) {
  Scene s = tessellated_sphere(3, {0, 0, 0}, 1.0f);
  SceneBvh4 bvh(s);
  std::mt19937 rng(9);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  int hits = 0;
  for (int i = 0; i < 2000; ++i) {
    const TriangleIndices& t = s.triangles[rng() % s.triangles.size()];
    float b1 = u01(rng), b2 = u01(rng) * (1.0f - b1);
    float3 p0 = s.positions[t.v0], p1 = s.positions[t.v1], p2 = s.positions[t.v2];
    Ray r{p0 * (1.0f - b1 - b2) + p1 * b1 + p2 * b2, 0.0f, to_float3(sample_uniform_sphere(u01(rng), u01(rng))),
          kInfinity};
    Hit hit;
    if (!bvh.intersect(r, hit)) continue;
    ++hits;
    ASSERT_LT(hit.prim, s.triangles.size());
    EXPECT_GE(hit.t, r.tmin);
    EXPECT_LT(hit.t, r.tmax);
    EXPECT_GE(hit.u, 0.0f);
    EXPECT_GE(hit.v, 0.0f);
    EXPECT_LE(hit.u + hit.v, 1.0f + 1e-6f);
    // The reported point lies on the reported triangle.
    const TriangleIndices& h = s.triangles[hit.prim];
    float3 on_tri = s.positions[h.v0] * (1.0f - hit.u - hit.v) + s.positions[h.v1] * hit.u + s.positions[h.v2] * hit.v;
    EXPECT_LT(length(on_tri - (r.org + r.dir * hit.t)), 1e-5f);
  }
  EXPECT_GT(hits, 1000);  // outward rays leave the sphere; inward ones hit it
}

/// Counts rays from inside the closed sphere that hit nothing.
template <class Accel>
int count_misses(const Accel& bvh, const std::vector<Ray>& rays) {
  int misses = 0;
  for (const Ray& r : rays) {
    Hit hit;
    misses += !bvh.intersect(r, hit);
  }
  return misses;
}

TEST(Bvh4Robustness, WatertightTestLetsNoRayOutOfAClosedSphere) {
  const float3 c{0.3f, -0.2f, 0.7f};
  Scene s = tessellated_sphere(5, c, 1.0f);  // 20480 triangles
  std::vector<Ray> rays;
  // Exactly at every vertex and every edge midpoint, from the centre.
  for (const float3& p : s.positions) rays.push_back({c, 0.0f, p - c, kInfinity});
  for (const TriangleIndices& t : s.triangles) {
    rays.push_back({c, 0.0f, (s.positions[t.v0] + s.positions[t.v1]) * 0.5f - c, kInfinity});
    rays.push_back(
        {c, 0.0f, (s.positions[t.v0] + s.positions[t.v1] + s.positions[t.v2]) * (1.0f / 3.0f) - c, kInfinity});
  }
  // Random origins inside, random directions.
  std::mt19937 rng(17);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  for (int i = 0; i < 100000; ++i) {
    float3 o = c + to_float3(sample_uniform_sphere(u01(rng), u01(rng))) * (0.9f * std::cbrt(u01(rng)));
    rays.push_back({o, 0.0f, to_float3(sample_uniform_sphere(u01(rng), u01(rng))), kInfinity});
  }
  const bench::WatertightBvh4 watertight(s);
  EXPECT_EQ(count_misses(watertight, rays), 0) << "of " << rays.size() << " rays";
  Bvh4Options split;  // a tree over fragments must not lose a hit either
  split.presplit_budget = 1.0f;
  EXPECT_EQ(count_misses(bench::WatertightBvh4(s, split), rays), 0) << "pre-split, of " << rays.size() << " rays";
  int mt_misses = count_misses(watertight.moller_trumbore(), rays);
  RecordProperty("moller_trumbore_misses", mt_misses);
  std::printf("Moller-Trumbore BVH4: %d of %zu rays escaped the closed sphere\n", mt_misses, rays.size());
}

}  // namespace
}  // namespace pt::test
