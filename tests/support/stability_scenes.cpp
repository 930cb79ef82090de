// Scene and camera builders for the stability tests.
#include "support/stability_scenes.h"

#include <cmath>

namespace pt::test {

namespace {

Scene floor_only() {
  Scene s;
  s.name = "floor";
  add_parallelogram(s, {-10, 0, 10}, {20, 0, 0}, {0, 0, -20}, add_material(s, float3(0.5f)));
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  return s;
}

}  // namespace

Scene floor_under_square_light(float side, float power) {
  Scene s = floor_only();
  add_area_light(s, {0, 1, 0}, {side, 0, 0}, {0, 0, side}, {0, -1, 0}, float3(power / (side * side)));
  finish_scene(s);
  return s;
}

Scene floor_under_delta_lights(bool point, bool directional) {
  Scene s = floor_only();
  if (point) s.point_lights.push_back({{0, 1, 0}, float3(1.0f)});
  if (directional) s.directional_lights.push_back({normalize(float3{0.3f, 1.0f, 0.2f}), float3(0.7f)});
  finish_scene(s);
  return s;
}

Scene light_seen_head_on() {
  Scene s;
  s.name = "light_head_on";
  add_parallelogram(s, {-1, -1, 0}, {2, 0, 0}, {0, 0, -2}, add_material(s, float3(0.5f)));
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  add_area_light(s, {0, 0, -2}, {2, 0, 0}, {0, 2, 0}, {0, 0, 1}, float3(3.0f));
  finish_scene(s);
  return s;
}

Scene floor_with_degenerate_triangles() {
  Scene s = floor_only();
  uint32_t grey = s.triangle_material[0];
  uint32_t base = static_cast<uint32_t>(s.positions.size());
  const float3 points[] = {{0.2f, 0.1f, 0.2f},   {0.2f, 0.1f, 0.2f},  {0.2f, 0.1f, 0.2f},        // one point
                           {-0.5f, 0.1f, 0},     {0, 0.1f, 0},        {0.5f, 0.1f, 0},           // a line
                           {-0.5f, 0.05f, 0.3f}, {0.5f, 0.05f, 0.3f}, {0, 0.05f, 0.3f + 1e-7f},  // a needle
                           {-0.3f, 0.2f, -0.3f}, {0.3f, 0.2f, -0.3f}, {0, 0.2f, -0.6f}};         // zero normals
  for (int i = 0; i < 12; ++i) {
    s.positions.push_back(points[i]);
    s.normals.push_back(i < 9 ? normalize(float3{0.1f, 1.0f, 0.0f}) : float3(0.0f));
  }
  for (uint32_t t = 0; t < 4; ++t) {
    s.triangles.push_back({base + 3 * t, base + 3 * t + 1, base + 3 * t + 2});
    s.triangle_material.push_back(grey);
  }
  s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  add_area_light(s, {0, 1, 0}, {0.5f, 0, 0}, {0, 0, 0.5f}, {0, -1, 0}, float3(4.0f));
  finish_scene(s);
  return s;
}

Scene scaled_scene(const Scene& scene, float k) {
  Scene s = scene;
  for (float3& p : s.positions) p *= k;
  for (Sphere& sp : s.spheres) {
    sp.center *= k;
    sp.radius *= k;
  }
  for (AreaLight& l : s.area_lights) {
    l.position *= k;
    l.dim_x *= k;
    l.dim_y *= k;
    l.area *= k * k;
  }
  for (PointLight& l : s.point_lights) l.position *= k;
  s.camera.near_clip *= k;
  s.camera.far_clip *= k;
  s.bounds = compute_scene_bounds(s);
  return s;
}

namespace {

/// Camera at `position` looking at `target` (up: +Y unless looking along it),
/// tan(half field of view) = tan_half on both axes, clip range 1e-4..1e4.
Camera square_view(float3 position, float3 target, float tan_half) {
  Camera c;
  c.position = position;
  c.to_camera = normalize(position - target);
  float3 up{0.0f, 1.0f, 0.0f};
  if (length(cross(up, c.to_camera)) < 1e-6f) up = {0.0f, 0.0f, -1.0f};
  c.screen_x = normalize(cross(up, c.to_camera));
  c.screen_y = cross(c.to_camera, c.screen_x);
  c.tan_half_hfov = c.tan_half_vfov = tan_half;
  c.near_clip = 1e-4f;
  c.far_clip = 1e4f;
  return c;
}

}  // namespace

Camera camera_above_floor() { return square_view({0, 0.5f, 0}, {0, 0, 0}, 0.5f); }

Camera camera_facing_minus_z() { return square_view({0, 0, 0}, {0, 0, -1}, 1.0f); }

Camera camera_grazing_floor() { return square_view({-9.0f, 1e-4f, 0}, {10.0f, -0.05f, 0}, 0.05f); }

}  // namespace pt::test
