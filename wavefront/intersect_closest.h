// Stage 2: closest hits of a ray queue: the whole queue through the tracer's
// queue tracer, or (for comparison) ray by ray, through the tracer's inline
// queries (bvh/tracers.h).
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "streams.h"
#include "trace_mode.h"
#include "wave_buffers.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// hits[i] = closest hit of rays[i] (prim = kInvalidId on a miss). Queue: a
/// RayQueue, or a ShadowQueue of hemisphere-sampling rays.
template <class Tracer, class Queue>
void intersect_closest(const Tracer& tracer, const Queue& rays, HitQueue& hits, TracingBuffers& tb, uint64_t& tests,
                       TraceMode mode) {
  hits.reserve(rays.size);
  hits.size = rays.size;
  const HitArrays out = hits.arrays();
  if (mode == TraceMode::kQueue) {
    tracer.intersect_queue(rays.arrays(), out, tb.scratch, tests);
    return;
  }
  for (size_t i = 0; i < rays.size; ++i) {
    Hit h;
    if (!tracer.intersect(rays.ray(i), h, tests)) h = Hit{rays.tmax[i], 0.0f, 0.0f, kInvalidId};
    out.store(i, h);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
