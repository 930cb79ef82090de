// The ray tracers the SIMD engines (wavefront, megakernel) run on, behind one
// small interface: intersect(ray, hit, tests), occluded(ray, tests) and their
// queue forms, where `tests` counts primitive tests when the tracer counts
// them. For code compiled per instruction-set level (the BVH4's queries are
// inlined).
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "scene_bvh2.h"
#include "scene_bvh4_queries.h"

namespace pt {
inline namespace PT_ISA_NS {

/// The 4-wide BVH. kCount: also count primitive tests (off in the fast path).
template <bool kCount = false>
struct Bvh4Tracer {
  const SceneBvh4& accel;

  /// query(counters) with counters that count (their primitive tests added
  /// to `tests`) or that compile away.
  template <class Query>
  static decltype(auto) counted(uint64_t& tests, Query&& query) {
    if constexpr (kCount) {
      TraversalCounters c;
      struct AddTests {
        const TraversalCounters& c;
        uint64_t& tests;
        ~AddTests() { tests += c.primitives; }
      } add{c, tests};
      return query(c);
    } else {
      NoCounters c;
      return query(c);
    }
  }
  /// Closest hits of a whole queue (the queue tracer).
  void intersect_queue(const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch, uint64_t& tests) const {
    counted(tests, [&](auto& c) { bvh4_queries::intersect_queue(accel, rays, hits, scratch, c); });
  }
  /// blocked[i] = whether ray i of a whole queue is blocked (the queue tracer).
  void occluded_queue(const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch, uint64_t& tests) const {
    counted(tests, [&](auto& c) { bvh4_queries::occluded_queue(accel, rays, blocked, scratch, c); });
  }
  bool intersect(const Ray& r, Hit& h, uint64_t& tests) const {
    return counted(tests, [&](auto& c) { return bvh4_queries::intersect(accel, r, h, c); });
  }
  bool occluded(const Ray& r, uint64_t& tests) const {
    return counted(tests, [&](auto& c) { return bvh4_queries::occluded(accel, r, c); });
  }
};

/// The midpoint binary BVH, or brute force; no queue tracer, so queues are
/// traced ray by ray.
struct Bvh2Tracer {
  const SceneBvh2& accel;
  void intersect_queue(const RayArrays& rays, const HitArrays& hits, QueueScratch&, uint64_t& tests) const {
    for (size_t i = 0; i < rays.size; ++i) {
      Hit h;
      const Ray r = rays.ray(i);
      if (!intersect(r, h, tests)) h = Hit{r.tmax, 0.0f, 0.0f, kInvalidId};
      hits.store(i, h);
    }
  }
  void occluded_queue(const RayArrays& rays, uint8_t* blocked, QueueScratch&, uint64_t& tests) const {
    for (size_t i = 0; i < rays.size; ++i) blocked[i] = occluded(rays.ray(i), tests);
  }
  bool intersect(const Ray& r, Hit& h, uint64_t& tests) const { return accel.intersect(r, h, tests); }
  bool occluded(const Ray& r, uint64_t& tests) const { return accel.occluded(r, tests); }
};

}  // namespace PT_ISA_NS
}  // namespace pt
