// The one place that names SIMD types and touches intrinsics. N = BVH
// branching factor (4): vfloat4 is SSE on x86 and NEON on aarch64, in every
// translation unit. K = lanes of the uniform (across-rays) stages: the widest
// float batch of the instruction-set level the translation unit is compiled
// for (SSE4.2 and NEON 4, AVX2 8, AVX-512 16). K-wide types exist only in code
// compiled once per level (PT_PER_LEVEL; kernels/simd/isa_namespace.h), so code built
// once for every CPU cannot pick up a width by accident. The operations xsimd
// 8.1 lacks (mask extraction, compaction, horizontal min/max, a contraction
// barrier, prefetch, denormal mode) are written here once per architecture.
#pragma once

#include <array>
#include <bit>
#include <cstddef>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"

// GCC 12's AVX-512 intrinsic headers start some vectors from an undefined
// register (`__Y`), which its own uninitialized-use analysis then reports at
// every use: those reports say nothing about this code.
#pragma GCC diagnostic push
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#pragma GCC diagnostic ignored "-Wuninitialized"
#if defined(__x86_64__)
#include <immintrin.h>
#elif defined(__aarch64__)
#include <arm_neon.h>
#else
#error "the SIMD kernels are written for x86-64 and aarch64"
#endif
#include <xsimd/xsimd.hpp>

#if XSIMD_WITH_NEON64
// Debian 12's xsimd divides and takes square roots of float batches on
// aarch64 by reciprocal estimates and Newton steps, which are not correctly
// rounded (one ulp off the float result); AArch64 has IEEE instructions for
// both. These specialisations of xsimd's neon kernels for neon64 use them,
// so a NEON lane computes the bits a float does, as every x86 level does.
namespace xsimd::kernel {
template <>
inline batch<float, neon64> div<neon64>(batch<float, neon64> const& lhs, batch<float, neon64> const& rhs,
                                        requires_arch<neon>) noexcept {
  return vdivq_f32(lhs, rhs);
}
template <>
inline batch<float, neon64> sqrt<neon64>(batch<float, neon64> const& arg, requires_arch<neon>) noexcept {
  return vsqrtq_f32(arg);
}
}  // namespace xsimd::kernel
#endif
#pragma GCC diagnostic pop

/// For the per-node and per-block tests of the traversal loops, which the
/// compiler otherwise calls out of line from large callers (the renderers).
#define PT_ALWAYS_INLINE inline __attribute__((always_inline))

