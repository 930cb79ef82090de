// Orthonormal shading frame around a unit normal, built without branches
// (Duff et al. 2017, "Building an Orthonormal Basis, Revisited"). Local +z is
// the normal. Templated over the lane type.
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/lane_math.h"
#include "kernels/math/vec3.h"

namespace pt {
inline namespace PT_ISA_NS {

template <class T>
struct Vec3T {
  T x, y, z;
};

template <class T>
inline Vec3T<T> select3(lane::mask_t<T> m, const Vec3T<T>& a, const Vec3T<T>& b) {
  return {lane::select(m, a.x, b.x), lane::select(m, a.y, b.y), lane::select(m, a.z, b.z)};
}

inline Vec3T<float> vec3t(const float3& a) { return {a.x, a.y, a.z}; }
inline float3 to_float3(const Vec3T<float>& v) { return {v.x, v.y, v.z}; }

/// Tangent vectors (t, b) such that (t, b, n) is right-handed and orthonormal.
template <class T>
inline void tangent_frame(T nx, T ny, T nz, Vec3T<T>& t, Vec3T<T>& b) {
  T s = lane::sign_of(nz);
  T a = T(-1.0f) / (s + nz);
  T c = nx * ny * a;
  t = {T(1.0f) + s * nx * nx * a, s * c, lane::neg(s) * nx};
  b = {c, s + ny * ny * a, lane::neg(ny)};
}

/// Local direction (lx, ly, lz) around normal n expressed in world space.
template <class T>
inline Vec3T<T> to_world(T nx, T ny, T nz, T lx, T ly, T lz) {
  Vec3T<T> t, b;
  tangent_frame(nx, ny, nz, t, b);
  return {t.x * lx + b.x * ly + nx * lz, t.y * lx + b.y * ly + ny * lz, t.z * lx + b.z * ly + nz * lz};
}

inline float3 to_world(float3 n, float3 local) {
  Vec3T<float> w = to_world(n.x, n.y, n.z, local.x, local.y, local.z);
  return {w.x, w.y, w.z};
}

}  // namespace PT_ISA_NS
}  // namespace pt
