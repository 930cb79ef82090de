// Small shading rules every engine shares (wavefront, megakernel, reference),
// so that they make the same choice:
// how far a shadow ray may go, how many rays the hemisphere estimator casts,
// which emission a bounce ray may count, and the normal-shading colour.
#pragma once

#include <algorithm>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"
#include "kernels/scene/lights.h"
#include "kernels/math/sampling.h"
#include "kernels/transport/surface.h"

namespace pt {
inline namespace PT_ISA_NS {

/// Whether rays that escape the scene see its sky: always an environment map
/// (the course renderer shows it), the file's sky unless --cs184-compat hides
/// it as the course does.
inline bool sky_is_visible(const Scene& s, const RenderSettings& rs) {
  return s.sky && (s.environment || !rs.cs184_invisible_sky);
}

/// Shadow rays stop this fraction short of the light sample, so the light's
/// own surface never occludes it (relative, hence independent of scale).
inline constexpr float kShadowRayShrink = 0x1p-13f;

inline float shadow_ray_tmax(float dist) { return dist * (1.0f - kShadowRayShrink); }

/// Rays the hemisphere estimator casts per shading point: the assignment's
/// (number of lights) x (samples per area light), at least one.
inline uint32_t hemisphere_sample_count(const Scene& s, const RenderSettings& rs) {
  return static_cast<uint32_t>(std::max<size_t>(1, s.light_count() * static_cast<size_t>(rs.light_samples)));
}

/// Whether a bounce ray that reaches `sp` adds its emission at full weight.
/// With light sampling, sampled lights were counted by their shadow rays;
/// emitters that no light sampler knows (emissive meshes) are counted here.
/// With hemisphere sampling the estimator at the previous vertex already
/// counted everything. (MIS weights sampled lights separately.)
inline bool emission_found_by_bounce(const Scene& s, const SurfacePoint& sp, const RenderSettings& rs) {
  if (rs.direct_by_hitting()) return false;
  const Material& m = s.materials[sp.material];
  return m.is_emitter() && m.area_light < 0;
}

/// Whether the path traces one more BSDF ray from its last vertex (vertex ==
/// max depth) only to collect emission that no light sampler covers: light
/// from emissive meshes (not area lights) arriving after exactly max-depth
/// bounces is found no other way. The hit-based estimators found it already.
inline bool traces_final_bounce(const Scene& s, const RenderSettings& rs) {
  if (rs.direct_by_hitting() || rs.max_depth < 1) return false;
  for (const Material& m : s.materials)
    if (m.is_emitter() && m.area_light < 0) return true;
  return false;
}

/// cos / pdf of a direction found by the hit-based direct estimators: uniform
/// hemisphere (pdf 1 / 2 pi) or cosine-weighted (pdf cos / pi).
template <class T>
inline T hit_sampling_weight(const RenderSettings& rs, T cos_theta) {
  return rs.direct == DirectLighting::kCosine ? T(kPi) : cos_theta / T(kInv2Pi);
}

/// Power heuristic weight of a strategy with (count x pdf) `a` against `b`.
template <class T>
inline T power_heuristic(T a, T b) {
  T a2 = a * a, b2 = b * b;
  return lane::select(a2 > T(0.0f), a2 / (a2 + b2), T(0.0f));
}

/// Russian roulette's continuation probability for a path of throughput beta.
template <class T>
inline T continuation_probability(const RenderSettings& rs, T beta_max) {
  return rs.roulette == RouletteMode::kThroughput ? lane::min(T(1.0f), beta_max) : T(rs.rr_continue);
}

/// Light that a BSDF-sampled ray (unit direction, pdf `bsdf_pdf`) finds under
/// MIS: an area light's emitting side or the sky (hit == nullptr: escaped),
/// times the power-heuristic weight against `light_samples` light samples.
/// Black for everything else.
inline float3 mis_light_found_by_bsdf(const Scene& s, const RenderSettings& rs, const Ray& ray, const Hit* hit,
                                      float bsdf_pdf) {
  const float n = static_cast<float>(rs.light_samples);
  if (!hit) {
    if (!sky_is_visible(s, rs)) return {};
    float3 L = sky_radiance(s, ray.dir);
    return is_black(L) ? L : L * power_heuristic(bsdf_pdf, n * sky_pdf(s, ray.dir));
  }
  SurfacePoint sp = surface_at(s, ray, *hit);
  const Material& m = s.materials[sp.material];
  if (m.area_light < 0) return {};
  float3 L = emitted_radiance(s, sp, ray, rs);
  if (is_black(L)) return L;
  return L * power_heuristic(bsdf_pdf,
                             n * area_light_pdf(s.area_lights[m.area_light], ray.dir, hit->t, rs.cs184_light_pdf));
}

/// Light that a ray leaving a delta lobe (mirror, glass, refraction) finds,
/// at full weight: no light sample was taken at its vertex, so whatever it
/// reaches counts, the emission of the surface `sp` it hits (any emitter), or
/// the sky where it escapes (sp == nullptr).
inline float3 light_found_after_delta(const Scene& s, const RenderSettings& rs, const Ray& ray,
                                      const SurfacePoint* sp) {
  if (!sp) return sky_is_visible(s, rs) ? sky_radiance(s, ray.dir) : float3{};
  return emitted_radiance(s, *sp, ray, rs);
}

/// The assignment's normal shading: n * 0.5 + 0.5 of the stored shading normal.
inline float3 normal_shading_color(const SurfacePoint& sp) { return sp.raw_ns * 0.5f + float3(0.5f); }

}  // namespace PT_ISA_NS
}  // namespace pt
