// The four light types of the CS184 scenes and how a shading point samples each
// (light importance sampling). Conventions follow the course renderer, except
// where it is physically inconsistent (see README: "Scene semantics").
#pragma once

#include <cmath>

#include "ray.h"
#include "sampling.h"
#include "vec3.h"

namespace pt {

/// 64 bytes. A parallelogram centred at `position` with edges dim_x, dim_y,
/// emitting `radiance` towards the side `direction` (unit) points to.
struct AreaLight {
  float3 position, dim_x, dim_y, direction, radiance;
  float area;
};
static_assert(sizeof(AreaLight) == 64);

/// 24 bytes. Delta light without distance falloff (the course's convention).
struct PointLight {
  float3 position, radiance;
};

/// 24 bytes. Delta light; `to_light` is the unit direction towards the light.
struct DirectionalLight {
  float3 to_light, radiance;
};

/// 12 bytes. Uniform radiance over the upper (+Y) hemisphere of directions.
struct SkyLight {
  float3 radiance;
};

/// One light sample seen from a shading point: unit direction to the light,
/// distance (infinity for directional and sky), solid-angle pdf (1 for delta
/// lights) and incident radiance (black when the sample cannot reach p).
struct LightSample {
  float3 wi;
  float dist = 0.0f;
  float pdf = 0.0f;
  float3 radiance;
};

inline LightSample sample_area_light(const AreaLight& l, const float3& p, float u1, float u2) {
  float3 q = l.position + l.dim_x * (u1 - 0.5f) + l.dim_y * (u2 - 0.5f);
  float3 d = q - p;
  float dist2 = dot(d, d);
  float dist = std::sqrt(dist2);
  LightSample s;
  s.wi = d / dist;
  s.dist = dist;
  float cos_light = dot(s.wi, l.direction);
  s.pdf = dist2 / (l.area * std::fabs(cos_light));
  if (cos_light < 0.0f && dist > 0.0f && std::isfinite(s.pdf)) s.radiance = l.radiance;
  return s;
}

/// Solid-angle pdf with which sample_area_light picks the point at distance
/// `dist` along unit direction wi (for multiple importance sampling).
inline float area_light_pdf(const AreaLight& l, const float3& wi, float dist) {
  float cos_light = std::fabs(dot(wi, l.direction));
  return cos_light > 0.0f ? dist * dist / (l.area * cos_light) : 0.0f;
}

inline LightSample sample_point_light(const PointLight& l, const float3& p) {
  float3 d = l.position - p;
  float dist = length(d);
  LightSample s;
  s.wi = d / dist;
  s.dist = dist;
  s.pdf = 1.0f;
  if (dist > 0.0f) s.radiance = l.radiance;
  return s;
}

inline LightSample sample_directional_light(const DirectionalLight& l) {
  return {l.to_light, kInfinity, 1.0f, l.radiance};
}

/// The sky's local frame has +Y as its pole: local (x, y, z) -> world (x, z, y)
/// keeps it right-handed up to a reflection that uniform sampling cannot see.
inline LightSample sample_sky_light(const SkyLight& l, float u1, float u2) {
  Vec3T<float> h = sample_uniform_hemisphere(u1, u2);
  return {float3{h.x, h.z, h.y}, kInfinity, kInv2Pi, l.radiance};
}

/// Radiance the sky sends along a ray leaving in direction d (unit).
inline float3 sky_radiance(const SkyLight& l, const float3& d) {
  return d.y > 0.0f ? l.radiance : float3{};
}

}  // namespace pt
