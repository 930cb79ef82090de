// The light types of the CS184 scenes and of Blender's exports (rectangular
// and elliptical area lights; point lights with or without distance falloff,
// a radius and a spot cone), the area light's, the soft point light's and the
// sky's sampling warps (lane-generic: one path or K lanes) and their pdfs. How
// a shading point combines them into direct light is kernels/transport/
// direct_light.h. Conventions follow the course renderer, except where it is
// physically inconsistent (docs/cs184_compatibility.md), and Cycles' for
// Blender's lights (docs/blender_scenes.md).
#pragma once

#include <cmath>
#include <cstdint>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/ray.h"
#include "kernels/math/sampling.h"
#include "kernels/math/vec3.h"

namespace pt {

/// The outline of an area light within its parallelogram.
enum class AreaShape : uint32_t {
  kParallelogram,  ///< the whole parallelogram (the course's square, Blender's square and rectangle)
  kEllipse,        ///< the ellipse inscribed in it (Blender's disk and ellipse)
};

/// 68 bytes. A parallelogram centred at `position` with edges dim_x, dim_y (or
/// the ellipse inscribed in it), emitting `radiance` towards the side
/// `direction` (unit) points to; `area` is the shape's.
struct AreaLight {
  float3 position, dim_x, dim_y, direction, radiance;
  float area;
  AreaShape shape = AreaShape::kParallelogram;
};
static_assert(sizeof(AreaLight) == 68);

/// 52 bytes. A point light. The course's (flags 0): a delta light without
/// distance falloff, `radiance` arriving as such. Blender's (Cycles'
/// conventions, kInverseSquare): `radiance` is the radiant intensity I
/// (W / sr per channel), arriving as I / d^2; with a `radius` it is a disk of
/// that radius facing the shading point, sampled uniformly (soft shadows);
/// with kSpot it is scaled by spot_factor() of the direction it leaves in.
struct PointLight {
  float3 position, radiance;
  uint32_t flags = 0;
  float radius = 0.0f;
  float3 spot_dir{0.0f, 0.0f, -1.0f};  ///< unit axis of the spot cone
  float spot_cos_half = -1.0f;         ///< cosine of half the cone's angle
  float spot_smooth = 0.0f;            ///< width of the smooth edge, in cosine: (1 - spot_cos_half) x blend

  static constexpr uint32_t kInverseSquare = 1, kSpot = 2;
};
static_assert(sizeof(PointLight) == 52);

/// Cycles' spot attenuation for unit direction `out` from the light: 0 outside
/// the cone, else the cosine to the axis, times smoothstep(0, smooth,
/// cos - cos_half) within the smooth edge.
template <class T>
inline T spot_factor(const PointLight& l, const Vec3T<T>& out) {
  T c = out.x * T(l.spot_dir.x) + out.y * T(l.spot_dir.y) + out.z * T(l.spot_dir.z);
  T t = c - T(l.spot_cos_half);
  T f = c;
  if (l.spot_smooth > 0.0f) {
    T x = lane::min(T(1.0f), lane::max(T(0.0f), t / T(l.spot_smooth)));
    f = f * (x * x * (T(3.0f) - T(2.0f) * x));
  }
  return lane::select(t > T(0.0f), f, T(0.0f));
}

/// 24 bytes. Delta light; `to_light` is the unit direction towards the light.
struct DirectionalLight {
  float3 to_light, radiance;
};

/// 12 bytes. Uniform radiance over the upper (+Y) hemisphere of directions.
struct SkyLight {
  float3 radiance;
};

inline namespace PT_ISA_NS {
/// Lane-generic area-light sample towards point (px, py, pz): the unit
/// direction, distance and solid-angle pdf. `facing` is true where the sample
/// can send light to p (it lies on the emitting side and the pdf is finite).
template <class T>
struct AreaLightSampleT {
  Vec3T<T> wi;
  T dist, pdf;
  lane::mask_t<T> facing;
};

/// `course_pdf`: the course renderer's pdf, dist / (area |cos|) (it takes the
/// cosine from the unnormalised vector to the sample), so that each sample
/// weighs dist times more than the physical dist^2 / (area |cos|) gives.
template <class T>
inline AreaLightSampleT<T> sample_area_light(const AreaLight& l, T px, T py, T pz, T u1, T u2,
                                             bool course_pdf = false) {
  T a = u1 - T(0.5f), b = u2 - T(0.5f);
  if (l.shape == AreaShape::kEllipse) {  // uniform over the inscribed ellipse
    T r = T(0.5f) * lane::sqrt(u1), s, c;
    lane::sincos_2pi(u2, s, c);
    a = r * c;
    b = r * s;
  }
  T dx = T(l.position.x) + T(l.dim_x.x) * a + T(l.dim_y.x) * b - px;
  T dy = T(l.position.y) + T(l.dim_x.y) * a + T(l.dim_y.y) * b - py;
  T dz = T(l.position.z) + T(l.dim_x.z) * a + T(l.dim_y.z) * b - pz;
  T dist2 = dx * dx + dy * dy + dz * dz;
  T dist = lane::sqrt(dist2);
  T inv = T(1.0f) / dist;
  AreaLightSampleT<T> s;
  s.wi = {dx * inv, dy * inv, dz * inv};
  s.dist = dist;
  T cos_light = s.wi.x * T(l.direction.x) + s.wi.y * T(l.direction.y) + s.wi.z * T(l.direction.z);
  s.pdf = dist2 / (T(l.area) * lane::abs(cos_light));
  if (course_pdf) s.pdf = s.pdf / dist;
  s.facing = (cos_light < T(0.0f)) && (dist > T(0.0f)) && (s.pdf < T(kInfinity));
  return s;
}

/// Solid-angle pdf with which sample_area_light picks the point at distance
/// `dist` along unit direction wi (for multiple importance sampling).
inline float area_light_pdf(const AreaLight& l, const float3& wi, float dist, bool course_pdf = false) {
  float cos_light = std::fabs(dot(wi, l.direction));
  if (!(cos_light > 0.0f)) return 0.0f;
  float pdf = dist * dist / (l.area * cos_light);
  return course_pdf ? pdf / dist : pdf;
}

/// The sky's local frame has +Y as its pole: local (x, y, z) -> world (x, z, y)
/// keeps it right-handed up to a reflection that uniform sampling cannot see.
template <class T>
inline Vec3T<T> sample_sky_direction(T u1, T u2) {
  Vec3T<T> h = sample_uniform_hemisphere(u1, u2);
  return {h.x, h.z, h.y};
}

/// Radiance the sky sends along a ray leaving in direction d (unit).
inline float3 sky_radiance(const SkyLight& l, const float3& d) { return d.y > 0.0f ? l.radiance : float3{}; }

}  // namespace PT_ISA_NS
}  // namespace pt