namespace pt {
inline namespace PT_ISA_NS {

#if defined(__x86_64__)
using Arch4 = xsimd::sse4_2;
#else
using Arch4 = xsimd::neon64;
#endif
using vfloat4 = xsimd::batch<float, Arch4>;
using vint4 = xsimd::batch<int32_t, Arch4>;
using vuint4 = xsimd::batch<uint32_t, Arch4>;
using vbool4 = xsimd::batch_bool<float, Arch4>;

/// The widest K of any level: streams are padded to it, so their layout is
/// the same at every level.
inline constexpr std::size_t kMaxLanes = 16;

/// The mask of the lowest n of 32 lanes (n <= 32).
constexpr uint32_t lanes_below(std::size_t n) { return n >= 32 ? ~0u : (1u << n) - 1u; }

namespace simd_detail {
/// pshufb / tbl controls that move the 32-bit lanes set in a 4-bit mask to
/// the front, in order (the other bytes repeat lane 0).
inline constexpr std::array<std::array<uint8_t, 16>, 16> kCompress4 = [] {
  std::array<std::array<uint8_t, 16>, 16> table{};
  for (uint32_t mask = 0; mask < 16; ++mask) {
    uint32_t out = 0;
    for (uint32_t lane = 0; lane < 4; ++lane)
      if (mask >> lane & 1) {
        for (uint32_t b = 0; b < 4; ++b) table[mask][4 * out + b] = static_cast<uint8_t>(4 * lane + b);
        ++out;
      }
    for (; out < 4; ++out)
      for (uint32_t b = 0; b < 4; ++b) table[mask][4 * out + b] = static_cast<uint8_t>(b);
  }
  return table;
}();
}  // namespace simd_detail

/// Bit mask of the true lanes of a 4-wide comparison (lane i -> bit i).
inline uint32_t movemask(vbool4 m) {
#if defined(__x86_64__)
  return static_cast<uint32_t>(_mm_movemask_ps(m));
#else
  const uint32x4_t bit = {1, 2, 4, 8};
  return vaddvq_u32(vandq_u32(m, bit));
#endif
}

/// `bit` in the true lanes of a 4-wide comparison, 0 in the others.
inline vuint4 bit_where(vbool4 m, uint32_t bit) {
#if defined(__x86_64__)
  return vuint4(_mm_and_si128(_mm_castps_si128(m), _mm_set1_epi32(static_cast<int>(bit))));
#else
  return vuint4(vandq_u32(m, vdupq_n_u32(bit)));
#endif
}

/// The four lanes of v, read from the register (not through memory).
inline void lanes_of(vuint4 v, uint32_t out[4]) {
#if defined(__x86_64__)
  out[0] = static_cast<uint32_t>(_mm_cvtsi128_si32(v));
  out[1] = static_cast<uint32_t>(_mm_extract_epi32(v, 1));
  out[2] = static_cast<uint32_t>(_mm_extract_epi32(v, 2));
  out[3] = static_cast<uint32_t>(_mm_extract_epi32(v, 3));
#else
  out[0] = vgetq_lane_u32(v, 0), out[1] = vgetq_lane_u32(v, 1);
  out[2] = vgetq_lane_u32(v, 2), out[3] = vgetq_lane_u32(v, 3);
#endif
}

/// Smallest of the four lanes; the lanes must not be NaN.
inline float reduce_min(vfloat4 v) {
#if defined(__x86_64__)
  __m128 a = _mm_min_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
  a = _mm_min_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(a);
#else
  return vminvq_f32(v);
#endif
}

/// Largest of the four lanes; the lanes must not be NaN.
inline float reduce_max(vfloat4 v) {
#if defined(__x86_64__)
  __m128 a = _mm_max_ps(v, _mm_shuffle_ps(v, v, _MM_SHUFFLE(2, 3, 0, 1)));
  a = _mm_max_ps(a, _mm_shuffle_ps(a, a, _MM_SHUFFLE(1, 0, 3, 2)));
  return _mm_cvtss_f32(a);
#else
  return vmaxvq_f32(v);
#endif
}

/// Returns v unchanged, rounded to float: the compiler cannot contract a
/// product passed through here into an FMA with what follows. Watertight edge
/// functions a*b - c*d need both products rounded so that the two triangles
/// sharing an edge compute exactly opposite values.
inline vfloat4 keep_rounded(vfloat4 v) {
  typename vfloat4::register_type x = v;
#if defined(__x86_64__)
  asm("" : "+x"(x));
#else
  asm("" : "+w"(x));
#endif
  return x;
}

/// x * y - z, rounded once where the CPU fuses multiply and add (x86 with
/// FMA3, aarch64), else rounded twice. xsimd's fms on the 4-wide SSE type
/// never fuses (its SSE4.2 arch has no FMA), and implicit contraction is off.
inline vfloat4 fused_mul_sub(vfloat4 x, vfloat4 y, vfloat4 z) {
#if defined(__FMA__)
  return _mm_fmsub_ps(x, y, z);
#elif defined(__x86_64__)
  return _mm_sub_ps(_mm_mul_ps(x, y), z);
#else
  return vfmaq_f32(vnegq_f32(z), x, y);
#endif
}

/// Hints the cache to load the 64-byte line holding p. Always inlined: GCC
/// takes a function whose body is only __builtin_prefetch for one without
/// side effects, and where it declines to inline it (into a caller with seven
/// or more such calls, or one that grew past its limits) it deletes the calls
/// as dead code, prefetches and all. So must be every helper made only of
/// prefetches that its own file calls (one called from another file, with no
/// link-time optimisation, stays a call).
PT_ALWAYS_INLINE void prefetch_l1(const void* p) { __builtin_prefetch(p, 0, 3); }

/// Flushes denormal results and inputs to zero on the calling thread (what
/// Embree asks of its callers). Results change only where a value would be
/// denormal, below 1.2e-38 in magnitude.
inline void enable_flush_denormals_to_zero() {
#if defined(__x86_64__)
  _mm_setcsr(_mm_getcsr() | 0x8040u);  // FTZ | DAZ
#else
  uint64_t fpcr;
  asm volatile("mrs %0, fpcr" : "=r"(fpcr));
  asm volatile("msr fpcr, %0" : : "r"(fpcr | (uint64_t(1) << 24)));  // FZ
#endif
}

#if XSIMD_WITH_AVX2
/// Two 4-wide vectors as the halves of one 8-wide vector (AVX2 and up; the
/// BVH4 leaf test takes two triangle blocks at once). Without AVX2 the
/// blocks go one at a time through the 4-wide test.
using vfloat8 = xsimd::batch<float, xsimd::avx2>;
using vbool8 = xsimd::batch_bool<float, xsimd::avx2>;

/// v in both halves.
inline vfloat8 repeat_halves(vfloat4 v) { return _mm256_set_m128(v, v); }

/// Half 0 (lanes 0-3) or 1 (lanes 4-7) of v.
inline vfloat4 half_of(vfloat8 v, int which) {
  return which == 0 ? _mm256_castps256_ps128(v) : _mm256_extractf128_ps(v, 1);
}

/// Four aligned floats at lo and four at hi as one vector.
inline vfloat8 load_halves(const float* lo, const float* hi) {
  return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(lo)), _mm_load_ps(hi), 1);
}

