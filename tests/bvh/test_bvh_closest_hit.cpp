// The binary BVH against brute force (bvh/scene_bvh2.h): for
// thousands of random rays per scene, the closest hit through the BVH is the
// brute-force closest hit ("equal" = the same primitive with the same t, u, v,
// or a different primitive at the same t within 1e-6 relative: an exact tie),
// and occlusion queries agree. Also the hierarchy's structural invariants and a
// centroid distribution that drives the midpoint split to its depth limit.
#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "bvh/bvh2.h"
#include "support/scene_builders.h"
#include "support/test_support.h"
#include "bvh/scene_bvh2.h"

namespace pt {
namespace {

/// A random point on primitive `prim` (triangles first, then spheres).
float3 point_on_primitive(const Scene& s, uint32_t prim, std::mt19937& rng) {
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  if (prim < s.triangles.size()) {
    const TriangleIndices& t = s.triangles[prim];
    float a = u01(rng), b = u01(rng);
    if (a + b > 1.0f) {
      a = 1.0f - a;
      b = 1.0f - b;
    }
    return s.positions[t.v0] * (1 - a - b) + s.positions[t.v1] * a + s.positions[t.v2] * b;
  }
  const Sphere& sp = s.spheres[prim - s.triangles.size()];
  std::normal_distribution<float> g;
  return sp.center + normalize(float3{g(rng), g(rng), g(rng)}) * sp.radius;
}

/// Three kinds of rays in equal numbers: from inside the (10% enlarged)
/// bounds in uniform directions; from outside aimed at random points of random
/// primitives; and segments between two points of the bounds with a random
/// tmin (unnormalised directions, tmax = 1).
std::vector<Ray> random_rays(const Scene& s, int count, uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> u01(0.0f, 1.0f);
  std::normal_distribution<float> g;
  const BBox b = s.bounds;
  const float3 lo = b.lower - b.extent() * 0.05f, ext = b.extent() * 1.1f;
  auto in_bounds = [&] { return lo + float3{u01(rng), u01(rng), u01(rng)} * ext; };
  auto any_dir = [&] { return normalize(float3{g(rng), g(rng), g(rng)}); };
  std::uniform_int_distribution<uint32_t> prim(0, static_cast<uint32_t>(s.primitive_count() - 1));
  std::vector<Ray> rays;
  for (int i = 0; i < count; ++i) {
    Ray r;
    switch (i % 3) {
      case 0: r = {in_bounds(), 0.0f, any_dir(), kInfinity}; break;
      case 1: {
        float3 org = b.center() + any_dir() * (2.0f * length(b.extent()));
        r = {org, 0.0f, normalize(point_on_primitive(s, prim(rng), rng) - org), kInfinity};
        break;
      }
      default: {
        float3 from = in_bounds();
        r = {from, 0.5f * u01(rng), in_bounds() - from, 1.0f};
      }
    }
    rays.push_back(r);
  }
  return rays;
}

struct Answer {
  bool found = false;
  Hit hit;
};

/// The brute-force closest hit of every ray (the expensive half, computed once per scene).
std::vector<Answer> brute_force_answers(const Scene& s, const std::vector<Ray>& rays) {
  SceneBvh2 brute(s, Bvh2Mode::kBruteForce);
  uint64_t tests = 0;
  std::vector<Answer> answers(rays.size());
  for (size_t i = 0; i < rays.size(); ++i) answers[i].found = brute.intersect(rays[i], answers[i].hit, tests);
  return answers;
}

/// Compares BVH answers (closest hit and occlusion) with brute force for every
/// ray; returns the number of rays that hit something.
int expect_bvh_equals_brute_force(const Scene& s, uint32_t leaf_size, const std::vector<Ray>& rays,
                                  const std::vector<Answer>& brute) {
  SceneBvh2 bvh(s, Bvh2Mode::kMidpoint, leaf_size);
  uint64_t tests = 0;
  int hits = 0, failures = 0;
  for (size_t i = 0; i < rays.size() && failures < 10; ++i) {
    const Ray& r = rays[i];
    const Hit& hf = brute[i].hit;
    Hit hb;
    bool found_b = bvh.intersect(r, hb, tests), found_f = brute[i].found;
    bool same = found_b == found_f;
    if (same && found_f) {
      same =
          hb.prim == hf.prim ? (hb.t == hf.t && hb.u == hf.u && hb.v == hf.v) : std::fabs(hb.t - hf.t) <= 1e-6f * hf.t;
      ++hits;
    }
    if (same) same = bvh.occluded(r, tests) == found_f;
    if (!same) {
      ++failures;
      ADD_FAILURE() << "leaf size " << leaf_size << ", ray " << i << ": bvh " << found_b << " prim " << hb.prim << " t "
                    << hb.t << " vs brute force " << found_f << " prim " << hf.prim << " t " << hf.t;
    }
  }
  return hits;
}

int expect_bvh_equals_brute_force(const Scene& s, uint32_t leaf_size, const std::vector<Ray>& rays) {
  return expect_bvh_equals_brute_force(s, leaf_size, rays, brute_force_answers(s, rays));
}

void expect_valid_hierarchy(const Scene& s, uint32_t leaf_size) {
  SceneBvh2 accel(s, Bvh2Mode::kMidpoint, leaf_size);
  const Bvh2& bvh = accel.bvh();
  std::vector<uint32_t> order = bvh.prim_order;
  std::sort(order.begin(), order.end());
  for (uint32_t i = 0; i < order.size(); ++i) ASSERT_EQ(order[i], i) << "prim_order is not a permutation";
  ASSERT_EQ(order.size(), s.primitive_count());
  auto contains = [](const BBox& outer, const BBox& inner) {
    return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y && outer.lower.z <= inner.lower.z &&
           outer.upper.x >= inner.upper.x && outer.upper.y >= inner.upper.y && outer.upper.z >= inner.upper.z;
  };
  std::vector<uint32_t> stack{0};
  size_t visited = 0, prims_in_leaves = 0;
  while (!stack.empty()) {
    const Bvh2Node& n = bvh.nodes[stack.back()];
    stack.pop_back();
    ++visited;
    if (n.is_leaf()) {
      ASSERT_LE(n.count, leaf_size);
      prims_in_leaves += n.count;
      for (uint32_t i = n.left_or_first; i < n.left_or_first + n.count; ++i) {
        uint32_t p = bvh.prim_order[i];
        BBox pb;
        if (p < s.triangles.size()) {
          for (uint32_t v : {s.triangles[p].v0, s.triangles[p].v1, s.triangles[p].v2}) pb.expand(s.positions[v]);
        } else {
          const Sphere& sp = s.spheres[p - s.triangles.size()];
          pb = {sp.center - float3(sp.radius), sp.center + float3(sp.radius)};
        }
        ASSERT_TRUE(contains(n.bounds(), pb)) << "primitive " << p << " outside its leaf";
      }
      continue;
    }
    for (uint32_t c : {n.left_or_first, n.left_or_first + 1}) {
      ASSERT_LT(c, bvh.nodes.size());
      ASSERT_TRUE(contains(n.bounds(), bvh.nodes[c].bounds())) << "child " << c << " outside its parent";
      stack.push_back(c);
    }
  }
  EXPECT_EQ(prims_in_leaves, s.primitive_count());
  EXPECT_EQ(visited, bvh.nodes.size()) << "unreachable nodes";
  // The traversal stack holds 2 * kBvh2MaxDepth entries and grows by at most one per level.
  EXPECT_LE(bvh2_shape(bvh).depth, 2 * kBvh2MaxDepth);
}

constexpr int kRaysPerScene = 3000;

class BvhSceneTest : public ::testing::TestWithParam<std::string> {};

TEST_P(BvhSceneTest, ClosestHitsAndOcclusionEqualBruteForce) {
  PT_REQUIRE_SHARED_SCENES();
  const Scene s = load_collada_file(test::shared_scene(GetParam())).scene;
  const std::vector<Ray> rays = random_rays(s, kRaysPerScene, 2024);
  const std::vector<Answer> brute = brute_force_answers(s, rays);
  for (uint32_t leaf : {1u, 4u}) {
    int hits = expect_bvh_equals_brute_force(s, leaf, rays, brute);
    EXPECT_GT(hits, kRaysPerScene / 3) << "too few hits to mean anything";
  }
}

TEST_P(BvhSceneTest, HierarchyIsValid) {
  PT_REQUIRE_SHARED_SCENES();
  const Scene s = load_collada_file(test::shared_scene(GetParam())).scene;
  for (uint32_t leaf : {1u, 4u, 8u}) expect_valid_hierarchy(s, leaf);
}

INSTANTIATE_TEST_SUITE_P(Public, BvhSceneTest, ::testing::ValuesIn(test::shared_scene_names()),
                         [](const auto& info) { return info.param.substr(0, info.param.find('.')); });

TEST(BvhProjectScene, CornellSpheresEqualsBruteForce) {
  const Scene s = load_collada_file(test::project_scene("cornell_spheres.dae")).scene;
  expect_valid_hierarchy(s, 4);
  const std::vector<Ray> rays = random_rays(s, 6000, 9);
  const std::vector<Answer> brute = brute_force_answers(s, rays);
  for (uint32_t leaf : {1u, 4u}) EXPECT_GT(expect_bvh_equals_brute_force(s, leaf, rays, brute), 2000);
}

// Equal quads (side 0.5) whose centroids step along x, y, z in turn by
// 0.49^l, l = 0..21: every midpoint split of the centroid box peels off one
// quad, so the build reaches its depth limit and must fall back to median
// splits; the result must still be a valid hierarchy that answers like brute
// force. (Offsets stay far above float spacing at 0.25, so centroids stay distinct.)
TEST(BvhDegenerate, ChainOfMidpointSplitsStaysWithinTheDepthLimit) {
  Scene s;
  uint32_t m = test::add_material(s, float3(0.5f));
  const float w = 0.25f;
  for (int k = 0; k < 66; ++k) {
    float3 c;
    c[k % 3] = std::pow(0.49f, static_cast<float>(k / 3));
    test::add_quad(s, c + float3{-w, -w, -w}, c + float3{w, -w, -w}, c + float3{w, w, w}, c + float3{-w, w, w},
                   {0, -1, 1}, m);
  }
  test::finish_scene(s);
  expect_valid_hierarchy(s, 1);
  EXPECT_GT(bvh2_shape(SceneBvh2(s, Bvh2Mode::kMidpoint, 1).bvh()).depth, kBvh2MaxDepth - 8)
      << "the scene no longer reaches the median fallback";
  EXPECT_GT(expect_bvh_equals_brute_force(s, 1, random_rays(s, 3000, 5)), 1000);
}

}  // namespace
}  // namespace pt
