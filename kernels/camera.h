// The pinhole camera as the course renderer models it: a position, a
// camera-to-world basis (screen x, screen y, direction towards the camera),
// tangents of the half fields of view, and near/far clip distances that become
// each camera ray's t range.
#pragma once

#include "frame.h"
#include "ray.h"
#include "vec3.h"

namespace pt {

/// 64 bytes. Fully resolved for one output image.
struct Camera {
  float3 position;
  float3 screen_x, screen_y, to_camera;  // columns of camera-to-world
  float tan_half_hfov = 0, tan_half_vfov = 0;
  float near_clip = 0, far_clip = 0;
};

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

inline Ray camera_ray(const Camera& c, float sx, float sy) {
  Vec3T<float> d = camera_ray_direction(c, sx, sy);
  return {c.position, c.near_clip, float3{d.x, d.y, d.z}, c.far_clip};
}

}  // namespace pt
