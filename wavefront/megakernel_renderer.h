// The megakernel engine: each path traced start to finish, one at a time, over
// the same tracer, pass schedule, threads and accumulators as the wavefront,
// by the same path rules and per-sample math (kernels/transport/path_rules.h,
// kernels/transport/direct_light.h) taken one lane wide. It exists to measure what the
// wavefront's queues and SIMD stages buy. Compiled per instruction-set level;
// engines.h is the entry point.
#pragma once

#include <chrono>

#include "kernels/transport/bounce_light.h"
#include "kernels/transport/camera_sample.h"
#include "kernels/transport/direct_light.h"
#include "kernels/transport/path_rules.h"
#include "kernels/transport/surface_bsdf.h"
#include "kernels/render/render_job.h"
#include "pass_driver.h"

namespace pt::wf {

/// One path of the megakernel.
template <class Tracer>
class MegakernelPath {
 public:
  MegakernelPath(const Scene& scene, const RenderSettings& rs, const Tracer& tracer)
      : scene_(scene), rs_(rs), tracer_(tracer), rules_(scene, rs), sky_visible_(sky_is_visible(scene, rs)) {}

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

template <class Tracer>
RenderOutput render_megakernel(const Scene& scene, const Camera& camera, const RenderSettings& rs, const Tracer& tracer,
                               const RenderControl& control = {}) {
  auto start = std::chrono::steady_clock::now();
  const MegakernelPath<Tracer> path(scene, rs, tracer);
  Accumulation acc = initial_accumulation(rs, control);
  RenderOutput out;
  auto chunk = [&](std::span<const uint32_t> pixels, uint32_t first, uint32_t len, Accumulation& px,
                   RenderStats& stats) {
    for (uint32_t pixel : pixels) {
      int x = static_cast<int>(pixel % static_cast<uint32_t>(rs.width));
      int y = static_cast<int>(pixel / static_cast<uint32_t>(rs.width));
      for (uint32_t s = first; s < first + len; ++s) {
        PathSampler ps(rs, pixel, s);
        if (!px.at(pixel).add(path.radiance(jittered_camera_ray(camera, rs, x, y, ps), ps, stats)))
          ++stats.invalid_samples;
      }
      stats.samples += len;
    }
  };
  run_passes(rs, 4096, control, acc, out.stats, chunk);
  out.film = film_from(acc, rs, control);
  out.cancelled = control.cancelled();
  out.stats.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return out;
}

}  // namespace pt::wf
