// In-code test scenes and cameras.
#include "support/scene_builders.h"

#include <cmath>
#include <utility>

namespace pt::test {

uint32_t add_material(Scene& s, float3 albedo, float3 emission) {
  Material m;
  m.albedo = albedo;
  m.emission = emission;
  s.materials.push_back(m);
  return static_cast<uint32_t>(s.materials.size() - 1);
}

void add_quad(Scene& s, float3 a, float3 b, float3 c, float3 d, float3 normal, uint32_t material) {
  if (dot(cross(b - a, c - a), normal) < 0.0f) std::swap(b, d);
  uint32_t base = static_cast<uint32_t>(s.positions.size());
  for (const float3& p : {a, b, c, d}) {
    s.positions.push_back(p);
    s.normals.push_back(normal);
  }
  s.triangles.push_back({base, base + 1, base + 2});
  s.triangles.push_back({base, base + 2, base + 3});
  s.triangle_material.push_back(material);
  s.triangle_material.push_back(material);
}

void add_parallelogram(Scene& s, float3 corner, float3 e1, float3 e2, uint32_t material) {
  add_quad(s, corner, corner + e1, corner + e1 + e2, corner + e2, normalize(cross(e1, e2)), material);
}

void add_area_light(Scene& s, float3 centre, float3 dim_x, float3 dim_y, float3 direction, float3 radiance) {
  s.area_lights.push_back({centre, dim_x, dim_y, direction, radiance, length(cross(dim_x, dim_y))});
  add_area_light_geometry(s, static_cast<uint32_t>(s.area_lights.size() - 1));
}

void add_inward_box(Scene& s, const BBox& box, uint32_t material) {
  const float3 l = box.lower, u = box.upper;
  add_quad(s, {l.x, l.y, l.z}, {u.x, l.y, l.z}, {u.x, l.y, u.z}, {l.x, l.y, u.z}, {0, 1, 0}, material);   // floor
  add_quad(s, {l.x, u.y, l.z}, {l.x, u.y, u.z}, {u.x, u.y, u.z}, {u.x, u.y, l.z}, {0, -1, 0}, material);  // ceiling
  add_quad(s, {l.x, l.y, l.z}, {l.x, u.y, l.z}, {u.x, u.y, l.z}, {u.x, l.y, l.z}, {0, 0, 1}, material);   // back
  add_quad(s, {l.x, l.y, u.z}, {u.x, l.y, u.z}, {u.x, u.y, u.z}, {l.x, u.y, u.z}, {0, 0, -1}, material);  // front
  add_quad(s, {l.x, l.y, l.z}, {l.x, l.y, u.z}, {l.x, u.y, u.z}, {l.x, u.y, l.z}, {1, 0, 0}, material);   // left
  add_quad(s, {u.x, l.y, l.z}, {u.x, u.y, l.z}, {u.x, u.y, u.z}, {u.x, l.y, u.z}, {-1, 0, 0}, material);  // right
}

void add_area_light_box(Scene& s, float h, float3 albedo, float3 radiance) {
  const float3 axes[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  for (int a = 0; a < 3; ++a)
    for (float side : {-1.0f, 1.0f}) {
      AreaLight l;
      l.position = axes[a] * (side * h);
      l.dim_x = axes[(a + 1) % 3] * (2.0f * h);
      l.dim_y = axes[(a + 2) % 3] * (2.0f * h);
      l.direction = axes[a] * -side;  // into the cube
      l.radiance = radiance;
      l.area = 4.0f * h * h;
      s.area_lights.push_back(l);
      add_area_light_geometry(s, static_cast<uint32_t>(s.area_lights.size() - 1));
      s.materials.back().albedo = albedo;
    }
}

void finish_scene(Scene& s) {
  if (s.area_lights.empty()) s.mesh_triangle_count = static_cast<uint32_t>(s.triangles.size());
  s.bounds = compute_scene_bounds(s);
}

Camera look_at(float3 eye, float3 target, float tan_half_h, float tan_half_v, float far_clip) {
  Camera c;
  c.position = eye;
  c.to_camera = normalize(eye - target);
  float3 up = std::fabs(c.to_camera.y) > 0.999f ? float3{0, 0, 1} : float3{0, 1, 0};
  c.screen_x = normalize(cross(up, c.to_camera));
  c.screen_y = cross(c.to_camera, c.screen_x);
  c.tan_half_hfov = tan_half_h;
  c.tan_half_vfov = tan_half_v;
  c.near_clip = 0.0f;
  c.far_clip = far_clip;
  return c;
}

float3 pixel_center_direction(const Camera& c, int width, int height, int x, int y) {
  Vec3T<float> d = camera_ray_direction(c, (x + 0.5f) / width, 1.0f - (y + 0.5f) / height);
  return {d.x, d.y, d.z};
}

RenderSettings fixed_settings(int width, int height, int spp) {
  return {.width = width,
          .height = height,
          .samples_per_pixel = spp,
          .max_depth = 1,
          .adaptive_tolerance = 0.0f,
          .seed = 1,
          .threads = 2};
}

}  // namespace pt::test
