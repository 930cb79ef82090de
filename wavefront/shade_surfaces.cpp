// shade_surfaces: per K-lane chunk, fetch surfaces, then emission (and light
// found by the previous BSDF sample), direct light and BSDF sampling as
// separate steps.
#include "shade_surfaces.h"

#include "fetch_surfaces.h"
#include "kernels/lights.h"
#include "kernels/path_sampler.h"
#include "kernels/sample_dimensions.h"
#include "kernels/sampling.h"
#include "kernels/shading.h"
#include "kernels/surface.h"
#include "lane_output.h"

namespace pt::wf {
namespace {

using V3 = Vec3T<vfloatK>;
using SamplerK = PathSamplerT<vuintK, vfloatK>;

/// What the steps of one chunk share.
struct Chunk {
  SurfaceBatch s;
  vuintK path;
  SamplerK ps;
  V3 beta, albedo;
  vboolK reflects;  ///< a surface with non-black albedo
  uint32_t vertex;
};

vintK as_index(vuintK u) { return xsimd::bitwise_cast<vintK>(u); }

V3 gather3(const AlignedVector<float>& r, const AlignedVector<float>& g, const AlignedVector<float>& b, vintK i) {
  return {gather(r.data(), i), gather(g.data(), i), gather(b.data(), i)};
}

vfloatK dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// Emission the rays see, and under MIS the light their BSDF sample found
/// (scalar: only lanes that hit emitters, or escaped where the sky counts).
void add_emission(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits, size_t i0,
                  uint32_t lanes, PathState& paths) {
  const RenderSettings& rs = ctx.settings;
  // Under MIS the previous vertex's BSDF sample competes with light samples
  // (unless it was the final, emission-only bounce).
  const bool mis = rs.direct == DirectLighting::kMis && depth > 0 && static_cast<int>(depth) < rs.max_depth &&
                   rs.counts_bounce(static_cast<int>(depth));
  for_each_lane(lanes, [&](size_t lane) {
    size_t i = i0 + lane;
    uint32_t path = rays.path[i];
    Ray ray = rays.ray(i);
    Hit hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]};
    float3 beta{paths.beta_r[path], paths.beta_g[path], paths.beta_b[path]};
    float3 L;
    if (!hit.valid()) {
      if (depth == 0 && rs.counts_bounce(0) && ctx.sky_visible) L = sky_radiance(*ctx.scene.sky, ray.dir);
      else if (mis) L = beta * mis_light_found_by_bsdf(ctx.scene, rs, ray, nullptr, paths.bsdf_pdf[path]);
    } else {
      SurfacePoint sp = surface_at(ctx.scene, ray, hit);
      if (depth == 0) {
        if (rs.counts_bounce(0)) L = emitted_radiance(ctx.scene, sp, ray, rs);
      } else if (emission_found_by_bounce(ctx.scene, sp, rs) && rs.counts_bounce(static_cast<int>(depth))) {
        L = beta * emitted_radiance(ctx.scene, sp, ray, rs);
      } else if (mis) {
        L = beta * mis_light_found_by_bsdf(ctx.scene, rs, ray, &hit, paths.bsdf_pdf[path]);
      }
    }
    if (!is_black(L)) paths.add_radiance(path, L.x, L.y, L.z);
  });
}

/// Pushes the shadow ray of one light sample per lane where it can contribute.
void push_light_sample(const Chunk& c, vboolK ok, const V3& wi, vfloatK tmax, const V3& weight, ShadowQueue& q) {
  ok = ok && dot(c.s.ns, wi) > vfloatK(0.0f) && dot(c.s.ng, wi) > vfloatK(0.0f);
  uint32_t mask = lane_mask(ok);
  if (!mask) return;
  push_shadow_lanes(mask, q, offset_origin(c.s.p, c.s.ng, c.s.offset, wi), wi, tmax, c.path, weight);
}

V3 light_weight(const V3& beta_f, const float3& radiance, vfloatK factor) {
  return {beta_f.x * (vfloatK(radiance.x) * factor), beta_f.y * (vfloatK(radiance.y) * factor),
          beta_f.z * (vfloatK(radiance.z) * factor)};
}

V3 throughput_times_bsdf(const Chunk& c) {
  const vfloatK inv_pi(kInvPi);
  return {c.beta.x * c.albedo.x * inv_pi, c.beta.y * c.albedo.y * inv_pi, c.beta.z * c.albedo.z * inv_pi};
}

