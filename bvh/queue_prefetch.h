// Prefetch of a queue's ray arrays ahead of the loop that reads them. A queue
// streamed from memory (a ray file, a benchmark's set of rays: every queue's
// arrays met for the first time) otherwise waits on the first load of every
// packet or list chunk: with eight arrays read and more written at once, the
// hardware's stream prefetchers fall behind. Within a render the wave's queues
// were written just before and sit in the caches, where this costs a few
// instructions per K rays.
#pragma once

#include <cstddef>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/ray_arrays.h"
#include "kernels/simd/simd.h"

namespace pt {
inline namespace PT_ISA_NS {

/// How far ahead of the rays being loaded prefetch_queue_rays reaches: a few
/// packets, a few hundred nanoseconds of tracing.
inline constexpr size_t kQueuePrefetchRays = 64;

/// Starts loading the cache line of each of the queue's arrays that holds
/// ray i; nothing past the queue's end. Always inlined, as prefetch_l1 is: a
/// call GCC keeps out of line to a function that only prefetches is deleted.
PT_ALWAYS_INLINE void prefetch_queue_rays(const RayArrays& q, size_t i) {
  if (i >= q.size) return;
  for (int a = 0; a < 3; ++a) prefetch_l1(q.org[a] + i), prefetch_l1(q.dir[a] + i);
  if (q.tmin) prefetch_l1(q.tmin + i);
  prefetch_l1(q.tmax + i);
}

}  // namespace PT_ISA_NS
}  // namespace pt
