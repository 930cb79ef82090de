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
#include "kernels/math/ray_arrays.h"
#include "queue_scratch.h"
#include "kernels/simd/isa.h"
#include "kernels/math/ray.h"
#include "kernels/scene/scene.h"
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
  bool intersect(const Ray& ray, Hit& hit) const { return queries_->intersect(*this, ray, hit, nullptr); }
  /// Any hit with ray.tmin <= t < ray.tmax.
  bool occluded(const Ray& ray) const { return queries_->occluded(*this, ray, nullptr); }
  /// Same queries, also counting nodes visited and primitives tested.
  bool intersect(const Ray& ray, Hit& hit, TraversalCounters& c) const {
    return queries_->intersect(*this, ray, hit, &c);
  }
  bool occluded(const Ray& ray, TraversalCounters& c) const { return queries_->occluded(*this, ray, &c); }

  /// Closest hits of rays[i] into hits[i], each ray traced on its own (one
  /// call for the whole range: no per-ray dispatch).
  void intersect_each(std::span<const Ray> rays, std::span<Hit> hits) const {
    queries_->intersect_each(*this, rays, hits);
  }
  /// blocked[i] = occluded(rays[i]) for every i, likewise.
  void occluded_each(std::span<const Ray> rays, std::span<uint8_t> blocked) const {
    queries_->occluded_each(*this, rays, blocked);
  }

  /// Closest hits of a whole queue of rays (the queue tracer, bvh4_stream.h):
  /// hits[i] as intersect(rays.ray(i)) gives it, bit for bit but for which of
  /// two triangles at exactly the same t is reported. `scratch` is the calling
  /// thread's, reused from queue to queue.
  void intersect(const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch) const {
    queries_->intersect_queue(*this, rays, hits, scratch, nullptr);
  }
  void intersect(const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch, TraversalCounters& c) const {
    queries_->intersect_queue(*this, rays, hits, scratch, &c);
  }
  /// blocked[i] = occluded(rays.ray(i)) (0 or 1) for every ray of a queue.
  void occluded(const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch) const {
    queries_->occluded_queue(*this, rays, blocked, scratch, nullptr);
  }
  void occluded(const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch, TraversalCounters& c) const {
    queries_->occluded_queue(*this, rays, blocked, scratch, &c);
  }
  /// Rays per packet: the lane count K of the level the queries run at.
  uint32_t packet_lanes() const { return queries_->packet_lanes; }
  /// Closest hits of rays[i] into hits[i] for every i. Runs of packet_lanes()
  /// consecutive rays are traced as packets: fastest when they are coherent
  /// (camera rays of a pixel block). Same answers as the single-ray query.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits) const {
    queries_->intersect_packets(*this, rays, hits);
  }
  /// One packet: traces rays[i] into hits[i] for the lanes i < packet_lanes()
  /// set in `lanes`; the other entries of both arrays are neither read nor written.
  void intersect_packet(const Ray* rays, Hit* hits, uint32_t lanes) const {
    queries_->intersect_packet(*this, rays, hits, lanes);
  }
  /// One packet of occlusion queries: the lanes i < packet_lanes() set in
  /// `lanes` whose ray rays[i] is blocked (the same answers as occluded(rays[i])).
  /// Fastest when the rays are coherent (shadow rays of one pixel's samples).
  uint32_t occluded_packet(const Ray* rays, uint32_t lanes) const {
    return queries_->occluded_packet(*this, rays, lanes);
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
