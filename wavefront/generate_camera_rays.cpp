// generate_camera_rays: identities in scalar, keys, jitter, lens samples and
// directions in SIMD.
#include "kernels/simd/isa_namespace.h"
#include "generate_camera_rays.h"

#include <algorithm>

#include "kernels/scene/camera.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/transport/sample_dimensions.h"
#include "soa_lanes.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

void generate_camera_rays(const WaveContext& ctx, std::span<const uint32_t> pixels, uint32_t first_sample,
                          uint32_t samples, PathState& paths, RayQueue& rays) {
  const RenderSettings& rs = ctx.settings;
  const Camera& cam = ctx.camera;
  const size_t n = pixels.size() * samples;
  paths.reserve(n);
  rays.reserve(n);
  paths.size = rays.size = n;
  const vfloatK width(static_cast<float>(rs.width)), height(static_cast<float>(rs.height));

  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    // Identities: integer division per path, in scalar.
    alignas(64) float fx[kLanes], fy[kLanes];
    alignas(64) uint32_t pixel_of[kLanes], sample_of[kLanes];
    for (size_t lane = 0; lane < kLanes; ++lane) {
      size_t i = std::min(i0 + lane, n - 1);  // tail lanes repeat the last path
      uint32_t pixel = pixels[i / samples];
      pixel_of[lane] = pixel;
      sample_of[lane] = first_sample + static_cast<uint32_t>(i % samples);
      fx[lane] = static_cast<float>(pixel % static_cast<uint32_t>(rs.width));
      fy[lane] = static_cast<float>(pixel / static_cast<uint32_t>(rs.width));
    }
    const vuintK pixel = vuintK::load_aligned(pixel_of), sample = vuintK::load_aligned(sample_of);
    PathSamplerT<vuintK, vfloatK> ps(rs, pixel, sample);
    vfloatK jx, jy;
    ps.get2d(dims::kCameraBounce, dims::kPixelJitter, jx, jy);
    vfloatK sx = (vfloatK::load_aligned(fx) + jx) / width;
    vfloatK sy = vfloatK(1.0f) - (vfloatK::load_aligned(fy) + jy) / height;
    Vec3T<vfloatK> d, o{vfloatK(cam.position.x), vfloatK(cam.position.y), vfloatK(cam.position.z)};
    if (cam.thin_lens()) {
      vfloatK u1, u2;
      ps.get2d(dims::kCameraBounce, dims::kLens, u1, u2);
      thin_lens_ray(cam, sx, sy, u1, u2, o, d);
    } else {
      d = camera_ray_direction(cam, sx, sy);
    }
    const vfloatK one(1.0f), zero(0.0f);
    store_lanes(
        paths, i0,
        PathLanes{.pixel = pixel, .sample = sample, .radiance_r = zero, .radiance_g = zero, .radiance_b = zero});
    store_lanes(rays, i0,
                RayLanes{.org_x = o.x,
                         .org_y = o.y,
                         .org_z = o.z,
                         .tmin = vfloatK(cam.near_clip),
                         .dir_x = d.x,
                         .dir_y = d.y,
                         .dir_z = d.z,
                         .tmax = vfloatK(cam.far_clip),
                         .path = xsimd::batch_cast<uint32_t>(lane_index()) + vuintK(static_cast<uint32_t>(i0)),
                         .beta_r = one,
                         .beta_g = one,
                         .beta_b = one,
                         .bsdf_pdf = zero});
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
