// The film every engine renders into: per-pixel mean radiance and samples
// taken, row 0 at the top. Only pixels inside the render region are written.
#pragma once

#include <cstdint>
#include <vector>

#include "vec3.h"

namespace pt {

struct Film {
  int width = 0, height = 0;
  uint32_t max_samples = 0;        ///< the -s limit, for the sample-rate image
  std::vector<float3> radiance;    ///< linear RGB mean per pixel
  std::vector<uint32_t> samples;   ///< camera samples taken per pixel
  std::vector<float> variance;     ///< variance of each pixel's mean illuminance (s^2 / n)

  Film() = default;
  Film(int w, int h, uint32_t max_spp)
      : width(w),
        height(h),
        max_samples(max_spp),
        radiance(size_t(w) * h),
        samples(size_t(w) * h, 0),
        variance(size_t(w) * h, 0.0f) {}
  size_t index(int x, int y) const { return size_t(y) * width + x; }
};

}  // namespace pt
