// SceneBvh2: build and the two queries.
#include "scene_bvh2.h"

#include "bvh2_traverse.h"
#include "kernels/scene/sphere_intersect.h"
#include "kernels/scene/triangle_intersect.h"

namespace pt {

SceneBvh2::SceneBvh2(const Scene& scene, Bvh2Mode mode, uint32_t max_leaf_size) : scene_(scene), mode_(mode) {
  if (mode_ != Bvh2Mode::kMidpoint) return;
  std::vector<BBox> boxes;
  std::vector<float3> centers;
  boxes.reserve(scene.primitive_count());
  for (const TriangleIndices& t : scene.triangles) {
    BBox b = BBox::of_point(scene.positions[t.v0]);
    b.expand(scene.positions[t.v1]);
    b.expand(scene.positions[t.v2]);
    boxes.push_back(b);
  }
  for (const Sphere& s : scene.spheres) boxes.push_back({s.center - float3(s.radius), s.center + float3(s.radius)});
  for (const BBox& b : boxes) centers.push_back(b.center());
  bvh_ = build_bvh2_midpoint(boxes, centers, max_leaf_size);
}

bool SceneBvh2::test_primitive(uint32_t prim, const Ray& ray, float tmax, Hit& hit) const {
  uint32_t n_tri = static_cast<uint32_t>(scene_.triangles.size());
  float t, u = 0, v = 0;
  if (prim < n_tri) {
    const TriangleIndices& tri = scene_.triangles[prim];
    if (!intersect_triangle_mt(ray.org, ray.dir, ray.tmin, tmax, scene_.positions[tri.v0], scene_.positions[tri.v1],
                               scene_.positions[tri.v2], t, u, v))
      return false;
    hit = {t, u, v, prim};
    return true;
  }
  const Sphere& s = scene_.spheres[prim - n_tri];
  if (!intersect_sphere(ray.org, ray.dir, ray.tmin, tmax, s.center, s.radius, t)) return false;
  hit = {t, 0.0f, 0.0f, sphere_prim_id(prim - n_tri)};
  return true;
}

bool SceneBvh2::intersect(const Ray& ray, Hit& hit, uint64_t& tests) const {
  hit = Hit{};
  hit.t = ray.tmax;
  float tmax = ray.tmax;
  bool found = false;
  if (mode_ == Bvh2Mode::kBruteForce) {
    uint32_t n = static_cast<uint32_t>(scene_.primitive_count());
    for (uint32_t p = 0; p < n; ++p) found |= test_primitive(p, ray, hit.t, hit);
    tests += n;
    return found;
  }
  traverse_bvh2<false>(bvh_, ray, tmax, [&](uint32_t first, uint32_t count, float& t_limit) {
    bool any = false;
    for (uint32_t i = first; i < first + count; ++i) any |= test_primitive(bvh_.prim_order[i], ray, hit.t, hit);
    tests += count;
    t_limit = hit.t;
    return any;
  });
  return hit.valid();
}

bool SceneBvh2::occluded(const Ray& ray, uint64_t& tests) const {
  Hit scratch;
  if (mode_ == Bvh2Mode::kBruteForce) {
    uint32_t n = static_cast<uint32_t>(scene_.primitive_count());
    for (uint32_t p = 0; p < n; ++p) {
      ++tests;
      if (test_primitive(p, ray, ray.tmax, scratch)) return true;
    }
    return false;
  }
  float tmax = ray.tmax;
  return traverse_bvh2<true>(bvh_, ray, tmax, [&](uint32_t first, uint32_t count, float&) {
    for (uint32_t i = first; i < first + count; ++i) {
      ++tests;
      if (test_primitive(bvh_.prim_order[i], ray, ray.tmax, scratch)) return true;
    }
    return false;
  });
}

}  // namespace pt
