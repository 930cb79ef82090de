// The reference path tracer for one camera sample, written one ray at a time
// in the assignment's structure: zero-bounce emission, direct lighting by light
// importance sampling or uniform hemisphere sampling, and indirect bounces with
// Russian roulette up to the maximum depth. The arbiter for the other engines.
#pragma once

#include <cstdint>

#include "kernels/render_settings.h"
#include "kernels/render_stats.h"
#include "kernels/scene.h"
#include "kernels/surface.h"
#include "kernels/frame.h"
#include "kernels/random.h"
#include "kernels/sample_dimensions.h"
#include "kernels/sampling.h"
#include "kernels/shading.h"
#include "reference_accel.h"

namespace pt::reference {

/// `Accel` answers intersect(ray, hit, tests) and occluded(ray, tests): the
/// reference's own ReferenceAccel, or (for the megakernel engine) the BVH4.
template <class Accel = ReferenceAccel>
class ReferenceIntegrator {
 public:
  ReferenceIntegrator(const Scene& scene, const Accel& accel, const RenderSettings& settings)
      : scene_(scene), accel_(accel), rs_(settings) {}

  /// Radiance along a camera ray for the path keyed by `path_key`.
  float3 radiance(const Ray& camera_ray, uint32_t path_key, RenderStats& stats) const;

  /// Direct light reflected at `sp` towards -wo_dir, for the path at `vertex`.
  float3 direct_light(const SurfacePoint& sp, uint32_t path_key, uint32_t vertex, RenderStats& stats) const;

 private:
  float3 light_sampling(const SurfacePoint& sp, uint32_t key, uint32_t vertex, RenderStats& stats) const;
  float3 hemisphere_sampling(const SurfacePoint& sp, uint32_t key, uint32_t vertex, RenderStats& stats) const;
  /// Incident radiance from one light sample if its shadow ray is clear,
  /// weighted by cos / pdf; black otherwise.
  float3 shadowed(const SurfacePoint& sp, const LightSample& ls, RenderStats& stats) const;
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
float3 ReferenceIntegrator<Accel>::shadowed(const SurfacePoint& sp, const LightSample& ls, RenderStats& stats) const {
  if (is_black(ls.radiance)) return {};
  float cos_surface = dot(sp.ns, ls.wi);
  if (cos_surface <= 0.0f || dot(sp.ng, ls.wi) <= 0.0f) return {};
  Ray shadow{offset_origin(sp, ls.wi), 0.0f, ls.wi, shadow_ray_tmax(ls.dist)};
  ++stats.shadow_rays;
  if (accel_.occluded(shadow, stats.intersection_tests)) return {};
  return ls.radiance * (cos_surface / ls.pdf);
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::light_sampling(const SurfacePoint& sp, uint32_t key, uint32_t vertex,
                                           RenderStats& stats) const {
  float3 sum;
  uint32_t k = 0;  // random light-sample index, see sample_dimensions.h
  auto uniform = [&](uint32_t dim) { return random_uniform(key, vertex, dim); };
  const float inv_n = 1.0f / static_cast<float>(rs_.light_samples);
  for (const AreaLight& light : scene_.area_lights) {
    float3 l;
    for (int j = 0; j < rs_.light_samples; ++j, ++k)
      l += shadowed(sp, sample_area_light(light, sp.p, uniform(dims::light_dim(k)), uniform(dims::light_dim(k) + 1)),
                    stats);
    sum += l * inv_n;
  }
  for (const PointLight& light : scene_.point_lights) sum += shadowed(sp, sample_point_light(light, sp.p), stats);
  for (const DirectionalLight& light : scene_.directional_lights)
    sum += shadowed(sp, sample_directional_light(light), stats);
  if (scene_.sky) {
    float3 l;
    for (int j = 0; j < rs_.light_samples; ++j, ++k)
      l += shadowed(sp, sample_sky_light(*scene_.sky, uniform(dims::light_dim(k)), uniform(dims::light_dim(k) + 1)),
                    stats);
    sum += l * inv_n;
  }
  return sum;
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::hemisphere_sampling(const SurfacePoint& sp, uint32_t key, uint32_t vertex,
                                                RenderStats& stats) const {
  uint32_t n = hemisphere_sample_count(scene_, rs_);
  float3 sum;
  for (uint32_t k = 0; k < n; ++k) {
    float3 local = to_float3(sample_uniform_hemisphere(random_uniform(key, vertex, dims::light_dim(k)),
                                                       random_uniform(key, vertex, dims::light_dim(k) + 1)));
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
    sum += incoming * (local.z / kInv2Pi);
  }
  return sum / static_cast<float>(n);
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::direct_light(const SurfacePoint& sp, uint32_t key, uint32_t vertex,
                                         RenderStats& stats) const {
  const float3 f = scene_.materials[sp.material].albedo * kInvPi;
  if (is_black(f)) return {};
  float3 li = rs_.direct == DirectLighting::kHemisphere ? hemisphere_sampling(sp, key, vertex, stats)
                                                        : light_sampling(sp, key, vertex, stats);
  return f * li;
}

template <class Accel>
float3 ReferenceIntegrator<Accel>::radiance(const Ray& camera_ray, uint32_t key, RenderStats& stats) const {
  Ray ray = camera_ray;
  Hit hit;
  ++stats.camera_rays;
  if (!accel_.intersect(ray, hit, stats.intersection_tests))
    return rs_.shading == ShadingMode::kNormals || !rs_.counts_bounce(0) ? float3{} : sky(ray.dir);
  SurfacePoint sp = surface_at(scene_, ray, hit);
  if (rs_.shading == ShadingMode::kNormals) return normal_shading_color(sp);

  float3 L;
  float3 beta{1.0f};
  if (rs_.counts_bounce(0)) L += emitted_radiance(scene_, sp, ray, rs_);
  for (uint32_t vertex = 1;; ++vertex) {
    if (rs_.counts_bounce(static_cast<int>(vertex))) L += beta * direct_light(sp, key, vertex, stats);
    if (static_cast<int>(vertex) >= rs_.max_depth) break;

    // Continue the path: Russian roulette after the first indirect bounce,
    // then a cosine-weighted bounce (f cos / pdf = albedo).
    const bool roulette = vertex >= 2;
    if (roulette && random_uniform(key, vertex, dims::kRoulette) >= rs_.rr_continue) break;
    const float3 albedo = scene_.materials[sp.material].albedo;
    if (is_black(albedo)) break;
    float3 local = to_float3(sample_cosine_hemisphere(random_uniform(key, vertex, dims::kBsdf),
                                                      random_uniform(key, vertex, dims::kBsdf + 1)));
    float3 wi = to_world(sp.ns, local);
    if (dot(wi, sp.ng) <= 0.0f) break;
    beta = beta * albedo;
    if (roulette) beta = beta / rs_.rr_continue;
    ray = Ray{offset_origin(sp, wi), 0.0f, wi, kInfinity};
    ++stats.bounce_rays;
    if (!accel_.intersect(ray, hit, stats.intersection_tests)) break;  // the sky was counted as direct light
    sp = surface_at(scene_, ray, hit);
    if (emission_found_by_bounce(scene_, sp, rs_) && rs_.counts_bounce(static_cast<int>(vertex)))
      L += beta * emitted_radiance(scene_, sp, ray, rs_);
  }
  return L;
}


}  // namespace pt::reference
