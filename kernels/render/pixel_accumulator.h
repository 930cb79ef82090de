// A pixel's running sums, shared by the engines that render in passes. Samples
// are added in sample order in double precision, so an image does not depend
// on how work was split into passes, waves or threads, and a saved set of
// accumulators resumes a render exactly. The pixel also keeps its means at the
// last three power-of-two sample counts it reached, from which the render
// estimates its own error (kernels/render/error_estimate.h).
#pragma once

#include <cstdint>

#include "kernels/render/adaptive.h"
#include "kernels/math/vec3.h"

namespace pt {

/// 88 bytes.
struct PixelAccumulator {
  double sum_r = 0, sum_g = 0, sum_b = 0;
  PixelMoments moments;  ///< of the samples' illuminance
  uint32_t samples = 0;
  uint32_t converged = 0;  ///< 1 once the adaptive test stopped the pixel
  /// The mean (r, g, b) at the last three power-of-two sample counts reached,
  /// newest first: after n samples, with P the largest power of two <= n,
  /// at_powers[0] is the mean of samples [0, P), [1] of [0, P/2), [2] of [0, P/4).
  float at_powers[3][3] = {};

  /// Adds one sample. A non-finite sample counts as black; returns false then.
  bool add(float3 L) {
    bool ok = is_finite(L);
    if (!ok) L = float3{};
    sum_r += L.x;
    sum_g += L.y;
    sum_b += L.z;
    moments.add(illuminance(L));
    ++samples;
    if ((samples & (samples - 1)) == 0) keep_power_of_two_mean();
    return ok;
  }
  float3 mean() const {
    if (samples == 0) return {};
    double inv = 1.0 / samples;
    return {static_cast<float>(sum_r * inv), static_cast<float>(sum_g * inv), static_cast<float>(sum_b * inv)};
  }

 private:
  /// At a power-of-two count: the older means move down, the current one is kept.
  void keep_power_of_two_mean() {
    for (int k = 2; k > 0; --k)
      for (int c = 0; c < 3; ++c) at_powers[k][c] = at_powers[k - 1][c];
    const float3 m = mean();
    at_powers[0][0] = m.x;
    at_powers[0][1] = m.y;
    at_powers[0][2] = m.z;
  }
};
static_assert(sizeof(PixelAccumulator) == 88);

}  // namespace pt
