// Pre-splitting: fragments cover their triangle (random points of it and the
// points where its edges cross the cut planes lie in some fragment box of that
// triangle), never reach outside its box, tighten the boxes of diagonal
// triangles, keep to the budget (and spend all there is to spend when it is
// larger) and are the same on 1 and 2 threads; a BVH4 built from them holds
// every triangle at most once per leaf and answers like brute force, single
// rays and packets alike.
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include <gtest/gtest.h>
#include <oneapi/tbb/task_arena.h>

#include "bvh/bvh4_build.h"
#include "bvh/presplit.h"
#include "bvh/scene_bvh2.h"
#include "bench/bench_queries.h"
#include "bvh/scene_bvh4.h"
#include "support/bvh4_support.h"
#include "support/test_support.h"

namespace pt::test {
namespace {

/// Long thin triangles in random orientations (the case pre-splitting is for),
/// plus an axis-aligned right triangle and a tiny one.
std::vector<float3> thin_triangles(int n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u(-10.0f, 10.0f), w(-0.3f, 0.3f);
  std::vector<float3> corners;
  for (int i = 0; i < n; ++i) {
    float3 a{u(rng), u(rng), u(rng)}, b{u(rng), u(rng), u(rng)};
    float3 c = (a + b) * 0.5f + float3{w(rng), w(rng), w(rng)};
    corners.insert(corners.end(), {a, b, c});
  }
  corners.insert(corners.end(), {{0, 0, 0}, {8, 0, 0}, {0, 8, 0}});
  corners.insert(corners.end(), {{1, 1, 1}, {1.001f, 1, 1}, {1, 1.001f, 1}});
  return corners;
}

bool inside(const BBox& b, const double (&p)[3]) {
  for (int a = 0; a < 3; ++a)
    if (!(p[a] >= b.lower[a] && p[a] <= b.upper[a])) return false;
  return true;
}

TEST(Presplit, FragmentsCoverTheirTriangleInsideItsBox) {
  std::vector<float3> corners = thin_triangles(400, 3);
  const size_t n = corners.size() / 3;
  for (float budget : {0.0f, 0.3f, 2.0f}) {
    SCOPED_TRACE(budget);
    SplitReferences refs = presplit_triangles(corners, budget);
    ASSERT_EQ(refs.boxes.size(), refs.triangle.size());
    ASSERT_EQ(refs.centers.size(), refs.triangle.size());
    EXPECT_GE(refs.triangle.size(), n);
    EXPECT_LE(refs.triangle.size(), n + size_t(budget * n));
    if (budget > 0.0f) { EXPECT_GT(refs.triangle.size(), n + size_t(0.9 * budget * n)) << "the budget is spent"; }
    std::vector<std::vector<BBox>> fragments(n);
    for (size_t r = 0; r < refs.triangle.size(); ++r) {
      ASSERT_LT(refs.triangle[r], n);
      if (r > 0) { EXPECT_GE(refs.triangle[r], refs.triangle[r - 1]) << "fragments in triangle order"; }
      fragments[refs.triangle[r]].push_back(refs.boxes[r]);
      EXPECT_EQ(refs.centers[r].x, refs.boxes[r].center().x);
    }
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> u01(0.0, 1.0);
    int uncovered = 0, crossings = 0;
    for (size_t t = 0; t < n; ++t) {
      ASSERT_FALSE(fragments[t].empty());
      BBox whole = BBox::of_point(corners[3 * t]);
      whole.expand(corners[3 * t + 1]);
      whole.expand(corners[3 * t + 2]);
      for (const BBox& f : fragments[t]) {
        for (int a = 0; a < 3; ++a) {
          EXPECT_GE(f.lower[a], whole.lower[a]);
          EXPECT_LE(f.upper[a], whole.upper[a]);
          EXPECT_LE(f.lower[a], f.upper[a]);
        }
      }
      // Points of the triangle, in double: the vertices, the edge midpoints
      // and random barycentric points.
      for (int k = 0; k < 203; ++k) {
        double b1, b2;
        if (k < 3) b1 = k == 1, b2 = k == 2;
        else if (k < 6) b1 = k == 3 ? 0.5 : k == 4 ? 0.5 : 0.0, b2 = k == 4 ? 0.5 : k == 5 ? 0.5 : 0.0;
        else {
          b1 = u01(rng), b2 = u01(rng);
          if (b1 + b2 > 1.0) b1 = 1.0 - b1, b2 = 1.0 - b2;
        }
        double p[3];
        for (int a = 0; a < 3; ++a) {
          double v0 = corners[3 * t][a], v1 = corners[3 * t + 1][a], v2 = corners[3 * t + 2][a];
          p[a] = v0 + b1 * (v1 - v0) + b2 * (v2 - v0);
          p[a] = std::clamp(p[a], double(whole.lower[a]), double(whole.upper[a]));
        }
        bool covered = false;
        for (const BBox& f : fragments[t]) covered = covered || inside(f, p);
        uncovered += !covered;
      }
      // Where the triangle's edges cross the fragments' faces (the cut
      // planes): points on the boundary between two fragments, the ones that
      // rounding in the clipping would lose.
      for (const BBox& f : fragments[t])
        for (int a = 0; a < 3; ++a)
          for (double plane : {double(f.lower[a]), double(f.upper[a])})
            for (int e = 0; e < 3; ++e) {
              const float3 &p0 = corners[3 * t + e], &p1 = corners[3 * t + (e + 1) % 3];
              double d0 = p0[a] - plane, d1 = p1[a] - plane;
              if (!(d0 < 0.0 && d1 > 0.0) && !(d0 > 0.0 && d1 < 0.0)) continue;
              double s = d0 / (d0 - d1), p[3];
              for (int k = 0; k < 3; ++k) p[k] = p0[k] + s * (double(p1[k]) - p0[k]);
              p[a] = plane;
              bool covered = false;
              for (const BBox& g : fragments[t]) covered = covered || inside(g, p);
              uncovered += !covered;
              ++crossings;
            }
    }
    EXPECT_EQ(uncovered, 0);
    if (budget > 0.0f) { EXPECT_GT(crossings, int(n)); }
  }
}

TEST(Presplit, CutsTightenADiagonalTriangleAndLeaveABudgetOfZeroAlone) {
  std::vector<float3> corners = {{0, 0, 0}, {10, 10, 10}, {10, 10.1f, 9.9f}};
  SplitReferences none = presplit_triangles(corners, 0.0f);
  ASSERT_EQ(none.boxes.size(), 1u);
  EXPECT_EQ(none.boxes[0].lower.x, 0.0f);
  EXPECT_EQ(none.boxes[0].upper.y, 10.1f);
  // With one triangle the budget allows 4 cuts: 5 fragments along the
  // diagonal whose boxes together have a fraction of the whole box's area.
  SplitReferences cut = presplit_triangles(corners, 4.0f);
  EXPECT_EQ(cut.boxes.size(), 5u);
  double sum = 0.0;
  for (const BBox& b : cut.boxes) sum += b.half_area();
  EXPECT_LT(sum, 0.5 * none.boxes[0].half_area());
}

TEST(Presplit, SameReferencesOnOneAndTwoThreads) {
  std::vector<float3> corners = thin_triangles(20000, 5);
  SplitReferences one, two;
  tbb::task_arena(1).execute([&] { one = presplit_triangles(corners, 0.5f); });
  tbb::task_arena(2).execute([&] { two = presplit_triangles(corners, 0.5f); });
  ASSERT_EQ(one.triangle, two.triangle);
  ASSERT_EQ(one.boxes.size(), two.boxes.size());
  EXPECT_EQ(std::memcmp(one.boxes.data(), two.boxes.data(), one.boxes.size() * sizeof(BBox)), 0);
}

Scene scene_of(const std::vector<float3>& corners) {
  Scene s;
  s.positions = corners;
  for (uint32_t i = 0; i + 2 < corners.size(); i += 3) s.triangles.push_back({i, i + 1, i + 2});
  s.triangle_material.assign(s.triangles.size(), 0);
  s.materials.push_back(Material{});
  s.bounds = compute_scene_bounds(s);
  return s;
}

TEST(Presplit, TreeHoldsEachTriangleOncePerLeafAndMatchesBruteForce) {
  Scene s = scene_of(thin_triangles(3000, 7));
  Bvh4Options o;
  o.presplit_budget = 1.0f;
  Bvh4BuildStats stats;
  Bvh4 bvh = build_bvh4(s.positions, s.triangles, o, &stats);
  EXPECT_EQ(stats.triangles, s.triangles.size());
  EXPECT_GT(stats.references, s.triangles.size());
  std::vector<int> leaves_holding(s.triangles.size(), 0);
  for (const Bvh4Node& node : bvh.nodes)
    for (uint32_t ref : node.child) {
      if (ref == bvh4_ref::kEmptyRef || !bvh4_ref::is_leaf(ref)) continue;
      std::set<uint32_t> in_leaf;
      for (uint32_t k = 0; k < bvh4_ref::leaf_block_count(ref); ++k)
        for (uint32_t p : bvh.leaf_blocks(ref)[k].prim)
          if (p != kInvalidId) { EXPECT_TRUE(in_leaf.insert(p).second) << "triangle " << p << " twice in one leaf"; }
      for (uint32_t p : in_leaf) ++leaves_holding[p];
    }
  uint32_t in_leaves = 0;
  for (const TriangleBlock4& b : bvh.blocks)
    for (uint32_t p : b.prim) in_leaves += p != kInvalidId;
  EXPECT_LT(in_leaves, stats.references) << "no leaf got two fragments of one triangle: the dedupe is untested";
  int split_across_leaves = 0;
  for (int c : leaves_holding) {
    EXPECT_GE(c, 1);
    split_across_leaves += c > 1;
  }
  EXPECT_GT(split_across_leaves, 0) << "some triangle's fragments ended in different leaves";

  // Against brute force (Moller-Trumbore, as the BVH4's default leaves), and
  // each leaf form against the same form without pre-splitting (the
  // watertight test and Moller-Trumbore disagree on some edge hits of these
  // intersecting triangles).
  SceneBvh2 oracle(s, Bvh2Mode::kBruteForce);
  std::vector<Ray> rays = uniform_random_rays(s, 4000, 19);
  {
    SceneBvh4 accel(s, o);
    uint64_t tests = 0;
    int wrong = 0, hits = 0;
    for (const Ray& r : rays) {
      Hit expected, actual;
      oracle.intersect(r, expected, tests);
      accel.intersect(r, actual);
      hits += expected.valid();
      wrong += !same_closest_hit(expected, actual, scene_scale(s));
      wrong += accel.occluded(r) != oracle.occluded(r, tests);
    }
    EXPECT_EQ(wrong, 0) << "Moller-Trumbore";
    EXPECT_GT(hits, 400);
  }
  {
    Bvh4Options plain;
    bench::WatertightBvh4 accel(s, o), unsplit(s, plain);
    int wrong = 0;
    for (const Ray& r : rays) {
      Hit expected, actual;
      unsplit.intersect(r, expected);
      accel.intersect(r, actual);
      wrong += !same_closest_hit(expected, actual, scene_scale(s));
      wrong += accel.occluded(r) != unsplit.occluded(r);
    }
    EXPECT_EQ(wrong, 0) << "watertight";
  }
  // The queue tracer (streams: subtrees handed to walks, triangles in several
  // leaves) answers like single rays on the same pre-split tree.
  SceneBvh4 accel(s, o);
  QueueArrays q(rays);
  QueueScratch scratch;
  accel.intersect_queue(q.rays(), q.hits(), scratch);
  std::vector<uint8_t> blocked(rays.size());
  accel.occluded_queue(q.rays(), blocked.data(), scratch);
  int wrong = 0;
  for (size_t i = 0; i < rays.size(); ++i) {
    Hit single;
    accel.intersect(rays[i], single);
    const Hit got = q.hit(i);
    wrong += std::memcmp(&single, &got, sizeof(Hit)) != 0;
    wrong += accel.occluded(rays[i]) != bool(blocked[i]);
  }
  EXPECT_EQ(wrong, 0) << "queue tracer";
}

TEST(Presplit, ABudgetBeyondWhatCanBeCutCutsEverySplittableTriangleTheMost) {
  // 100 flat axis-aligned triangles (never cut) and two diagonal ones: a
  // budget of 4 per triangle exceeds the 2 x 64 cuts there are to make.
  std::vector<float3> corners;
  for (int i = 0; i < 100; ++i)
    corners.insert(corners.end(), {{float(i), 0, 0}, {float(i) + 1, 0, 0}, {float(i), 1, 0}});
  corners.insert(corners.end(), {{0, 0, 0}, {50, 40, 30}, {50, 40.5f, 29.5f}});
  corners.insert(corners.end(), {{100, 0, 30}, {0, 40, 0}, {0.5f, 40, 0.5f}});
  SplitReferences refs = presplit_triangles(corners, 4.0f);
  std::vector<int> per_triangle(102, 0);
  for (uint32_t t : refs.triangle) ++per_triangle[t];
  for (int i = 0; i < 100; ++i) EXPECT_EQ(per_triangle[i], 1);
  EXPECT_EQ(per_triangle[100], 65);
  EXPECT_EQ(per_triangle[101], 65);
}

}  // namespace
}  // namespace pt::test
