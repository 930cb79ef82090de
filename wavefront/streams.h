// The wavefront's streams. Long-lived per-path state (PathState) is kept apart
// from the short-lived queues that stages pass to each other; queue items
// carry the index of their path.
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/ray.h"
#include "kernels/math/ray_arrays.h"
#include "soa.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

/// 20 bytes per path: identity (whose sampler the stages rebuild:
/// sampler_lanes.h) and radiance so far. The throughput travels with the
/// path's ray (RayQueue), which the stages read in queue order.
// clang-format off
#define PT_PATH_FIELDS(X)                                                         \
  X(uint32_t, pixel) X(uint32_t, sample)                                          \
  X(float, radiance_r) X(float, radiance_g) X(float, radiance_b)
// clang-format on
struct PathState {
  PT_SOA_STREAM(PT_PATH_FIELDS)
  void add_radiance(uint32_t path, float r, float g, float b) {
    radiance_r[path] += r;
    radiance_g[path] += g;
    radiance_b[path] += b;
  }
};

/// 52 bytes per ray: closest-hit query of one path, with the path's
/// throughput and the pdf of the BSDF sample that made the ray (for MIS when
/// it finds a light; < 0: a delta lobe; 0 for camera rays).
// clang-format off
#define PT_RAY_FIELDS(X)                                                           \
  X(float, org_x) X(float, org_y) X(float, org_z) X(float, tmin)                   \
  X(float, dir_x) X(float, dir_y) X(float, dir_z) X(float, tmax) X(uint32_t, path) \
  X(float, beta_r) X(float, beta_g) X(float, beta_b) X(float, bsdf_pdf)
// clang-format on
struct RayQueue {
  PT_SOA_STREAM(PT_RAY_FIELDS)
  Ray ray(size_t i) const { return {{org_x[i], org_y[i], org_z[i]}, tmin[i], {dir_x[i], dir_y[i], dir_z[i]}, tmax[i]}; }
  /// The queue as the BVH's queue tracer reads it.
  RayArrays arrays() const {
    return {{org_x.data(), org_y.data(), org_z.data()},
            {dir_x.data(), dir_y.data(), dir_z.data()},
            tmin.data(),
            tmax.data(),
            size};
  }
};

/// 16 bytes per hit, parallel to a RayQueue (prim == kInvalidId: miss).
#define PT_HIT_FIELDS(X) X(float, t) X(float, u) X(float, v) X(uint32_t, prim)
struct HitQueue {
  PT_SOA_STREAM(PT_HIT_FIELDS)
  HitArrays arrays() { return {t.data(), u.data(), v.data(), prim.data()}; }
};

/// 44 bytes per shadow ray: an occlusion query and the radiance it adds to
/// its path when nothing blocks it. Also used for hemisphere-sampling rays,
/// where the weight multiplies whatever emission the ray finds.
// clang-format off
#define PT_SHADOW_FIELDS(X)                                                        \
  X(float, org_x) X(float, org_y) X(float, org_z)                                  \
  X(float, dir_x) X(float, dir_y) X(float, dir_z) X(float, tmax) X(uint32_t, path) \
  X(float, weight_r) X(float, weight_g) X(float, weight_b)
// clang-format on
struct ShadowQueue {
  PT_SOA_STREAM(PT_SHADOW_FIELDS)
  Ray ray(size_t i) const { return {{org_x[i], org_y[i], org_z[i]}, 0.0f, {dir_x[i], dir_y[i], dir_z[i]}, tmax[i]}; }
  /// The queue as the BVH's queue tracer reads it (tmin = 0).
  RayArrays arrays() const {
    return {{org_x.data(), org_y.data(), org_z.data()},
            {dir_x.data(), dir_y.data(), dir_z.data()},
            nullptr,
            tmax.data(),
            size};
  }
};

}  // namespace PT_ISA_NS
}  // namespace pt::wf
