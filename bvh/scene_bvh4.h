// SceneBvh4: the renderer's ray queries over a whole Scene. Triangles go
// through the 4-wide BVH; spheres (0-2 in the CS184 scenes) sit in a small
// list tested after (closest hit) or before (any hit) the BVH walk. The
// queries are inline so that the renderers' hot loops pay no call.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh4.h"
#include "bvh4_build.h"
#include "bvh4_traverse.h"
#include "kernels/ray.h"
#include "kernels/scene.h"
#include "kernels/sphere_intersect.h"
#include "traversal_counters.h"

namespace pt {

class SceneBvh4 {
 public:

  /// BVH4 over all of scene.triangles and scene.spheres. threads = 0: all available.
  explicit SceneBvh4(const Scene& scene, const Bvh4Options& options = {});

  /// Closest hit with ray.tmin <= t < ray.tmax. On a hit fills `hit` with t, u, v and
  /// prim = the index into scene.triangles, or sphere_prim_id(i) for sphere i; u, v are
  /// barycentrics w.r.t. the scene's vertex order (u weights v1, v weights v2; 0 for
  /// spheres). On a miss hit = {ray.tmax, 0, 0, kInvalidId}. Rays with a NaN or
  /// infinite origin or direction, or a NaN or empty t range, hit nothing.
  bool intersect(const Ray& ray, Hit& hit) const {
    NoCounters c;
    return intersect_counted(ray, hit, c);
  }
  /// Any hit with ray.tmin <= t < ray.tmax.
  bool occluded(const Ray& ray) const {
    NoCounters c;
    return occluded_counted(ray, c);
  }
  /// Same queries, also counting nodes visited and primitives tested.
  bool intersect(const Ray& ray, Hit& hit, TraversalCounters& c) const { return intersect_counted(ray, hit, c); }
  bool occluded(const Ray& ray, TraversalCounters& c) const { return occluded_counted(ray, c); }

  /// Closest hits of rays[i] into hits[i] for every i. Runs of kLanes consecutive
  /// rays are traced as packets: fastest when they are coherent (camera rays of
  /// a pixel block). Same answers as the single-ray query.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const;
  /// One packet: traces rays[i] into hits[i] for the lanes i < kLanes set in
  /// `lanes`; the other entries of both arrays are neither read nor written.
  void intersect_packet(const Ray* rays, Hit* hits, uint32_t lanes) const;
  /// One packet of occlusion queries: the lanes i < kLanes set in `lanes`
  /// whose ray rays[i] is blocked (the same answers as occluded(rays[i])).
  /// Fastest when the rays are coherent (shadow rays of one pixel's samples).
  uint32_t occluded_packet(const Ray* rays, uint32_t lanes) const;

  /// Closest hits of a large batch of incoherent rays (bounce rays), traced one
  /// by one in parallel in the calling oneTBB arena. When the BVH has at least
  /// Bvh4Options::reorder_min_bytes they are traced in the order of coherent_order (ray_order.h):
  /// sorting costs less than the cache misses it saves only when the tree does
  /// not fit the caches. Same answers as the single-ray query.
  void intersect_incoherent(std::span<const Ray> rays, std::span<Hit> hits) const;
  /// Occlusion of a large batch of incoherent rays, likewise: blocked[i] = 0 or 1.
  void occluded_incoherent(std::span<const Ray> rays, std::span<uint8_t> blocked) const;

  const Bvh4BuildStats& stats() const { return stats_; }
  /// Bytes of nodes, triangle blocks and spheres: allocated (arrays of 1 MiB
  /// and more take whole 2 MiB huge pages), and of those in use.
  size_t bytes() const {
    return decltype(bvh_.nodes)::allocator_type::allocated_bytes(bvh_.nodes.capacity()) +
           decltype(bvh_.blocks)::allocator_type::allocated_bytes(bvh_.blocks.capacity()) +
           spheres_.capacity() * sizeof(SphereShape);
  }
  size_t used_bytes() const { return stats_.bytes + spheres_.size() * sizeof(SphereShape); }
  const Bvh4& bvh() const { return bvh_; }

 private:
  /// 16 bytes.
  struct SphereShape {
    float3 center;
    float radius;
  };

  template <class C> bool intersect_counted(const Ray& ray, Hit& hit, C& c) const {
    bool found = bvh_.form == TriangleForm::kWatertight ? bvh4_intersect<TriangleForm::kWatertight>(bvh_, ray, hit, c)
                                                          : bvh4_intersect<TriangleForm::kMollerTrumbore>(bvh_, ray, hit, c);
    if (spheres_.empty() || !ray_is_traceable(ray)) return found;
    c.primitives_tested(static_cast<uint32_t>(spheres_.size()));
    for (uint32_t i = 0; i < spheres_.size(); ++i) {
      float t;
      if (!intersect_sphere(ray.org, ray.dir, ray.tmin, hit.t, spheres_[i].center, spheres_[i].radius, t)) continue;
      hit = {t, 0.0f, 0.0f, sphere_prim_id(i)};
      found = true;
    }
    return found;
  }

  template <class C> bool occluded_counted(const Ray& ray, C& c) const {
    if (!spheres_.empty() && ray_is_traceable(ray)) {
      c.primitives_tested(static_cast<uint32_t>(spheres_.size()));
      for (const SphereShape& s : spheres_) {
        float t;
        if (intersect_sphere(ray.org, ray.dir, ray.tmin, ray.tmax, s.center, s.radius, t)) return true;
      }
    }
    return bvh_.form == TriangleForm::kWatertight ? bvh4_occluded<TriangleForm::kWatertight>(bvh_, ray, c)
                                                   : bvh4_occluded<TriangleForm::kMollerTrumbore>(bvh_, ray, c);
  }

  Bvh4 bvh_;
  std::vector<SphereShape> spheres_;
  BBox bounds_;  ///< of all vertices and spheres: the grid of ray_order_key
  size_t reorder_min_bytes_;
  Bvh4BuildStats stats_;
};

}  // namespace pt
