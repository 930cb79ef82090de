// shade_microfacet: rough conductors. Light samples (or hemisphere probes)
// weighted by the microfacet BRDF and, under MIS, by its pdf; a continuation
// reflected about a Beckmann-sampled normal (kernels/transport/bsdf.h), K lanes wide.
#include "kernels/simd/isa_namespace.h"
#include "kernels/transport/bsdf.h"
#include "kernels/transport/direct_light.h"
#include "kernels/transport/sample_dimensions.h"
#include "kernels/transport/surface.h"
#include "lane_output.h"
#include "shade_kernels.h"

namespace pt::wf {
inline namespace PT_ISA_NS {

void shade_microfacet(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits,
                      PathState& paths, ShadeOutputs out) {
  const RenderSettings& rs = ctx.settings;
  const uint32_t vertex = depth + 1;
  const bool direct = ctx.rules.estimates_direct_light(vertex);
  const bool samples_bsdf = ctx.rules.traces_bsdf_ray(vertex);
  if (!direct && !samples_bsdf) return;
  const bool course = rs.cs184_materials;
  const MaterialArrays& mats = ctx.materials;
  for (size_t i0 = 0; i0 < rays.size; i0 += kLanes) {
    SurfaceBatch s = fetch_surfaces(ctx, rays, hits, i0);
    s.hit = hits_of_kind(ctx, s, MaterialKind::kMicrofacet);
    if (!lane_mask(s.hit)) continue;
    vintK path = lane_paths(rays, i0, s.valid);
    const vuintK path_u = xsimd::bitwise_cast<vuintK>(path);
    V3 wo{-vfloatK::load_aligned(&rays.dir_x[i0]), -vfloatK::load_aligned(&rays.dir_y[i0]),
          -vfloatK::load_aligned(&rays.dir_z[i0])};
    const V3 wo_local = local_of(wo, s.ns);
    const ConductorT<vfloatK> m{gather(mats.alpha.data(), s.material),
                                gather3(mats.eta_r, mats.eta_g, mats.eta_b, s.material),
                                gather3(mats.k_r, mats.k_g, mats.k_b, s.material)};
    const SamplerK ps = sampler_of_paths(rs, paths, path);
    const V3 beta = lane_beta(rays, i0);
    const ShadingPointT<vfloatK> point{s.p, s.ng, s.ns, s.offset, s.hit};
    auto eval = [&](const V3& wi) { return eval_microfacet(m, wo_local, local_of(wi, s.ns), course); };

    if (direct) {
      if (rs.direct_by_hitting()) {
        sample_hemisphere_rays(ctx.scene, rs, point, ps, vertex,
                               [&](vboolK ok, const V3& org, const V3& wi, vfloatK w) {
                                 V3 f = eval(wi).f;
                                 push_shadow_lanes(lane_mask(ok), out.hemisphere, org, wi, vfloatK(kInfinity), path_u,
                                                   times(beta, {f.x * w, f.y * w, f.z * w}));
                               });
      } else {
        sample_light_sources(
            ctx.scene, rs, point, ps, vertex, ctx.rules.bsdf_competes(vertex),
            [&](const V3& wi, vfloatK) { return eval(wi).pdf; },
            [&](vboolK ok, const V3& org, const V3& wi, vfloatK tmax, const V3& weight) {
              push_shadow_lanes(lane_mask(ok), out.shadows, org, wi, tmax, path_u,
                                times(times(beta, weight), eval(wi).f));
            });
      }
    }
    if (!samples_bsdf) continue;
    vfloatK u1, u2;
    ps.get2d(vertex, dims::kBsdf, u1, u2);
    MicrofacetSampleT<vfloatK> ms = sample_microfacet(m, wo_local, u1, u2, course);
    V3 wi = to_world(s.ns.x, s.ns.y, s.ns.z, ms.wi.x, ms.wi.y, ms.wi.z);
    uint32_t mask = lane_mask(s.hit && ms.ok && dot3(wi, s.ng) > vfloatK(0.0f));
    if (!mask) continue;
    continue_paths(mask, path_u, times(beta, ms.weight), ms.pdf, out.continuations,
                   offset_origin(s.p, s.ng, s.offset, wi), wi);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
