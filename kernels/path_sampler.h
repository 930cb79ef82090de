// Where a path's random numbers come from: independent counter-based numbers
// (random.h), or Owen-scrambled Sobol points (sobol.h) for the 2D decisions
// (pixel jitter, light samples, BSDF directions). Either way a number is a
// pure function of (seed, pixel, sample, bounce, dimension). Lane-generic:
// U is uint32_t or a batch of them, F the matching float type.
#pragma once

#include <cstdint>

#include "random.h"
#include "render_settings.h"
#include "sobol.h"

namespace pt {

template <class U, class F>
struct PathSamplerT {
  U pixel;      ///< pixel_key(seed, pixel index)
  U sample;     ///< sample index
  U sample_k;   ///< sample_key(sample index)
  bool sobol = false;

  PathSamplerT(const RenderSettings& rs, U pixel_index, U sample_index)
      : pixel(pixel_key(rs.seed, pixel_index)),
        sample(sample_index),
        sample_k(sample_key(sample_index)),
        sobol(rs.sampler == PixelSampler::kSobol) {}

  F get1d(uint32_t bounce, uint32_t dim) const { return random_float<U, F>(pixel, sample_k, dimension_key(bounce, dim)); }

  /// Dimensions (dim, dim + 1) at `bounce`.
  void get2d(uint32_t bounce, uint32_t dim, F& u1, F& u2) const {
    if (sobol) {
      owen_sobol_2d<U, F>(sample, hash32(pixel ^ U(dimension_key(bounce, dim))), u1, u2);
    } else {
      u1 = get1d(bounce, dim);
      u2 = get1d(bounce, dim + 1);
    }
  }
};

using PathSampler = PathSamplerT<uint32_t, float>;

}  // namespace pt
