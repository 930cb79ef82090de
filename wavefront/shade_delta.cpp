// shade_delta: mirrors, glass and refraction, one kind per call, so every
// lane takes the same lobe code. No light samples (a delta lobe cannot be
// hit by one); the continuation is marked delta (bsdf_pdf < 0) so that the
// light it finds counts at full weight (shade_diffuse's add_emission).
#include "kernels/simd/isa_namespace.h"
#include "kernels/transport/bsdf.h"
#include "kernels/transport/sample_dimensions.h"
#include "kernels/transport/surface.h"
#include "lane_output.h"
#include "shade_kernels.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

void shade_delta(const WaveContext& ctx, uint32_t depth, MaterialKind kind, const RayQueue& rays, const HitQueue& hits,
                 PathState& paths, ShadeOutputs out) {
  const uint32_t vertex = depth + 1;
  if (!ctx.rules.traces_delta_ray(vertex)) return;
  const RenderSettings& rs = ctx.settings;
  const MaterialArrays& mats = ctx.materials;
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
    SurfaceBatch s = fetch_surfaces(ctx, rays, hits, i0);
    s.hit = hits_of_kind(ctx, s, kind);
    if (!lane_mask(s.hit)) continue;
    vintK path = lane_paths(rays, i0, s.valid);
    V3 wo{-vfloatK::load_aligned(&rays.dir_x[i0]), -vfloatK::load_aligned(&rays.dir_y[i0]),
          -vfloatK::load_aligned(&rays.dir_z[i0])};
    V3 wo_local = local_of(wo, s.ns);
    V3 reflectance = gather3(mats.albedo_r, mats.albedo_g, mats.albedo_b, s.material);
    DeltaScatterT<vfloatK> d;
    if (kind == MaterialKind::kMirror) {
      d = {mirror_direction(wo_local), reflectance, wo_local.z > vfloatK(0.0f)};
    } else {
      SamplerK ps = sampler_of_paths(rs, paths, path);
      vfloatK u1, u2;
      ps.get2d(vertex, dims::kBsdf, u1, u2);
      d = scatter_dielectric(wo_local, s.front, gather(mats.ior.data(), s.material), reflectance,
                             gather3(mats.trans_r, mats.trans_g, mats.trans_b, s.material), u1,
                             kind == MaterialKind::kGlass, rs.cs184_materials);
    }
    V3 wi = to_world(s.ns.x, s.ns.y, s.ns.z, d.wi.x, d.wi.y, d.wi.z);
    // Reflection must leave above, refraction below the geometric surface.
    vboolK above = dot3(wi, s.ng) > vfloatK(0.0f), up = d.wi.z > vfloatK(0.0f);
    uint32_t mask = lane_mask(s.hit && d.ok && ((above && up) || !(above || up)));
    if (!mask) continue;
    continue_paths(mask, xsimd::bitwise_cast<vuintK>(path), times(lane_beta(rays, i0), d.weight), vfloatK(-1.0f),
                   out.continuations, offset_origin(s.p, s.ng, s.offset, wi), wi);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
