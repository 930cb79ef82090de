// Math that is written once for a single float and for a SIMD batch of floats,
// so the float instantiation of a kernel is the test oracle of its batch one.
// For scalars these forward to <cmath>; for batches to xsimd.
#pragma once

#include <cmath>
#include <cstdint>
#include <type_traits>

#include "simd.h"

namespace pt::lane {

template <class T>
inline constexpr bool is_scalar_v = std::is_arithmetic_v<T>;

template <class T> using mask_t = std::conditional_t<is_scalar_v<T>, bool, typename T::batch_bool_type>;

template <class T> inline T select(mask_t<T> m, T a, T b) {
  if constexpr (is_scalar_v<T>) return m ? a : b; else return xsimd::select(m, a, b);
}
template <class T> inline T sqrt(T a) {
  if constexpr (is_scalar_v<T>) return std::sqrt(a); else return xsimd::sqrt(a);
}
template <class T> inline T abs(T a) {
  if constexpr (is_scalar_v<T>) return std::fabs(a); else return xsimd::abs(a);
}
template <class T> inline T min(T a, T b) {
  if constexpr (is_scalar_v<T>) return a < b ? a : b; else return xsimd::min(a, b);
}
template <class T> inline T max(T a, T b) {
  if constexpr (is_scalar_v<T>) return a > b ? a : b; else return xsimd::max(a, b);
}
template <class T> inline void sincos(T x, T& s, T& c) {
  if constexpr (is_scalar_v<T>) { s = std::sin(x); c = std::cos(x); }
  else { auto sc = xsimd::sincos(x); s = sc.first; c = sc.second; }
}
/// +1 or -1 with the sign bit of x (so -0 gives -1).
template <class T> inline T sign_of(T x) {
  if constexpr (is_scalar_v<T>) return std::copysign(1.0f, x);
  else return xsimd::copysign(T(1.0f), x);
}

}  // namespace pt::lane
