// Math that is written once for a single float and for a SIMD batch of floats,
// so the float instantiation of a kernel is the test oracle of its batch one.
// For scalars these forward to <cmath>; for batches to xsimd.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <type_traits>

#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"

namespace pt::lane {
inline namespace PT_ISA_NS {

template <class T>
inline constexpr bool is_scalar_v = std::is_arithmetic_v<T>;

template <class T, bool = is_scalar_v<T>>
struct mask_of {
  using type = bool;
};
template <class T>
struct mask_of<T, false> {
  using type = typename T::batch_bool_type;
};
/// bool for a scalar lane type, the batch's boolean batch otherwise.
template <class T>
using mask_t = typename mask_of<T>::type;

template <class T>
inline T select(mask_t<T> m, T a, T b) {
  if constexpr (is_scalar_v<T>) return m ? a : b;
  else return xsimd::select(m, a, b);
}
/// Whether any lane of the mask is set (the bool itself for a scalar).
template <class M>
inline bool any(M m) {
  if constexpr (std::is_same_v<M, bool>) return m;
  else return xsimd::any(m);
}
template <class T>
inline T sqrt(T a) {
  if constexpr (is_scalar_v<T>) return std::sqrt(a);
  else return xsimd::sqrt(a);
}
template <class T>
inline T abs(T a) {
  if constexpr (is_scalar_v<T>) return std::fabs(a);
  else return xsimd::abs(a);
}
template <class T>
inline T min(T a, T b) {
  if constexpr (is_scalar_v<T>) return a < b ? a : b;
  else return xsimd::min(a, b);
}
template <class T>
inline T max(T a, T b) {
  if constexpr (is_scalar_v<T>) return a > b ? a : b;
  else return xsimd::max(a, b);
}
template <class T>
inline void sincos(T x, T& s, T& c) {
  if constexpr (is_scalar_v<T>) {
    s = std::sin(x);
    c = std::cos(x);
  } else {
    auto sc = xsimd::sincos(x);
    s = sc.first;
    c = sc.second;
  }
}
/// -a with the sign bit flipped, also for zeros (xsimd's unary minus on a
/// batch computes 0 - a, which turns -0 into +0 unlike scalar negation).
template <class T>
inline T neg(T a) {
  if constexpr (is_scalar_v<T>) return -a;
  else return a ^ T(-0.0f);
}

template <class T>
inline T floor(T a) {
  if constexpr (is_scalar_v<T>) return std::floor(a);
  else return xsimd::floor(a);
}

/// sin and cos of 2 pi u for u in [0, 1], by quadrant reduction and short
/// polynomials (absolute error < 2e-7). The same operations run for a float
/// and for a batch, so scalar and SIMD callers get identical bits.
template <class T>
inline void sincos_2pi(T u, T& s, T& c) {
  T y = u * T(4.0f);
  T q = floor(y + T(0.5f));
  T x = (y - q) * T(1.57079632679489662f);  // in [-pi/4, pi/4]
  T z = x * x;
  T sn = x * (T(1.0f) +
              z * (T(-1.0f / 6.0f) + z * (T(1.0f / 120.0f) + z * (T(-1.0f / 5040.0f) + z * T(1.0f / 362880.0f)))));
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
template <class T>
inline T sign_of(T x) {
  if constexpr (is_scalar_v<T>) return std::copysign(1.0f, x);
  else return xsimd::copysign(T(1.0f), x);
}

/// The float's bits scaled by 2^n for integral n in [-126, 127] (exact).
template <class T>
inline T exp2_int(T n) {
  if constexpr (is_scalar_v<T>) {
    return std::bit_cast<float>(static_cast<int32_t>(n + 127.0f) << 23);
  } else {
    auto bits = xsimd::batch_cast<int32_t>(n + T(127.0f)) << 23;
    return xsimd::bitwise_cast<T>(bits);
  }
}

/// The polynomial c[0] x^(N-1) + ... + c[N-1] by Horner's rule, highest
/// power first: the same operations in the same order for a float and a batch.
template <class T, size_t N>
inline T horner(T x, const float (&c)[N]) {
  T p = T(c[0]);
  for (size_t i = 1; i < N; ++i) p = p * x + T(c[i]);
  return p;
}

/// e^x with relative error < 3e-7, 0 below -87 and clamped above 88, by the
/// same operations for a float and a batch (identical bits at every ISA).
template <class T>
inline T exp(T x) {
  T xc = min(max(x, T(-87.0f)), T(88.0f));
  T n = floor(xc * T(1.44269504088896341f) + T(0.5f));
  T r = (xc - n * T(0.693145751953125f)) - n * T(1.42860682030941723e-6f);  // ln 2 in two parts
  static constexpr float kTaylor[] = {1.0f / 5040.0f, 1.0f / 720.0f, 1.0f / 120.0f, 1.0f / 24.0f,
                                      1.0f / 6.0f,    0.5f,          1.0f,          1.0f};
  return select(x < T(-87.0f), T(0.0f), horner(r, kTaylor) * exp2_int(n));
}

/// Natural logarithm of x > 0 (normal floats) with absolute error < 3e-7:
/// x = m 2^e with m in [sqrt(1/2), sqrt(2)), log m = 2 atanh((m - 1) / (m + 1)).
template <class T>
inline T log(T x) {
  T e, m;
  if constexpr (is_scalar_v<T>) {
    int32_t bits = std::bit_cast<int32_t>(x);
    e = static_cast<float>((bits >> 23) - 127);
    m = std::bit_cast<float>((bits & 0x007fffff) | 0x3f800000);
  } else {
    using I = xsimd::batch<int32_t, typename T::arch_type>;
    I bits = xsimd::bitwise_cast<I>(x);
    e = xsimd::batch_cast<float>((bits >> 23) - I(127));
    m = xsimd::bitwise_cast<T>((bits & I(0x007fffff)) | I(0x3f800000));
  }
  mask_t<T> big = m > T(1.41421356237309505f);
  m = select(big, m * T(0.5f), m);
  e = select(big, e + T(1.0f), e);
  T s = (m - T(1.0f)) / (m + T(1.0f));
  T s2 = s * s;
  static constexpr float kAtanh[] = {2.0f / 11.0f, 2.0f / 9.0f, 2.0f / 7.0f, 2.0f / 5.0f, 2.0f / 3.0f, 2.0f};
  return e * T(0.693147180559945309f) + s * horner(s2, kAtanh);
}

}  // namespace PT_ISA_NS
}  // namespace pt::lane
