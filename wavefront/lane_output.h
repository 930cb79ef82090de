// What the stages write lane by lane: K-wide results appended to a queue
// (stream compaction through the streams' lane structs, soa_lanes.h), and
// scalar access to the lanes of a register. Queue order follows lane order.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/simd/simd.h"
#include "soa_lanes.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

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
template <class F>
inline void for_each_lane(uint32_t mask, F&& f) {
  for (; mask; mask &= mask - 1) f(static_cast<size_t>(__builtin_ctz(mask)));
}

/// Appends the shadow rays of the lanes in `mask`.
inline void push_shadow_lanes(uint32_t mask, ShadowQueue& q, const Vec3T<vfloatK>& org, const Vec3T<vfloatK>& dir,
                              vfloatK tmax, vuintK path, const Vec3T<vfloatK>& weight) {
  append_lanes(q, mask,
               ShadowLanes{.org_x = org.x,
                           .org_y = org.y,
                           .org_z = org.z,
                           .dir_x = dir.x,
                           .dir_y = dir.y,
                           .dir_z = dir.z,
                           .tmax = tmax,
                           .path = path,
                           .weight_r = weight.x,
                           .weight_g = weight.y,
                           .weight_b = weight.z});
}

/// The paths of the lanes in `mask` go on: each one's ray from `org` along
/// `dir` (t in [0, inf)) joins `q`, carrying the path's throughput, now
/// `beta`, and the pdf of its BSDF sample `pdf` (negative for a delta lobe:
/// no MIS).
inline void continue_paths(uint32_t mask, vuintK path, const Vec3T<vfloatK>& beta, vfloatK pdf, RayQueue& q,
                           const Vec3T<vfloatK>& org, const Vec3T<vfloatK>& dir) {
  append_lanes(q, mask,
               RayLanes{.org_x = org.x,
                        .org_y = org.y,
                        .org_z = org.z,
                        .tmin = vfloatK(0.0f),
                        .dir_x = dir.x,
                        .dir_y = dir.y,
                        .dir_z = dir.z,
                        .tmax = vfloatK(kInfinity),
                        .path = path,
                        .beta_r = beta.x,
                        .beta_g = beta.y,
                        .beta_b = beta.z,
                        .bsdf_pdf = pdf});
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
