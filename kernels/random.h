// Counter-based random numbers: every number is a pure function of
// (seed, pixel, sample, bounce, dimension), so an image does not depend on the
// thread count, the batch size or the order in which work is done, and any one
// sample can be replayed on its own. Written over a lane type U (uint32_t or a
// batch of them) so the SIMD stages draw exactly the numbers the scalar
// reference draws.
#pragma once

#include <cstdint>
#include <type_traits>

#include "simd.h"

namespace pt {

/// 32-bit integer hash with low bias (C. Wellons' "lowbias32"): a bijection on
/// uint32 whose output bits each flip with probability ~0.5 per input bit.
template <class U> inline U hash32(U x) {
  x ^= x >> 16;
  x *= U(0x7feb352du);
  x ^= x >> 15;
  x *= U(0x846ca68bu);
  x ^= x >> 16;
  return x;
}

/// Key of one path: hashes (seed, pixel, sample). Computed once per camera sample.
template <class U> inline U path_key(uint32_t seed, U pixel, U sample) {
  return hash32(pixel ^ hash32(sample + U(hash32(seed ^ 0x9e3779b9u))));
}

/// Key of one random dimension at one bounce; the same for every path.
constexpr uint32_t dimension_key(uint32_t bounce, uint32_t dim) {
  uint32_t x = (bounce << 16) ^ dim ^ 0x85ebca6bu;
  x ^= x >> 16; x *= 0x7feb352du; x ^= x >> 15; x *= 0x846ca68bu; x ^= x >> 16;
  return x;
}

/// Uniform float in [0, 1) (never 1) from a path key and a dimension key.
template <class U, class F> inline F random_float(U key, uint32_t dim_key) {
  U bits = hash32(key ^ U(dim_key)) >> 8;
  if constexpr (std::is_arithmetic_v<U>) return static_cast<F>(bits) * 0x1p-24f;
  else return xsimd::batch_cast<float>(xsimd::batch_cast<int32_t>(bits)) * F(0x1p-24f);
}

/// Scalar convenience: the uniform float for (key, bounce, dim).
inline float random_uniform(uint32_t key, uint32_t bounce, uint32_t dim) {
  return random_float<uint32_t, float>(key, dimension_key(bounce, dim));
}

}  // namespace pt
