// Rebuilds the surface at a hit from the scene arrays (shading reads only the
// primitive id and barycentrics), evaluates emission, and offsets new ray
// origins off the surface by a distance that scales with the coordinates'
// magnitude, so scenes at any scale are free of self-intersection.
#pragma once

#include <cmath>

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/simd/lane_math.h"
#include "kernels/math/ray.h"
#include "kernels/render/render_settings.h"
#include "kernels/scene/scene.h"
#include "kernels/math/vec3.h"

namespace pt {
inline namespace PT_ISA_NS {

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
  bool front = true;  ///< the ray arrived on the side the stored normal faces
};

template <class T>
inline T dot3(const Vec3T<T>& a, const Vec3T<T>& b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class T>
inline Vec3T<T> scale3(const Vec3T<T>& a, T s) {
  return {a.x * s, a.y * s, a.z * s};
}

/// Lane-generic triangle part of surface_at: the same operations, in the same
/// order, for one float or a SIMD batch.
template <class T>
struct TriangleSurfaceT {
  Vec3T<T> p, ng, ns, raw_ns;
  T offset;
  lane::mask_t<T> front;
};

template <class T>
inline TriangleSurfaceT<T> triangle_surface(const Vec3T<T>& p0, const Vec3T<T>& p1, const Vec3T<T>& p2,
                                            const Vec3T<T>& n0, const Vec3T<T>& n1, const Vec3T<T>& n2, T u, T v,
                                            const Vec3T<T>& dir) {
  TriangleSurfaceT<T> s;
  T w = T(1.0f) - u - v;
  auto interpolate = [&](const Vec3T<T>& a, const Vec3T<T>& b, const Vec3T<T>& c) {
    return Vec3T<T>{a.x * w + b.x * u + c.x * v, a.y * w + b.y * u + c.y * v, a.z * w + b.z * u + c.z * v};
  };
  auto unit_or = [](const Vec3T<T>& a, const Vec3T<T>& fallback) {
    T len = lane::sqrt(dot3(a, a));
    return select3(len > T(0.0f), scale3(a, T(1.0f) / len), fallback);
  };
  s.p = interpolate(p0, p1, p2);
  Vec3T<T> e1{p1.x - p0.x, p1.y - p0.y, p1.z - p0.z}, e2{p2.x - p0.x, p2.y - p0.y, p2.z - p0.z};
  Vec3T<T> ng = unit_or({e1.y * e2.z - e1.z * e2.y, e1.z * e2.x - e1.x * e2.z, e1.x * e2.y - e1.y * e2.x},
                        {T(0.0f), T(1.0f), T(0.0f)});
  s.raw_ns = unit_or(interpolate(n0, n1, n2), ng);
  auto max_abs = [](const Vec3T<T>& a) { return lane::max(lane::abs(a.x), lane::max(lane::abs(a.y), lane::abs(a.z))); };
  s.offset = lane::max(lane::max(max_abs(p0), max_abs(p1)), max_abs(p2)) * T(kOffsetScale);
  s.front = dot3(dir, ng) < T(0.0f);
  s.ng = select3(s.front, ng, Vec3T<T>{lane::neg(ng.x), lane::neg(ng.y), lane::neg(ng.z)});
  Vec3T<T> ns =
      select3(s.front, s.raw_ns, Vec3T<T>{lane::neg(s.raw_ns.x), lane::neg(s.raw_ns.y), lane::neg(s.raw_ns.z)});
  s.ns = select3(dot3(ns, s.ng) < T(0.0f), s.ng, ns);
  return s;
}

/// Origin for a ray leaving a surface at p (normal ng, offset) in direction dir.
template <class T>
inline Vec3T<T> offset_origin(const Vec3T<T>& p, const Vec3T<T>& ng, T offset, const Vec3T<T>& dir) {
  T d = lane::select(dot3(dir, ng) >= T(0.0f), offset, lane::neg(offset));
  return {p.x + ng.x * d, p.y + ng.y * d, p.z + ng.z * d};
}

inline SurfacePoint surface_at(const Scene& s, const Ray& ray, const Hit& hit) {
  SurfacePoint sp;
  if (hit.is_sphere()) {
    const Sphere& sph = s.spheres[hit.index()];
    float3 p = ray.org + ray.dir * hit.t;
    float3 d = p - sph.center;
    float len = length(d);
    float3 ng = len > 0.0f ? d / len : float3{0.0f, 1.0f, 0.0f};
    sp.p = sph.center + ng * sph.radius;  // reproject onto the sphere
    sp.raw_ns = ng;
    sp.offset = (max_component(abs(sph.center)) + sph.radius) * kOffsetScale;
    sp.material = sph.material;
    sp.front = dot(ray.dir, ng) < 0.0f;
    sp.ng = sp.front ? ng : -ng;
    sp.ns = sp.ng;
    return sp;
  }
  const TriangleIndices& t = s.triangles[hit.index()];
  TriangleSurfaceT<float> ts = triangle_surface<float>(
      vec3t(s.positions[t.v0]), vec3t(s.positions[t.v1]), vec3t(s.positions[t.v2]), vec3t(s.normals[t.v0]),
      vec3t(s.normals[t.v1]), vec3t(s.normals[t.v2]), hit.u, hit.v, vec3t(ray.dir));
  sp.p = to_float3(ts.p);
  sp.ng = to_float3(ts.ng);
  sp.ns = to_float3(ts.ns);
  sp.raw_ns = to_float3(ts.raw_ns);
  sp.offset = ts.offset;
  sp.front = ts.front;
  sp.material = s.triangle_material[hit.index()];
  return sp;
}

/// Origin for a ray leaving the surface in direction `dir`.
inline float3 offset_origin(const SurfacePoint& sp, const float3& dir) {
  return to_float3(offset_origin<float>(vec3t(sp.p), vec3t(sp.ng), sp.offset, vec3t(dir)));
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

}  // namespace PT_ISA_NS
}  // namespace pt
