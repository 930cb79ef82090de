// shade_diffuse: the Lambertian kernel, which also takes the rays that hit
// emitters or escaped. Per K-lane chunk, fetch surfaces, then emission (and
// light found by the previous BSDF sample), direct light and BSDF sampling
// as separate steps, by the path rules and per-sample math every engine
// shares (kernels/transport/path_rules.h, kernels/transport/direct_light.h) taken K lanes wide.
#include "kernels/simd/isa_namespace.h"
#include "shade_kernels.h"

#include <optional>

#include "fetch_surfaces.h"
#include "kernels/transport/bounce_light.h"
#include "kernels/transport/direct_light.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"
#include "lane_output.h"

namespace pt::wf {
inline namespace PT_ISA_NS {
namespace {

/// What the steps of one chunk share.
struct Chunk {
  ShadingPointT<vfloatK> point;  ///< on: lanes whose surface reflects (non-black albedo)
  vuintK path;
  SamplerK ps;
  V3 beta, albedo;
  uint32_t vertex;
};

/// Emission the rays see, and the light their BSDF sample found
/// (light_found_by_bounce; scalar: only lanes that hit emitters, or escaped
/// where the sky counts). The surfaces are the chunk's, `s`.
void add_emission(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits, size_t i0,
                  uint32_t lanes, const SurfaceBatch& s, PathState& paths) {
  const RenderSettings& rs = ctx.settings;
  std::optional<SurfaceLanes> surfaces;  // only where a lane hit (escaped rays need none)
  if (lanes & lane_mask(s.hit)) surfaces.emplace(s);
  for_each_lane(lanes, [&](size_t lane) {
    size_t i = i0 + lane;
    uint32_t path = rays.path[i];
    Ray ray = rays.ray(i);
    Hit hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]};
    float3 beta{rays.beta_r[i], rays.beta_g[i], rays.beta_b[i]};
    float3 L;
    SurfacePoint sp;
    if (hit.valid()) sp = surfaces->point(lane);
    if (depth == 0) {
      if (!hit.valid()) {
        if (ctx.rules.counts_escape(0, ctx.sky_visible)) L = sky_radiance(ctx.scene, ray.dir);
      } else if (ctx.rules.counts(0)) {
        L = emitted_radiance(ctx.scene, sp, ray, rs);
      }
    } else {
      const float pdf = rays.bsdf_pdf[i];  // < 0: the ray left a delta lobe
      L = beta * light_found_by_bounce(ctx.scene, rs, ctx.rules, depth, ray, hit.valid() ? &hit : nullptr,
                                       hit.valid() ? &sp : nullptr, pdf, ctx.has_delta && pdf < 0.0f);
    }
    if (!is_black(L)) paths.add_radiance(path, L.x, L.y, L.z);
  });
}

V3 throughput_times_bsdf(const Chunk& c) {
  const vfloatK inv_pi(kInvPi);
  return {c.beta.x * c.albedo.x * inv_pi, c.beta.y * c.albedo.y * inv_pi, c.beta.z * c.albedo.z * inv_pi};
}

/// Direct light: shadow rays of the light samples (each with the radiance it
/// brings, times the path's throughput and BSDF), or the probe rays of the
/// hit-based estimators.
void sample_direct_light(const WaveContext& ctx, const Chunk& c, ShadeOutputs& out) {
  const V3 beta_f = throughput_times_bsdf(c);
  if (ctx.settings.direct_by_hitting()) {
    sample_hemisphere_rays(ctx.scene, ctx.settings, c.point, c.ps, c.vertex,
                           [&](vboolK ok, const V3& org, const V3& wi, vfloatK weight) {
                             push_shadow_lanes(lane_mask(ok), out.hemisphere, org, wi, vfloatK(kInfinity), c.path,
                                               {beta_f.x * weight, beta_f.y * weight, beta_f.z * weight});
                           });
    return;
  }
  sample_light_sources(ctx.scene, ctx.settings, c.point, c.ps, c.vertex, ctx.rules.bsdf_competes(c.vertex),
                       LambertianPdf{}, [&](vboolK ok, const V3& org, const V3& wi, vfloatK tmax, const V3& weight) {
                         push_shadow_lanes(lane_mask(ok), out.shadows, org, wi, tmax, c.path, times(beta_f, weight));
                       });
}

/// Cosine-weighted continuation; throughput *= albedo (f cos / pdf).
void sample_bsdf(const Chunk& c, RayQueue& q) {
  BsdfSampleT<vfloatK> bs = sample_lambertian(c.point, c.ps, c.vertex);
  uint32_t mask = lane_mask(bs.ok);
  if (!mask) return;
  continue_paths(mask, c.path, times(c.beta, c.albedo), bs.pdf, q,
                 offset_origin(c.point.p, c.point.ng, c.point.offset, bs.wi), bs.wi);
}

}  // namespace

