// Stage 2: closest hits of a ray queue: coherent queues (camera rays) as SIMD
// packets of K rays, incoherent ones (bounce rays) ray by ray with the 4-wide
// node test, through the tracer's inline queries (bvh/tracers.h).
#pragma once

#include <algorithm>

#include "streams.h"

namespace pt::wf {

inline void store_hit(HitQueue& hits, size_t i, const Hit& h) {
  hits.t[i] = h.t;
  hits.u[i] = h.u;
  hits.v[i] = h.v;
  hits.prim[i] = h.prim;
}

/// hits[i] = closest hit of rays[i] (prim = kInvalidId on a miss). With
/// `coherent` (camera rays: consecutive rays are samples of one pixel) runs of
/// K rays go through the tracer's SIMD packet traversal.
template <class Tracer>
void intersect_closest(const Tracer& tracer, const RayQueue& rays, HitQueue& hits, uint64_t& tests, bool coherent) {
  hits.reserve(rays.size);
  hits.size = rays.size;
  if (coherent) {
    Ray packet[kLanes];
    Hit found[kLanes];
    for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
      size_t n = std::min(kLanes, rays.size - i0);
      for (size_t l = 0; l < n; ++l) packet[l] = rays.ray(i0 + l);
      tracer.intersect_packet(packet, found, lanes_below(n), tests);
      for (size_t l = 0; l < n; ++l) store_hit(hits, i0 + l, found[l]);
    }
    return;
  }
  for (size_t i = 0; i < rays.size; ++i) {
    Hit h;
    if (!tracer.intersect(rays.ray(i), h, tests)) h = Hit{rays.tmax[i], 0.0f, 0.0f, kInvalidId};
    store_hit(hits, i, h);
  }
}

}  // namespace pt::wf
