// generate_camera_rays: identities in scalar, keys, jitter and directions in SIMD.
#include "generate_camera_rays.h"

#include "kernels/camera.h"
#include "kernels/path_sampler.h"
#include "kernels/sample_dimensions.h"

namespace pt::wf {

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
    for (size_t lane = 0; lane < kLanes; ++lane) {
      size_t i = std::min(i0 + lane, n - 1);  // tail lanes repeat the last path
      uint32_t pixel = pixels[i / samples];
      paths.pixel[i0 + lane] = pixel;
      paths.sample[i0 + lane] = first_sample + static_cast<uint32_t>(i % samples);
      fx[lane] = static_cast<float>(pixel % static_cast<uint32_t>(rs.width));
      fy[lane] = static_cast<float>(pixel / static_cast<uint32_t>(rs.width));
    }
    PathSamplerT<vuintK, vfloatK> ps(rs, vuintK::load_aligned(&paths.pixel[i0]), vuintK::load_aligned(&paths.sample[i0]));
    ps.pixel.store_aligned(&paths.pixel_key[i0]);
    ps.sample_k.store_aligned(&paths.sample_key[i0]);
    vfloatK jx, jy;
    ps.get2d(dims::kCameraBounce, dims::kPixelJitter, jx, jy);
    vfloatK sx = (vfloatK::load_aligned(fx) + jx) / width;
    vfloatK sy = vfloatK(1.0f) - (vfloatK::load_aligned(fy) + jy) / height;
    Vec3T<vfloatK> d = camera_ray_direction(cam, sx, sy);
    d.x.store_aligned(&rays.dir_x[i0]);
    d.y.store_aligned(&rays.dir_y[i0]);
    d.z.store_aligned(&rays.dir_z[i0]);
    vfloatK(cam.position.x).store_aligned(&rays.org_x[i0]);
    vfloatK(cam.position.y).store_aligned(&rays.org_y[i0]);
    vfloatK(cam.position.z).store_aligned(&rays.org_z[i0]);
    vfloatK(cam.near_clip).store_aligned(&rays.tmin[i0]);
    vfloatK(cam.far_clip).store_aligned(&rays.tmax[i0]);
    vfloatK one(1.0f), zero(0.0f);
    one.store_aligned(&paths.beta_r[i0]);
    one.store_aligned(&paths.beta_g[i0]);
    one.store_aligned(&paths.beta_b[i0]);
    zero.store_aligned(&paths.radiance_r[i0]);
    zero.store_aligned(&paths.radiance_g[i0]);
    zero.store_aligned(&paths.radiance_b[i0]);
    (xsimd::batch_cast<uint32_t>(lane_index()) + vuintK(static_cast<uint32_t>(i0))).store_aligned(&rays.path[i0]);
  }
}

}  // namespace pt::wf