void shade_diffuse(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits, PathState& paths,
                   ShadeOutputs out) {
  const RenderSettings& rs = ctx.settings;
  const uint32_t vertex = depth + 1;
  const bool direct = ctx.rules.estimates_direct_light(vertex);
  const bool samples_bsdf = ctx.rules.traces_bsdf_ray(vertex);
  const bool escapes_count = depth == 0 || ctx.rules.counts_escape(depth, ctx.sky_visible) ||
                             (ctx.has_delta && ctx.sky_visible && ctx.rules.counts(depth));
  const size_t n = rays.size;
  out.shadows.reserve(n * ctx.shadow_rays_per_vertex);
  out.hemisphere.reserve(rs.direct_by_hitting() ? n * ctx.shadow_rays_per_vertex : 0);
  // out.continuations: reserved by run_wave for the whole shaded queue
  const MaterialArrays& mats = ctx.materials;

  prefetch_surfaces(ctx, hits, 0, false);  // the first two chunks' indices: the loop starts two ahead
  prefetch_surfaces(ctx, hits, kLanes, false);
  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    prefetch_surfaces(ctx, hits, i0 + 2 * kLanes, false);  // indices two chunks ahead,
    prefetch_surfaces(ctx, hits, i0 + kLanes, true);       // vertices one chunk ahead
    SurfaceBatch s = fetch_surfaces(ctx, rays, hits, i0);
    vboolK emits = s.hit && as_float_mask(gather(mats.emits.data(), s.material) != vintK(0));
    uint32_t emission_lanes = lane_mask(emits) | (escapes_count ? lane_mask(s.valid && !s.hit) : 0);
    if (emission_lanes) add_emission(ctx, depth, rays, hits, i0, emission_lanes, s, paths);
    if (!direct && !samples_bsdf) continue;

    vintK path = xsimd::select(as_int_mask(s.valid), as_index(vuintK::load_aligned(&rays.path[i0])), vintK(0));
    V3 albedo = gather3(mats.albedo_r, mats.albedo_g, mats.albedo_b, s.material);
    const vfloatK zero(0.0f);
    vboolK reflects = s.hit && (albedo.x != zero || albedo.y != zero || albedo.z != zero);
    if (!ctx.diffuse_only()) reflects = reflects && as_float_mask(gather(mats.kind.data(), s.material) == vintK(0));
    // A chunk where no lane reflects (emitters hit, rays escaped: the hit-point
    // order puts them together) samples nothing: every light sample, probe and
    // continuation of it would be masked off.
    if (!lane_mask(reflects)) continue;
    Chunk c{{s.p, s.ng, s.ns, s.offset, reflects},
            xsimd::bitwise_cast<vuintK>(path),
            sampler_of_paths(rs, paths, path),
            lane_beta(rays, i0),
            albedo,
            vertex};
    if (direct) sample_direct_light(ctx, c, out);
    if (samples_bsdf) sample_bsdf(c, out.continuations);
  }
}

}  // namespace PT_ISA_NS
}  // namespace pt::wf
