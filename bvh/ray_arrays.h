// Queues of rays and their answers as separate arrays (structure of arrays),
// the form in which the wavefront holds them: what the BVH4's queue tracer
// reads and writes, and the per-thread scratch it reuses from queue to queue.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "kernels/math/ray.h"

namespace pt {

/// `size` rays: ray i starts at (org[0][i], org[1][i], org[2][i]), runs along
/// (dir[0][i], dir[1][i], dir[2][i]) over [tmin[i], tmax[i]). `tmin` may be
/// null: 0 for every ray.
struct RayArrays {
  const float* org[3] = {};
  const float* dir[3] = {};
  const float* tmin = nullptr;
  const float* tmax = nullptr;
  size_t size = 0;

  Ray ray(size_t i) const {
    return {{org[0][i], org[1][i], org[2][i]}, tmin ? tmin[i] : 0.0f, {dir[0][i], dir[1][i], dir[2][i]}, tmax[i]};
  }
};

/// Closest hits, one per ray of a RayArrays: as SceneBvh4::intersect leaves a
/// Hit (a miss: t = the ray's tmax, u = v = 0, prim = kInvalidId).
struct HitArrays {
  float* t = nullptr;
  float* u = nullptr;
  float* v = nullptr;
  uint32_t* prim = nullptr;

  void store(size_t i, const Hit& h) const {
    t[i] = h.t;
    u[i] = h.u;
    v[i] = h.v;
    prim[i] = h.prim;
  }
  Hit load(size_t i) const { return {t[i], u[i], v[i], prim[i]}; }
};

/// What the queue tracer keeps between queues on one thread: the lists it
/// splits a queue into and each ray's current tmax. Reused, so that a render
/// allocates it once per thread.
struct QueueScratch {
  std::vector<uint32_t> ids;  ///< the lists of rays, one after the other (bvh4_stream.h)
  std::vector<float> tmax;    ///< any hit: the ray's tmax, -inf once blocked

  size_t bytes() const { return ids.capacity() * sizeof(uint32_t) + tmax.capacity() * sizeof(float); }
};

}  // namespace pt
