// The one place that names SIMD types. N = BVH branching factor (4), K = lanes of
// the uniform (across-rays) stages: the widest float batch xsimd picks for the
// build target. Everything else says vfloat4 / vfloatK and never touches
// intrinsics directly; the few operations xsimd 8.1 lacks (mask extraction,
// horizontal minimum, a contraction barrier, prefetch, denormal mode) are
// wrapped here.
#pragma once

#include <cstddef>
#include <cstdint>

// GCC 12's AVX-512 intrinsic headers start some vectors from an undefined
// register (`__Y`), which its own uninitialized-use analysis then reports at
// every use: those reports say nothing about this code.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <immintrin.h>
#include <xsimd/xsimd.hpp>
#pragma GCC diagnostic pop

/// For the per-node and per-block tests of the traversal loops, which the
/// compiler otherwise calls out of line from large callers (the renderers).
#define PT_ALWAYS_INLINE inline __attribute__((always_inline))

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
/// xsimd 8.1 has no portable mask extraction.
inline uint32_t movemask(vbool4 m) { return static_cast<uint32_t>(_mm_movemask_ps(m)); }

using vbooluK = xsimd::batch_bool<uint32_t>;
using vbooliK = xsimd::batch_bool<int32_t>;

/// A K-wide integer comparison's result as a float mask.
template <class M> inline vboolK as_float_mask(M m) {
#if XSIMD_WITH_AVX512F
  return vboolK(static_cast<__mmask16>(m));
#else
  using I = typename M::value_type;
  return xsimd::bitwise_cast<vfloatK>(xsimd::select(m, xsimd::batch<I>(I(~0u)), xsimd::batch<I>(I(0)))) != vfloatK(0.0f);
#endif
}

/// A K-wide float mask as an int32 mask.
inline vbooliK as_int_mask(vboolK m) {
#if XSIMD_WITH_AVX512F
  return vbooliK(static_cast<__mmask16>(m));
#else
  return xsimd::bitwise_cast<vintK>(xsimd::select(m, vfloatK(-1.0f), vfloatK(0.0f))) != vintK(0);
#endif
}

/// base[index[i]] per lane, with the hardware gather where there is one
/// (xsimd 8.1 gathers floats element by element). For random indices (the
/// wavefront's surface and path lookups) it is as fast as element-wise loads
/// here; for gathering the fields of contiguous structures (a ray packet) a
/// transposition through the stack is several times faster on AMD's cores.
inline vfloatK gather(const float* base, vintK index) {
#if XSIMD_WITH_AVX512F
  return _mm512_i32gather_ps(index, base, 4);
#elif XSIMD_WITH_AVX2
  return _mm256_i32gather_ps(base, index, 4);
#else
  return vfloatK::gather(base, index);
#endif
}
inline vintK gather(const int32_t* base, vintK index) {
#if XSIMD_WITH_AVX512F
  return _mm512_i32gather_epi32(index, base, 4);
#elif XSIMD_WITH_AVX2
  return _mm256_i32gather_epi32(base, index, 4);
#else
  return vintK::gather(base, index);
#endif
}
inline vuintK gather(const uint32_t* base, vintK index) {
  return xsimd::bitwise_cast<vuintK>(gather(reinterpret_cast<const int32_t*>(base), index));
}

/// Stores the lanes of v selected by `mask` contiguously at dst, lowest lane
/// first (stream compaction). Writes K values: the caller has room for K at
/// dst; only popcount(mask) of them are meaningful. Compresses in a register
/// (the memory form of vcompressps is microcoded on AMD Zen 4 and 5).
inline void store_compressed(float* dst, uint32_t mask, vfloatK v) {
#if XSIMD_WITH_AVX512F
  _mm512_storeu_ps(dst, _mm512_maskz_compress_ps(static_cast<__mmask16>(mask), v));
#else
  alignas(64) float lanes[kLanes];
  v.store_aligned(lanes);
  for (; mask; mask &= mask - 1) *dst++ = lanes[__builtin_ctz(mask)];
#endif
}
inline void store_compressed(uint32_t* dst, uint32_t mask, vuintK v) {
#if XSIMD_WITH_AVX512F
  _mm512_storeu_si512(dst, _mm512_maskz_compress_epi32(static_cast<__mmask16>(mask), v));
#else
  alignas(64) uint32_t lanes[kLanes];
  v.store_aligned(lanes);
  for (; mask; mask &= mask - 1) *dst++ = lanes[__builtin_ctz(mask)];
#endif
}