/// cos / pdf, times the MIS weight against the BSDF sample when it competes.
vfloatK light_factor(vfloatK cos_s, vfloatK pdf, vfloatK mis_count) {
  vfloatK g = cos_s / pdf;
  return g * lane::select(mis_count > vfloatK(0.0f), power_heuristic(mis_count * pdf, cos_s * vfloatK(kInvPi)),
                          vfloatK(1.0f));
}

void sample_lights(const WaveContext& ctx, const Chunk& c, vboolK on, bool bsdf_competes, ShadowQueue& q) {
  const Scene& scene = ctx.scene;
  const int n = ctx.settings.light_samples;
  const vfloatK inv_n(1.0f / static_cast<float>(n));
  const vfloatK mis_count(bsdf_competes ? static_cast<float>(n) : 0.0f);
  const V3 beta_f = throughput_times_bsdf(c);
  uint32_t k = 0;
  vfloatK u1, u2;
  for (const AreaLight& light : scene.area_lights)
    for (int j = 0; j < n; ++j, ++k) {
      c.ps.get2d(c.vertex, dims::light_dim(k), u1, u2);
      AreaLightSampleT<vfloatK> ls = sample_area_light<vfloatK>(light, c.s.p.x, c.s.p.y, c.s.p.z, u1, u2);
      vfloatK g = light_factor(dot(c.s.ns, ls.wi), ls.pdf, mis_count) * inv_n;
      push_light_sample(c, on && ls.facing, ls.wi, ls.dist * vfloatK(1.0f - kShadowRayShrink),
                        light_weight(beta_f, light.radiance, g), q);
    }
  for (const PointLight& light : scene.point_lights) {
    V3 d{vfloatK(light.position.x) - c.s.p.x, vfloatK(light.position.y) - c.s.p.y, vfloatK(light.position.z) - c.s.p.z};
    vfloatK dist = xsimd::sqrt(dot(d, d));
    vfloatK inv = vfloatK(1.0f) / dist;
    V3 wi{d.x * inv, d.y * inv, d.z * inv};
    push_light_sample(c, on && dist > vfloatK(0.0f), wi, dist * vfloatK(1.0f - kShadowRayShrink),
                      light_weight(beta_f, light.radiance, dot(c.s.ns, wi)), q);
  }
  for (const DirectionalLight& light : scene.directional_lights) {
    V3 wi{vfloatK(light.to_light.x), vfloatK(light.to_light.y), vfloatK(light.to_light.z)};
    push_light_sample(c, on, wi, vfloatK(kInfinity), light_weight(beta_f, light.radiance, dot(c.s.ns, wi)), q);
  }
  if (scene.sky)
    for (int j = 0; j < n; ++j, ++k) {
      c.ps.get2d(c.vertex, dims::light_dim(k), u1, u2);
      V3 wi = sample_sky_direction(u1, u2);
      vfloatK g = light_factor(dot(c.s.ns, wi), vfloatK(kInv2Pi), mis_count) * inv_n;
      push_light_sample(c, on, wi, vfloatK(kInfinity), light_weight(beta_f, scene.sky->radiance, g), q);
    }
}

/// Hemisphere (-H) or cosine-weighted sampling: rays that find emitters.
void sample_by_hitting(const WaveContext& ctx, const Chunk& c, vboolK on, ShadowQueue& q) {
  const RenderSettings& rs = ctx.settings;
  const uint32_t n = hemisphere_sample_count(ctx.scene, rs);
  const vfloatK scale(1.0f / static_cast<float>(n));
  const V3 beta_f = throughput_times_bsdf(c);
  const bool cosine = rs.direct == DirectLighting::kCosine;
  vfloatK u1, u2;
  for (uint32_t k = 0; k < n; ++k) {
    c.ps.get2d(c.vertex, dims::light_dim(k), u1, u2);
    V3 local = cosine ? sample_cosine_hemisphere(u1, u2) : sample_uniform_hemisphere(u1, u2);
    V3 wi = to_world(c.s.ns.x, c.s.ns.y, c.s.ns.z, local.x, local.y, local.z);
    vboolK ok = on && dot(c.s.ng, wi) > vfloatK(0.0f);
    vfloatK g = hit_sampling_weight(rs, local.z) * scale;
    V3 w{beta_f.x * g, beta_f.y * g, beta_f.z * g};
    push_shadow_lanes(lane_mask(ok), q, offset_origin(c.s.p, c.s.ng, c.s.offset, wi), wi, vfloatK(kInfinity), c.path, w);
  }
}

