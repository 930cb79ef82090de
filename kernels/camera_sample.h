// The camera ray of sample `sample` of pixel (x, y): jittered uniformly inside
// the pixel by the sample's own random numbers. Pixel (0, 0) is top-left.
#pragma once

#include "camera.h"
#include "random.h"
#include "render_settings.h"
#include "sample_dimensions.h"

namespace pt {

inline uint32_t pixel_index(const RenderSettings& rs, int x, int y) {
  return static_cast<uint32_t>(y) * static_cast<uint32_t>(rs.width) + static_cast<uint32_t>(x);
}

inline Ray jittered_camera_ray(const Camera& c, const RenderSettings& rs, int x, int y, uint32_t key) {
  float jx = random_uniform(key, dims::kCameraBounce, dims::kPixelJitter);
  float jy = random_uniform(key, dims::kCameraBounce, dims::kPixelJitter + 1);
  return camera_ray(c, (x + jx) / rs.width, 1.0f - (y + jy) / rs.height);
}

}  // namespace pt
