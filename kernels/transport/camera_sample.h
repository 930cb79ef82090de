// The camera ray of sample `sample` of pixel (x, y): jittered uniformly inside
// the pixel by the sample's own random numbers, and through a point of the
// lens for a thin-lens camera. Pixel (0, 0) is top-left.
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/scene/camera.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/render/render_settings.h"
#include "kernels/transport/sample_dimensions.h"

namespace pt {
inline namespace PT_ISA_NS {

inline uint32_t pixel_index(const RenderSettings& rs, int x, int y) {
  return static_cast<uint32_t>(y) * static_cast<uint32_t>(rs.width) + static_cast<uint32_t>(x);
}

inline Ray jittered_camera_ray(const Camera& c, const RenderSettings& rs, int x, int y, const PathSampler& ps) {
  float jx, jy;
  ps.get2d(dims::kCameraBounce, dims::kPixelJitter, jx, jy);
  const float sx = (x + jx) / rs.width, sy = 1.0f - (y + jy) / rs.height;
  if (!c.thin_lens()) return camera_ray(c, sx, sy);
  float u1, u2;
  ps.get2d(dims::kCameraBounce, dims::kLens, u1, u2);
  Vec3T<float> org, dir;
  thin_lens_ray(c, sx, sy, u1, u2, org, dir);
  return {to_float3(org), c.near_clip, to_float3(dir), c.far_clip};
}

}  // namespace PT_ISA_NS
}  // namespace pt
