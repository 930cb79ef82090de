// Single-ray triangle tests: Moller-Trumbore (the assignment's test, used by the
// reference renderer) and the watertight test of Woop, Benthin and Wald (2013).
// Both reject NaN results: every comparison is written so NaN fails it.
#pragma once

#include <cmath>
#include <utility>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/ray.h"
#include "kernels/math/vec3.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Moller-Trumbore. On a hit with tmin <= t < tmax writes t, u (weight of p1)
/// and v (weight of p2) and returns true. Double-sided; a degenerate triangle
/// (det == 0) never hits.
inline bool intersect_triangle_mt(const float3& org, const float3& dir, float tmin, float tmax, const float3& p0,
                                  const float3& p1, const float3& p2, float& t_out, float& u_out, float& v_out) {
  float3 e1 = p1 - p0, e2 = p2 - p0;
  float3 pvec = cross(dir, e2);
  float det = dot(e1, pvec);
  if (det == 0.0f) return false;
  float inv_det = 1.0f / det;
  float3 tvec = org - p0;
  float u = dot(tvec, pvec) * inv_det;
  if (!(u >= 0.0f && u <= 1.0f)) return false;
  float3 qvec = cross(tvec, e1);
  float v = dot(dir, qvec) * inv_det;
  if (!(v >= 0.0f && u + v <= 1.0f)) return false;
  float t = dot(e2, qvec) * inv_det;
  if (!(t >= tmin && t < tmax)) return false;
  t_out = t;
  u_out = u;
  v_out = v;
  return true;
}

/// Per-ray setup of the watertight test: the dominant axis of the direction
/// becomes z and the shear maps the direction onto +z.
struct WatertightRay {
  int kx, ky, kz;
  float sx, sy, sz;

  explicit WatertightRay(const float3& dir) {
    float3 a = abs(dir);
    kz = max_axis(a);
    kx = (kz + 1) % 3;
    ky = (kx + 1) % 3;
    if (dir[kz] < 0.0f) std::swap(kx, ky);  // keep winding
    sx = dir[kx] / dir[kz];
    sy = dir[ky] / dir[kz];
    sz = 1.0f / dir[kz];
  }
};

/// Woop et al. watertight test: no ray passes between two triangles that share
/// an edge. Same contract as intersect_triangle_mt.
inline bool intersect_triangle_watertight(const float3& org, const WatertightRay& w, float tmin, float tmax,
                                          const float3& p0, const float3& p1, const float3& p2, float& t_out,
                                          float& u_out, float& v_out) {
  float3 a = p0 - org, b = p1 - org, c = p2 - org;
  float ax = a[w.kx] - w.sx * a[w.kz], ay = a[w.ky] - w.sy * a[w.kz];
  float bx = b[w.kx] - w.sx * b[w.kz], by = b[w.ky] - w.sy * b[w.kz];
  float cx = c[w.kx] - w.sx * c[w.kz], cy = c[w.ky] - w.sy * c[w.kz];
  // Edge functions from double products: exact for float inputs, so the shared
  // edge of two triangles gets exactly opposite values whatever the compiler
  // does with multiply-adds.
  float U = static_cast<float>(double(cx) * by - double(cy) * bx);
  float V = static_cast<float>(double(ax) * cy - double(ay) * cx);
  float W = static_cast<float>(double(bx) * ay - double(by) * ax);
  if ((U < 0.0f || V < 0.0f || W < 0.0f) && (U > 0.0f || V > 0.0f || W > 0.0f)) return false;
  float det = U + V + W;
  if (!(det != 0.0f)) return false;
  float az = w.sz * a[w.kz], bz = w.sz * b[w.kz], cz = w.sz * c[w.kz];
  float T = U * az + V * bz + W * cz;
  float inv_det = 1.0f / det;
  float t = T * inv_det;
  if (!(t >= tmin && t < tmax)) return false;
  t_out = t;
  u_out = V * inv_det;
  v_out = W * inv_det;
  return true;
}

}  // namespace PT_ISA_NS
}  // namespace pt
