// SceneBvh4 against brute force on every shared CS184 scene and the built-in
// scene: closest hits (same primitive, or the same t on exact ties) and
// occlusion answers for camera, uniformly random, diffuse-bounce and shadow
// rays, with both triangle tests; counted and uncounted queries agree; every
// instruction-set level breaks ties between leaf blocks alike.
#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>
#include <set>

#include <gtest/gtest.h>

#include "bench/bench_queries.h"
#include "bvh/scene_bvh4.h"
#include "kernels/simd/isa.h"
#include "support/bvh4_support.h"
#include "support/test_support.h"

namespace pt::test {
namespace {

/// A ray set with brute force's answers: closest hits and occlusion.
struct Expected {
  const char* kind;
  std::vector<Ray> rays;
  std::vector<Hit> hits;
  std::vector<char> occluded;
};

Expected brute_force(const char* kind, std::vector<Ray> rays, const SceneBvh2& oracle) {
  Expected e{kind, std::move(rays), {}, {}};
  uint64_t tests = 0;
  for (const Ray& r : e.rays) {
    Hit h;
    oracle.intersect(r, h, tests);
    e.hits.push_back(h);
    e.occluded.push_back(oracle.occluded(r, tests));
  }
  return e;
}

/// Camera, random, bounce and shadow rays: 300..3000 per set, fewer for big
/// scenes (brute force costs rays x triangles; about 6e7 tests per scene).
std::vector<Expected> expected_answers(const Scene& scene) {
  SceneBvh2 oracle(scene, Bvh2Mode::kBruteForce);
  size_t per_set = std::clamp<size_t>(60'000'000 / (8 * std::max<size_t>(scene.primitive_count(), 1)), 300, 3000);
  int height = static_cast<int>(std::sqrt(per_set * 0.75));
  std::vector<Ray> camera = camera_rays(scene, height * 4 / 3, height);
  std::vector<Expected> sets;
  std::vector<Hit> first = closest_hits(oracle, camera);
  sets.push_back(brute_force("bounce", diffuse_rays(scene, camera, first, 11), oracle));
  sets.push_back(brute_force("shadow", shadow_rays(scene, camera, first, 13), oracle));
  sets.push_back(brute_force("random", uniform_random_rays(scene, per_set, 7), oracle));
  sets.push_back(brute_force("camera", std::move(camera), oracle));
  return sets;
}

template <class Accel>
void expect_same_answers(const Scene& scene, const Accel& bvh, const Expected& e) {
  int failures = 0;
  float scale = scene_scale(scene);
  for (size_t i = 0; i < e.rays.size() && failures < 5; ++i) {
    Hit actual;
    bool found = bvh.intersect(e.rays[i], actual);
    EXPECT_EQ(found, actual.valid()) << e.kind << " ray " << i;
    auto same = same_closest_hit(e.hits[i], actual, scale);
    bool occluded = bvh.occluded(e.rays[i]);
    failures += !same + (occluded != bool(e.occluded[i]));
    EXPECT_TRUE(same) << scene.name << ": " << e.kind << " ray " << i;
    EXPECT_EQ(bool(e.occluded[i]), occluded) << scene.name << ": occlusion of " << e.kind << " ray " << i;
  }
}

/// Both triangle tests (the renderer's, and the benchmark's watertight
/// form) against the same brute-force answers.
void check_scene(const Scene& scene) {
  std::vector<Expected> sets = expected_answers(scene);
  ASSERT_FALSE(sets.back().rays.empty());
  const bench::WatertightBvh4 bvh(scene);
  {
    SCOPED_TRACE("Moller-Trumbore");
    for (const Expected& e : sets) expect_same_answers(scene, bvh.moller_trumbore(), e);
  }
  SCOPED_TRACE("watertight");
  for (const Expected& e : sets) expect_same_answers(scene, bvh, e);
}

class Bvh4SharedScene : public ::testing::TestWithParam<std::string> {};

TEST_P(Bvh4SharedScene, MatchesBruteForce) {
  PT_REQUIRE_SHARED_SCENES();
  check_scene(load_collada_file(shared_scene(GetParam())).scene);
}

INSTANTIATE_TEST_SUITE_P(AllScenes, Bvh4SharedScene, ::testing::ValuesIn(shared_scene_names()), [](const auto& info) {
  std::string name = info.param.substr(0, info.param.find('.'));
  return name;
});

TEST(Bvh4BuiltInScene, MatchesBruteForce) {
  Scene scene = load_collada_file(project_scene("cornell_spheres.dae")).scene;
  ASSERT_FALSE(scene.spheres.empty());
  check_scene(scene);
}

TEST(Bvh4Counters, CountedQueriesGiveTheSameAnswersAndCountWork) {
  Scene scene = load_collada_file(project_scene("cornell_spheres.dae")).scene;
  Bvh4Options small_leaves;  // 12 triangles would otherwise fit one leaf
  small_leaves.collapse.max_leaf_size = 4;
  SceneBvh4 bvh(scene, small_leaves);
  std::vector<Ray> rays = uniform_random_rays(scene, 500, 3);
  ASSERT_FALSE(bvh4_ref::is_leaf(bvh.bvh().root));
  for (const Ray& r : rays) {
    Hit plain, counted;
    TraversalCounters c;
    bool a = bvh.intersect(r, plain), b = bvh.intersect(r, counted, &c);
    EXPECT_EQ(a, b);
    EXPECT_EQ(plain.prim, counted.prim);
    EXPECT_EQ(plain.t, counted.t);
    EXPECT_GE(c.nodes, 1u);                         // the root is an inner node: its children are always tested
    EXPECT_GE(c.primitives, scene.spheres.size());  // spheres are always tested
    TraversalCounters o;
    EXPECT_EQ(bvh.occluded(r), bvh.occluded(r, &o));
    EXPECT_GE(o.primitives, scene.spheres.size());
  }
}

TEST(Bvh4Counters, OneTriangleIsOneLeafAndOneTest) {
  Scene scene;
  scene.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}};
  scene.triangles = {{0, 1, 2}};
  SceneBvh4 bvh(scene);
  TraversalCounters c;
  Hit hit;
  ASSERT_TRUE(bvh.intersect(Ray{{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, kInfinity}, hit, &c));
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_FLOAT_EQ(hit.u, 0.25f);
  EXPECT_FLOAT_EQ(hit.v, 0.25f);
  EXPECT_EQ(c.nodes, 0u);       // the root is the leaf
  EXPECT_EQ(c.primitives, 1u);  // padding lanes are not counted
  EXPECT_TRUE(bvh.occluded(Ray{{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, 1.5f}, &c));
  EXPECT_EQ(c.primitives, 2u);
}

// One leaf of two blocks, four triangles in each, every ray through all
// eight. In one plane, all eight are hit at exactly one t, and the first
// triangle of the first block must win (a later hit must be strictly nearer);
// with the second four eight float steps nearer (2^-20 at t = 1), one of those
// must win. Every level this CPU runs must find the same hits bit for bit:
// the levels that test both blocks at once (AVX2 and up) as the one-block
// loop (SSE4.2).
TEST(Bvh4Levels, BlockPairsFindWhatBlocksOneAfterTheOtherFind) {
  for (bool nearer : {false, true}) {
    // Thin right triangles along x, right angles at x = 0 (k < 4) or at x = 10
    // (k >= 4): sorted by centroid x (about 3 against 7) they fill one block each.
    Scene s;
    for (int k = 0; k < 8; ++k) {
      float z = nearer && k >= 4 ? 0x1p-20f : 0.0f;
      float corner = k < 4 ? 0.0f : 10.0f, length = 10.0f - 0.5f * float(k % 4);
      float tip = k < 4 ? length : 10.0f - length;
      uint32_t v = static_cast<uint32_t>(s.positions.size());
      s.positions.insert(s.positions.end(), {{corner, 0.0f, z}, {tip, 0.0f, z}, {corner, 0.4f, z}});
      s.triangles.push_back({v, v + 1, v + 2});
      s.triangle_material.push_back(0);
    }
    s.bounds = compute_scene_bounds(s);
    Bvh4Options one_leaf;
    one_leaf.collapse.node = 1e6f;  // no inner node pays: all eight triangles in one leaf
    std::mt19937 rng(5);
    std::uniform_real_distribution<float> along(0.0f, 1.0f);
    std::vector<Ray> rays;
    for (int i = 0; i < 2000; ++i)
      rays.push_back({{3.0f + 3.0f * along(rng), 0.05f * along(rng), 1.0f}, 0.0f, {0.0f, 0.0f, -1.0f}, INFINITY});
    std::vector<Hit> first;
    std::set<uint32_t> winners;
    Isa first_isa{};
    for (Isa isa : compiled_isas()) {
      if (!cpu_supports(isa)) continue;
      SceneBvh4 bvh(s, one_leaf, isa);
      ASSERT_TRUE(bvh4_ref::is_leaf(bvh.bvh().root));
      ASSERT_EQ(bvh4_ref::leaf_block_count(bvh.bvh().root), 2u);
      for (int lane = 0; lane < 4; ++lane) {  // otherwise both blocks would not be hit
        ASSERT_LT(bvh.bvh().blocks[0].prim[lane], 4u);
        ASSERT_GE(bvh.bvh().blocks[1].prim[lane], 4u);
      }
      std::vector<Hit> hits(rays.size());
      for (size_t i = 0; i < rays.size(); ++i) {
        ASSERT_TRUE(bvh.intersect(rays[i], hits[i])) << isa_name(isa);
        EXPECT_TRUE(bvh.occluded(rays[i]));
        if (nearer) { EXPECT_GE(hits[i].prim, 4u) << isa_name(isa) << ", ray " << i; }
        winners.insert(hits[i].prim);
      }
      if (first.empty()) {
        first = hits;
        first_isa = isa;
        continue;
      }
      size_t differ = 0;
      for (size_t i = 0; i < rays.size(); ++i) differ += std::memcmp(&hits[i], &first[i], sizeof(Hit)) != 0;
      EXPECT_EQ(differ, 0u) << isa_name(isa) << " against " << isa_name(first_isa)
                            << (nearer ? ", second four nearer" : ", all in one plane");
    }
    if (!nearer) {  // exact ties: the first triangle of the first block, as in one block after the other
      EXPECT_EQ(winners.size(), 1u);
      EXPECT_EQ(*winners.begin(), SceneBvh4(s, one_leaf, first_isa).bvh().blocks[0].prim[0]);
    }
  }
}

}  // namespace
}  // namespace pt::test
