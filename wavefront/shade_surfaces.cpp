// shade_surfaces: per K-lane chunk, fetch surfaces, then emission, direct
// light and BSDF sampling as separate steps.
#include "shade_surfaces.h"

#include "fetch_surfaces.h"
#include "kernels/lights.h"
#include "kernels/random.h"
#include "kernels/sample_dimensions.h"
#include "kernels/sampling.h"
#include "kernels/shading.h"
#include "kernels/surface.h"
#include "lane_output.h"

namespace pt::wf {
namespace {

using V3 = Vec3T<vfloatK>;

/// What the steps of one chunk share.
struct Chunk {
  SurfaceBatch s;
  vuintK path, key;
  V3 beta, albedo;
  vboolK reflects;  ///< a surface with non-black albedo
  uint32_t vertex;
};

vfloatK uniform(vuintK key, uint32_t vertex, uint32_t dim) {
  return random_float<vuintK, vfloatK>(key, dimension_key(vertex, dim));
}

V3 gather_paths3(const AlignedVector<float>& r, const AlignedVector<float>& g, const AlignedVector<float>& b,
                 vuintK path) {
  vintK i = xsimd::bitwise_cast<vintK>(path);
  return {vfloatK::gather(r.data(), i), vfloatK::gather(g.data(), i), vfloatK::gather(b.data(), i)};
}

vfloatK dot(const V3& a, const V3& b) { return a.x * b.x + a.y * b.y + a.z * b.z; }

/// Emission the rays see (scalar: only lanes that hit emitters, and camera rays that escape).
void add_emission(const WaveContext& ctx, uint32_t depth, const RayQueue& rays, const HitQueue& hits, size_t i0,
                  uint64_t lanes, PathState& paths) {
  const RenderSettings& rs = ctx.settings;
  for_each_lane(lanes, [&](size_t lane) {
    size_t i = i0 + lane;
    uint32_t path = rays.path[i];
    Ray ray = rays.ray(i);
    float3 L;
    if (hits.prim[i] == kInvalidId) {
      if (depth == 0 && rs.counts_bounce(0) && ctx.sky_visible) L = sky_radiance(*ctx.scene.sky, ray.dir);
    } else {
      SurfacePoint sp = surface_at(ctx.scene, ray, Hit{hits.t[i], hits.u[i], hits.v[i], hits.prim[i]});
      if (depth == 0) {
        if (rs.counts_bounce(0)) L = emitted_radiance(ctx.scene, sp, ray, rs);
      } else if (emission_found_by_bounce(ctx.scene, sp, rs) && rs.counts_bounce(static_cast<int>(depth))) {
        float3 beta{paths.beta_r[path], paths.beta_g[path], paths.beta_b[path]};
        L = beta * emitted_radiance(ctx.scene, sp, ray, rs);
      }
    }
    if (!is_black(L)) paths.add_radiance(path, L.x, L.y, L.z);
  });
}

/// Pushes the shadow ray of one light sample per lane where it can contribute.
void push_light_sample(const Chunk& c, vboolK ok, const V3& wi, vfloatK tmax, const V3& weight, ShadowQueue& q) {
  ok = ok && dot(c.s.ns, wi) > vfloatK(0.0f) && dot(c.s.ng, wi) > vfloatK(0.0f);
  uint64_t mask = bitmask(ok);
  if (!mask) return;
  push_shadow_lanes(mask, q, offset_origin(c.s.p, c.s.ng, c.s.offset, wi), wi, tmax, c.path, weight);
}

V3 light_weight(const V3& beta_f, const float3& radiance, vfloatK factor) {
  return {beta_f.x * (vfloatK(radiance.x) * factor), beta_f.y * (vfloatK(radiance.y) * factor),
          beta_f.z * (vfloatK(radiance.z) * factor)};
}

void sample_lights(const WaveContext& ctx, const Chunk& c, vboolK on, ShadowQueue& q) {
  const Scene& scene = ctx.scene;
  const int n = ctx.settings.light_samples;
  const vfloatK inv_n(1.0f / static_cast<float>(n));
  const vfloatK inv_pi(kInvPi);
  V3 beta_f{c.beta.x * c.albedo.x * inv_pi, c.beta.y * c.albedo.y * inv_pi, c.beta.z * c.albedo.z * inv_pi};
  uint32_t k = 0;
  for (const AreaLight& light : scene.area_lights)
    for (int j = 0; j < n; ++j, ++k) {
      vfloatK u1 = uniform(c.key, c.vertex, dims::light_dim(k)), u2 = uniform(c.key, c.vertex, dims::light_dim(k) + 1);
      AreaLightSampleT<vfloatK> ls = sample_area_light<vfloatK>(light, c.s.p.x, c.s.p.y, c.s.p.z, u1, u2);
      vfloatK g = dot(c.s.ns, ls.wi) / ls.pdf * inv_n;
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
      vfloatK u1 = uniform(c.key, c.vertex, dims::light_dim(k)), u2 = uniform(c.key, c.vertex, dims::light_dim(k) + 1);
      V3 wi = sample_sky_direction(u1, u2);
      vfloatK g = dot(c.s.ns, wi) / vfloatK(kInv2Pi) * inv_n;
      push_light_sample(c, on, wi, vfloatK(kInfinity), light_weight(beta_f, scene.sky->radiance, g), q);
    }
}

void sample_hemisphere(const WaveContext& ctx, const Chunk& c, vboolK on, ShadowQueue& q) {
  const uint32_t n = hemisphere_sample_count(ctx.scene, ctx.settings);
  const vfloatK scale(1.0f / static_cast<float>(n));
  const vfloatK inv_pi(kInvPi);
  V3 beta_f{c.beta.x * c.albedo.x * inv_pi, c.beta.y * c.albedo.y * inv_pi, c.beta.z * c.albedo.z * inv_pi};
  for (uint32_t k = 0; k < n; ++k) {
    vfloatK u1 = uniform(c.key, c.vertex, dims::light_dim(k)), u2 = uniform(c.key, c.vertex, dims::light_dim(k) + 1);
    V3 local = sample_uniform_hemisphere(u1, u2);
    V3 wi = to_world(c.s.ns.x, c.s.ns.y, c.s.ns.z, local.x, local.y, local.z);
    vboolK ok = on && dot(c.s.ng, wi) > vfloatK(0.0f);
    vfloatK g = local.z / vfloatK(kInv2Pi) * scale;
    V3 w{beta_f.x * g, beta_f.y * g, beta_f.z * g};
    push_shadow_lanes(bitmask(ok), q, offset_origin(c.s.p, c.s.ng, c.s.offset, wi), wi, vfloatK(kInfinity), c.path, w);
  }
}

/// Cosine-weighted continuation; throughput *= albedo (f cos / pdf).
void sample_bsdf(const Chunk& c, PathState& paths, RayQueue& q) {
  V3 local = sample_cosine_hemisphere(uniform(c.key, c.vertex, dims::kBsdf), uniform(c.key, c.vertex, dims::kBsdf + 1));
  V3 wi = to_world(c.s.ns.x, c.s.ns.y, c.s.ns.z, local.x, local.y, local.z);
  vboolK ok = c.reflects && dot(wi, c.s.ng) > vfloatK(0.0f);
  uint64_t mask = bitmask(ok);
  if (!mask) return;
  LaneFloats br(c.beta.x * c.albedo.x), bg(c.beta.y * c.albedo.y), bb(c.beta.z * c.albedo.z);
  LaneUints path(c.path);
  for_each_lane(mask, [&](size_t l) {
    paths.beta_r[path[l]] = br[l];
    paths.beta_g[path[l]] = bg[l];
    paths.beta_b[path[l]] = bb[l];
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
  const size_t n = rays.size;
  out.shadows.reserve(n * ctx.shadow_rays_per_vertex);
  out.hemisphere.reserve(rs.direct == DirectLighting::kHemisphere ? n * ctx.shadow_rays_per_vertex : 0);
  out.continuations.reserve(n);
  const MaterialArrays& mats = ctx.materials;

  for (size_t i0 = 0; i0 < n; i0 += kLanes) {
    Chunk c;
    c.s = fetch_surfaces(ctx, rays, hits, i0);
    c.vertex = vertex;
    vboolK emits = c.s.hit && as_float_mask(vintK::gather(mats.emits.data(), c.s.material) != vintK(0));
    vboolK escaped = c.s.valid && !c.s.hit;
    uint64_t emission_lanes = bitmask(emits) | (depth == 0 ? bitmask(escaped) : 0);
    if (emission_lanes) add_emission(ctx, depth, rays, hits, i0, emission_lanes, paths);
    if (!direct && !continues) continue;

    vintK raw_path = xsimd::bitwise_cast<vintK>(vuintK::load_aligned(&rays.path[i0]));
    c.path = xsimd::bitwise_cast<vuintK>(xsimd::select(as_int_mask(c.s.valid), raw_path, vintK(0)));
    c.key = vuintK::gather(paths.key.data(), xsimd::bitwise_cast<vintK>(c.path));
    c.beta = gather_paths3(paths.beta_r, paths.beta_g, paths.beta_b, c.path);
    c.albedo = {vfloatK::gather(mats.albedo_r.data(), c.s.material), vfloatK::gather(mats.albedo_g.data(), c.s.material),
                vfloatK::gather(mats.albedo_b.data(), c.s.material)};
    vfloatK zero(0.0f);
    c.reflects = c.s.hit && (c.albedo.x != zero || c.albedo.y != zero || c.albedo.z != zero);

    if (direct) {
      if (rs.direct == DirectLighting::kHemisphere) sample_hemisphere(ctx, c, c.reflects, out.hemisphere);
      else sample_lights(ctx, c, c.reflects, out.shadows);
    }
    if (continues) sample_bsdf(c, paths, out.continuations);
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
