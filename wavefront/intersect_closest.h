// Stage 2: closest hits of a ray queue: the whole queue through the tracer's
// queue tracer, or (for comparison) as SIMD packets of K rays or ray by ray,
// through the tracer's inline queries (bvh/tracers.h).
#pragma once

#include <algorithm>

#include "kernels/simd/isa_namespace.h"
#include "streams.h"
#include "trace_mode.h"
#include "wave_buffers.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// hits[i] = closest hit of rays[i] (prim = kInvalidId on a miss).
template <class Tracer>
void intersect_closest(const Tracer& tracer, const RayQueue& rays, HitQueue& hits, TracingBuffers& tb, uint64_t& tests,
                       QueueMethod method) {
  hits.reserve(rays.size);
  hits.size = rays.size;
  const HitArrays out = hits.arrays();
  switch (method) {
    case QueueMethod::kQueue: tracer.intersect_queue(rays.arrays(), out, tb.scratch, tests); return;
    case QueueMethod::kPackets: {
      Ray packet[kLanes];
      Hit found[kLanes];
      for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
        size_t n = std::min(kLanes, rays.size - i0);
        for (size_t l = 0; l < n; ++l) packet[l] = rays.ray(i0 + l);
        tracer.intersect_packet(packet, found, lanes_below(n), tests);
        for (size_t l = 0; l < n; ++l) out.store(i0 + l, found[l]);
      }
      return;
    }
    case QueueMethod::kSingle: break;
  }
  for (size_t i = 0; i < rays.size; ++i) {
    Hit h;
    if (!tracer.intersect(rays.ray(i), h, tests)) h = Hit{rays.tmax[i], 0.0f, 0.0f, kInvalidId};
    out.store(i, h);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
