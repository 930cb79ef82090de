// The camera ray of sample `sample` of pixel (x, y): jittered uniformly inside
// the pixel by the sample's own random numbers. Pixel (0, 0) is top-left.
#pragma once

#include "camera.h"
#include "path_sampler.h"
#include "render_settings.h"
#include "sample_dimensions.h"

namespace pt {

inline uint32_t pixel_index(const RenderSettings& rs, int x, int y) {
  return static_cast<uint32_t>(y) * static_cast<uint32_t>(rs.width) + static_cast<uint32_t>(x);
}

inline Ray jittered_camera_ray(const Camera& c, const RenderSettings& rs, int x, int y, const PathSampler& ps) {
  float jx, jy;
  ps.get2d(dims::kCameraBounce, dims::kPixelJitter, jx, jy);
  return camera_ray(c, (x + jx) / rs.width, 1.0f - (y + jy) / rs.height);
}

}  // namespace pt
