// The reference path tracer for one camera sample, written one ray at a time
// in the assignment's structure: zero-bounce emission, direct lighting at every
// vertex (light importance sampling, uniform or cosine hemisphere sampling, or
// multiple importance sampling of lights and the BSDF), and indirect bounces
// with Russian roulette up to the maximum depth. The arbiter for the other
// engines; `Accel` answers intersect(ray, hit, tests) and occluded(ray, tests).
#pragma once

#include <cstdint>

#include "kernels/frame.h"
#include "kernels/path_sampler.h"
#include "kernels/render_settings.h"
#include "kernels/render_stats.h"
#include "kernels/sample_dimensions.h"
#include "kernels/sampling.h"
#include "kernels/scene.h"
#include "kernels/shading.h"
#include "kernels/surface.h"
#include "reference_accel.h"

namespace pt::reference {

template <class Accel = ReferenceAccel>
class ReferenceIntegrator {
 public:
  ReferenceIntegrator(const Scene& scene, const Accel& accel, const RenderSettings& settings)
      : scene_(scene), accel_(accel), rs_(settings) {}

  /// Radiance along a camera ray, for the path whose numbers `ps` draws.
  float3 radiance(const Ray& camera_ray, const PathSampler& ps, RenderStats& stats) const;

 private:
  /// Direct light reflected at path vertex `vertex`. `bsdf_competes`: the
  /// path's next BSDF sample also looks for the lights (MIS).
  float3 direct_light(const SurfacePoint& sp, const PathSampler& ps, uint32_t vertex, bool bsdf_competes,
                      RenderStats& stats) const;
  float3 light_sampling(const SurfacePoint& sp, const PathSampler& ps, uint32_t vertex, bool bsdf_competes,
                        RenderStats& stats) const;
  float3 hit_sampling(const SurfacePoint& sp, const PathSampler& ps, uint32_t vertex, RenderStats& stats) const;
  /// Incident radiance of one light sample if its shadow ray is clear,
  /// weighted by cos / pdf (and the MIS weight); black otherwise.
  float3 shadowed(const SurfacePoint& sp, const LightSample& ls, float mis_count, RenderStats& stats) const;
  float3 sky(const float3& dir) const;

