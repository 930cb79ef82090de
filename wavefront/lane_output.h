// Appends the active lanes of K-wide results to a queue (stream compaction):
// one in-register compress and one store per field (store_compressed,
// kernels/simd.h). Queue order follows lane order.
#pragma once

#include <cstdint>

#include "kernels/frame.h"
#include "kernels/simd.h"
#include "streams.h"

namespace pt::wf {

struct LaneFloats {
  alignas(64) float v[kLanes];
  explicit LaneFloats(vfloatK x) { x.store_aligned(v); }
  float operator[](size_t i) const { return v[i]; }
};

struct LaneUints {
  alignas(64) uint32_t v[kLanes];
  explicit LaneUints(vuintK x) { x.store_aligned(v); }
  uint32_t operator[](size_t i) const { return v[i]; }
};

/// Calls f(lane) for each set bit of mask, lowest first.
template <class F> inline void for_each_lane(uint32_t mask, F&& f) {
  for (; mask; mask &= mask - 1) f(static_cast<size_t>(__builtin_ctz(mask)));
}

/// Makes room for K more items, the most one compressed append can write.
template <class Queue> inline void reserve_lanes(Queue& q) {
  if (q.size + kLanes > q.capacity) q.reserve(2 * q.capacity + kLanes);
}

inline void push_shadow_lanes(uint32_t mask, ShadowQueue& q, const Vec3T<vfloatK>& org, const Vec3T<vfloatK>& dir,
                              vfloatK tmax, vuintK path, const Vec3T<vfloatK>& weight) {
  if (!mask) return;
  reserve_lanes(q);
  size_t at = q.size;
  store_compressed(&q.org_x[at], mask, org.x);
  store_compressed(&q.org_y[at], mask, org.y);
  store_compressed(&q.org_z[at], mask, org.z);
  store_compressed(&q.dir_x[at], mask, dir.x);
  store_compressed(&q.dir_y[at], mask, dir.y);
  store_compressed(&q.dir_z[at], mask, dir.z);
  store_compressed(&q.tmax[at], mask, tmax);
  store_compressed(&q.path[at], mask, path);
  store_compressed(&q.weight_r[at], mask, weight.x);
  store_compressed(&q.weight_g[at], mask, weight.y);
  store_compressed(&q.weight_b[at], mask, weight.z);
  q.size += static_cast<size_t>(__builtin_popcount(mask));
}

inline void push_ray_lanes(uint32_t mask, RayQueue& q, const Vec3T<vfloatK>& org, const Vec3T<vfloatK>& dir,
                           vuintK path) {
  if (!mask) return;
  reserve_lanes(q);
  size_t at = q.size;
  store_compressed(&q.org_x[at], mask, org.x);
  store_compressed(&q.org_y[at], mask, org.y);
  store_compressed(&q.org_z[at], mask, org.z);
  store_compressed(&q.dir_x[at], mask, dir.x);
  store_compressed(&q.dir_y[at], mask, dir.y);
  store_compressed(&q.dir_z[at], mask, dir.z);
  vfloatK(0.0f).store_unaligned(&q.tmin[at]);
  vfloatK(kInfinity).store_unaligned(&q.tmax[at]);
  store_compressed(&q.path[at], mask, path);
  q.size += static_cast<size_t>(__builtin_popcount(mask));
}

}  // namespace pt::wf
