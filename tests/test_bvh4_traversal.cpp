// SceneBvh4 against brute force on every shared CS184 scene and the built-in
// scene: closest hits (same primitive, or the same t on exact ties) and
// occlusion answers for camera, uniformly random, diffuse-bounce and shadow
// rays, with both triangle tests; counted and uncounted queries agree.
#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "bvh/scene_bvh4.h"
#include "test_bvh4_support.h"
#include "test_support.h"

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

void expect_same_answers(const Scene& scene, const SceneBvh4& bvh, const Expected& e) {
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

/// Both triangle tests against the same brute-force answers.
void check_scene(const Scene& scene) {
  std::vector<Expected> sets = expected_answers(scene);
  ASSERT_FALSE(sets.back().rays.empty());
  for (bool watertight : {false, true}) {
    SCOPED_TRACE(watertight ? "watertight" : "Moller-Trumbore");
    Bvh4Options options;
    options.watertight = watertight;
    SceneBvh4 bvh(scene, options);
    for (const Expected& e : sets) expect_same_answers(scene, bvh, e);
  }
}

class Bvh4SharedScene : public ::testing::TestWithParam<std::string> {};

TEST_P(Bvh4SharedScene, MatchesBruteForce) {
  PT_REQUIRE_SHARED_SCENES();
  check_scene(load_collada_file(shared_scene(GetParam())).scene);
}

INSTANTIATE_TEST_SUITE_P(AllScenes, Bvh4SharedScene, ::testing::ValuesIn(shared_scene_names()),
                         [](const auto& info) {
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
    bool a = bvh.intersect(r, plain), b = bvh.intersect(r, counted, c);
    EXPECT_EQ(a, b);
    EXPECT_EQ(plain.prim, counted.prim);
    EXPECT_EQ(plain.t, counted.t);
    EXPECT_GE(c.nodes, 1u);  // the root is an inner node: its children are always tested
    EXPECT_GE(c.primitives, scene.spheres.size());  // spheres are always tested
    TraversalCounters o;
    EXPECT_EQ(bvh.occluded(r), bvh.occluded(r, o));
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
  ASSERT_TRUE(bvh.intersect(Ray{{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, kInfinity}, hit, c));
  EXPECT_EQ(hit.prim, 0u);
  EXPECT_FLOAT_EQ(hit.t, 1.0f);
  EXPECT_FLOAT_EQ(hit.u, 0.25f);
  EXPECT_FLOAT_EQ(hit.v, 0.25f);
  EXPECT_EQ(c.nodes, 0u);       // the root is the leaf
  EXPECT_EQ(c.primitives, 1u);  // padding lanes are not counted
  EXPECT_TRUE(bvh.occluded(Ray{{0.25f, 0.25f, 1.0f}, 0.0f, {0, 0, -1}, 1.5f}, c));
  EXPECT_EQ(c.primitives, 2u);
}

}  // namespace
}  // namespace pt::test
