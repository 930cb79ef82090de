// The ray tracers the SIMD engines (wavefront, megakernel) run on, behind one
// small interface: intersect(ray, hit, tests), occluded(ray, tests) and their
// packet forms over the lanes set in a mask, where `tests` counts primitive
// tests when the tracer counts them. For code compiled per instruction-set
// level (the BVH4's queries are inlined).
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "scene_bvh2.h"
#include "scene_bvh4_queries.h"

namespace pt {
inline namespace PT_ISA_NS {

/// The 4-wide BVH. kCount: also count primitive tests (off in the fast path;
/// counting traces packets ray by ray).
template <bool kCount = false>
struct Bvh4Tracer {
  const SceneBvh4& accel;
  /// rays[i] -> hits[i] for the lanes set in `lanes`, as one SIMD packet.
  void intersect_packet(const Ray* rays, Hit* hits, uint32_t lanes, uint64_t& tests) const {
    if constexpr (kCount) {
      for (uint32_t m = lanes; m; m &= m - 1) intersect(rays[__builtin_ctz(m)], hits[__builtin_ctz(m)], tests);
    } else {
      bvh4_queries::intersect_packet(accel, rays, hits, lanes);
    }
  }
  /// The lanes of `lanes` whose rays are blocked, as one SIMD packet.
  uint32_t occluded_packet(const Ray* rays, uint32_t lanes, uint64_t& tests) const {
    if constexpr (kCount) {
      uint32_t blocked = 0;
      for (uint32_t m = lanes; m; m &= m - 1)
        if (occluded(rays[__builtin_ctz(m)], tests)) blocked |= 1u << __builtin_ctz(m);
      return blocked;
    } else {
      return bvh4_queries::occluded_packet(accel, rays, lanes);
    }
  }
  /// Closest hits of a whole queue (the queue tracer).
  void intersect_queue(const RayArrays& rays, const HitArrays& hits, QueueScratch& scratch, uint64_t& tests) const {
    if constexpr (kCount) {
      TraversalCounters c;
      bvh4_queries::intersect_queue(accel, rays, hits, scratch, c);
      tests += c.primitives;
    } else {
      NoCounters c;
      bvh4_queries::intersect_queue(accel, rays, hits, scratch, c);
    }
  }
  /// blocked[i] = whether ray i of a whole queue is blocked (the queue tracer).
  void occluded_queue(const RayArrays& rays, uint8_t* blocked, QueueScratch& scratch, uint64_t& tests) const {
    if constexpr (kCount) {
      TraversalCounters c;
      bvh4_queries::occluded_queue(accel, rays, blocked, scratch, c);
      tests += c.primitives;
    } else {
      NoCounters c;
      bvh4_queries::occluded_queue(accel, rays, blocked, scratch, c);
    }
  }
  bool intersect(const Ray& r, Hit& h, uint64_t& tests) const {
    if constexpr (kCount) {
      TraversalCounters c;
      bool found = bvh4_queries::intersect(accel, r, h, c);
      tests += c.primitives;
      return found;
    } else {
      return bvh4_queries::intersect(accel, r, h);
    }
  }
  bool occluded(const Ray& r, uint64_t& tests) const {
    if constexpr (kCount) {
      TraversalCounters c;
      bool blocked = bvh4_queries::occluded(accel, r, c);
      tests += c.primitives;
      return blocked;
    } else {
      return bvh4_queries::occluded(accel, r);
    }
  }
};

/// The midpoint binary BVH, or brute force; no packet traversal, so packets
/// are traced ray by ray.
struct Bvh2Tracer {
  const SceneBvh2& accel;
  void intersect_packet(const Ray* rays, Hit* hits, uint32_t lanes, uint64_t& tests) const {
    for (uint32_t m = lanes; m; m &= m - 1) {
      uint32_t i = __builtin_ctz(m);
      if (!intersect(rays[i], hits[i], tests)) hits[i] = Hit{rays[i].tmax, 0.0f, 0.0f, kInvalidId};
    }
  }
  uint32_t occluded_packet(const Ray* rays, uint32_t lanes, uint64_t& tests) const {
    uint32_t blocked = 0;
    for (uint32_t m = lanes; m; m &= m - 1)
      if (occluded(rays[__builtin_ctz(m)], tests)) blocked |= 1u << __builtin_ctz(m);
    return blocked;
  }
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
