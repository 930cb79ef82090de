// The builders' invariants: the SAH binary BVH is a valid hierarchy over a
// permutation of the inputs with bounded depth; the 4-wide collapse holds every
// triangle exactly once in precomputed blocks under boxes that contain it; the
// build is the same byte for byte on 1 and 2 threads; statistics add up; a
// tree that fits in L1 is collapsed with its own block cost.
#include <cstring>
#include <functional>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "bvh/bvh2.h"
#include "bvh/bvh4_build.h"
#include "bvh/scene_bvh4.h"
#include "support/bvh4_support.h"

namespace pt::test {
namespace {

bool contains(const BBox& outer, const BBox& inner) {
  return outer.lower.x <= inner.lower.x && outer.lower.y <= inner.lower.y && outer.lower.z <= inner.lower.z &&
         outer.upper.x >= inner.upper.x && outer.upper.y >= inner.upper.y && outer.upper.z >= inner.upper.z;
}

std::vector<BBox> triangle_boxes(const Scene& s) {
  std::vector<BBox> boxes;
  for (const TriangleIndices& t : s.triangles) {
    BBox b = BBox::of_point(s.positions[t.v0]);
    b.expand(s.positions[t.v1]);
    b.expand(s.positions[t.v2]);
    boxes.push_back(b);
  }
  return boxes;
}

std::vector<float3> centers_of(const std::vector<BBox>& boxes) {
  std::vector<float3> c;
  for (const BBox& b : boxes) c.push_back(b.center());
  return c;
}

/// Checks the hierarchy below `node` and returns its depth (leaf = 1).
int check_bvh2_node(const Bvh2& bvh, uint32_t node, const std::vector<BBox>& boxes, uint32_t max_leaf,
                    std::vector<int>& seen) {
  const Bvh2Node& n = bvh.nodes[node];
  if (n.is_leaf()) {
    EXPECT_LE(n.count, max_leaf);
    for (uint32_t i = n.left_or_first; i < n.left_or_first + n.count; ++i) {
      ++seen[bvh.prim_order[i]];
      EXPECT_TRUE(contains(n.bounds(), boxes[bvh.prim_order[i]]));
    }
    return 1;
  }
  int depth = 0;
  for (uint32_t c = n.left_or_first; c < n.left_or_first + 2; ++c) {
    EXPECT_GT(c, node);  // depth-first: children after their parent
    EXPECT_TRUE(contains(n.bounds(), bvh.nodes[c].bounds()));
    depth = std::max(depth, check_bvh2_node(bvh, c, boxes, max_leaf, seen));
  }
  return depth + 1;
}

void expect_valid_bvh2(const Bvh2& bvh, const std::vector<BBox>& boxes, uint32_t max_leaf) {
  std::vector<int> seen(boxes.size(), 0);
  int depth = check_bvh2_node(bvh, 0, boxes, max_leaf, seen);
  EXPECT_LE(depth, kBvh2MaxDepth);
  for (size_t i = 0; i < seen.size(); ++i) ASSERT_EQ(seen[i], 1) << "primitive " << i;
}

TEST(Bvh2Sah, IsAValidHierarchyOverAPermutation) {
  Scene sphere = tessellated_sphere(4, {1, 2, 3}, 2.0f);
  std::vector<BBox> boxes = triangle_boxes(sphere);
  SahBuildOptions o;
  Bvh2 bvh = build_bvh2_sah(boxes, centers_of(boxes), o);
  expect_valid_bvh2(bvh, boxes, o.max_leaf_size);
  EXPECT_GT(bvh2_shape(bvh).leaves, boxes.size() / o.max_leaf_size);
}

TEST(Bvh2Sah, DepthStaysBoundedOnAdversarialInput) {
  // Boxes in geometric progression: SAH peels off the largest box at every
  // split, a chain as deep as there are primitives.
  std::vector<BBox> boxes;
  for (int i = 0; i < 300; ++i) {
    float x = std::pow(1.3f, float(i));
    boxes.push_back({{x, 0, 0}, {x * 1.2f, 1, 1}});
  }
  SahBuildOptions o;
  o.max_leaf_size = 1;
  Bvh2 bvh = build_bvh2_sah(boxes, centers_of(boxes), o);
  expect_valid_bvh2(bvh, boxes, 1);
}

TEST(Bvh2Sah, CoincidentCentroidsAndTinyInputs) {
  std::vector<BBox> same(100, BBox{{0, 0, 0}, {1, 1, 1}});
  SahBuildOptions o;
  expect_valid_bvh2(build_bvh2_sah(same, centers_of(same), o), same, o.max_leaf_size);
  std::vector<BBox> one(1, BBox{{0, 0, 0}, {1, 1, 1}});
  Bvh2 single = build_bvh2_sah(one, centers_of(one), o);
  ASSERT_EQ(single.nodes.size(), 1u);
  EXPECT_EQ(single.nodes[0].count, 1u);
  Bvh2 none = build_bvh2_sah({}, {}, o);
  EXPECT_TRUE(none.prim_order.empty());
}

/// Walks the 4-wide tree: every triangle exactly once, boxes contain their content.
void expect_valid_bvh4(const Bvh4& bvh, const Scene& s, uint32_t expected_triangles) {
  std::vector<int> seen(s.triangles.size(), 0);
  uint32_t leaves = 0;
  std::function<void(uint32_t, const BBox&)> walk = [&](uint32_t ref, const BBox& box) {
    if (bvh4_ref::is_leaf(ref)) {
      ++leaves;
      const TriangleBlock4* b = bvh.leaf_blocks(ref);
      for (uint32_t k = 0; k < bvh4_ref::leaf_block_count(ref); ++k)
        for (int lane = 0; lane < 4; ++lane) {
          uint32_t p = b[k].prim[lane];
          if (p == kInvalidId) continue;
          ++seen[p];
          const TriangleIndices& t = s.triangles[p];
          float3 p0 = s.positions[t.v0], e1 = s.positions[t.v1] - p0, e2 = s.positions[t.v2] - p0;
          for (int a = 0; a < 3; ++a) {
            EXPECT_EQ(b[k].v0[a][lane], p0[a]);
            EXPECT_EQ(b[k].r1[a][lane], e1[a]);
            EXPECT_EQ(b[k].r2[a][lane], e2[a]);
          }
          for (uint32_t v : {t.v0, t.v1, t.v2}) EXPECT_TRUE(contains(box, BBox::of_point(s.positions[v])));
        }
      return;
    }
    const Bvh4Node& n = bvh.node(ref);
    for (int i = 0; i < 4; ++i) {
      BBox child{{n.bounds[0][i], n.bounds[2][i], n.bounds[4][i]}, {n.bounds[1][i], n.bounds[3][i], n.bounds[5][i]}};
      if (n.child[i] == bvh4_ref::kEmptyRef) {
        EXPECT_EQ(child.lower.x, INFINITY);
        EXPECT_EQ(child.upper.x, -INFINITY);
        continue;
      }
      EXPECT_TRUE(contains(box, child));
      walk(n.child[i], child);
    }
  };
  walk(bvh.root, BBox{float3(-INFINITY), float3(INFINITY)});
  uint32_t total = 0;
  for (int c : seen) {
    EXPECT_LE(c, 1);
    total += c;
  }
  EXPECT_EQ(total, expected_triangles);
}

TEST(Bvh4Build, HoldsEveryTriangleOnceInBlocksUnderContainingBoxes) {
  Scene sphere = tessellated_sphere(4, {0, 0, 0}, 1.0f);
  Bvh4BuildStats stats;
  Bvh4 bvh = build_bvh4(sphere.positions, sphere.triangles, {}, &stats);
  expect_valid_bvh4(bvh, sphere, static_cast<uint32_t>(sphere.triangles.size()));
  EXPECT_EQ(stats.triangles, sphere.triangles.size());
  EXPECT_EQ(stats.nodes, bvh.nodes.size());
  EXPECT_EQ(stats.blocks, bvh.blocks.size());
  EXPECT_EQ(stats.bytes, stats.nodes * sizeof(Bvh4Node) + stats.blocks * sizeof(TriangleBlock4));
  EXPECT_DOUBLE_EQ(stats.bytes_per_triangle, double(stats.bytes) / stats.triangles);
  EXPECT_GE(stats.blocks * 4, stats.triangles);
  EXPECT_GT(stats.sah_cost, 1.0);
  EXPECT_GT(stats.depth, 1);
}

TEST(Bvh4Build, LeavesOutTrianglesWithNonFiniteVertices) {
  Scene s = tessellated_sphere(2, {0, 0, 0}, 1.0f);
  s.positions.push_back({NAN, 0, 0});
  s.positions.push_back({INFINITY, 1, 0});
  uint32_t n = static_cast<uint32_t>(s.positions.size());
  s.triangles.push_back({n - 2, 0, 1});
  s.triangles.push_back({2, n - 1, 3});
  Bvh4BuildStats stats;
  Bvh4 bvh = build_bvh4(s.positions, s.triangles, {}, &stats);
  EXPECT_EQ(stats.triangles, s.triangles.size() - 2);
  expect_valid_bvh4(bvh, s, stats.triangles);
}

TEST(Bvh4Build, EmptySceneHitsNothing) {
  Scene empty;
  SceneBvh4 bvh(empty);
  Hit hit;
  EXPECT_FALSE(bvh.intersect(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 5.0f}, hit));
  EXPECT_EQ(hit.t, 5.0f);
  EXPECT_EQ(hit.prim, kInvalidId);
  EXPECT_FALSE(bvh.occluded(Ray{{0, 0, 0}, 0.0f, {0, 0, 1}, 5.0f}));
  EXPECT_EQ(bvh.stats().triangles, 0u);
}

/// The same tree byte for byte: root, nodes and leaf blocks.
bool same_tree(const Bvh4& a, const Bvh4& b) {
  return a.root == b.root && a.nodes.size() == b.nodes.size() && a.blocks.size() == b.blocks.size() &&
         std::memcmp(a.nodes.data(), b.nodes.data(), a.nodes.size() * sizeof(Bvh4Node)) == 0 &&
         std::memcmp(a.blocks.data(), b.blocks.data(), a.blocks.size() * sizeof(TriangleBlock4)) == 0;
}

TEST(Bvh4Build, SameTreeOnOneAndTwoThreads) {
  // 81920 triangles: enough for parallel binning (>= 65536) and parallel subtrees.
  Scene sphere = tessellated_sphere(6, {0.5f, -1, 2}, 3.0f);
  Bvh4Options one, two;
  one.threads = 1;
  two.threads = 2;
  EXPECT_TRUE(same_tree(build_bvh4(sphere.positions, sphere.triangles, one),
                        build_bvh4(sphere.positions, sphere.triangles, two)));
}

/// The first n triangles of a 1280-triangle sphere.
Scene sphere_part(size_t n) {
  Scene s = tessellated_sphere(3, {0, 0, 0}, 1.0f);
  s.triangles.resize(n);
  return s;
}

TEST(Bvh4Build, ATreeThatFitsInL1IsCollapsedWithItsOwnBlockCost) {
  Bvh4Options fixed;  // collapse.block for every scene
  fixed.l1_resident_block_cost = 0.0f;
  Bvh4Options l1_costs = fixed;
  l1_costs.collapse.block = Bvh4Options{}.l1_resident_block_cost;
  auto build = [](const Scene& s, const Bvh4Options& o, Bvh4BuildStats* stats = nullptr) {
    return build_bvh4(s.positions, s.triangles, o, stats);
  };

  // At the bound: the L1 cost, and a different tree from the one the other cost makes.
  Scene small = sphere_part(kL1ResidentTriangles);
  Bvh4BuildStats by_default, by_fixed;
  Bvh4 tree = build(small, {}, &by_default);
  EXPECT_TRUE(same_tree(tree, build(small, l1_costs)));
  EXPECT_FALSE(same_tree(tree, build(small, fixed, &by_fixed)));
  EXPECT_GT(by_default.leaves, by_fixed.leaves);  // dearer blocks, smaller leaves
  expect_valid_bvh4(tree, small, static_cast<uint32_t>(small.triangles.size()));

  // The option's value, not a constant.
  Bvh4Options other_l1 = {}, other_fixed = fixed;
  other_l1.l1_resident_block_cost = other_fixed.collapse.block = 0.45f;
  EXPECT_TRUE(same_tree(build(small, other_l1), build(small, other_fixed)));

  // One triangle past the bound: the usual cost, where the L1 cost would make another tree.
  Scene large = sphere_part(kL1ResidentTriangles + 1);
  Bvh4 usual = build(large, {});
  EXPECT_TRUE(same_tree(usual, build(large, fixed)));
  EXPECT_FALSE(same_tree(usual, build(large, l1_costs)));
}

}  // namespace
}  // namespace pt::test