/// Bit mask of the true lanes (lane i -> bit i).
inline uint32_t movemask(vbool8 m) { return static_cast<uint32_t>(_mm256_movemask_ps(m)); }
#endif

}  // namespace PT_ISA_NS
}  // namespace pt

#if PT_PER_LEVEL
namespace pt {
inline namespace PT_ISA_NS {

using vfloatK = xsimd::batch<float>;
using vintK = xsimd::batch<int32_t>;
using vuintK = xsimd::batch<uint32_t>;
using vboolK = xsimd::batch_bool<float>;
using vbooliK = xsimd::batch_bool<int32_t>;

inline constexpr std::size_t kLanes = vfloatK::size;
static_assert((kLanes == 4 || kLanes == 8 || kLanes == 16) && kLanes <= kMaxLanes);

/// Bit mask of the true lanes of a K-wide comparison (lane i -> bit i).
inline uint32_t lane_mask(vboolK m) {
#if XSIMD_WITH_AVX512F
  return static_cast<uint32_t>(static_cast<__mmask16>(m));
#elif XSIMD_WITH_AVX
  return static_cast<uint32_t>(_mm256_movemask_ps(m));
#else
  return movemask(m);  // K = 4: vboolK is vbool4
#endif
}

/// A K-wide integer comparison's result as a float mask. Reinterprets the
/// mask register (full-width lanes, or an AVX-512 mask register): never
/// through float values, whose all-ones lanes are NaN.
template <class M>
inline vboolK as_float_mask(M m) {
  return xsimd::bool_cast(vbooliK(static_cast<typename M::register_type>(m)));
}

/// The lanes of v that hold exactly the bits of x (so -0 is not +0, and a
/// NaN matches only its own bits).
inline vboolK same_bits(vfloatK v, float x) {
  return as_float_mask(xsimd::bitwise_cast<vintK>(v) == vintK(std::bit_cast<int32_t>(x)));
}

/// A K-wide float mask as an int32 mask.
inline vbooliK as_int_mask(vboolK m) { return xsimd::bool_cast(m); }

/// Lane indices 0, 1, ..., K-1.
inline vintK lane_index() {
  alignas(64) static constexpr int32_t kIndex[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15};
  return vintK::load_aligned(kIndex);
}

/// The K-wide mask whose lane i is bit i of `bits`.
inline vboolK lanes_of_mask(uint32_t bits) {
#if XSIMD_WITH_AVX512F
  return vboolK(static_cast<__mmask16>(bits));
#else
  alignas(64) static constexpr int32_t kBit[16] = {1 << 0,  1 << 1,  1 << 2,  1 << 3, 1 << 4,  1 << 5,
                                                   1 << 6,  1 << 7,  1 << 8,  1 << 9, 1 << 10, 1 << 11,
                                                   1 << 12, 1 << 13, 1 << 14, 1 << 15};
  return as_float_mask((vintK(static_cast<int32_t>(bits)) & vintK::load_aligned(kBit)) != vintK(0));
#endif
}

#if XSIMD_WITH_AVX2 && !XSIMD_WITH_AVX512F
namespace simd_detail {
/// The AVX2 gathers, written out so that the index never sits in ymm4:
/// qemu 7.2 (Debian 12's, which the emulated-CPU test runs) decodes a VSIB
/// index in register 4 as "no index" and loads base[0] into every lane, so
/// an image would change with the compiler's choice of register. The
/// clobber keeps every operand out of ymm4; the array operand tells the
/// compiler what the gather may read (any element an int32 index reaches).
inline __m256 gather8(const float* base, __m256i index) {
  __m256 mask = _mm256_castsi256_ps(_mm256_set1_epi32(-1)), out;
  asm("vgatherdps %[mask], (%[base],%[index],4), %[out]"
      : [out] "=&x"(out), [mask] "+&x"(mask)
      : [base] "r"(base), [index] "x"(index), "m"(*reinterpret_cast<const float(*)[size_t(1) << 31]>(base))
      : "xmm4");
  return out;
}
inline __m256i gather8(const int32_t* base, __m256i index) {
  __m256i mask = _mm256_set1_epi32(-1), out;
  asm("vpgatherdd %[mask], (%[base],%[index],4), %[out]"
      : [out] "=&x"(out), [mask] "+&x"(mask)
      : [base] "r"(base), [index] "x"(index), "m"(*reinterpret_cast<const int32_t(*)[size_t(1) << 31]>(base))
      : "xmm4");
  return out;
}
}  // namespace simd_detail
#endif

/// base[index[i]] per lane, with the hardware gather where there is one
/// (xsimd 8.1 gathers element by element). For random indices (the
/// wavefront's surface and path lookups) it is as fast as element-wise loads;
/// for the fields of contiguous structures (a ray packet) a transposition
/// through the stack is several times faster on AMD's cores.
inline vfloatK gather(const float* base, vintK index) {
#if XSIMD_WITH_AVX512F
  return _mm512_i32gather_ps(index, base, 4);
#elif XSIMD_WITH_AVX2
  return simd_detail::gather8(base, index);
#else
  return vfloatK::gather(base, index);
#endif
}
inline vintK gather(const int32_t* base, vintK index) {
#if XSIMD_WITH_AVX512F
  return _mm512_i32gather_epi32(index, base, 4);
#elif XSIMD_WITH_AVX2
  return simd_detail::gather8(base, index);
#else
  return vintK::gather(base, index);
#endif
}
inline vuintK gather(const uint32_t* base, vintK index) {
  return xsimd::bitwise_cast<vuintK>(gather(reinterpret_cast<const int32_t*>(base), index));
}

#if defined(__x86_64__)
namespace simd_detail {
/// Per 128-bit block, the transposition of four records (x, y, z, -): out
/// lane 4j + q of x, y, z comes from block j of a[q].
#if XSIMD_WITH_AVX512F
inline void transpose_records3(const __m512 (&a)[4], vfloatK out[3]) {
  const __m512 t0 = _mm512_unpacklo_ps(a[0], a[1]), t1 = _mm512_unpackhi_ps(a[0], a[1]);
  const __m512 t2 = _mm512_unpacklo_ps(a[2], a[3]), t3 = _mm512_unpackhi_ps(a[2], a[3]);
  out[0] = _mm512_castpd_ps(_mm512_unpacklo_pd(_mm512_castps_pd(t0), _mm512_castps_pd(t2)));
  out[1] = _mm512_castpd_ps(_mm512_unpackhi_pd(_mm512_castps_pd(t0), _mm512_castps_pd(t2)));
  out[2] = _mm512_castpd_ps(_mm512_unpacklo_pd(_mm512_castps_pd(t1), _mm512_castps_pd(t3)));
}
#elif XSIMD_WITH_AVX
inline void transpose_records3(const __m256 (&a)[4], vfloatK out[3]) {
  const __m256 t0 = _mm256_unpacklo_ps(a[0], a[1]), t1 = _mm256_unpackhi_ps(a[0], a[1]);
  const __m256 t2 = _mm256_unpacklo_ps(a[2], a[3]), t3 = _mm256_unpackhi_ps(a[2], a[3]);
  out[0] = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(t0), _mm256_castps_pd(t2)));
  out[1] = _mm256_castpd_ps(_mm256_unpackhi_pd(_mm256_castps_pd(t0), _mm256_castps_pd(t2)));
  out[2] = _mm256_castpd_ps(_mm256_unpacklo_pd(_mm256_castps_pd(t1), _mm256_castps_pd(t3)));
}
#else
inline void transpose_records3(const __m128 (&a)[4], vfloatK out[3]) {
  const __m128 t0 = _mm_unpacklo_ps(a[0], a[1]), t1 = _mm_unpackhi_ps(a[0], a[1]);
  const __m128 t2 = _mm_unpacklo_ps(a[2], a[3]), t3 = _mm_unpackhi_ps(a[2], a[3]);
  out[0] = _mm_movelh_ps(t0, t2);
  out[1] = _mm_movehl_ps(t2, t0);
  out[2] = _mm_movelh_ps(t1, t3);
}
#endif
}  // namespace simd_detail
#endif

