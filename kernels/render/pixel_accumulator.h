// A pixel's running sums, shared by the engines that render in passes. Samples
// are added in sample order in double precision, so an image does not depend
// on how work was split into passes, waves or threads, and a saved set of
// accumulators resumes a render exactly.
#pragma once

#include <cstdint>

#include "kernels/render/adaptive.h"
#include "kernels/math/vec3.h"

namespace pt {

/// 48 bytes.
struct PixelAccumulator {
  double sum_r = 0, sum_g = 0, sum_b = 0;
  PixelMoments moments;  ///< of the samples' illuminance
  uint32_t samples = 0;
  uint32_t converged = 0;  ///< 1 once the adaptive test stopped the pixel

  /// Adds one sample. A non-finite sample counts as black; returns false then.
  bool add(float3 L) {
    bool ok = is_finite(L);
    if (!ok) L = float3{};
    sum_r += L.x;
    sum_g += L.y;
    sum_b += L.z;
    moments.add(illuminance(L));
    ++samples;
    return ok;
  }
  float3 mean() const {
    if (samples == 0) return {};
    double inv = 1.0 / samples;
    return {static_cast<float>(sum_r * inv), static_cast<float>(sum_g * inv), static_cast<float>(sum_b * inv)};
  }
};
static_assert(sizeof(PixelAccumulator) == 48);

}  // namespace pt
