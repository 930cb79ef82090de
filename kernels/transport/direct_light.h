// Direct light at a shading point, for one path (T = float) or K paths at once
// (T = a SIMD batch), written once for every engine: light importance
// sampling (each area light and the sky -l times, each delta light once; the
// power heuristic against the BSDF sample where it competes) and the hit-based
// estimators (uniform or cosine hemisphere sampling, -H). Each sample is handed
// to a callback as a ray to trace and the radiance it carries if it gets
// through; the engines trace it at once (reference, megakernel) or queue it
// (wavefront). Random dimensions: sample_dimensions.h.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/scene/lights.h"
#include "kernels/transport/path_sampler.h"
#include "kernels/transport/sample_dimensions.h"
#include "kernels/math/sampling.h"
#include "kernels/scene/scene.h"
#include "kernels/simd/simd.h"
#include "kernels/transport/shading.h"
#include "kernels/transport/surface.h"

namespace pt {
inline namespace PT_ISA_NS {

/// What direct lighting needs of a shading point (a lane's, or one path's).
template <class T>
struct ShadingPointT {
  Vec3T<T> p, ng, ns;  ///< position, geometric and shading normals facing the incoming ray
  T offset;            ///< origin offset along ng (surface.h)
  lane::mask_t<T> on;  ///< lanes that shade (hit a reflecting surface)
};

/// cos / pdf of a light sample, times the power-heuristic weight against the
/// BSDF sample (pdf `bsdf_pdf`) when `mis_count` (the light's sample count) is
/// positive.
template <class T>
inline T light_sample_factor(T cos_s, T pdf, T mis_count, T bsdf_pdf) {
  T g = cos_s / pdf;
  return g * lane::select(mis_count > T(0.0f), power_heuristic(mis_count * pdf, bsdf_pdf), T(1.0f));
}

/// The Lambertian BSDF's pdf of a direction at cosine cos_s (cos / pi), as
/// sample_light_sources' `bsdf_pdf` argument.
struct LambertianPdf {
  template <class T>
  T operator()(const Vec3T<T>&, T cos_s) const {
    return cos_s * T(kInvPi);
  }
};

/// An environment-map sample per lane (scalar lookups: the map's CDFs are
/// searched lane by lane); `ok` is false where the pdf is 0.
template <class T>
struct EnvironmentSampleT {
  Vec3T<T> wi, radiance;
  T pdf;
  lane::mask_t<T> ok;
};

template <class T>
inline EnvironmentSampleT<T> sample_environment(const EnvironmentMap& env, T u1, T u2) {
  if constexpr (lane::is_scalar_v<T>) {
    EnvironmentMap::Sample s = env.sample(u1, u2);
    bool ok = s.pdf > 0.0f;
    return {vec3t(s.wi), vec3t(s.radiance), ok ? s.pdf : 1.0f, ok};
  } else {
    constexpr size_t K = T::size;
    alignas(64) float a[K], b[K], out[7][K];
    u1.store_aligned(a);
    u2.store_aligned(b);
    for (size_t l = 0; l < K; ++l) {
      EnvironmentMap::Sample s = env.sample(a[l], b[l]);
      const float v[7] = {s.wi.x, s.wi.y, s.wi.z, s.radiance.x, s.radiance.y, s.radiance.z, s.pdf};
      for (int c = 0; c < 7; ++c) out[c][l] = v[c];
    }
    auto ld = [&](int c) { return T::load_aligned(out[c]); };
    T pdf = ld(6);
    auto ok = pdf > T(0.0f);
    return {{ld(0), ld(1), ld(2)}, {ld(3), ld(4), ld(5)}, lane::select(ok, pdf, T(1.0f)), ok};
  }
}

/// A delta light's sample: unit direction, distance (kInfinity for
/// directional lights) and the lanes where it can arrive.
template <class T>
struct DeltaLightSampleT {
  Vec3T<T> wi;
  T dist;
  lane::mask_t<T> ok;
};

template <class T>
inline DeltaLightSampleT<T> sample_point_light(const PointLight& l, const Vec3T<T>& p) {
  Vec3T<T> d{T(l.position.x) - p.x, T(l.position.y) - p.y, T(l.position.z) - p.z};
  T dist = lane::sqrt(dot3(d, d));
  T inv = T(1.0f) / dist;
  return {{d.x * inv, d.y * inv, d.z * inv}, dist, dist > T(0.0f)};
}

/// Cycles' soft point light: a point uniform on the disk of the light's radius
/// centred at its position and facing p, taken as the light's position for
/// that sample (Cycles weighs it as I / dist^2, its cosine taken as 1).
template <class T>
inline DeltaLightSampleT<T> sample_soft_point_light(const PointLight& l, const Vec3T<T>& p, T u1, T u2) {
  Vec3T<T> n{p.x - T(l.position.x), p.y - T(l.position.y), p.z - T(l.position.z)};
  T inv_len = T(1.0f) / lane::sqrt(dot3(n, n));
  T r = T(l.radius) * lane::sqrt(u1), s, c;
  lane::sincos_2pi(u2, s, c);
  Vec3T<T> o = to_world(n.x * inv_len, n.y * inv_len, n.z * inv_len, r * c, r * s, T(0.0f));
  Vec3T<T> d{T(l.position.x) + o.x - p.x, T(l.position.y) + o.y - p.y, T(l.position.z) + o.z - p.z};
  T dist = lane::sqrt(dot3(d, d));
  T inv = T(1.0f) / dist;
  return {{d.x * inv, d.y * inv, d.z * inv}, dist, dist > T(0.0f) && dist < T(kInfinity)};
}

/// The lanes whose point p may receive light from the area light: false only
/// where every point q of the parallelogram lies behind its emitting side
/// ((q - p) . direction >= 0 there, so that no sample faces p) or below the
/// plane of ns or of ng, each by a margin of 1e-4 of the coordinates'
/// magnitudes: thousands of times the rounding of sample_area_light and of
/// the tests on its samples (emit, below), so that a lane ruled out here would
/// have had every sample masked off. Over the parallelogram, q = position +
/// a dim_x + b dim_y with |a|, |b| <= 1/2, (q - p) . v ranges over
/// (position - p) . v -+ (|dim_x . v| + |dim_y . v|) / 2.
template <class T>
inline lane::mask_t<T> area_light_may_reach(const AreaLight& l, const ShadingPointT<T>& sp) {
  const Vec3T<T> to_centre{T(l.position.x) - sp.p.x, T(l.position.y) - sp.p.y, T(l.position.z) - sp.p.z};
  const float light_size = std::fabs(l.position.x) + std::fabs(l.position.y) + std::fabs(l.position.z) +
                           std::fabs(l.dim_x.x) + std::fabs(l.dim_x.y) + std::fabs(l.dim_x.z) + std::fabs(l.dim_y.x) +
                           std::fabs(l.dim_y.y) + std::fabs(l.dim_y.z);
  const T margin = T(1e-4f) * (lane::abs(sp.p.x) + lane::abs(sp.p.y) + lane::abs(sp.p.z) + T(light_size));
  auto spread = [&](const Vec3T<T>& v) {
    const Vec3T<T> dx{T(l.dim_x.x), T(l.dim_x.y), T(l.dim_x.z)}, dy{T(l.dim_y.x), T(l.dim_y.y), T(l.dim_y.z)};
    return T(0.5f) * (lane::abs(dot3(dx, v)) + lane::abs(dot3(dy, v)));
  };
  const Vec3T<T> n{T(l.direction.x), T(l.direction.y), T(l.direction.z)};
  const lane::mask_t<T> behind = dot3(to_centre, n) - spread(n) > margin;
  const lane::mask_t<T> below_ns = dot3(to_centre, sp.ns) + spread(sp.ns) < lane::neg(margin);
  const lane::mask_t<T> below_ng = dot3(to_centre, sp.ng) + spread(sp.ng) < lane::neg(margin);
  return sp.on && !(behind || below_ns || below_ng);
}

/// Light samples go in groups: the random numbers of a whole group first,
/// then each sample's light. A sample's numbers (a Sobol point: hashes and bit
/// reversals) and its light (a square root and divisions) are each a long
/// chain of dependent instructions; taken one sample after the other, the
/// chains of two samples lie too far apart in the instruction stream for the
/// CPU to run them side by side, and shading waits on them. The same numbers
/// in the same order, so the image does not change.
inline constexpr int kLightSampleGroup = 4;

/// Calls each(u1, u2) for light samples k .. k + n - 1 of vertex `vertex`
/// (random dimensions light_dim(k) and the next), in order; k ends past them.
template <class T, class U, class Each>
PT_ALWAYS_INLINE void for_light_samples(const PathSamplerT<U, T>& ps, uint32_t vertex, int n, uint32_t& k,
                                        Each&& each) {
  for (int j0 = 0; j0 < n; j0 += kLightSampleGroup) {
    const int g = std::min(kLightSampleGroup, n - j0);
    T u1[kLightSampleGroup], u2[kLightSampleGroup];
    for (int j = 0; j < g; ++j) ps.get2d(vertex, dims::light_dim(k + static_cast<uint32_t>(j)), u1[j], u2[j]);
    for (int j = 0; j < g; ++j) each(u1[j], u2[j]);
    k += static_cast<uint32_t>(g);
  }
}

/// Calls shadow(ok, origin, wi, tmax, weight) for every light sample of
/// vertex `vertex` at point `sp`: `weight` is the RGB radiance the sample
/// brings if the shadow ray (origin, wi, [0, tmax)) is unblocked, already
/// divided by its pdf and sample count and multiplied by the cosine at the
/// surface (and the MIS weight where `bsdf_competes`); `ok` marks the lanes
/// where it can arrive (light facing the point, above both normals).
/// `bsdf_pdf(wi, cos)` is the pdf with which the vertex's BSDF sample picks
/// wi (LambertianPdf, or the rough conductor's).
template <class T, class U, class BsdfPdf, class Shadow>
void sample_light_sources(const Scene& scene, const RenderSettings& rs, const ShadingPointT<T>& sp,
                          const PathSamplerT<U, T>& ps, uint32_t vertex, bool bsdf_competes, BsdfPdf&& bsdf_pdf,
                          Shadow&& shadow) {
  const int n = rs.light_samples;
  const T inv_n(1.0f / static_cast<float>(n));
  const T mis_count(bsdf_competes ? static_cast<float>(n) : 0.0f);
  // Every sample that can arrive leaves above ng (the tests below), so its
  // origin is offset_origin's for any such direction (ng itself), the same
  // for all of them.
  const Vec3T<T> origin = offset_origin(sp.p, sp.ng, sp.offset, sp.ng);
  auto emit = [&](lane::mask_t<T> ok, const Vec3T<T>& wi, T tmax, const float3& radiance, T factor) {
    ok = ok && sp.on && dot3(sp.ns, wi) > T(0.0f) && dot3(sp.ng, wi) > T(0.0f);
    Vec3T<T> weight{T(radiance.x) * factor, T(radiance.y) * factor, T(radiance.z) * factor};
    shadow(ok, origin, wi, tmax, weight);
  };
  uint32_t k = 0;  // light-sample index over all lights, in scene order
  for (const AreaLight& light : scene.area_lights) {
    if (!lane::any(area_light_may_reach(light, sp))) {  // no sample would pass; the numbering goes on
      k += static_cast<uint32_t>(n);
      continue;
    }
    for_light_samples(ps, vertex, n, k, [&](T u1, T u2) {
      AreaLightSampleT<T> ls = sample_area_light<T>(light, sp.p.x, sp.p.y, sp.p.z, u1, u2, rs.cs184_light_pdf);
      T cos_s = dot3(sp.ns, ls.wi);
      emit(ls.facing, ls.wi, ls.dist * T(1.0f - kShadowRayShrink), light.radiance,
           light_sample_factor(cos_s, ls.pdf, mis_count, bsdf_pdf(ls.wi, cos_s)) * inv_n);
    });
  }
  for (const PointLight& light : scene.point_lights) {
    if (light.flags == 0) {  // the course's point light: no falloff
      DeltaLightSampleT<T> ls = sample_point_light<T>(light, sp.p);
      emit(ls.ok, ls.wi, ls.dist * T(1.0f - kShadowRayShrink), light.radiance, dot3(sp.ns, ls.wi));
      continue;
    }
    DeltaLightSampleT<T> ls;
    if (light.radius > 0.0f) {  // one sample of the disk facing p
      T u1, u2;
      ps.get2d(vertex, dims::light_dim(k++), u1, u2);
      ls = sample_soft_point_light<T>(light, sp.p, u1, u2);
    } else {
      ls = sample_point_light<T>(light, sp.p);
    }
    T factor = dot3(sp.ns, ls.wi) / (ls.dist * ls.dist);
    if (light.flags & PointLight::kSpot) factor = factor * spot_factor(light, Vec3T<T>{-ls.wi.x, -ls.wi.y, -ls.wi.z});
    emit(ls.ok, ls.wi, ls.dist * T(1.0f - kShadowRayShrink), light.radiance, factor);
  }
  for (const DirectionalLight& light : scene.directional_lights) {
    Vec3T<T> wi{T(light.to_light.x), T(light.to_light.y), T(light.to_light.z)};
    emit(sp.on, wi, T(kInfinity), light.radiance, dot3(sp.ns, wi));
  }
  if (scene.environment)
    for_light_samples(ps, vertex, n, k, [&](T u1, T u2) {
      EnvironmentSampleT<T> es = sample_environment(*scene.environment, u1, u2);
      T cos_s = dot3(sp.ns, es.wi);
      T factor = light_sample_factor(cos_s, es.pdf, mis_count, bsdf_pdf(es.wi, cos_s)) * inv_n;
      lane::mask_t<T> ok = sp.on && es.ok && dot3(sp.ns, es.wi) > T(0.0f) && dot3(sp.ng, es.wi) > T(0.0f);
      Vec3T<T> weight{es.radiance.x * factor, es.radiance.y * factor, es.radiance.z * factor};
      shadow(ok, origin, es.wi, T(kInfinity), weight);
    });
  else if (scene.sky)
    for_light_samples(ps, vertex, n, k, [&](T u1, T u2) {
      Vec3T<T> wi = sample_sky_direction(u1, u2);
      T cos_s = dot3(sp.ns, wi);
      emit(sp.on, wi, T(kInfinity), scene.sky->radiance,
           light_sample_factor(cos_s, T(kInv2Pi), mis_count, bsdf_pdf(wi, cos_s)) * inv_n);
    });
}

/// Calls probe(ok, origin, wi, weight) for every ray of the hit-based direct
/// estimators (-H: uniform hemisphere; --direct cosine) at vertex `vertex`:
/// the ray's closest hit (or escape) supplies the incident radiance, which
/// `weight` (cos / pdf over the ray count) multiplies.
template <class T, class U, class Probe>
void sample_hemisphere_rays(const Scene& scene, const RenderSettings& rs, const ShadingPointT<T>& sp,
                            const PathSamplerT<U, T>& ps, uint32_t vertex, Probe&& probe) {
  const uint32_t n = hemisphere_sample_count(scene, rs);
  const T scale(1.0f / static_cast<float>(n));
  const bool cosine = rs.direct == DirectLighting::kCosine;
  uint32_t k = 0;
  for_light_samples(ps, vertex, static_cast<int>(n), k, [&](T u1, T u2) {
    Vec3T<T> local = cosine ? sample_cosine_hemisphere(u1, u2) : sample_uniform_hemisphere(u1, u2);
    Vec3T<T> wi = to_world(sp.ns.x, sp.ns.y, sp.ns.z, local.x, local.y, local.z);
    lane::mask_t<T> ok = sp.on && dot3(sp.ng, wi) > T(0.0f);
    probe(ok, offset_origin(sp.p, sp.ng, sp.offset, wi), wi, hit_sampling_weight(rs, local.z) * scale);
  });
}

/// The continuation of a path at a Lambertian surface: a cosine-weighted
/// direction (f cos / pdf = albedo) with its pdf; `ok` is false where the
/// direction falls below the geometric surface.
template <class T>
struct BsdfSampleT {
  Vec3T<T> wi;
  T pdf;
  lane::mask_t<T> ok;
};

template <class T, class U>
inline BsdfSampleT<T> sample_lambertian(const ShadingPointT<T>& sp, const PathSamplerT<U, T>& ps, uint32_t vertex) {
  T u1, u2;
  ps.get2d(vertex, dims::kBsdf, u1, u2);
  Vec3T<T> local = sample_cosine_hemisphere(u1, u2);
  Vec3T<T> wi = to_world(sp.ns.x, sp.ns.y, sp.ns.z, local.x, local.y, local.z);
  return {wi, local.z * T(kInvPi), sp.on && dot3(wi, sp.ng) > T(0.0f)};
}

/// The shading point of a surface point (one path).
inline ShadingPointT<float> shading_point(const SurfacePoint& sp, bool reflects) {
  return {vec3t(sp.p), vec3t(sp.ng), vec3t(sp.ns), sp.offset, reflects};
}

}  // namespace PT_ISA_NS
}  // namespace pt
