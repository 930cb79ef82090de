// SceneBvh4: the renderer's ray queries over a whole Scene. Triangles go
// through the 4-wide BVH; spheres (0-2 in the CS184 scenes) sit in a small
// list tested after (closest hit) or before (any hit) the BVH walk. The
// build is compiled once for every CPU; the queries are compiled once per
// instruction-set level (scene_bvh4_queries.h) and reached here through the
// table of the level that was active when the structure was built. Code
// compiled per level (the engines) calls the inline queries directly.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "bvh4.h"
#include "bvh4_build.h"
#include "bvh4_query_table.h"
#include "kernels/math/ray.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/scene/scene.h"
#include "kernels/simd/isa.h"
#include "queue_scratch.h"
#include "traversal_counters.h"

namespace pt {

class SceneBvh4 {
 public:
  /// 16 bytes.
  struct SphereShape {
    float3 center;
    float radius;
  };

  /// BVH4 over all of scene.triangles and scene.spheres, queried with the
  /// kernels of `isa` (default: active_isa()). threads = 0: all available.
  explicit SceneBvh4(const Scene& scene, const Bvh4Options& options = {});
  SceneBvh4(const Scene& scene, const Bvh4Options& options, Isa isa);

  /// Closest hit with ray.tmin <= t < ray.tmax. On a hit fills `hit` with t, u, v and
  /// prim = the index into scene.triangles, or sphere_prim_id(i) for sphere i; u, v are
  /// barycentrics w.r.t. the scene's vertex order (u weights v1, v weights v2; 0 for
  /// spheres). On a miss hit = {ray.tmax, 0, 0, kInvalidId}. Rays with a NaN or
  /// infinite origin or direction, or a NaN or empty t range, hit nothing.
  /// `counters`, when given, add the nodes visited and primitives tested.
  bool intersect(const Ray& ray, Hit& hit, TraversalCounters* counters = nullptr) const {
    return queries_->intersect(*this, ray, hit, counters);
  }
  /// Whether something lies on the ray with ray.tmin <= t < ray.tmax.
  bool occluded(const Ray& ray, TraversalCounters* counters = nullptr) const {
    return queries_->occluded(*this, ray, counters);
  }
  /// Closest hits of a whole queue of rays (the queue tracer, docs/bvh.md):
  /// hits[i] as intersect(rays.ray(i)) gives it, bit for bit. `scratch` is
  /// the calling thread's, reused from queue to queue.
  void intersect_queue(const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch,
                       TraversalCounters* counters = nullptr) const {
    queries_->intersect_queue(*this, rays, hits, scratch, counters);
  }
  /// blocked[i] = occluded(rays.ray(i)) (0 or 1) for every ray of a queue.
  void occluded_queue(const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch,
                      TraversalCounters* counters = nullptr) const {
    queries_->occluded_queue(*this, rays, blocked, scratch, counters);
  }

  /// The instruction-set level the queries run at.
  Isa isa() const { return queries_->isa; }
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
  std::span<const SphereShape> spheres() const { return spheres_; }

 private:
  Bvh4 bvh_;
  std::vector<SphereShape> spheres_;
  Bvh4BuildStats stats_;
  const Bvh4QueryTable* queries_;
};

}  // namespace pt
