// The BVH overlays' queries: the boxes of each depth nest inside the depth
// above and cover every child slot once; the walk of a ray (camera rays, and
// rays from inside the scene, where entry distances tie) finds the hit the
// engine finds, to the bit, and tests as many inner nodes as the engine's
// counters count, at the level the engine runs.
#include <random>

#include <gtest/gtest.h>

#include "bvh/bvh4_inspect.h"
#include "bvh/scene_bvh4.h"
#include "io/camera_setup.h"
#include "kernels/simd/isa.h"
#include "support/test_support.h"

namespace pt {
namespace {

std::vector<std::filesystem::path> scenes() {
  std::vector<std::filesystem::path> s = {test::project_scene("cornell_spheres.dae"),
                                          test::project_scene("cornell_materials.dae")};
  if (test::shared_scenes_available())
    for (const char* name : {"CBbunny.dae", "CBcoil.dae", "bunny.dae"}) s.push_back(test::shared_scene(name));
  return s;
}

bool inside(const BBox& inner, const BBox& outer) {
  return inner.lower.x >= outer.lower.x && inner.lower.y >= outer.lower.y && inner.lower.z >= outer.lower.z &&
         inner.upper.x <= outer.upper.x && inner.upper.y <= outer.upper.y && inner.upper.z <= outer.upper.z;
}

TEST(Bvh4Level, BoxesNestByDepthAndCoverEverySlotOnce) {
  for (const auto& path : scenes()) {
    SCOPED_TRACE(path.filename().string());
    LoadResult loaded = load_collada_file(path);
    const Scene& scene = loaded.scene;
    SceneBvh4 accel(scene);
    const Bvh4& bvh = accel.bvh();
    BBox triangles;
    for (const TriangleIndices& t : scene.triangles)
      for (uint32_t v : {t.v0, t.v1, t.v2}) triangles.expand(scene.positions[v]);
    Bvh4Level root = bvh4_level(bvh, 0, 10);
    ASSERT_EQ(root.boxes.size(), 1u);
    EXPECT_TRUE(inside(triangles, root.boxes[0]));  // the build rounds boxes outwards by a few ulps
    const float slack = 1e-6f * length(triangles.extent());
    EXPECT_LE(length(root.boxes[0].lower - triangles.lower), slack);
    EXPECT_LE(length(root.boxes[0].upper - triangles.upper), slack);
    size_t slots = 0;
    for (const Bvh4Node& n : bvh.nodes)
      for (uint32_t c : n.child) slots += c != bvh4_ref::kEmptyRef;
    size_t listed = 0;
    const int deepest = bvh4_max_depth(bvh);
    std::vector<BBox> above = root.boxes;
    for (int d = 1; d <= deepest + 1; ++d) {
      Bvh4Level l = bvh4_level(bvh, d, size_t(1) << 30);
      EXPECT_FALSE(l.truncated);
      EXPECT_EQ(l.boxes.empty(), d > deepest) << d;
      for (const BBox& b : l.boxes) {
        bool nested = false;
        for (const BBox& a : above) nested |= inside(b, a);
        ASSERT_TRUE(nested) << "depth " << d;
      }
      listed += l.boxes.size();
      above = l.boxes;
    }
    EXPECT_EQ(listed, slots);
    Bvh4Level cut = bvh4_level(bvh, 2, 3);
    EXPECT_EQ(cut.boxes.size(), std::min<size_t>(3, bvh4_level(bvh, 2, 1 << 30).boxes.size()));
    EXPECT_EQ(cut.truncated, bvh4_level(bvh, 2, 1 << 30).boxes.size() > 3);
  }
}

/// Whether the ray's segment [tmin, tmax] meets box b (within a relative
/// 1e-5 of the box's size, the slab test's rounding).
bool segment_meets(const Ray& r, const BBox& b) {
  float tn = r.tmin, tf = r.tmax;
  const float3 pad = b.extent() * 1e-5f + float3(1e-6f);
  for (int a = 0; a < 3; ++a) {
    const float lo = (b.lower[a] - pad[a] - r.org[a]) / r.dir[a], hi = (b.upper[a] + pad[a] - r.org[a]) / r.dir[a];
    tn = std::max(tn, std::min(lo, hi));
    tf = std::min(tf, std::max(lo, hi));
  }
  return tn <= tf;
}

TEST(Bvh4Walk, FindsTheEnginesHitAndTestsItsNodes) {
  // The walk the live view draws is the engine's: the same hit and nodes,
  // and every node or leaf it visits lies one level below one visited before
  // (or higher up, after a pop), in a box the ray's segment meets.
  for (const auto& path : scenes()) {
    SCOPED_TRACE(path.filename().string());
    LoadResult loaded = load_collada_file(path);
    const Scene& scene = loaded.scene;
    SceneBvh4 accel(scene);
    std::vector<Ray> rays;
    const int w = 64, h = 48;
    const Camera c = resolve_camera(scene, w, h);
    for (int y = 0; y < h; ++y)
      for (int x = 0; x < w; ++x) rays.push_back(camera_ray(c, (x + 0.5f) / w, 1.0f - (y + 0.5f) / h));
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> u(0.0f, 1.0f), s(-1.0f, 1.0f);
    const BBox& b = scene.bounds;
    for (int i = 0; i < 3000; ++i) {  // from inside the scene: many boxes entered at t = tmin
      float3 o = b.lower + float3(u(rng), u(rng), u(rng)) * b.extent();
      float3 d{s(rng), s(rng), s(rng)};
      if (length(d) < 1e-3f) continue;
      rays.push_back({o, 0.0f, normalize(d), 1e30f});
    }
    size_t visits_checked = 0;
    for (const Ray& r : rays) {
      TraversalCounters counters;
      Hit engine;
      accel.intersect(r, engine, &counters);
      Bvh4Walk walk = walk_bvh4(accel, r, 1 << 20);
      ASSERT_EQ(walk.inner_nodes, counters.nodes);
      ASSERT_EQ(walk.visits.size(), walk.inner_nodes + walk.leaves);
      if (!engine.is_sphere()) {
        ASSERT_EQ(walk.hit.prim, engine.prim);
        ASSERT_EQ(walk.hit.t, engine.t);
      } else if (walk.hit.valid()) {
        ASSERT_GE(walk.hit.t, engine.t);  // the walk sees triangles only; the sphere was nearer
      }
      if (!walk.visits.empty()) {
        EXPECT_EQ(walk.visits[0].depth, 0u);
        visits_checked += walk.visits.size();
      }
      for (size_t k = 1; k < walk.visits.size(); ++k) {
        ASSERT_LE(walk.visits[k].depth, walk.visits[k - 1].depth + 1) << "visit " << k;
        ASSERT_TRUE(segment_meets(r, walk.visits[k].box)) << "visit " << k;
      }
    }
    if (bvh4_max_depth(accel.bvh()) > 0) { EXPECT_GT(visits_checked, rays.size()); }
  }
}

TEST(Bvh4Walk, RaysThatCannotBeTracedVisitNothing) {
  LoadResult loaded = load_collada_file(test::project_scene("cornell_spheres.dae"));
  SceneBvh4 accel(loaded.scene);
  for (Ray r : {Ray{{0, 0, 0}, 0.0f, {NAN, 0, 0}, 1e30f}, Ray{{INFINITY, 0, 0}, 0.0f, {0, 0, 1}, 1e30f},
                Ray{{0, 0, 0}, 1.0f, {0, 0, 1}, 1.0f}}) {
    Bvh4Walk w = walk_bvh4(accel, r, 100);
    EXPECT_TRUE(w.visits.empty());
    EXPECT_FALSE(w.hit.valid());
  }
}

}  // namespace
}  // namespace pt
