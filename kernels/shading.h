// Small shading rules both engines share, so that they make the same choice:
// how far a shadow ray may go, how many rays the hemisphere estimator casts,
// which emission a bounce ray may count, and the normal-shading colour.
#pragma once

#include <algorithm>
#include <cstdint>

#include "render_settings.h"
#include "scene.h"
#include "surface.h"

namespace pt {

/// Shadow rays stop this fraction short of the light sample, so the light's
/// own surface never occludes it (relative, hence independent of scale).
inline constexpr float kShadowRayShrink = 0x1p-13f;

inline float shadow_ray_tmax(float dist) { return dist * (1.0f - kShadowRayShrink); }

/// Rays the hemisphere estimator casts per shading point: the assignment's
/// (number of lights) x (samples per area light), at least one.
inline uint32_t hemisphere_sample_count(const Scene& s, const RenderSettings& rs) {
  return static_cast<uint32_t>(std::max<size_t>(1, s.light_count() * static_cast<size_t>(rs.light_samples)));
}

/// Whether a bounce ray that reaches `sp` adds its emission. With light
/// sampling, sampled lights were counted by their shadow rays; emitters that
/// no light sampler knows (emissive meshes) are counted here. With hemisphere
/// sampling the estimator at the previous vertex already counted everything.
inline bool emission_found_by_bounce(const Scene& s, const SurfacePoint& sp, const RenderSettings& rs) {
  if (rs.direct == DirectLighting::kHemisphere) return false;
  const Material& m = s.materials[sp.material];
  return m.is_emitter() && m.area_light < 0;
}

/// The assignment's normal shading: n * 0.5 + 0.5 of the stored shading normal.
inline float3 normal_shading_color(const SurfacePoint& sp) { return sp.raw_ns * 0.5f + float3(0.5f); }

}  // namespace pt