/// The records of three consecutive floats (a float3) at base + 3 * index[i],
/// as three K-wide vectors: out[c] lane i = base[3 * index[i] + c]. `records`
/// is how many there are. On x86 each lane's record is one 16-byte load and
/// the K loads are transposed in registers: on AMD's cores that takes half
/// the time of three gathers. A 16-byte load reads one float past its record,
/// so a batch that holds the last record takes the three gathers instead.
inline void gather_records3(const float* base, vintK index, int32_t records, vfloatK out[3]) {
#if defined(__x86_64__)
  if (lane_mask(as_float_mask(index >= vintK(records - 1))) == 0) {
    alignas(64) int32_t i[kLanes];
    index.store_aligned(i);
    auto record = [&](size_t lane) { return _mm_loadu_ps(base + 3 * static_cast<size_t>(i[lane])); };
#if XSIMD_WITH_AVX512F
    __m512 a[4];
    for (size_t q = 0; q < 4; ++q) {
      __m512 v = _mm512_castps128_ps512(record(q));
      v = _mm512_insertf32x4(v, record(q + 4), 1);
      v = _mm512_insertf32x4(v, record(q + 8), 2);
      a[q] = _mm512_insertf32x4(v, record(q + 12), 3);
    }
#elif XSIMD_WITH_AVX
    __m256 a[4];
    for (size_t q = 0; q < 4; ++q) a[q] = _mm256_insertf128_ps(_mm256_castps128_ps256(record(q)), record(q + 4), 1);
#else
    __m128 a[4];
    for (size_t q = 0; q < 4; ++q) a[q] = record(q);
#endif
    simd_detail::transpose_records3(a, out);
    return;
  }
#endif
  const vintK i3 = index * vintK(3);
  for (int c = 0; c < 3; ++c) out[c] = gather(base, i3 + vintK(c));
}
inline void gather_records3(const int32_t* base, vintK index, int32_t records, vintK out[3]) {
  vfloatK f[3];  // the bits moved as they are
  gather_records3(reinterpret_cast<const float*>(base), index, records, f);
  for (int c = 0; c < 3; ++c) out[c] = xsimd::bitwise_cast<vintK>(f[c]);
}

