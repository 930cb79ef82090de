// Where a path's random numbers come from: Owen-scrambled Sobol points
// (sobol.h, the default) or independent counter-based numbers (random.h,
// `--sampler independent` and the course renderer's). Either way a number is
// a pure function of (seed, pixel, sample, bounce, dimension). Lane-generic:
// U is uint32_t or a batch of them, F the matching float type.
#pragma once

#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/random.h"
#include "kernels/render/render_settings.h"
#include "kernels/math/sobol.h"

namespace pt {
inline namespace PT_ISA_NS {

template <class U, class F>
struct PathSamplerT {
  U pixel;     ///< pixel_key(seed, pixel index)
  U sample_k;  ///< the sample's word: sample_key(sample index) for independent numbers, the index's bits reversed for
               ///< Sobol
  bool sobol = false;

  PathSamplerT(const RenderSettings& rs, U pixel_index, U sample_index)
      : pixel(pixel_key(rs.seed, pixel_index)),
        sample_k(rs.sampler == PixelSampler::kSobol ? reverse_bits32(sample_index) : sample_key(sample_index)),
        sobol(rs.sampler == PixelSampler::kSobol) {}

  /// Dimension `dim` at `bounce`.
  PT_ALWAYS_INLINE F get1d(uint32_t bounce, uint32_t dim) const {
    if (sobol) return owen_sobol_1d_reversed<U, F>(sample_k, hash32(pixel ^ U(dimension_key(bounce, dim))));
    return random_float<U, F>(pixel, sample_k, dimension_key(bounce, dim));
  }

  /// Dimensions (dim, dim + 1) at `bounce`.
  PT_ALWAYS_INLINE void get2d(uint32_t bounce, uint32_t dim, F& u1, F& u2) const {
    if (sobol) {
      owen_sobol_2d_reversed<U, F>(sample_k, hash32(pixel ^ U(dimension_key(bounce, dim))), u1, u2);
    } else {
      u1 = random_float<U, F>(pixel, sample_k, dimension_key(bounce, dim));
      u2 = random_float<U, F>(pixel, sample_k, dimension_key(bounce, dim + 1));
    }
  }
};

using PathSampler = PathSamplerT<uint32_t, float>;

}  // namespace PT_ISA_NS
}  // namespace pt