  const Scene& scene_;
  const Accel& accel_;
  const RenderSettings& rs_;
};

template <class Accel>
float3 ReferenceIntegrator<Accel>::sky(const float3& dir) const {
  if (!scene_.sky || rs_.cs184_invisible_sky) return {};
  return sky_radiance(*scene_.sky, dir);
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::shadowed(const SurfacePoint& sp, const LightSample& ls, float mis_count,
                                            RenderStats& stats) const {
  if (is_black(ls.radiance)) return {};
  float cos_surface = dot(sp.ns, ls.wi);
  if (cos_surface <= 0.0f || dot(sp.ng, ls.wi) <= 0.0f) return {};
  Ray shadow{offset_origin(sp, ls.wi), 0.0f, ls.wi, shadow_ray_tmax(ls.dist)};
  ++stats.shadow_rays;
  if (accel_.occluded(shadow, stats.intersection_tests)) return {};
  float weight = mis_count > 0.0f ? power_heuristic(mis_count * ls.pdf, cos_surface * kInvPi) : 1.0f;
  return ls.radiance * (cos_surface / ls.pdf * weight);
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::light_sampling(const SurfacePoint& sp, const PathSampler& ps, uint32_t vertex,
                                                  bool bsdf_competes, RenderStats& stats) const {
  float3 sum;
  uint32_t k = 0;  // random light-sample index, see sample_dimensions.h
  const float n = static_cast<float>(rs_.light_samples), inv_n = 1.0f / n;
  const float mis_count = bsdf_competes ? n : 0.0f;  // delta lights never compete
  float u1, u2;
  for (const AreaLight& light : scene_.area_lights) {
    float3 l;
    for (int j = 0; j < rs_.light_samples; ++j, ++k) {
      ps.get2d(vertex, dims::light_dim(k), u1, u2);
      l += shadowed(sp, sample_area_light(light, sp.p, u1, u2), mis_count, stats);
    }
    sum += l * inv_n;
  }
  for (const PointLight& light : scene_.point_lights) sum += shadowed(sp, sample_point_light(light, sp.p), 0, stats);
  for (const DirectionalLight& light : scene_.directional_lights)
    sum += shadowed(sp, sample_directional_light(light), 0, stats);
  if (scene_.sky) {
    float3 l;
    for (int j = 0; j < rs_.light_samples; ++j, ++k) {
      ps.get2d(vertex, dims::light_dim(k), u1, u2);
      l += shadowed(sp, sample_sky_light(*scene_.sky, u1, u2), mis_count, stats);
    }
    sum += l * inv_n;
  }
  return sum;
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::hit_sampling(const SurfacePoint& sp, const PathSampler& ps, uint32_t vertex,
                                                RenderStats& stats) const {
  uint32_t n = hemisphere_sample_count(scene_, rs_);
  float3 sum;
  float u1, u2;
  for (uint32_t k = 0; k < n; ++k) {
    ps.get2d(vertex, dims::light_dim(k), u1, u2);
    float3 local = to_float3(rs_.direct == DirectLighting::kCosine ? sample_cosine_hemisphere(u1, u2)
                                                                   : sample_uniform_hemisphere(u1, u2));
    float3 wi = to_world(sp.ns, local);
    if (dot(wi, sp.ng) <= 0.0f) continue;
    Ray ray{offset_origin(sp, wi), 0.0f, wi, kInfinity};
    ++stats.shadow_rays;
    Hit hit;
    float3 incoming;
    if (accel_.intersect(ray, hit, stats.intersection_tests))
      incoming = emitted_radiance(scene_, surface_at(scene_, ray, hit), ray, rs_);
    else
      incoming = sky(wi);
    sum += incoming * hit_sampling_weight(rs_, local.z);
  }
  return sum / static_cast<float>(n);
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::direct_light(const SurfacePoint& sp, const PathSampler& ps, uint32_t vertex,
                                                bool bsdf_competes, RenderStats& stats) const {
  const float3 f = scene_.materials[sp.material].albedo * kInvPi;
  if (is_black(f)) return {};
  float3 li = rs_.direct_by_hitting() ? hit_sampling(sp, ps, vertex, stats)
                                      : light_sampling(sp, ps, vertex, bsdf_competes, stats);
  return f * li;
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::radiance(const Ray& camera_ray, const PathSampler& ps, RenderStats& stats) const {
  Ray ray = camera_ray;
  Hit hit;
  ++stats.camera_rays;
  if (!accel_.intersect(ray, hit, stats.intersection_tests))
    return rs_.shading == ShadingMode::kNormals || !rs_.counts_bounce(0) ? float3{} : sky(ray.dir);
  SurfacePoint sp = surface_at(scene_, ray, hit);
  if (rs_.shading == ShadingMode::kNormals) return normal_shading_color(sp);

  const bool mis = rs_.direct == DirectLighting::kMis;
  const bool final_bounce = traces_final_bounce(scene_, rs_);
  float3 L;
  float3 beta{1.0f};
  if (rs_.counts_bounce(0)) L += emitted_radiance(scene_, sp, ray, rs_);
  for (uint32_t vertex = 1;; ++vertex) {
    const bool continues = static_cast<int>(vertex) < rs_.max_depth;
    const bool last = static_cast<int>(vertex) == rs_.max_depth;
    if (rs_.counts_bounce(static_cast<int>(vertex)))
      L += beta * direct_light(sp, ps, vertex, mis && continues, stats);
    if (!continues && !(last && final_bounce)) break;

    // Continue: a cosine-weighted bounce (f cos / pdf = albedo), then Russian
    // roulette from the second indirect bounce on.
    const float3 albedo = scene_.materials[sp.material].albedo;
    if (is_black(albedo)) break;
    float u1, u2;
    ps.get2d(vertex, dims::kBsdf, u1, u2);
    float3 local = to_float3(sample_cosine_hemisphere(u1, u2));
    float3 wi = to_world(sp.ns, local);
    if (dot(wi, sp.ng) <= 0.0f) break;
    beta = beta * albedo;
    if (vertex >= 2) {
      float p = continuation_probability(rs_, max_component(beta));
      if (ps.get1d(vertex, dims::kRoulette) >= p) break;
      beta = beta / p;
    }
    const float bsdf_pdf = local.z * kInvPi;
    ray = Ray{offset_origin(sp, wi), 0.0f, wi, kInfinity};
    ++stats.bounce_rays;
    bool found = accel_.intersect(ray, hit, stats.intersection_tests);
    if (mis && continues && rs_.counts_bounce(static_cast<int>(vertex)))
      L += beta * mis_light_found_by_bsdf(scene_, rs_, ray, found ? &hit : nullptr, bsdf_pdf);
    if (!found) break;
    sp = surface_at(scene_, ray, hit);
    if (emission_found_by_bounce(scene_, sp, rs_) && rs_.counts_bounce(static_cast<int>(vertex)))
      L += beta * emitted_radiance(scene_, sp, ray, rs_);
    if (!continues) break;  // the final bounce only collects emission
  }
  return L;
}

}  // namespace pt::reference
