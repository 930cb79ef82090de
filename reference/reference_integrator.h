// The reference path tracer for one camera sample, one ray at a time, in the
// assignment's structure: zero-bounce emission, direct lighting at every
// vertex (light importance sampling, uniform or cosine hemisphere sampling,
// or multiple importance sampling of lights and the BSDF), and indirect
// bounces with Russian roulette up to the maximum depth. The arbiter of the
// SIMD engines: it traces only through the midpoint BVH2 or brute force
// (SceneBvh2), and shares with them the scene model, the keyed random
// numbers, the path rules and the per-sample math of kernels/, never their
// queues, compaction, roulette bookkeeping or 4-wide traversal.
#pragma once

#include <cstdint>

#include "bvh/scene_bvh2.h"
#include "kernels/transport/bounce_light.h"
#include "kernels/transport/direct_light.h"
#include "kernels/transport/path_rules.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/render/render_settings.h"
#include "kernels/render/render_stats.h"
#include "kernels/scene/scene.h"
#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"
#include "kernels/transport/surface_bsdf.h"

namespace pt::reference {

class ReferenceIntegrator {
 public:
  ReferenceIntegrator(const Scene& scene, const SceneBvh2& accel, const RenderSettings& settings)
      : scene_(scene), accel_(accel), rs_(settings), rules_(scene, settings) {}

  /// Radiance along a camera ray, for the path whose numbers `ps` draws.
  float3 radiance(const Ray& camera_ray, const PathSampler& ps, RenderStats& stats) const {
    Ray ray = camera_ray;
    Hit hit;
    ++stats.camera_rays;
    if (!accel_.intersect(ray, hit, stats.intersection_tests))
      return rs_.shading == ShadingMode::kNormals || !rules_.counts_escape(0, sky_visible()) ? float3{} : sky(ray.dir);
    SurfacePoint sp = surface_at(scene_, ray, hit);
    if (rs_.shading == ShadingMode::kNormals) return normal_shading_color(sp);

    float3 L, beta{1.0f};
    if (rules_.counts(0)) L += emitted_radiance(scene_, sp, ray, rs_);
    for (uint32_t vertex = 1;; ++vertex) {
      const Material& material = scene_.materials[sp.material];
      const SurfaceBsdf bsdf(material, sp, ray.dir, rs_);
      const ShadingPointT<float> point = shading_point(sp, bsdf.samples_lights());
      if (rules_.estimates_direct_light(vertex) && point.on) {
        if (bsdf.lambertian()) L += beta * material.albedo * kInvPi * direct_light(point, ps, vertex, stats, nullptr);
        else L += beta * direct_light(point, ps, vertex, stats, &bsdf);
      }
      if (!(bsdf.delta() ? rules_.traces_delta_ray(vertex) : rules_.traces_bsdf_ray(vertex))) break;

      // Continue: the BSDF's sample (f cos / pdf = weight), then Russian roulette.
      const BsdfScatter bs = bsdf.sample(point, ps, vertex);
      if (!bs.ok) break;
      beta = beta * bs.weight;
      if (PathRules::roulette_applies(vertex)) {
        float p = continuation_probability(rs_, max_component(beta));
        if (ps.get1d(vertex, dims::kRoulette) >= p) break;
        beta = beta / p;
      }
      const float3 wi{bs.wi.x, bs.wi.y, bs.wi.z};
      ray = Ray{offset_origin(sp, wi), 0.0f, wi, kInfinity};
      ++stats.bounce_rays;
      bool found = accel_.intersect(ray, hit, stats.intersection_tests);
      if (found) sp = surface_at(scene_, ray, hit);
      L += beta * light_found_by_bounce(scene_, rs_, rules_, vertex, ray, found ? &hit : nullptr, found ? &sp : nullptr,
                                        bs.pdf, bs.delta);
      if (!found || !rules_.continues(vertex)) break;  // the final bounce only collects emission
    }
    return L;
  }

 private:
  bool sky_visible() const { return sky_is_visible(scene_, rs_); }
  float3 sky(const float3& dir) const { return sky_visible() ? sky_radiance(scene_, dir) : float3{}; }

  /// Direct light at vertex `vertex` from its light samples, each shadow or
  /// probe ray traced at once: the incident radiance (cos / pdf weighted)
  /// before the Lambertian BSDF when `glossy` is null, else times the rough
  /// conductor's f.
  float3 direct_light(const ShadingPointT<float>& point, const PathSampler& ps, uint32_t vertex, RenderStats& stats,
                      const SurfaceBsdf* glossy) const {
    float3 sum;
    auto f = [&](const Vec3T<float>& wi) { return glossy ? to_float3(glossy->eval(wi).f) : float3(1.0f); };
    if (rs_.direct_by_hitting()) {
      sample_hemisphere_rays(scene_, rs_, point, ps, vertex,
                             [&](bool ok, const Vec3T<float>& org, const Vec3T<float>& wi, float weight) {
                               if (!ok) return;
                               Ray ray{to_float3(org), 0.0f, to_float3(wi), kInfinity};
                               ++stats.shadow_rays;
                               Hit hit;
                               float3 incoming = accel_.intersect(ray, hit, stats.intersection_tests)
                                                     ? emitted_radiance(scene_, surface_at(scene_, ray, hit), ray, rs_)
                                                     : sky(ray.dir);
                               if (!is_black(incoming)) sum += incoming * weight * f(wi);
                             });
      return sum;
    }
    auto shadow = [&](bool ok, const Vec3T<float>& org, const Vec3T<float>& wi, float tmax,
                      const Vec3T<float>& weight) {
      if (!ok) return;
      ++stats.shadow_rays;
      if (!accel_.occluded(Ray{to_float3(org), 0.0f, to_float3(wi), tmax}, stats.intersection_tests))
        sum += to_float3(weight) * f(wi);
    };
    if (glossy)
      sample_light_sources(
          scene_, rs_, point, ps, vertex, rules_.bsdf_competes(vertex),
          [&](const Vec3T<float>& wi, float) { return glossy->eval(wi).pdf; }, shadow);
    else sample_light_sources(scene_, rs_, point, ps, vertex, rules_.bsdf_competes(vertex), LambertianPdf{}, shadow);
    return sum;
  }

  const Scene& scene_;
  const SceneBvh2& accel_;
  const RenderSettings& rs_;
  PathRules rules_;
};

}  // namespace pt::reference
