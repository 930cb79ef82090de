// Which random dimension each decision of a path uses. Every engine draws
// through this table, so with the same seed they make the same choices.
// A number is keyed by (pixel, sample, bounce, dim); bounce 0 is the camera,
// bounce k >= 1 the k-th surface the path reaches.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"

namespace pt::dims {
inline namespace PT_ISA_NS {

inline constexpr uint32_t kCameraBounce = 0;
inline constexpr uint32_t kPixelJitter = 0;  ///< 2 dims at bounce 0
inline constexpr uint32_t kLens = 2;         ///< 2 dims at bounce 0: the thin lens's point

inline constexpr uint32_t kBsdf = 0;         ///< 2 dims: the continuation direction (glass: the first picks the lobe)
inline constexpr uint32_t kRoulette = 2;     ///< 1 dim: Russian roulette
inline constexpr uint32_t kDirectFirst = 3;  ///< 2 dims per direct-light sample

/// Direct-light sample `k` (numbered over all lights in scene order: area
/// lights, point, directional, sky) uses dims (light_dim(k), light_dim(k) + 1).
constexpr uint32_t light_dim(uint32_t k) { return kDirectFirst + 2 * k; }

}  // namespace PT_ISA_NS
}  // namespace pt::dims