namespace simd_detail {
#if XSIMD_WITH_AVX2 && !XSIMD_WITH_AVX512F
/// For each 8-bit mask, the indices of its set lanes in order, 4 bits each.
inline constexpr std::array<uint32_t, 256> kCompress8 = [] {
  std::array<uint32_t, 256> table{};
  for (uint32_t mask = 0; mask < 256; ++mask) {
    uint32_t packed = 0, out = 0;
    for (uint32_t lane = 0; lane < 8; ++lane)
      if (mask >> lane & 1) packed |= lane << (4 * out++);
    table[mask] = packed;
  }
  return table;
}();
#endif

/// v's 32-bit lanes set in `mask` moved to the front, in order; the other
/// lanes hold unspecified values of v. AVX-512 compresses with v as the
/// merge source, which ties the result to v's own register: with zeroing,
/// GCC may give successive compresses one destination register, and AMD's
/// cores then chain them through it (a compaction's stores waited on it).
inline vintK compress(vintK v, uint32_t mask) {
#if XSIMD_WITH_AVX512F
  return _mm512_mask_compress_epi32(v, static_cast<__mmask16>(mask), v);
#elif XSIMD_WITH_AVX2
  const __m256i packed = _mm256_set1_epi32(static_cast<int32_t>(kCompress8[mask & 0xFFu]));
  const __m256i order = _mm256_and_si256(_mm256_srlv_epi32(packed, _mm256_setr_epi32(0, 4, 8, 12, 16, 20, 24, 28)),
                                         _mm256_set1_epi32(15));
  return _mm256_permutevar8x32_epi32(v, order);
#elif defined(__x86_64__)
  return _mm_shuffle_epi8(v, _mm_load_si128(reinterpret_cast<const __m128i*>(kCompress4[mask & 15u].data())));
#else
  return vreinterpretq_s32_u8(vqtbl1q_u8(vreinterpretq_u8_s32(v), vld1q_u8(kCompress4[mask & 15u].data())));
#endif
}
}  // namespace simd_detail

