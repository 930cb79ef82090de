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

template <class T, bool = is_scalar_v<T>> struct mask_of { using type = bool; };
template <class T> struct mask_of<T, false> { using type = typename T::batch_bool_type; };
/// bool for a scalar lane type, the batch's boolean batch otherwise.
template <class T> using mask_t = typename mask_of<T>::type;

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
/// -a with the sign bit flipped, also for zeros (xsimd's unary minus on a
/// batch computes 0 - a, which turns -0 into +0 unlike scalar negation).
template <class T> inline T neg(T a) {
  if constexpr (is_scalar_v<T>) return -a; else return a ^ T(-0.0f);
}

template <class T> inline T floor(T a) {
  if constexpr (is_scalar_v<T>) return std::floor(a); else return xsimd::floor(a);
}

/// sin and cos of 2 pi u for u in [0, 1], by quadrant reduction and short
/// polynomials (absolute error < 2e-7). The same operations run for a float
/// and for a batch, so scalar and SIMD callers get identical bits.
template <class T> inline void sincos_2pi(T u, T& s, T& c) {
  T y = u * T(4.0f);
  T q = floor(y + T(0.5f));
  T x = (y - q) * T(1.57079632679489662f);  // in [-pi/4, pi/4]
  T z = x * x;
  T sn = x * (T(1.0f) + z * (T(-1.0f / 6.0f) + z * (T(1.0f / 120.0f) + z * (T(-1.0f / 5040.0f) +
                                                                          z * T(1.0f / 362880.0f)))));
  T cs = T(1.0f) + z * (T(-0.5f) + z * (T(1.0f / 24.0f) + z * (T(-1.0f / 720.0f) + z * T(1.0f / 40320.0f))));
  T q_mod4 = q - T(4.0f) * floor(q * T(0.25f));  // 0, 1, 2 or 3
  mask_t<T> odd = (q_mod4 == T(1.0f)) || (q_mod4 == T(3.0f));
  mask_t<T> neg_s = q_mod4 >= T(2.0f);
  mask_t<T> neg_c = (q_mod4 == T(1.0f)) || (q_mod4 == T(2.0f));
  T s0 = select(odd, cs, sn), c0 = select(odd, sn, cs);
  s = select(neg_s, neg(s0), s0);
  c = select(neg_c, neg(c0), c0);
}

/// +1 or -1 with the sign bit of x (so -0 gives -1).
template <class T> inline T sign_of(T x) {
  if constexpr (is_scalar_v<T>) return std::copysign(1.0f, x);
  else return xsimd::copysign(T(1.0f), x);
}

}  // namespace pt::lane