/// Cosine-weighted continuation; throughput *= albedo (f cos / pdf).
void sample_bsdf(const Chunk& c, PathState& paths, RayQueue& q) {
  vfloatK u1, u2;
  c.ps.get2d(c.vertex, dims::kBsdf, u1, u2);
  V3 local = sample_cosine_hemisphere(u1, u2);
  V3 wi = to_world(c.s.ns.x, c.s.ns.y, c.s.ns.z, local.x, local.y, local.z);
  vboolK ok = c.reflects && dot(wi, c.s.ng) > vfloatK(0.0f);
  uint32_t mask = lane_mask(ok);
  if (!mask) return;
  LaneFloats br(c.beta.x * c.albedo.x), bg(c.beta.y * c.albedo.y), bb(c.beta.z * c.albedo.z);
  LaneFloats pdf(local.z * vfloatK(kInvPi));
  LaneUints path(c.path);
  for_each_lane(mask, [&](size_t l) {
    paths.beta_r[path[l]] = br[l];
    paths.beta_g[path[l]] = bg[l];
    paths.beta_b[path[l]] = bb[l];
    paths.bsdf_pdf[path[l]] = pdf[l];
  });
  push_ray_lanes(mask, q, offset_origin(c.s.p, c.s.ng, c.s.offset, wi), wi, c.path);
}

}  // namespace

void shade_surfaces(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits,
                    PathState& paths, ShadeOutputs out) {
  const RenderSettings& rs = ctx.settings;
  const uint32_t vertex = depth + 1;
  const bool direct = rs.counts_bounce(static_cast<int>(vertex));
  const bool continues = static_cast<int>(vertex) < rs.max_depth;
  const bool samples_bsdf = continues || (static_cast<int>(vertex) == rs.max_depth && ctx.final_bounce);
  const bool escapes_count = depth == 0 || (rs.direct == DirectLighting::kMis && ctx.sky_visible &&
                                            static_cast<int>(depth) < rs.max_depth &&
                                            rs.counts_bounce(static_cast<int>(depth)));
  const size_t n = rays.size;
  out.shadows.reserve(n * ctx.shadow_rays_per_vertex);
  out.hemisphere.reserve(rs.direct_by_hitting() ? n * ctx.shadow_rays_per_vertex : 0);
  out.continuations.reserve(n);
  const MaterialArrays& mats = ctx.materials;

  if (n > 0) prefetch_surfaces(ctx, hits, 0, false);
  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    prefetch_surfaces(ctx, hits, i0 + 2 * kLanes, false);  // indices two chunks ahead,
    prefetch_surfaces(ctx, hits, i0 + kLanes, true);       // vertices one chunk ahead
    SurfaceBatch s = fetch_surfaces(ctx, rays, hits, i0);
    vboolK emits = s.hit && as_float_mask(gather(mats.emits.data(), s.material) != vintK(0));
    uint32_t emission_lanes = lane_mask(emits) | (escapes_count ? lane_mask(s.valid && !s.hit) : 0);
    if (emission_lanes) add_emission(ctx, depth, rays, hits, i0, emission_lanes, paths);
    if (!direct && !samples_bsdf) continue;

    vintK path = xsimd::select(as_int_mask(s.valid), as_index(vuintK::load_aligned(&rays.path[i0])), vintK(0));
    Chunk c{s,
            xsimd::bitwise_cast<vuintK>(path),
            SamplerK(rs, gather(paths.pixel.data(), path), gather(paths.sample.data(), path)),
            gather3(paths.beta_r, paths.beta_g, paths.beta_b, path),
            gather3(mats.albedo_r, mats.albedo_g, mats.albedo_b, s.material),
            vboolK(false),
            vertex};
    vfloatK zero(0.0f);
    c.reflects = s.hit && (c.albedo.x != zero || c.albedo.y != zero || c.albedo.z != zero);

    if (direct) {
      if (rs.direct_by_hitting()) sample_by_hitting(ctx, c, c.reflects, out.hemisphere);
      else sample_lights(ctx, c, c.reflects, rs.direct == DirectLighting::kMis && continues, out.shadows);
    }
    if (samples_bsdf) sample_bsdf(c, paths, out.continuations);
  }
}

void shade_normals(const WaveContext& ctx, const RayQueue& rays, const HitQueue& hits, PathState& paths) {
  for (size_t i = 0; i < rays.size; ++i) {
    if (hits.prim[i] == kInvalidId) continue;
    SurfacePoint sp = surface_at(ctx.scene, rays.ray(i), Hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]});
    float3 c = normal_shading_color(sp);
    paths.add_radiance(rays.path[i], c.x, c.y, c.z);
  }
}

}  // namespace pt::wf