/// Stores the lanes of v selected by `mask` contiguously at dst, lowest lane
/// first (stream compaction). Writes K values: the caller has room for K at
/// dst; only popcount(mask) of them are meaningful. Compresses in a register
/// (the memory form of vcompressps is microcoded on AMD's AVX-512 cores).
inline void store_compressed(int32_t* dst, uint32_t mask, vintK v) {
  simd_detail::compress(v, mask).store_unaligned(dst);
}
inline void store_compressed(uint32_t* dst, uint32_t mask, vuintK v) {
  store_compressed(reinterpret_cast<int32_t*>(dst), mask, xsimd::bitwise_cast<vintK>(v));
}
inline void store_compressed(float* dst, uint32_t mask, vfloatK v) {
  store_compressed(reinterpret_cast<int32_t*>(dst), mask, xsimd::bitwise_cast<vintK>(v));
}

/// Each 32-bit lane's bits in reverse order (bit 0 <-> bit 31). xsimd 8.1 has
/// no bit reversal: on x86 two nibble lookups by byte shuffle reverse each
/// byte and a third shuffle reverses the bytes of a lane (7 instructions per
/// 128 or 512 bits against 25 shifts and masks); aarch64 has both steps as
/// instructions.
inline vuintK reverse_bits(vuintK v) {
#if defined(__x86_64__)
  alignas(64) static constexpr uint8_t kLowNibbleToHigh[64] = {
      0x00, 0x80, 0x40, 0xC0, 0x20, 0xA0, 0x60, 0xE0, 0x10, 0x90, 0x50, 0xD0, 0x30, 0xB0, 0x70, 0xF0,
      0x00, 0x80, 0x40, 0xC0, 0x20, 0xA0, 0x60, 0xE0, 0x10, 0x90, 0x50, 0xD0, 0x30, 0xB0, 0x70, 0xF0,
      0x00, 0x80, 0x40, 0xC0, 0x20, 0xA0, 0x60, 0xE0, 0x10, 0x90, 0x50, 0xD0, 0x30, 0xB0, 0x70, 0xF0,
      0x00, 0x80, 0x40, 0xC0, 0x20, 0xA0, 0x60, 0xE0, 0x10, 0x90, 0x50, 0xD0, 0x30, 0xB0, 0x70, 0xF0};
  alignas(64) static constexpr uint8_t kHighNibbleToLow[64] = {
      0x0, 0x8, 0x4, 0xC, 0x2, 0xA, 0x6, 0xE, 0x1, 0x9, 0x5, 0xD, 0x3, 0xB, 0x7, 0xF, 0x0, 0x8, 0x4, 0xC, 0x2, 0xA,
      0x6, 0xE, 0x1, 0x9, 0x5, 0xD, 0x3, 0xB, 0x7, 0xF, 0x0, 0x8, 0x4, 0xC, 0x2, 0xA, 0x6, 0xE, 0x1, 0x9, 0x5, 0xD,
      0x3, 0xB, 0x7, 0xF, 0x0, 0x8, 0x4, 0xC, 0x2, 0xA, 0x6, 0xE, 0x1, 0x9, 0x5, 0xD, 0x3, 0xB, 0x7, 0xF};
  alignas(64) static constexpr uint8_t kByteSwap[64] = {
      3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12,
      3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12, 3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12};
#if XSIMD_WITH_AVX512F
  const __m512i x = v, nibble = _mm512_set1_epi8(0x0F);
  const __m512i lo = _mm512_and_si512(x, nibble), hi = _mm512_and_si512(_mm512_srli_epi16(x, 4), nibble);
  const __m512i bytes = _mm512_or_si512(_mm512_shuffle_epi8(_mm512_load_si512(kLowNibbleToHigh), lo),
                                        _mm512_shuffle_epi8(_mm512_load_si512(kHighNibbleToLow), hi));
  return _mm512_shuffle_epi8(bytes, _mm512_load_si512(kByteSwap));
#elif XSIMD_WITH_AVX2
  __m256i low_lut = _mm256_load_si256(reinterpret_cast<const __m256i*>(kLowNibbleToHigh));
  __m256i high_lut = _mm256_load_si256(reinterpret_cast<const __m256i*>(kHighNibbleToLow));
  __m256i swap = _mm256_load_si256(reinterpret_cast<const __m256i*>(kByteSwap));
  // Register operands only: qemu 7.2 (Debian 12's qemu-user, under which the
  // emulated-CPU test runs this level) computes the 256-bit vpshufb with a
  // memory operand wrongly, and a render that contains one differs there.
  asm("" : "+x"(low_lut), "+x"(high_lut), "+x"(swap));
  const __m256i x = v, nibble = _mm256_set1_epi8(0x0F);
  const __m256i lo = _mm256_and_si256(x, nibble), hi = _mm256_and_si256(_mm256_srli_epi16(x, 4), nibble);
  const __m256i bytes = _mm256_or_si256(_mm256_shuffle_epi8(low_lut, lo), _mm256_shuffle_epi8(high_lut, hi));
  return _mm256_shuffle_epi8(bytes, swap);
#else
  const __m128i x = v, nibble = _mm_set1_epi8(0x0F);
  const __m128i lo = _mm_and_si128(x, nibble), hi = _mm_and_si128(_mm_srli_epi16(x, 4), nibble);
  const __m128i bytes =
      _mm_or_si128(_mm_shuffle_epi8(_mm_load_si128(reinterpret_cast<const __m128i*>(kLowNibbleToHigh)), lo),
                   _mm_shuffle_epi8(_mm_load_si128(reinterpret_cast<const __m128i*>(kHighNibbleToLow)), hi));
  return _mm_shuffle_epi8(bytes, _mm_load_si128(reinterpret_cast<const __m128i*>(kByteSwap)));
#endif
#else
  return vreinterpretq_u32_u8(vrev32q_u8(vrbitq_u8(vreinterpretq_u8_u32(v))));
#endif
}

