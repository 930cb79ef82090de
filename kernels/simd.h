// The one place that names SIMD types. N = BVH branching factor (4), K = lanes of
// the uniform (across-rays) stages: the widest float batch xsimd picks for the
// build target. Everything else says vfloat4 / vfloatK and never touches
// intrinsics directly.
#pragma once

#include <cstddef>
#include <cstdint>

#include <immintrin.h>
#include <xsimd/xsimd.hpp>

namespace pt {

using vfloat4 = xsimd::batch<float, xsimd::sse4_2>;
using vint4 = xsimd::batch<int32_t, xsimd::sse4_2>;
using vuint4 = xsimd::batch<uint32_t, xsimd::sse4_2>;
using vbool4 = xsimd::batch_bool<float, xsimd::sse4_2>;

using vfloatK = xsimd::batch<float>;
using vintK = xsimd::batch<int32_t>;
using vuintK = xsimd::batch<uint32_t>;
using vboolK = xsimd::batch_bool<float>;

inline constexpr std::size_t kBvhWidth = 4;
inline constexpr std::size_t kLanes = vfloatK::size;

/// Bit mask of the true lanes of a 4-wide comparison (lane i -> bit i).
/// xsimd 8.1 has no portable mask extraction; this is the one raw intrinsic.
inline uint32_t movemask(vbool4 m) { return static_cast<uint32_t>(_mm_movemask_ps(m)); }

/// Bit mask of the true lanes of a K-wide comparison (lane i -> bit i).
inline uint64_t bitmask(vboolK m) {
#if defined(__AVX512F__)
  return static_cast<uint64_t>(static_cast<__mmask16>(m));
#elif defined(__AVX__)
  return static_cast<uint64_t>(_mm256_movemask_ps(m));
#else
  return static_cast<uint64_t>(_mm_movemask_ps(m));
#endif
}

using vbooluK = xsimd::batch_bool<uint32_t>;
using vbooliK = xsimd::batch_bool<int32_t>;

/// A K-wide integer comparison's result as a float mask.
template <class M> inline vboolK as_float_mask(M m) {
#if defined(__AVX512F__)
  return vboolK(static_cast<__mmask16>(m));
#else
  using I = typename M::value_type;
  return xsimd::bitwise_cast<vfloatK>(xsimd::select(m, xsimd::batch<I>(I(~0u)), xsimd::batch<I>(I(0)))) != vfloatK(0.0f);
#endif
}

/// A K-wide float mask as an int32 mask.
inline vbooliK as_int_mask(vboolK m) {
#if defined(__AVX512F__)
  return vbooliK(static_cast<__mmask16>(m));
#else
  return xsimd::bitwise_cast<vintK>(xsimd::select(m, vfloatK(-1.0f), vfloatK(0.0f))) != vintK(0);
#endif
}

/// Lane indices 0, 1, ..., K-1.
inline vintK lane_index() {
  alignas(64) int32_t idx[kLanes];
  for (size_t i = 0; i < kLanes; ++i) idx[i] = static_cast<int32_t>(i);
  return vintK::load_aligned(idx);
}

}  // namespace pt