/// Lane indices 0, 1, ..., K-1.
inline vintK lane_index() {
  alignas(64) int32_t idx[kLanes];
  for (size_t i = 0; i < kLanes; ++i) idx[i] = static_cast<int32_t>(i);
  return vintK::load_aligned(idx);
}

/// Bit mask of the true lanes of a K-wide comparison (lane i -> bit i).
inline uint32_t lane_mask(vboolK m) {
#if XSIMD_WITH_AVX512F
  return static_cast<uint32_t>(static_cast<__mmask16>(m));
#elif XSIMD_WITH_AVX
  return static_cast<uint32_t>(_mm256_movemask_ps(m));
#else
  return static_cast<uint32_t>(_mm_movemask_ps(m));
#endif
}

/// The K-wide mask whose lane i is bit i of `bits`.
inline vboolK lanes_of_mask(uint32_t bits) {
#if XSIMD_WITH_AVX512F
  return vboolK(static_cast<__mmask16>(bits));
#else
  alignas(64) int32_t one_bit[kLanes];
  for (std::size_t i = 0; i < kLanes; ++i) one_bit[i] = int32_t(1u << i);
  vintK selected = vintK(static_cast<int32_t>(bits)) & vintK::load_aligned(one_bit);
  return xsimd::bool_cast(selected != vintK(0));
#endif
}

#if XSIMD_WITH_AVX512F
/// The upper and lower 256-bit halves of a 16-lane batch.
inline __m256 upper_half(__m512 v) { return _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(v), 1)); }
#endif

/// Smallest of the K lanes; the lanes must not be NaN.
inline float reduce_min_k(vfloatK v) {
#if XSIMD_WITH_AVX512F
  __m256 a = _mm256_min_ps(_mm512_castps512_ps256(v), upper_half(v));
  __m128 b = _mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
  b = _mm_min_ps(b, _mm_movehl_ps(b, b));
  return _mm_cvtss_f32(_mm_min_ss(b, _mm_movehdup_ps(b)));
#else
  alignas(64) float lanes[kLanes];
  v.store_aligned(lanes);
  float m = lanes[0];
  for (std::size_t i = 1; i < kLanes; ++i) m = lanes[i] < m ? lanes[i] : m;
  return m;
#endif
}

/// Largest of the K lanes; the lanes must not be NaN.
inline float reduce_max_k(vfloatK v) {
#if XSIMD_WITH_AVX512F
  __m256 a = _mm256_max_ps(_mm512_castps512_ps256(v), upper_half(v));
  __m128 b = _mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1));
  b = _mm_max_ps(b, _mm_movehl_ps(b, b));
  return _mm_cvtss_f32(_mm_max_ss(b, _mm_movehdup_ps(b)));
#else
  alignas(64) float lanes[kLanes];
  v.store_aligned(lanes);
  float m = lanes[0];
  for (std::size_t i = 1; i < kLanes; ++i) m = lanes[i] > m ? lanes[i] : m;
  return m;
#endif
}

/// Smallest of the four lanes; the lanes must not be NaN.
inline float reduce_min(vfloat4 v) {
  __m128 a = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
  a = _mm_min_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(a);
}

/// Returns v unchanged, rounded to float: the compiler cannot contract a
/// product passed through here into an FMA with what follows. Watertight edge
/// functions a*b - c*d need both products rounded so that the two triangles
/// sharing an edge compute exactly opposite values.
inline vfloat4 keep_rounded(vfloat4 v) {
  __m128 x = v;
  asm("" : "+x"(x));
  return x;
}

/// Hints the cache to load the 64-byte line holding p.
inline void prefetch_l1(const void* p) { _mm_prefetch(static_cast<const char*>(p), _MM_HINT_T0); }

/// Flushes denormal results and inputs to zero on the calling thread (what
/// Embree asks of its callers). Results change only where a value would be
/// denormal, below 1.2e-38 in magnitude.
inline void enable_flush_denormals_to_zero() { _mm_setcsr(_mm_getcsr() | 0x8040u); }

}  // namespace pt
