// Counter-based random numbers: every number is a pure function of
// (seed, pixel, sample, bounce, dimension), so an image does not depend on the
// thread count, the batch size or the order in which work is done, and any one
// sample can be replayed on its own. Written over a lane type U (uint32_t or a
// batch of them) so the SIMD stages draw exactly the numbers the scalar
// reference draws.
//
// A number is hash(hash(pixel_key ^ dimension_key) ^ sample_key): the pixel
// and the sample enter through separate 32-bit words, so two different paths
// never share all their numbers (a single 32-bit key per path would: with
// 10^8-10^9 paths per image its birthday collisions repeat whole paths).
#pragma once

#include <cstdint>
#include <type_traits>

#include "kernels/simd/isa_namespace.h"
#include "kernels/simd/simd.h"

namespace pt {
inline namespace PT_ISA_NS {

/// 32-bit integer hash with low bias (C. Wellons' "lowbias32"): a bijection on
/// uint32 whose output bits each flip with probability ~0.5 per input bit.
template <class U>
inline U hash32(U x) {
  x ^= x >> 16;
  x *= U(0x7feb352du);
  x ^= x >> 15;
  x *= U(0x846ca68bu);
  x ^= x >> 16;
  return x;
}

/// Key of a pixel under a seed.
template <class U>
inline U pixel_key(uint32_t seed, U pixel) {
  return hash32(pixel ^ U(hash32(seed ^ 0x7f4a7c15u)));
}

/// Key of a sample index (the same for every pixel; mixed with the pixel's
/// numbers only after they are hashed).
template <class U>
inline U sample_key(U sample) {
  return hash32(sample ^ U(0x9e3779b9u));
}

/// Key of one random dimension at one bounce; the same for every path.
constexpr uint32_t dimension_key(uint32_t bounce, uint32_t dim) {
  uint32_t x = (bounce << 16) ^ dim ^ 0x85ebca6bu;
  x ^= x >> 16;
  x *= 0x7feb352du;
  x ^= x >> 15;
  x *= 0x846ca68bu;
  x ^= x >> 16;
  return x;
}

/// The top 24 bits as a float in [0, 1) (never 1).
template <class U, class F>
inline F bits_to_unit(U bits) {
  U top = bits >> 8;
  if constexpr (std::is_arithmetic_v<U>) return static_cast<F>(top) * 0x1p-24f;
  else return xsimd::batch_cast<float>(xsimd::batch_cast<int32_t>(top)) * F(0x1p-24f);
}

/// The uniform number of one dimension of one path.
template <class U, class F>
inline F random_float(U pixel_key, U sample_key, uint32_t dim_key) {
  return bits_to_unit<U, F>(hash32(hash32(pixel_key ^ U(dim_key)) ^ sample_key));
}

/// Scalar convenience: the uniform number for (keys, bounce, dim).
inline float random_uniform(uint32_t pixel_key, uint32_t sample_key, uint32_t bounce, uint32_t dim) {
  return random_float<uint32_t, float>(pixel_key, sample_key, dimension_key(bounce, dim));
}

}  // namespace PT_ISA_NS
}  // namespace pt