/// x * y - z in K lanes, with one rounding where the CPU has FMA (xsimd 8.1's
/// fms never fuses), as fused_mul_sub does in four.
inline vfloatK fused_mul_sub_k(vfloatK x, vfloatK y, vfloatK z) {
#if XSIMD_WITH_AVX512F
  return _mm512_fmsub_ps(x, y, z);
#elif XSIMD_WITH_AVX2 && defined(__FMA__)
  return _mm256_fmsub_ps(x, y, z);
#else
  return fused_mul_sub(x, y, z);  // K = 4: vfloatK is vfloat4
#endif
}

/// Smallest of the K lanes; the lanes must not be NaN.
inline float reduce_min_k(vfloatK v) {
#if XSIMD_WITH_AVX512F
  __m256 a = _mm256_min_ps(_mm512_castps512_ps256(v), _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(v), 1)));
  return reduce_min(vfloat4(_mm_min_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1))));
#elif XSIMD_WITH_AVX
  return reduce_min(vfloat4(_mm_min_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1))));
#else
  return reduce_min(v);           // K = 4: vfloatK is vfloat4
#endif
}

/// Largest of the K lanes; the lanes must not be NaN.
inline float reduce_max_k(vfloatK v) {
#if XSIMD_WITH_AVX512F
  __m256 a = _mm256_max_ps(_mm512_castps512_ps256(v), _mm256_castpd_ps(_mm512_extractf64x4_pd(_mm512_castps_pd(v), 1)));
  return reduce_max(vfloat4(_mm_max_ps(_mm256_castps256_ps128(a), _mm256_extractf128_ps(a, 1))));
#elif XSIMD_WITH_AVX
  return reduce_max(vfloat4(_mm_max_ps(_mm256_castps256_ps128(v), _mm256_extractf128_ps(v, 1))));
#else
  return reduce_max(v);
#endif
}

}  // namespace PT_ISA_NS
}  // namespace pt
#endif  // PT_PER_LEVEL
