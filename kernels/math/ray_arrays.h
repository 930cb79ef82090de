// Queues of rays and their closest hits as separate arrays (structure of
// arrays), the form in which the wavefront holds them and the BVH4's queue
// tracer reads and writes them.
#pragma once

#include <cstddef>
#include <cstdint>

#include "ray.h"

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

  [[gnu::always_inline]] Ray ray(size_t i) const {
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

}  // namespace pt
