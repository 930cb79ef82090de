// Appends the active lanes of K-wide results to a queue (stream compaction):
// the values are stored to small aligned arrays, then copied lane by lane for
// the set bits of the mask. Queue order follows lane order.
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
template <class F> inline void for_each_lane(uint64_t mask, F&& f) {
  for (; mask; mask &= mask - 1) f(static_cast<size_t>(__builtin_ctzll(mask)));
}

inline void push_shadow_lanes(uint64_t mask, ShadowQueue& q, const Vec3T<vfloatK>& org, const Vec3T<vfloatK>& dir,
                              vfloatK tmax, vuintK path, const Vec3T<vfloatK>& weight) {
  if (!mask) return;
  LaneFloats ox(org.x), oy(org.y), oz(org.z), dx(dir.x), dy(dir.y), dz(dir.z), tm(tmax), wr(weight.x),
      wg(weight.y), wb(weight.z);
  LaneUints p(path);
  for_each_lane(mask, [&](size_t l) {
    q.push({ox[l], oy[l], oz[l], dx[l], dy[l], dz[l], tm[l], p[l], wr[l], wg[l], wb[l]});
  });
}

inline void push_ray_lanes(uint64_t mask, RayQueue& q, const Vec3T<vfloatK>& org, const Vec3T<vfloatK>& dir,
                           vuintK path) {
  if (!mask) return;
  LaneFloats ox(org.x), oy(org.y), oz(org.z), dx(dir.x), dy(dir.y), dz(dir.z);
  LaneUints p(path);
  for_each_lane(mask, [&](size_t l) {
    q.push({ox[l], oy[l], oz[l], 0.0f, dx[l], dy[l], dz[l], kInfinity, p[l]});
  });
}

}  // namespace pt::wf
