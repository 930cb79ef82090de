// Rebuilds the surface at a hit from the scene arrays (shading reads only the
// primitive id and barycentrics), evaluates emission, and offsets new ray
// origins off the surface by a distance that scales with the coordinates'
// magnitude, so scenes at any scale are free of self-intersection.
#pragma once

#include <cmath>

#include "ray.h"
#include "render_settings.h"
#include "scene.h"
#include "vec3.h"

namespace pt {

/// Relative size of a hit point's rounding error we push new origins past:
/// 2^-19 of the coordinates' magnitude, about 8x the error bound of the
/// barycentric interpolation that computes the point.
inline constexpr float kOffsetScale = 0x1p-19f;

struct SurfacePoint {
  float3 p;          ///< on the surface
  float3 ng;         ///< unit geometric normal, turned to face the incoming ray
  float3 ns;         ///< unit shading normal, on the same side as ng
  float3 raw_ns;     ///< shading normal as stored (for normal shading)
  float offset = 0;  ///< distance to move p along +-ng to leave the surface
  uint32_t material = 0;
  bool front = true; ///< the ray arrived on the side the stored normal faces
};

inline SurfacePoint surface_at(const Scene& s, const Ray& ray, const Hit& hit) {
  SurfacePoint sp;
  float3 ng;
  if (hit.is_sphere()) {
    const Sphere& sph = s.spheres[hit.index()];
    float3 p = ray.org + ray.dir * hit.t;
    float3 d = p - sph.center;
    float len = length(d);
    ng = len > 0.0f ? d / len : float3{0.0f, 1.0f, 0.0f};
    sp.p = sph.center + ng * sph.radius;  // reproject onto the sphere
    sp.raw_ns = ng;
    sp.offset = (max_component(abs(sph.center)) + sph.radius) * kOffsetScale;
    sp.material = sph.material;
  } else {
    const TriangleIndices& t = s.triangles[hit.index()];
    const float3 &p0 = s.positions[t.v0], &p1 = s.positions[t.v1], &p2 = s.positions[t.v2];
    float w = 1.0f - hit.u - hit.v;
    sp.p = p0 * w + p1 * hit.u + p2 * hit.v;
    ng = cross(p1 - p0, p2 - p0);
    float len = length(ng);
    ng = len > 0.0f ? ng / len : float3{0.0f, 1.0f, 0.0f};
    float3 n = s.normals[t.v0] * w + s.normals[t.v1] * hit.u + s.normals[t.v2] * hit.v;
    float nlen = length(n);
    sp.raw_ns = nlen > 0.0f ? n / nlen : ng;
    sp.offset = max_component(max(max(abs(p0), abs(p1)), abs(p2))) * kOffsetScale;
    sp.material = s.triangle_material[hit.index()];
  }
  sp.front = dot(ray.dir, ng) < 0.0f;
  sp.ng = sp.front ? ng : -ng;
  sp.ns = sp.front ? sp.raw_ns : -sp.raw_ns;
  if (dot(sp.ns, sp.ng) < 0.0f) sp.ns = sp.ng;  // shading normal from the other side: use the true one
  return sp;
}

/// Origin for a ray leaving the surface in direction `dir`.
inline float3 offset_origin(const SurfacePoint& sp, const float3& dir) {
  return sp.p + sp.ng * (dot(dir, sp.ng) >= 0.0f ? sp.offset : -sp.offset);
}

/// Radiance the surface emits towards the ray's origin.
inline float3 emitted_radiance(const Scene& s, const SurfacePoint& sp, const Ray& ray, const RenderSettings& rs) {
  const Material& m = s.materials[sp.material];
  if (!m.is_emitter()) return {};
  if ((m.flags & Material::kOneSided) && !sp.front) return {};
  if (rs.cs184_light_quirk && m.area_light >= 0) {
    // The course renderer's area-light triangles: colour / area * cos.
    const AreaLight& l = s.area_lights[m.area_light];
    float cos_view = -dot(ray.dir, l.direction) / length(ray.dir);
    return m.emission * (std::max(cos_view, 0.0f) / l.area);
  }
  return m.emission;
}

}  // namespace pt
