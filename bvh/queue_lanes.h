// K rays of a queue held as arrays (RayArrays), loaded into lanes: their
// origins, directions and segment, the slab test's constants as NodeRay
// computes them, and which of them can be traced; and the prefetch of a
// queue's arrays ahead of the loop that reads them. The sets and streams of
// the queue tracer load their rays here.
#pragma once

#include <algorithm>
#include <cstddef>

#include "bvh4_node_test.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"

#if !PT_PER_LEVEL
#error "queue_lanes.h is for code compiled once per instruction-set level"
#endif

namespace pt {
inline namespace PT_ISA_NS {

/// Lane l of K values of a queue's array from index i: a[i + l], or the last
/// ray's value for lanes past the queue's end.
PT_ALWAYS_INLINE vfloatK load_queue_lanes(const float* a, size_t i, size_t size) {
  if (i + kLanes <= size) return vfloatK::load_unaligned(a + i);
  alignas(64) float tail[kLanes];
  for (size_t l = 0; l < kLanes; ++l) tail[l] = a[std::min(i + l, size - 1)];
  return vfloatK::load_aligned(tail);
}

/// K rays of a queue from ray i (lanes past its end repeat its last ray, and
/// are not traceable).
struct QueueLanes {
  vfloatK org[3], dir[3], tmin, tmax;
  vfloatK rdir[3], org_rdir[3];  ///< NodeRay's constants
  uint32_t traceable;            ///< lanes that are in the queue and pass ray_is_traceable's test

  PT_ALWAYS_INLINE QueueLanes(const RayArrays& rays, size_t i) {
    auto load = [&](const float* a) { return load_queue_lanes(a, i, rays.size); };
    for (int a = 0; a < 3; ++a) org[a] = load(rays.org[a]), dir[a] = load(rays.dir[a]);
    tmin = rays.tmin ? load(rays.tmin) : vfloatK(0.0f);
    tmax = load(rays.tmax);
    traceable = lanes_below(std::min(kLanes, rays.size - i)) & lane_mask(lanes_traceable(org, dir, tmin, tmax));
    slab_constants(org, dir, rdir, org_rdir);
  }
};

/// How far ahead of the rays being loaded prefetch_queue_rays reaches: a few
/// packets, a few hundred nanoseconds of tracing.
inline constexpr size_t kQueuePrefetchRays = 64;

/// Starts loading the cache line of each of the queue's arrays that holds
/// ray i; nothing past the queue's end. A queue streamed from memory (a ray
/// file, a benchmark's set of rays) otherwise waits on the first load of
/// every chunk: with eight arrays read at once, the hardware's stream
/// prefetchers fall behind.
PT_ALWAYS_INLINE void prefetch_queue_rays(const RayArrays& q, size_t i) {
  if (i >= q.size) return;
  for (int a = 0; a < 3; ++a) prefetch_l1(q.org[a] + i), prefetch_l1(q.dir[a] + i);
  if (q.tmin) prefetch_l1(q.tmin + i);
  prefetch_l1(q.tmax + i);
}

}  // namespace PT_ISA_NS
}  // namespace pt
