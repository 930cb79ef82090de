// The camera as the course renderer models it: a position, a camera-to-world
// basis (screen x, screen y, direction towards the camera), tangents of the
// half fields of view, near/far clip distances that become each camera ray's
// t range, and an optional thin lens (lens radius 0: the pinhole).
#pragma once

#include "kernels/simd/isa_namespace.h"
#include "kernels/math/frame.h"
#include "kernels/simd/lane_math.h"
#include "kernels/math/ray.h"
#include "kernels/math/vec3.h"

namespace pt {

/// 72 bytes. Fully resolved for one output image.
struct Camera {
  float3 position;
  float3 screen_x, screen_y, to_camera;  // columns of camera-to-world
  float tan_half_hfov = 0, tan_half_vfov = 0;
  float near_clip = 0, far_clip = 0;
  float lens_radius = 0;     ///< thin lens: radius of the aperture (0: pinhole)
  float focal_distance = 1;  ///< thin lens: distance to the plane in focus, along the view direction

  bool thin_lens() const { return lens_radius > 0.0f; }
};
static_assert(sizeof(Camera) == 72);

inline namespace PT_ISA_NS {
/// Ray through film position (sx, sy) in [0,1]^2, (0,0) = bottom-left corner.
template <class T>
inline Vec3T<T> camera_ray_direction(const Camera& c, T sx, T sy) {
  T x = (T(2.0f) * sx - T(1.0f)) * T(c.tan_half_hfov);
  T y = (T(2.0f) * sy - T(1.0f)) * T(c.tan_half_vfov);
  T dx = T(c.screen_x.x) * x + T(c.screen_y.x) * y - T(c.to_camera.x);
  T dy = T(c.screen_x.y) * x + T(c.screen_y.y) * y - T(c.to_camera.y);
  T dz = T(c.screen_x.z) * x + T(c.screen_y.z) * y - T(c.to_camera.z);
  T inv = T(1.0f) / lane::sqrt(dx * dx + dy * dy + dz * dz);
  return {dx * inv, dy * inv, dz * inv};
}

/// A thin-lens camera ray through film position (sx, sy) and lens sample
/// (u1, u2) in [0,1)^2, the course's way: a point uniform on the lens disk,
/// aimed at the point where the pinhole ray meets the plane of focus
/// (camera-space z = -focal_distance). Writes the origin and unit direction.
template <class T>
inline void thin_lens_ray(const Camera& c, T sx, T sy, T u1, T u2, Vec3T<T>& org, Vec3T<T>& dir) {
  T x = (T(2.0f) * sx - T(1.0f)) * T(c.tan_half_hfov);
  T y = (T(2.0f) * sy - T(1.0f)) * T(c.tan_half_vfov);
  T r = T(c.lens_radius) * lane::sqrt(u1), s, co;
  lane::sincos_2pi(u2, s, co);
  T lx = r * co, ly = r * s, inv_f(1.0f / c.focal_distance);
  // Camera space, divided by f: from the lens point to the point in focus
  // (x f, y f, -f), so that no focal distance overflows.
  T cx = x - lx * inv_f, cy = y - ly * inv_f;
  T dx = T(c.screen_x.x) * cx + T(c.screen_y.x) * cy - T(c.to_camera.x);
  T dy = T(c.screen_x.y) * cx + T(c.screen_y.y) * cy - T(c.to_camera.y);
  T dz = T(c.screen_x.z) * cx + T(c.screen_y.z) * cy - T(c.to_camera.z);
  T inv = T(1.0f) / lane::sqrt(dx * dx + dy * dy + dz * dz);
  dir = {dx * inv, dy * inv, dz * inv};
  org = {T(c.position.x) + T(c.screen_x.x) * lx + T(c.screen_y.x) * ly,
         T(c.position.y) + T(c.screen_x.y) * lx + T(c.screen_y.y) * ly,
         T(c.position.z) + T(c.screen_x.z) * lx + T(c.screen_y.z) * ly};
}

inline Ray camera_ray(const Camera& c, float sx, float sy) {
  Vec3T<float> d = camera_ray_direction(c, sx, sy);
  return {c.position, c.near_clip, float3{d.x, d.y, d.z}, c.far_clip};
}

}  // namespace PT_ISA_NS
}  // namespace pt
