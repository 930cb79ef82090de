// Analytic ray-sphere test in the numerically careful form of Haines et al.
// (Ray Tracing Gems, ch. 7): the discriminant is computed from the distance of
// closest approach, so large spheres and distant origins keep their precision.
#pragma once

#include <cmath>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/vec3.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Nearest root t with tmin <= t < tmax of |org + t dir - center| = radius.
inline bool intersect_sphere(const float3& org, const float3& dir, float tmin, float tmax, const float3& center,
                             float radius, float& t_out) {
  float3 f = org - center;
  float a = dot(dir, dir);
  float b = dot(f, dir);  // half of the usual b
  float c = dot(f, f) - radius * radius;
  float3 l = f - dir * (b / a);  // closest approach
  float disc = a * (radius * radius - dot(l, l));
  if (!(disc >= 0.0f)) return false;
  float q = -b - std::copysign(std::sqrt(disc), b);
  if (q == 0.0f) return false;
  float t0 = c / q, t1 = q / a;
  if (t0 > t1) std::swap(t0, t1);
  if (t0 >= tmin && t0 < tmax) {
    t_out = t0;
    return true;
  }
  if (t1 >= tmin && t1 < tmax) {
    t_out = t1;
    return true;
  }
  return false;
}

}  // namespace PT_ISA_NS
}  // namespace pt
