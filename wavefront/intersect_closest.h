// Stage 2: closest hits of a ray queue, one ray at a time through the 4-wide
// BVH (single-ray traversal, the per-ray setup hoisted inside the tracer).
#pragma once

#include "streams.h"

namespace pt::wf {

/// hits[i] = closest hit of rays[i] (prim = kInvalidId on a miss).
/// `Tracer` offers bool intersect(const Ray&, Hit&, uint64_t& tests) const.
template <class Tracer>
void intersect_closest(const Tracer& tracer, const RayQueue& rays, HitQueue& hits, uint64_t& tests) {
  hits.reserve(rays.size);
  hits.size = rays.size;
  for (size_t i = 0; i < rays.size; ++i) {
    Hit h;
    if (!tracer.intersect(rays.ray(i), h, tests)) h = Hit{rays.tmax[i], 0.0f, 0.0f, kInvalidId};
    hits.t[i] = h.t;
    hits.u[i] = h.u;
    hits.v[i] = h.v;
    hits.prim[i] = h.prim;
  }
}

}  // namespace pt::wf
