// The one-path loop, written once and templated on the tracer: the reference
// engine runs it through the midpoint BVH2 or brute force (reference/), the
// megakernel through the BVH4 (wavefront/megakernel_renderer.h). In the
// assignment's structure: zero-bounce emission, direct light at every vertex
// (light importance sampling, uniform or cosine hemisphere sampling, or MIS
// of lights and the BSDF), and indirect bounces with Russian roulette up to
// the maximum depth. The wavefront's staged, K-wide loop is separate, so the
// reference stays an independent arbiter of it: they share the path rules
// and per-sample math below, never queues, compaction, roulette bookkeeping
// or traversal.
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/render/render_settings.h"
#include "kernels/render/render_stats.h"
#include "kernels/scene/scene.h"
#include "kernels/transport/bounce_light.h"
#include "kernels/transport/direct_light.h"
#include "kernels/transport/path_rules.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"
#include "kernels/transport/surface_bsdf.h"

namespace pt {
inline namespace PT_ISA_NS {

/// One path at a time through any tracer with intersect(ray, hit, tests)
/// and occluded(ray, tests).
template <class Tracer>
class PathIntegrator {
 public:
  PathIntegrator(const Scene& scene, const RenderSettings& rs, const Tracer& tracer)
      : scene_(scene), rs_(rs), tracer_(tracer), rules_(scene, rs), sky_visible_(sky_is_visible(scene, rs)) {}

  /// Radiance along a camera ray, for the path whose numbers `ps` draws.
  float3 radiance(Ray ray, const PathSampler& ps, RenderStats& stats) const {
    Hit hit;
    ++stats.camera_rays;
    if (!tracer_.intersect(ray, hit, stats.intersection_tests))
      return rs_.shading != ShadingMode::kNormals && rules_.counts_escape(0, sky_visible_)
                 ? sky_radiance(scene_, ray.dir)
                 : float3{};
    SurfacePoint sp = surface_at(scene_, ray, hit);
    if (rs_.shading == ShadingMode::kNormals) return normal_shading_color(sp);
    float3 L, beta{1.0f};
    if (rules_.counts(0)) L += emitted_radiance(scene_, sp, ray, rs_);
    for (uint32_t vertex = 1;; ++vertex) {
      const Material& material = scene_.materials[sp.material];
      const SurfaceBsdf bsdf(material, sp, ray.dir, rs_);
      const ShadingPointT<float> point = shading_point(sp, bsdf.samples_lights());
      if (rules_.estimates_direct_light(vertex) && point.on) {
        if (bsdf.lambertian()) add_direct_light(point, ps, vertex, beta * material.albedo * kInvPi, nullptr, L, stats);
        else add_direct_light(point, ps, vertex, beta, &bsdf, L, stats);
      }
      if (!(bsdf.delta() ? rules_.traces_delta_ray(vertex) : rules_.traces_bsdf_ray(vertex))) break;
      const BsdfScatter bs = bsdf.sample(point, ps, vertex);
      if (!bs.ok) break;
      beta = beta * bs.weight;
      if (PathRules::roulette_applies(vertex)) {
        float p = continuation_probability(rs_, max_component(beta));
        if (ps.get1d(vertex, dims::kRoulette) >= p) break;
        beta = beta / p;
      }
      ray = Ray{to_float3(offset_origin(point.p, point.ng, point.offset, bs.wi)), 0.0f, to_float3(bs.wi), kInfinity};
      ++stats.bounce_rays;
      bool found = tracer_.intersect(ray, hit, stats.intersection_tests);
      if (found) sp = surface_at(scene_, ray, hit);
      L += beta * light_found_by_bounce(scene_, rs_, rules_, vertex, ray, found ? &hit : nullptr, found ? &sp : nullptr,
                                        bs.pdf, bs.delta);
      if (!found || !rules_.continues(vertex)) break;  // the final bounce only collects emission
    }
    return L;
  }

 private:
  /// Adds beta_f x the direct light of vertex `vertex` to L, tracing each
  /// sample's shadow (or probe) ray at once; each sample is also multiplied
  /// by the rough conductor's f where `glossy` is given.
  void add_direct_light(const ShadingPointT<float>& point, const PathSampler& ps, uint32_t vertex, float3 beta_f,
                        const SurfaceBsdf* glossy, float3& L, RenderStats& stats) const {
    auto f = [&](const Vec3T<float>& wi) { return glossy ? to_float3(glossy->eval(wi).f) : float3(1.0f); };
    if (rs_.direct_by_hitting()) {
      sample_hemisphere_rays(scene_, rs_, point, ps, vertex,
                             [&](bool ok, const Vec3T<float>& org, const Vec3T<float>& wi, float weight) {
                               if (!ok) return;
                               Ray ray{to_float3(org), 0.0f, to_float3(wi), kInfinity};
                               ++stats.shadow_rays;
                               Hit hit;
                               float3 incoming;
                               if (tracer_.intersect(ray, hit, stats.intersection_tests))
                                 incoming = emitted_radiance(scene_, surface_at(scene_, ray, hit), ray, rs_);
                               else if (sky_visible_) incoming = sky_radiance(scene_, ray.dir);
                               L += beta_f * incoming * weight * f(wi);
                             });
      return;
    }
    auto shadow = [&](bool ok, const Vec3T<float>& org, const Vec3T<float>& wi, float tmax,
                      const Vec3T<float>& weight) {
      if (!ok) return;
      ++stats.shadow_rays;
      if (!tracer_.occluded(Ray{to_float3(org), 0.0f, to_float3(wi), tmax}, stats.intersection_tests))
        L += beta_f * to_float3(weight) * f(wi);
    };
    if (glossy)
      sample_light_sources(
          scene_, rs_, point, ps, vertex, rules_.bsdf_competes(vertex),
          [&](const Vec3T<float>& wi, float) { return glossy->eval(wi).pdf; }, shadow);
    else sample_light_sources(scene_, rs_, point, ps, vertex, rules_.bsdf_competes(vertex), LambertianPdf{}, shadow);
  }

  const Scene& scene_;
  const RenderSettings& rs_;
  const Tracer& tracer_;
  PathRules rules_;
  bool sky_visible_;
};

}  // namespace PT_ISA_NS
}  // namespace pt
