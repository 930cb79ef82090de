// The ray-sphere test of sphere_intersect.h over K rays at once: the same
// operations in the same order in every lane (the project compiles without
// floating-point contraction, and SIMD square roots and divisions round as the
// scalar ones do), so each lane answers with the scalar test's bits.
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"
#include "sphere_intersect.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Per lane: whether a root lies in [tmin, tmax) and the nearest such root.
template <class V>
struct SphereLaneHits {
  typename V::batch_bool_type hit;
  V t;
};

/// intersect_sphere for the rays in the lanes of org, dir, tmin and tmax.
template <class V>
PT_ALWAYS_INLINE SphereLaneHits<V> intersect_sphere_lanes(const V (&org)[3], const V (&dir)[3], const V& tmin,
                                                          const V& tmax, const float3& center, float radius) {
  const V fx = org[0] - V(center.x), fy = org[1] - V(center.y), fz = org[2] - V(center.z);
  const V a = dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2];
  const V b = fx * dir[0] + fy * dir[1] + fz * dir[2];
  const V r2(radius * radius);
  const V c = (fx * fx + fy * fy + fz * fz) - r2;
  const V s = b / a;
  const V lx = fx - dir[0] * s, ly = fy - dir[1] * s, lz = fz - dir[2] * s;
  const V disc = a * (r2 - (lx * lx + ly * ly + lz * lz));
  if (!xsimd::any(disc >= V(0.0f))) return {typename V::batch_bool_type(false), disc};  // every lane misses
  const V q = -b - xsimd::copysign(xsimd::sqrt(disc), b);
  const auto ok = (disc >= V(0.0f)) & (q != V(0.0f));
  const V t0 = c / q, t1 = q / a;
  const auto swap = t0 > t1;
  const V lo = xsimd::select(swap, t1, t0), hi = xsimd::select(swap, t0, t1);
  const auto first = ok & (lo >= tmin) & (lo < tmax);
  const auto second = ok & (hi >= tmin) & (hi < tmax);
  return {first | second, xsimd::select(first, lo, hi)};
}

}  // namespace PT_ISA_NS
}  // namespace pt
