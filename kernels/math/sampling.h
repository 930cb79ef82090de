// Warps from the unit square to directions and points, with their densities.
// Each takes (u1, u2) in [0, 1)^2 and stays finite for u -> 1. Templated over
// the lane type; local +z is the surface normal.
#pragma once

#include <numbers>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/simd/lane_math.h"

namespace pt {
inline namespace PT_ISA_NS {

inline constexpr float kPi = std::numbers::pi_v<float>;
inline constexpr float kInvPi = 1.0f / kPi;
inline constexpr float kInv2Pi = 0.5f / kPi;

/// Uniform over the hemisphere z >= 0; pdf = 1 / (2 pi) per steradian.
template <class T>
inline Vec3T<T> sample_uniform_hemisphere(T u1, T u2) {
  T z = u1;
  T r = lane::sqrt(lane::max(T(0.0f), T(1.0f) - z * z));
  T s, c;
  lane::sincos_2pi(u2, s, c);
  return {r * c, r * s, z};
}

/// Cosine-weighted over the hemisphere z >= 0 (Malley); pdf = z / pi.
template <class T>
inline Vec3T<T> sample_cosine_hemisphere(T u1, T u2) {
  T r = lane::sqrt(u1);
  T s, c;
  lane::sincos_2pi(u2, s, c);
  return {r * c, r * s, lane::sqrt(lane::max(T(0.0f), T(1.0f) - u1))};
}

/// Uniform on the sphere; pdf = 1 / (4 pi).
template <class T>
inline Vec3T<T> sample_uniform_sphere(T u1, T u2) {
  T z = T(1.0f) - T(2.0f) * u1;
  T r = lane::sqrt(lane::max(T(0.0f), T(1.0f) - z * z));
  T s, c;
  lane::sincos_2pi(u2, s, c);
  return {r * c, r * s, z};
}

}  // namespace PT_ISA_NS
}  // namespace pt
